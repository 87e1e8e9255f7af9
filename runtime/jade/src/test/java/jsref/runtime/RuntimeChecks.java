package jsref.runtime;

import java.util.ArrayList;
import java.util.Comparator;
import java.util.Iterator;
import java.util.List;
import java.util.Random;

/** The runtime's unit checks, without a test framework: the stable priority
    queue (R3b), the port of OCaml 4.13's {@code Random.State} (R6, D17),
    the JSON writer and reader, and the JADE names of agents (D48). Prints {@code N passed, M failed}; exit status
    1 on a failure.
    <pre>java -cp target/classes:target/test-classes:target/lib/jade-4.3.jar jsref.runtime.RuntimeChecks</pre> */
public final class RuntimeChecks {
  private RuntimeChecks() {}

  private static int passed;
  private static int failed;

  private static void check(String what, boolean ok) {
    if (ok) passed++;
    else { failed++; System.out.println("FAIL: " + what); }
  }

  private static void equal(String what, Object expected, Object got) {
    boolean ok = expected == null ? got == null : expected.equals(got);
    if (!ok) System.out.println("  expected: " + expected + "\n  got:      " + got);
    check(what, ok);
  }

  /** Runs every check. @param args ignored */
  public static void main(String[] args) {
    queue();
    random();
    json();
    names();
    System.out.println(passed + " passed, " + failed + " failed");
    System.exit(failed == 0 ? 0 : 1);
  }

  // ------------------------------------------------------------ queue

  private static String order(PerceptQueue q) {
    StringBuilder b = new StringBuilder();
    while (!q.isEmpty()) { PerceptEntry e = q.pop(); b.append(e.percept()).append(' '); }
    return b.toString().trim();
  }

  private static void queue() {
    // the example of docs/semantics.md
    PerceptQueue q = new PerceptQueue();
    q.insert(new PerceptEntry("position(1,2)", 2, 1));
    q.insert(new PerceptEntry("obstacle", 8, 2));
    q.insert(new PerceptEntry("position(3,4)", 2, 3));
    equal("highest priority first, then smallest seq", "obstacle position(1,2) position(3,4)", order(q));

    // ties: equal priorities leave in seq order, whatever the type
    q = new PerceptQueue();
    for (int s = 1; s <= 6; s++) q.insert(new PerceptEntry("p" + s, s % 2 == 0 ? 4 : 4, s));
    equal("ties to the smallest seq", "p1 p2 p3 p4 p5 p6", order(q));

    // an insert out of seq order is placed by seq (stable among equal seqs)
    q = new PerceptQueue();
    q.insert(new PerceptEntry("a", 1, 5));
    q.insert(new PerceptEntry("b", 1, 2));
    q.insert(new PerceptEntry("c", 1, 9));
    q.insert(new PerceptEntry("d", 1, 2));
    equal("placed by seq, after equal seqs", "b d a c", order(q));

    // peek and size
    q = new PerceptQueue();
    check("empty", q.isEmpty() && q.peek() == null && q.pop() == null && q.size() == 0);
    q.insert(new PerceptEntry("x", 0, 1));
    q.insert(new PerceptEntry("y", 10, 2));
    check("peek does not remove", q.peek().percept().equals("y") && q.size() == 2);

    // random interleavings of inserts and pops against a sorted model
    Random r = new Random(13);
    for (int round = 0; round < 300; round++) {
      PerceptQueue pq = new PerceptQueue();
      List<PerceptEntry> model = new ArrayList<>();
      int seq = 0;
      boolean ok = true;
      for (int op = 0; op < 60 && ok; op++) {
        if (r.nextInt(3) > 0) {
          PerceptEntry e = new PerceptEntry("p" + (++seq), r.nextInt(5), seq);
          pq.insert(e);
          model.add(e);
        } else {
          model.sort(Comparator.comparingInt((PerceptEntry e) -> -e.priority()).thenComparingInt(PerceptEntry::seq));
          PerceptEntry want = model.isEmpty() ? null : model.remove(0);
          PerceptEntry got = pq.pop();
          ok = want == got;
        }
      }
      model.sort(Comparator.comparingInt((PerceptEntry e) -> -e.priority()).thenComparingInt(PerceptEntry::seq));
      Iterator<PerceptEntry> it = pq.inOrder();
      for (PerceptEntry e : model) ok &= it.hasNext() && it.next() == e;
      ok &= !it.hasNext() && pq.size() == model.size();
      check("random queue " + round, ok);
    }
  }

  // ------------------------------------------------------------ random

  private static String ints(int[] a) {
    StringBuilder b = new StringBuilder();
    for (int x : a) { if (b.length() > 0) b.append(' '); b.append(x); }
    return b.toString();
  }

