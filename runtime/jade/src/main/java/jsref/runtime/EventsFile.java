package jsref.runtime;

import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import jsref.values.LiteralError;
import jsref.values.Literals;
import jsref.values.Schema;

/** The host's events file (docs/trace-format.md, "Events files"), read as
    the reference reads it ({@code lib/interp/events.ml}): one host action per
    line, every line checked before anything runs, a bad line reported as
    {@code FILE:LINE:COL: error: message} with the reference's wording where
    the reference has one. Its keys are written here once. */
final class EventsFile {
  private EventsFile() {}

  // the keys of a line, and the word of {"run": "idle"}
  static final String AGENT = "agent";
  static final String NOTIFY = "notify";
  static final String PRIORITY = "priority";
  static final String PUT = "put";
  static final String MESSAGE = "message";
  static final String PERFORMATIVE = "performative";
  static final String RUN = "run";
  /** D42: {@code "during": "step"}, a message for the agent's next behaviour step. */
  static final String DURING = "during";
  static final String STEP = "step";
  static final String RULES = "rules";
  static final String IDLE = "idle";

  /** One host action. */
  sealed interface HostEvent permits Notify, Put, Msg, Run, RunRules, RunIdle {}
  /** {@code notifyEvent(p)}, or {@code notifyEvent(p, k)} when the priority is given (R2a, R2b). */
  record Notify(String agent, Schema percept, Integer priority) implements HostEvent {}
  /** A non-percept object into the O2A queue (R2c). */
  record Put(String agent, Object value) implements HostEvent {}
  /** A message from the host (R5e); {@code duringStep}: it arrives during
      the agent's next behaviour step (D42). */
  record Msg(String agent, String performative, Object content, boolean duringStep) implements HostEvent {}
  /** {@code {"run": n}}: n rounds (D20). */
  record Run(long rounds) implements HostEvent {}
  /** {@code {"run": "idle"}}: rounds until every agent is idle. */
  record RunIdle() implements HostEvent {}
  /** {@code {"run": {"rules": n}}} (D23): n single rules of the first agent not idle. */
  record RunRules(long rules) implements HostEvent {}

