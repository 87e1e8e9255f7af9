package jsref.runtime;

import java.io.FileOutputStream;
import java.io.IOException;
import java.io.PrintStream;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.TreeSet;
import java.util.regex.Pattern;
import java.util.stream.Stream;
import jsref.runtime.TraceFormat.Effect;

/** One owner of the trace format in the Java runtime (docs/jade.md,
    "The trace"): {@link TraceFormat} holds every name, {@link Trace} writes
    every line.

    <pre>java ... jsref.runtime.TraceFormatCheck SRC SAMPLES NAMES</pre>

    <ol>
    <li>No other source of the runtime ({@code SRC}: {@code jsref/runtime}
    and {@code jade/core}) writes a name of the format (an event, a field of
    a line or of the header, an action) as a string literal. Two other
    formats share some of its words and own them the same way, each as
    constants of one class and nowhere else: the host's events file
    ({@link EventsFile}: {@code "notify"}, {@code "agent"}...) and the link
    between two JVMs ({@link Link}: {@code "create"}, {@code "name"}...).</li>
    <li>Writes to {@code SAMPLES} a trace with one line of every kind, each
    written by its method of {@link Trace}, and to {@code NAMES} every name
    of {@link TraceFormat} ({@code event create}, {@code field step},
    {@code action Init}, {@code header trace}, one a line).</li>
    </ol>

    The OCaml side ({@code runtime/jade/src/test/ocaml/trace_format_check.ml})
    then reads {@code SAMPLES} with the OCaml owner of the format
    ({@code lib/trace}): every line must be read strictly and written again
    byte for byte, every kind of event of OCaml's {@code Trace.event} must be
    there, and {@code NAMES} must be exactly OCaml's names. Prints
    {@code N passed, M failed}; exit status 1 on a failure. */
public final class TraceFormatCheck {
  private TraceFormatCheck() {}

  private static int passed;
  private static int failed;

  private static void check(String what, boolean ok) {
    if (ok) passed++;
    else { failed++; System.out.println("FAIL: " + what); }
  }

  /** The classes that hold the trace's names, by the category NAMES gives them. */
  private static final Map<String, Class<?>> CATEGORIES = new LinkedHashMap<>();
  static {
    CATEGORIES.put("event", TraceFormat.Event.class);
    CATEGORIES.put("field", TraceFormat.Field.class);
    CATEGORIES.put("action", TraceFormat.Action.class);
    CATEGORIES.put("header", TraceFormat.Header.class);
  }

  /** The files that own a format and may write its names, as constants only:
      file name -> the format. TraceFormat.java may write them anywhere. */
  private static final Map<String, String> OTHER_OWNERS = Map.of(
      "EventsFile.java", "the host's events file",
      "Link.java", "the link between two JVMs");

  /** Runs the checks. @param args SRC SAMPLES NAMES @throws IOException on a file error */
  public static void main(String[] args) throws IOException {
    if (args.length != 3) {
      System.err.println("usage: TraceFormatCheck SRC SAMPLES NAMES");
      System.exit(2);
    }
    Map<String, String> names = names();   // name -> category
    check("TraceFormat declares names", names.size() > 40);
    literals(Path.of(args[0]), names);
    samples(args[1]);
    try (PrintStream out = new PrintStream(new FileOutputStream(args[2]), true, StandardCharsets.UTF_8)) {
      for (Map.Entry<String, Class<?>> c : CATEGORIES.entrySet())
        for (String n : constants(c.getValue())) out.println(c.getKey() + " " + n);
    }
    System.out.println(passed + " passed, " + failed + " failed");
    System.exit(failed == 0 ? 0 : 1);
  }

  /** The String constants of a class of TraceFormat. */
  private static List<String> constants(Class<?> c) {
    List<String> l = new ArrayList<>();
    for (Field f : c.getDeclaredFields()) {
      int m = f.getModifiers();
      if (Modifier.isStatic(m) && Modifier.isFinal(m) && f.getType() == String.class) {
        try { l.add((String) f.get(null)); } catch (IllegalAccessException e) { throw new IllegalStateException(e); }
      }
    }
    return l;
  }

  private static Map<String, String> names() {
    Map<String, String> m = new TreeMap<>();
    for (Map.Entry<String, Class<?>> c : CATEGORIES.entrySet())
      for (String n : constants(c.getValue())) m.putIfAbsent(n, c.getKey());
    return m;
  }

  // ------------------------------------------------------------ literals

  /** A string literal of a Java source: its text (escapes kept as written)
      and its line. */
  record Literal(String text, int line) {}

  /** The string literals of a Java source, outside comments (text blocks
      and character literals skipped). */
  static List<Literal> stringLiterals(String src) {
    List<Literal> l = new ArrayList<>();
    int line = 1;
    int i = 0;
    int n = src.length();
    while (i < n) {
      char c = src.charAt(i);
      if (c == '\n') { line++; i++; }
      else if (src.startsWith("//", i)) { while (i < n && src.charAt(i) != '\n') i++; }
      else if (src.startsWith("/*", i)) {
        int end = src.indexOf("*/", i + 2);
        end = end < 0 ? n : end + 2;
        for (int k = i; k < end; k++) if (src.charAt(k) == '\n') line++;
        i = end;
      } else if (src.startsWith("\"\"\"", i)) {
        int end = src.indexOf("\"\"\"", i + 3);
        end = end < 0 ? n : end + 3;
        for (int k = i; k < end; k++) if (src.charAt(k) == '\n') line++;
        i = end;
      } else if (c == '"' || c == '\'') {
        StringBuilder b = new StringBuilder();
        int start = line;
        i++;
        while (i < n && src.charAt(i) != c && src.charAt(i) != '\n') {
          if (src.charAt(i) == '\\' && i + 1 < n) { b.append(src, i, i + 2); i += 2; }
          else b.append(src.charAt(i++));
        }
        i++;
        if (c == '"') l.add(new Literal(b.toString(), start));
      } else i++;
    }
    return l;
  }

