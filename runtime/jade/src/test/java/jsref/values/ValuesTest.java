package jsref.values;

import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import jsref.runtime.BehaviourInfo;
import jsref.runtime.JadescriptAgent;
import jsref.runtime.ProgramInfo;

/** The test of jsref.values: a plain Java program (no test framework), run by
    scripts/jade-compile-check as
    {@code java jsref.values.ValuesTest [CASES]}. CASES is the output of the
    interpreter's side, {@code test/backend/gen_values.exe} (values with their
    {@code Value.to_text}, {@code Value.to_literal} and {@code Value.equal}):
    the Java must agree on every line. Then fixed cases: integer wrap-around,
    float rounding, the interpreter's error messages, schema values and
    numbers as map keys, host literals. Prints each failure, then
    {@code N passed, M failed}; exit status 1 on a failure. */
public final class ValuesTest {
  private ValuesTest() {}

  private static int passed = 0, failed = 0;

  private static void check(String what, Object expected, Object actual) {
    if (expected == null ? actual == null : expected.equals(actual)) passed++;
    else { failed++; System.out.println("FAIL " + what + ": expected <" + expected + ">, got <" + actual + ">"); }
  }

  private static void error(String what, String at, String message, Runnable r) {
    try {
      r.run();
      failed++;
      System.out.println("FAIL " + what + ": no error");
    } catch (JadescriptError e) {
      check(what, at + ": error: " + message, e.toString());
    }
  }

  /** A schema value of any name and slots, as the interpreter's Value.Schema. */
  static final class Rec extends Schema {
    private static final long serialVersionUID = 1L;
    final String name; final String[] names; final Object[] values; final boolean percept; final int priority;
    Rec(String name, Object[] values, boolean percept, int priority) {
      this.name = name; this.values = values; this.percept = percept; this.priority = priority;
      names = new String[values.length];
      for (int i = 0; i < values.length; i++) names[i] = "s" + i;
    }
    Rec(String name, Object... values) { this(name, values, false, 0); }
    @Override public String schemaName() { return name; }
    @Override public String[] slotNames() { return names.clone(); }
    @Override public Object[] slotValues() { return values.clone(); }
    @Override public Object get(String slot) {
      for (int i = 0; i < names.length; i++) if (names[i].equals(slot)) return values[i];
      return null;
    }
    @Override public boolean set(String slot, Object v) {
      for (int i = 0; i < names.length; i++) if (names[i].equals(slot)) { values[i] = v; return true; }
      return false;
    }
    @Override public boolean isPercept() { return percept; }
    @Override public int defaultPriority() { return priority; }
  }

  // ------------------------------------------------------ the interpreter's cases

  private static String unhex(String h) {
    byte[] b = new byte[h.length() / 2];
    for (int i = 0; i < b.length; i++) b[i] = (byte) Integer.parseInt(h.substring(2 * i, 2 * i + 2), 16);
    return new String(b, StandardCharsets.UTF_8);
  }

  private static Object decode(String[] toks, int[] pos) {
    String t = toks[pos[0]++];
    String[] p = t.split(":", -1);
    switch (p[0]) {
      case "i": return Integer.parseInt(p[1]);
      case "d": return Double.longBitsToDouble(Long.parseUnsignedLong(p[1], 16));
      case "f": return Float.intBitsToFloat(Integer.parseUnsignedInt(p[1], 16));
      case "b": return p[1].equals("1");
      case "t": return unhex(p[1]);
      case "a": return new Aid(unhex(p[1]));
      case "n": return Nothing.NOTHING;
      case "L": {
        JList l = new JList();
        for (int i = Integer.parseInt(p[1]); i > 0; i--) l.add(decode(toks, pos));
        return l;
      }
      case "M": {
        JMap m = new JMap();
        for (int i = Integer.parseInt(p[1]); i > 0; i--) { Object k = decode(toks, pos); m.put(k, decode(toks, pos)); }
        return m;
      }
      case "S": {
        Object[] vs = new Object[Integer.parseInt(p[2])];
        for (int i = 0; i < vs.length; i++) vs[i] = decode(toks, pos);
        return new Rec(unhex(p[1]), vs);
      }
      default: throw new IllegalArgumentException("bad token " + t);
    }
  }

  private static Object decode(String enc) { return decode(enc.split(" "), new int[] { 0 }); }