  /** Values printed by OCaml 4.13.1 for
      {@code let r = Random.State.make [| seed |]}: eight {@code bits r},
      then {@code int r (i + 1)} for i = 0..7, then four {@code int r 1000000}. */
  private static void random() {
    Object[][] expected = {
      { 0L, "218040752 178628190 911923154 33712936 1041571162 675934603 1036154868 964306322",
        "0 1 1 1 3 1 4 6", "653048 476195 569356 296398" },
      { 7L, "132754482 354598343 700418544 731207158 916218758 76181660 369812431 850068142",
        "0 1 1 1 2 1 1 3", "188257 526790 588009 231057" },
      { 42L, "1001215014 905297655 49291623 328501953 104130057 795793355 982752234 570925001",
        "0 0 0 0 0 0 4 2", "350806 686201 607057 826571" },
      { -5L, "638983422 1072006411 37028206 270829641 521483706 1044727059 962173078 765951538",
        "0 0 1 3 3 0 2 0", "365624 271604 990338 730635" },
      { 123456789L, "1047213900 619322777 232370739 831219731 841638859 1040356514 291394478 487865846",
        "0 0 2 1 2 3 2 6", "838018 185865 597244 652977" },
    };
    for (Object[] row : expected) {
      long seed = (Long) row[0];
      OcamlRandom r = new OcamlRandom(seed);
      int[] bits = new int[8], small = new int[8], big = new int[4];
      for (int i = 0; i < 8; i++) bits[i] = r.bits();
      for (int i = 0; i < 8; i++) small[i] = r.nextInt(i + 1);
      for (int i = 0; i < 4; i++) big[i] = r.nextInt(1000000);
      equal("Random.State.bits, seed " + seed, row[1], ints(bits));
      equal("Random.State.int small, seed " + seed, row[2], ints(small));
      equal("Random.State.int 1000000, seed " + seed, row[3], ints(big));
    }
    // Runtime.order for three agents under seed 7, three rounds (OCaml:
    // the Fisher-Yates shuffle of lib/interp/runtime.ml)
    OcamlRandom r = new OcamlRandom(7);
    StringBuilder b = new StringBuilder();
    for (int round = 0; round < 3; round++) b.append('[').append(ints(r.order(3))).append(']');
    equal("Runtime.order, seed 7", "[2 1 0][1 2 0][1 0 2]", b.toString());
  }

  // ------------------------------------------------------------ json

  /** D48: {@link Names#jade} is one to one, and no two of its names are
      equal ignoring case (JADE's {@code AID.equals}), nor {@code ams} or
      {@code df}; {@link Names#jadescript} undoes it. */
  private static void names() {
    List<String> all = List.of("bob", "Bob", "BOB", "b0b-1", "ams", "AMS", "Ams", "df", "DF", "host", "HOST",
        "_426f62", "_", "a_b", "Ä", "ä", "ß", "SS", "ss", "\u212a", "k", "K", "x y", "r\"1", "é", "e\u0301", "🤖");
    java.util.Set<String> seen = new java.util.HashSet<>();
    for (String n : all) {
      String j = Names.jade(n);
      equal("D48 the name " + n + " comes back", n, Names.jadescript(j));
      check("D48 the JADE name of " + n + " is not the platform's", !j.equalsIgnoreCase("ams") && !j.equalsIgnoreCase("df"));
      check("D48 the JADE name of " + n + " is no other's, ignoring case", seen.add(j.toLowerCase(java.util.Locale.ROOT)));
      check("D48 the JADE name of " + n + " is its own lower case", j.equals(j.toLowerCase(java.util.Locale.ROOT)));
    }
    equal("D48 a plain name is kept", "r1-x", Names.jade("r1-x"));
    equal("D48 another is hex-encoded", "_426f62", Names.jade("Bob"));
  }

  private static void json() {
    Json.Obj o = new Json.Obj().put("step", 1).put("agent", "r").put("text", "a\"b\\c\nd\te\u0001\u007f/é")
        .put("n", null).put("l", List.of("x", 2)).put("b", true);
    equal("Yojson's escapes", "{\"step\":1,\"agent\":\"r\",\"text\":\"a\\\"b\\\\c\\nd\\te\\u0001\\u007f/é\","
        + "\"n\":null,\"l\":[\"x\",2],\"b\":true}", o.toString());
    try {
      Object v = Json.parse(" {\"agent\": \"r\", \"notify\": \"qr(\\\"A7\\\")\", \"priority\": 9, \"x\": [1.5, null, false]} ");
      check("parse an object", v instanceof java.util.Map<?, ?> m && "qr(\"A7\")".equals(m.get("notify"))
          && Long.valueOf(9).equals(m.get("priority")) && m.get("x") instanceof List<?> l && l.size() == 3
          && Double.valueOf(1.5).equals(l.get(0)) && l.get(1) == Json.NULL && Boolean.FALSE.equals(l.get(2)));
    } catch (Json.Error e) {
      check("parse an object: " + e.getMessage(), false);
    }
    try {
      Json.parse("{\"a\": }");
      check("a syntax error is refused", false);
    } catch (Json.Error e) {
      check("a syntax error has its column", e.column == 7);
    }
  }
}