  private static final Pattern CONSTANT = Pattern.compile("\\s*(?:public |private )?static final String [A-Z][A-Z_]* = \".*\";.*");

  /** No trace name as a literal outside TraceFormat (and the two other
      owners' constants): one check per source file. */
  private static void literals(Path src, Map<String, String> names) throws IOException {
    List<Path> files = new ArrayList<>();
    for (String dir : List.of("jsref/runtime", "jade/core"))
      try (Stream<Path> s = Files.walk(src.resolve(dir))) {
        s.filter(p -> p.toString().endsWith(".java")).sorted().forEach(files::add);
      }
    check("the runtime's sources found under " + src, files.size() > 10);
    for (Path p : files) {
      String file = p.getFileName().toString();
      if (file.equals("TraceFormat.java")) continue;
      String text = Files.readString(p, StandardCharsets.UTF_8);
      String[] lines = text.split("\n", -1);
      List<String> bad = new ArrayList<>();
      for (Literal lit : stringLiterals(text)) {
        String category = names.get(lit.text());
        if (category == null) continue;
        String where = lines[lit.line() - 1];
        if (OTHER_OWNERS.containsKey(file) && CONSTANT.matcher(where).matches()) continue;
        bad.add(p + ":" + lit.line() + ": \"" + lit.text() + "\" (a name of the trace format, " + category
            + ") written as a literal: use TraceFormat");
      }
      for (String b : bad) System.out.println("  " + b);
      check(file + " writes no name of the trace format" + (OTHER_OWNERS.containsKey(file)
          ? " except as constants of " + OTHER_OWNERS.get(file) : ""), bad.isEmpty());
    }
  }

  // ------------------------------------------------------------ samples

  /** One line of every kind, each from its method of Trace. */
  private static void samples(String path) throws IOException {
    Trace t = new Trace(new FileOutputStream(path));
    Map<String, String> agents = new LinkedHashMap<>();
    agents.put("a", "A");
    agents.put("b", "B");
    Map<String, Integer> percepts = new LinkedHashMap<>();
    percepts.put("falling", 10);
    percepts.put("position", 2);
    t.header("reference", 3, 4, 7, agents, Map.of("b", TraceFormat.Value.PERIPHERAL),
        List.of(new BehaviourInfo("W", "cyclic", true, 2, 1), new BehaviourInfo("H", "oneshot", false, 0, 0)),
        percepts);
    PerceptEntry e = new PerceptEntry("p(\"\\\"\")", 2, 1);
    Message m = new Message("inform", "c\n", "b");
    t.create("a", "A", new Object[] { 1, "x" }, List.of("W"));
    t.notify("a", e, false);
    t.notify("a", new PerceptEntry("falling", 9, 2), true);
    t.refused("a", "falling");
    t.refusedPut("a", "box");
    t.put("a", "box", 1);
    t.deliver("a", m, 1, false);
    t.deliver("a", m, 2, true);
    t.undeliverable("a", "z", "inform", "c");
    t.transfer("a", 2);
    t.transferOne("a", e);
    t.transferSpin("a", "box");
    t.transferEnd("a");
    t.dequeue("a", e);
    t.handle("a", 1, "W", 2, e.percept(), e.seq(), List.of(Effect.activate("H"), Effect.DEACTIVATE));
    t.skip("a", 1, "W", 1);
    t.endDispatch("a", 1, false);
    t.endDispatch("a", 2, true);
    t.behaviourStep("a", 1, "W", null, 0, null, null, null, null);
    t.behaviourStep("a", 1, "W", null, 0, null, List.of(), null, null);
    t.behaviourStep("a", 1, "W", m, 1, null, null, 1, List.of());
    t.behaviourStep("a", 1, "W", m, 1, null, List.of(Effect.DEACTIVATE), 1, List.of(Effect.activate("H")));
    t.behaviourStep("a", 1, "W", null, 0, e, List.of(), 2, List.of());
    t.nextIteration("a");
    t.idle("a");
    t.log("a", TraceFormat.Action.HANDLE, "l\t\u00e9");
    t.invoke("a", TraceFormat.Action.INIT, "callStop", "RoboMe", List.of("1", "\"t\""), "nothing");
    t.send("a", TraceFormat.Action.BEHAVIOUR_STEP, "inform", "c", List.of("a", "b"));
    t.activate("a", TraceFormat.Action.HANDLE, "H");
    t.deactivate("a", TraceFormat.Action.HANDLE, 2);
    t.error("a", TraceFormat.Action.DESTROY, "f.jade:1:2", "m\"");
    t.destroy("a");
    t.close();
    check("the samples are written", Files.size(Path.of(path)) > 0);
    // each method wrote one line, with its step
    TreeSet<Integer> steps = new TreeSet<>();
    List<String> ls = Files.readAllLines(Path.of(path), StandardCharsets.UTF_8);
    for (String l : ls.subList(1, ls.size())) {
      try {
        Object j = Json.parse(l);
        if (j instanceof Map<?, ?> mm && mm.get(TraceFormat.Field.STEP) instanceof Long s) steps.add((int) (long) s);
      } catch (Json.Error x) {
        check("a sample line is JSON: " + l, false);
      }
    }
    check("one line per sample, numbered from 1", steps.size() == ls.size() - 1 && steps.first() == 1
        && steps.last() == ls.size() - 1);
  }
}