  private static void differential(String file) throws IOException {
    int n = 0;
    for (String line : Files.readAllLines(Paths.get(file), StandardCharsets.UTF_8)) {
      if (line.isEmpty()) continue;
      String[] f = line.split("\t", -1);
      n++;
      if (f[0].equals("show")) {
        Object v = decode(f[1]);
        check("text of " + f[1], unhex(f[2]), Text.text(v));
        check("literal of " + f[1], unhex(f[3]), Text.literal(v));
      } else {
        Object a = decode(f[1]), b = decode(f[2]);
        boolean eq = f[3].equals("1");
        check("equal " + f[1] + " / " + f[2], eq, Ops.equal(a, b));
        if (eq) {
          check("hash " + f[1] + " / " + f[2], Ops.hash(a), Ops.hash(b));
          JMap m = new JMap();
          m.put(a, "x");
          check("map key " + f[1] + " / " + f[2], "x", m.get(b));
        }
      }
    }
    check("interpreter's cases read", true, n > 0);
  }

  // ------------------------------------------------------------ fixed cases

  /** A program with one percept type, position(x as float, y as float), priority 2. */
  static final class Prog implements ProgramInfo {
    @Override public String[] files() { return new String[] { "p.jade" }; }
    @Override public Class<? extends JadescriptAgent> agentClass(String type) { return null; }
    @Override public List<BehaviourInfo> behaviours() { return new ArrayList<>(); }
    @Override public LinkedHashMap<String, Integer> percepts() { LinkedHashMap<String, Integer> m = new LinkedHashMap<>(); m.put("position", 2); return m; }
    @Override public Object construct(String at, String schema, List<Object> args) {
      if (schema.equals("stop")) { Ops.arity(at, "stop", 0, args.size()); return new Rec("stop"); }
      if (!schema.equals("position")) throw JadescriptError.at(at, "unknown schema " + schema);
      Ops.arity(at, "position", 2, args.size());
      return new Rec("position", new Object[] { Ops.slot(at, "position", "x", Type.FLOAT, args.get(0)),
                                                Ops.slot(at, "position", "y", Type.FLOAT, args.get(1)) }, true, 2);
    }
    @Override public boolean isSchema(String name) { return name.equals("position") || name.equals("stop"); }
    @Override public int slotCount(String name) { return name.equals("position") ? 2 : 0; }
    @Override public boolean isPercept(String name) { return name.equals("position"); }
    @Override public int defaultPriority(String name) { return name.equals("position") ? 2 : 0; }
    @Override public boolean visibleTo(String agentType, String schema) { return agentType.equals("Robot"); }
  }

  private static void literalError(String src, int col, String message) {
    try {
      Literals.parse(src, new Prog(), "--agent");
      failed++;
      System.out.println("FAIL literal " + src + ": no error");
    } catch (LiteralError e) {
      check("literal error " + src, col + ": " + message, e.column() + ": " + e.message());
    }
  }