  /** Read an events file, every line checked before anything runs: the
      host's actions in order, or every bad line as {@code FILE:LINE:COL:
      error: message}. @param program the program (literals are read with its
      ontologies) @param agents the agents' names and types @param file the file
      @return the actions @throws Main.Stop with every bad line */
  static List<HostEvent> read(ProgramInfo program, Map<String, String> agents, String file) throws Main.Stop {
    String text;
    try {
      text = Files.readString(Path.of(file), StandardCharsets.UTF_8);
    } catch (java.nio.file.NoSuchFileException e) {
      throw new Main.Stop(file + ":1:1: error: cannot read the events file: " + file + ": No such file or directory");
    } catch (IOException | java.io.UncheckedIOException e) {
      throw new Main.Stop(file + ":1:1: error: cannot read the events file: " + e.getMessage());
    }
    String[] lines = text.split("\n", -1);
    List<HostEvent> evs = new ArrayList<>();
    List<String> errors = new ArrayList<>();
    for (int k = 0; k < lines.length; k++) {
      int n = k + 1;
      String line = lines[k].strip();
      if (line.isEmpty() || line.charAt(0) == '#') continue;
      Object j;
      try {
        j = Json.parse(line);
      } catch (Json.Error e) {
        errors.add(file + ":" + n + ":1: error: not a JSON object: " + e.getMessage() + " at column " + e.column);
        continue;
      }
      if (!(j instanceof Map<?, ?> m)) { errors.add(file + ":" + n + ":1: error: each line is a JSON object"); continue; }
      Object notify = m.get(NOTIFY), put = m.get(PUT), msg = m.get(MESSAGE), run = m.get(RUN);
      final int line_ = n;
      java.util.function.BiConsumer<Integer, String> bad =
          (col, s) -> errors.add(file + ":" + line_ + ":" + col + ": error: " + s);
      if (notify instanceof String p && put == null && msg == null && run == null) {
        String ag = eventAgent(m, agents, bad);
        if (ag == null) continue;
        Schema v;
        try {
          v = Literals.percept(p, program, agents.get(ag), file);
        } catch (LiteralError e) { bad.accept(e.column(), e.message()); continue; }
        Object pr = m.get(PRIORITY);
        if (pr == null) evs.add(new Notify(ag, v, null));
        else if (pr instanceof Long k2 && k2 >= 0 && k2 <= Integer.MAX_VALUE) evs.add(new Notify(ag, v, (int) (long) k2));
        // integers are Java's int (D8); the same lines as the reference's reader
        else if (pr instanceof Long)
          bad.accept(columnOf(line, PRIORITY), "\"priority\" is a natural number of 32 bits (R2a, D8): 0 to 2147483647");
        else bad.accept(columnOf(line, PRIORITY), "\"priority\" is a natural number (R2a)");
      } else if (notify == null && put instanceof String o && msg == null && run == null) {
        // as the reference: the object is read before the agent is looked up
        Object v = null;
        boolean ok = true;
        try { v = Literals.parse(o, program, file); }
        catch (LiteralError e) { bad.accept(e.column(), e.message()); ok = false; }
        String ag = eventAgent(m, agents, bad);
        if (ag != null && ok) evs.add(new Put(ag, v));
      } else if (notify == null && put == null && msg instanceof String c && run == null) {
        Object pf = m.get(PERFORMATIVE);
        String perf = pf == null ? "inform" : pf instanceof String s && PERFORMATIVES.contains(s) ? s : null;
        boolean ok = true;
        if (perf == null) {
          // as the reference (Interp.Events): only the performatives the language knows
          bad.accept(columnOf(line, PERFORMATIVE),
              "\"performative\" is one of the FIPA performatives the language knows: "
              + String.join(", ", PERFORMATIVES));
          ok = false;
        }
        Object v = null;
        try { v = Literals.parse(c, program, file); }
        catch (LiteralError e) { bad.accept(e.column(), e.message()); ok = false; }
        // D42: "during": "step", the message arrives during the agent's next behaviour step (R5d)
        Object during = m.get(DURING);
        if (during != null && !STEP.equals(during)) {
          bad.accept(columnOf(line, DURING),
              "\"during\" is \"step\": the message arrives during the agent's next behaviour step (D42)");
          ok = false;
        }
        String ag = eventAgent(m, agents, bad);
        if (ag != null && ok) evs.add(new Msg(ag, perf, v, during != null));
      } else if (notify == null && put == null && msg == null && run instanceof Long k2 && k2 >= 0) {
        evs.add(new Run(k2));
      } else if (notify == null && put == null && msg == null && IDLE.equals(run)) {
        evs.add(new RunIdle());
      } else if (notify == null && put == null && msg == null && run instanceof Map<?, ?> rm) {
        if (rm.size() == 1 && rm.get(RULES) instanceof Long k2 && k2 >= 0) evs.add(new RunRules(k2));
        else bad.accept(1, "\"run\": {\"rules\": N} takes one field, a natural number");
      } else {
        bad.accept(1, "expected one of \"notify\", \"put\", \"message\" (with \"agent\") or \"run\" (a number, \"idle\" or {\"rules\": N})");
      }
    }
    if (!errors.isEmpty()) throw new Main.Stop(String.join("\n", errors));
    return evs;
  }

  /** The FIPA performatives the language knows, in the order of the
      reference's list (Typing.performatives, lib/typing/check.ml). */
  static final List<String> PERFORMATIVES = List.of(
      "accept_proposal", "agree", "cancel", "cfp", "confirm", "disconfirm", "failure",
      "inform", "inform_if", "inform_ref", "not_understood", "propagate", "propose",
      "proxy", "query_if", "query_ref", "refuse", "reject_proposal", "request",
      "request_when", "request_whenever", "subscribe");

  /** The 1-based column of a field's name in a line, as the reference's
      events reader finds it; 1 when it is not there. */
  private static int columnOf(String line, String field) {
    int i = line.indexOf("\"" + field + "\"");
    return i < 0 ? 1 : i + 1;
  }

  private static String eventAgent(Map<?, ?> m, Map<String, String> agents,
                                   java.util.function.BiConsumer<Integer, String> bad) {
    Object a = m.get(AGENT);
    if (!(a instanceof String name)) { bad.accept(1, "this line needs an \"agent\""); return null; }
    if (agents.containsKey(name)) return name;
    bad.accept(1, "there is no agent " + name);
    return null;
  }}