  private static void fixed() throws LiteralError {
    String at = "p.jade:3:5";
    // integers: Java's int, wrapping around
    check("wrap +", Integer.MIN_VALUE, Ops.add(at, Integer.MAX_VALUE, 1));
    check("wrap *", -2147483648, Ops.mul(at, 65536, 32768));
    check("wrap neg", Integer.MIN_VALUE, Ops.neg(at, Integer.MIN_VALUE));
    check("int division truncates", -2, Ops.div(at, -7, 3));
    check("int %", -1, Ops.mod(at, -7, 3));
    check("MIN / -1", Integer.MIN_VALUE, Ops.div(at, Integer.MIN_VALUE, -1));
    error("division by zero", at, "division by zero", () -> Ops.div(at, 1, 0));
    error("% by zero", at, "division by zero (%)", () -> Ops.mod(at, 1, 0));
    check("float / 0", Float.POSITIVE_INFINITY, Ops.div(at, 1.0f, 0));
    // float32 rounding; a double beside a float is a float (as_float_pair)
    check("float + double literal", 0.3f, Ops.add(at, 0.1f, 0.2));
    check("int + float in double, rounded", (float) (16777217.0 + 0.0), Ops.add(at, 16777217, 0.0f));
    check("float text", "0.3", Text.text(Ops.add(at, 0.1f, 0.2)));
    check("double text", "0.30000000000000004", Text.text(Ops.add(at, 0.1, 0.2)));
    check("int + double", 3.5, Ops.add(at, 1, 2.5));
    check("float = double literal", true, Ops.eqRL(0.1, 0.1f));
    check("1 = 1.0", true, Ops.eqRL(1.0, 1));
    check("NaN = NaN (the interpreter's order)", true, Ops.eqRL(Double.NaN, Double.NaN));
    check("NaN < 1 (the interpreter's order)", true, Ops.ltRL(at, 1.0, Double.NaN));
    check("texts by code point", true, Ops.ltRL(at, "\uD83D\uDE00", "\uFFFD"));
    error("compare", at, "cannot compare integer with text", () -> Ops.ltRL(at, "a", 1));
    error("arith", at, "cannot apply an arithmetic operator to boolean and integer", () -> Ops.sub(at, true, 1));
    check("text + number", "a1.5", Ops.add(at, "a", 1.5));
    check("number + text", "2.0x", Ops.add(at, 2.0f, "x"));
    check("text + list", "l: [\"a\", 1]", Ops.add(at, "l: ", JList.of("a", 1)));
    error("not", at, "not needs a boolean, not a integer", () -> Ops.not(at, 3));
    error("and", at, "and needs booleans, not a text", () -> Ops.truth(at, "and", "x"));
    error("condition", at, "a condition is a boolean, not a integer", () -> Ops.cond(at, 1));
    error("when", at, "a when condition is a boolean, not a nothing", () -> Ops.whenCond(at, Nothing.NOTHING));
    // collections
    JList l = JList.of(1, 2, 3);
    check("index", 2, Ops.index(at, l, 1));
    error("index bounds", at, "index 3 is out of bounds (the list has 3 elements)", () -> Ops.index(at, l, 3));
    error("index negative", at, "index -1 is out of bounds (the list has 3 elements)", () -> Ops.setIndex(at, l, -1, 0));
    error("index a number", at, "cannot index a integer", () -> Ops.index(at, 5, 0));
    JMap m = new JMap();
    m.put(1, "one");
    check("1.0 finds 1", "one", Ops.index(at, m, 1.0));
    check("1.0f finds 1", "one", Ops.index(at, m, 1.0f));
    m.put(1.0, "uno");
    check("same key kept", "{1: \"uno\"}", Text.literal(m));
    error("missing key", at, "the map has no key \"k\"", () -> Ops.index(at, m, "k"));
    Rec p1 = new Rec("position", new Object[] { 1.0f, 2.0f }, true, 2);
    Rec p2 = new Rec("position", new Object[] { 1.0f, 2.0f }, true, 2);
    Rec p3 = new Rec("position", new Object[] { 2.0f, 2.0f }, true, 2);
    JMap world = new JMap();
    world.put(p1, "A7");
    world.put(new Rec("position", 1, 2), "B1");   // integers equal to the floats: the same key (R1c)
    check("schema key", "B1", world.get(p2));
    check("schema keys merged", 1, world.size());
    check("schema other key", null, world.get(p3));
    check("schema equals", true, p1.equals(p2));
    check("schema hashCode", p1.hashCode(), p2.hashCode());
    check("insertion order", "[3, 1, 2]", Text.literal(JList.copyOf(mapOf(3, 1, 2).keys())));
    check("for over a map copies its keys", 3, Ops.iter(at, mapOf(3, 1, 2)).size());
    error("iterate", at, "cannot iterate over a text", () -> Ops.iter(at, "abc"));
    check("length of text (UTF-8 bytes)", 5, Ops.of(at, "length", "caf\u00e9", null));
    check("priority of a percept", 2, Ops.of(at, "priority", p1, null));
    error("priority of a concept", at, "stop has no priority", () -> Ops.of(at, "priority", new Rec("stop"), null));
    error("no slot", at, "position has no slot z", () -> Ops.of(at, "z", p1, null));
    error("no property", at, "a integer has no property size", () -> Ops.of(at, "size", 3, null));
    List<String> rs = new ArrayList<>();
    Ops.addReceivers(at, JList.of(new Aid("a"), new Aid("b")), rs);
    check("receivers", "[a, b]", rs.toString());
    error("receiver", at, "a receiver is an aid, not a text", () -> Ops.addReceivers(at, "a", new ArrayList<>()));
    // conversions
    check("coerce int to float", 3.0f, Ops.coerce(Type.FLOAT, 3));
    check("coerce double to float", 0.1f, Ops.coerce(Type.FLOAT, 0.1));
    check("coerce float stays for double", 0.5f, Ops.coerce(Type.DOUBLE, 0.5f));
    check("coerceParam refuses", null, Ops.coerceParam(Type.TEXT, 1));
    error("slot type", at, "slot x of position is a float, not a text",
          () -> Ops.slot(at, "position", "x", Type.FLOAT, "a"));
    check("type text", "map of (list of integer):text", Type.map(Type.list(Type.INTEGER), Type.TEXT).toString());
    // text formats
    check("double 1e7", "1.0E7", Text.text(1e7));
    check("double 1e-4", "1.0E-4", Text.text(1e-4));
    check("float 100", "100.0", Text.text(100f));
    check("min double: the interpreter's shortest digits", "5.0E-324", Text.text(Double.MIN_VALUE));
    check("text literal", "\"a\\\"b\\\\c\\n\\u0001\"", Text.literal("a\"b\\c\n\u0001"));
    check("aid", "aid(\"r\")", Text.text(new Aid("r")));
    check("nothing", "nothing", Text.text(Nothing.NOTHING));
    check("message", "message(\"inform\", 1, aid(\"host\"))", Text.text(new MessageValue("inform", 1, "host")));
    // host literals (Eval.literal_value, percept_value, split_args)
    Prog prog = new Prog();
    check("literal list", "[1, -2, 2.5, \"x\", true, aid(\"b\")]",
          Text.literal(Literals.parse("[1, -2, 2.5, \"x\", true, aid(\"b\")]", prog, "--agent")));
    check("literal map", "{\"a\": [1], 2: {}}", Text.literal(Literals.parse("{\"a\": [1], 2: {}}", prog, "--agent")));
    check("literal schema widened", "position(1.0, 2.0)", Text.literal(Literals.parse("position(1, 2)", prog, "--agent")));
    check("literal proposition", "stop", Text.literal(Literals.parse("stop", prog, "--agent")));
    check("literal escapes", "a\"\n\u00e9", Literals.parse("\"a\\\"\\n\\u00e9\"", prog, "--agent"));
    literalError("1 + 2", 1, "only literal values can be given here");
    literalError("[1, x]", 5, "x is not a value the host can give (a literal, aid(\"name\") or a schema construction)");
    literalError("position(1)", 1, "position takes 2 arguments, not 1");
    literalError("position(\"a\", 1)", 1, "slot x of position is a float, not a text");
    literalError("aid(1)", 1, "aid takes a text");
    literalError("-\"a\"", 1, "only numbers can be negated");
    literalError("\"abc", 1, "this text literal is never closed: a '\"' is missing before the end of the line");
    literalError("{1: y, z: 2}", 5, "y is not a value the host can give (a literal, aid(\"name\") or a schema construction)");
    Schema pc = Literals.percept("position(1, 2.5)", prog, "Robot", "events.jsonl");
    check("percept", "position(1.0, 2.5)", Text.literal(pc));
    check("percept priority", 2, pc.defaultPriority());
    try {
      Literals.percept("position(1, 2)", prog, "Other", "events.jsonl");
      failed++; System.out.println("FAIL percept not visible: no error");
    } catch (LiteralError e) {
      check("percept not visible", "percept type position is not in an ontology that agent type Other uses", e.message());
    }
    try {
      Literals.percept("stop", prog, "Robot", "events.jsonl");
      failed++; System.out.println("FAIL not a percept: no error");
    } catch (LiteralError e) {
      check("not a percept", "stop is not a percept type (it does not extend percept)", e.message());
    }
    check("split", "[a, b(1, 2), \"x,y\", [3, 4]]", Literals.split("a, b(1, 2),\"x,y\" ,[3, 4]").toString());
    check("split empty", "[]", Literals.split("").toString());
  }

  private static JMap mapOf(Object... keys) {
    JMap m = new JMap();
    for (Object k : keys) m.put(k, true);
    return m;
  }

  /** Runs the cases. @param args the interpreter's cases file (optional)
      @throws Exception never, except a bug of the test */
  public static void main(String[] args) throws Exception {
    if (args.length > 0) differential(args[0]);
    fixed();
    System.out.println(passed + " passed, " + failed + " failed");
    if (failed > 0) System.exit(1);
  }
}
