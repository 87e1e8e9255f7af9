package jsref.runtime;

import java.lang.reflect.InvocationTargetException;
import java.lang.reflect.Method;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.atomic.AtomicInteger;
import jsref.values.JadescriptError;
import jsref.values.Nothing;
import jsref.values.Text;

/** The body being run (a handler, an action block, {@code on create},
    {@code on destroy}) and the services generated code calls from it
    (CONTRACT.md, "jsref.runtime"): its fuel and call depth (R7), what it did
    in order (its events, written after the line of the rule that ran it,
    R8), its effects on behaviours (activate, R5g; deactivate, R5h) and the
    new instance ids (D2). An effect changes the runtime's list of active
    instances at once, and JADE's ready and blocked lists when the rule is
    over ({@link #applyJade}, with the rule's line): so that a message
    arriving meanwhile wakes the blocked behaviours wholly before the rule's
    effects or wholly after them, as its line is before or after the rule's. The agent's public services
    ({@link JadescriptAgent#log} and the others) call these. Only the agent's
    thread runs bodies. */
final class Body {
  /** Behaviour instance numbers ({@code uid}), one counter per JVM as the
      interpreter's. */
  private static final AtomicInteger UIDS = new AtomicInteger();
  /** The effect {@code deactivate this} in {@link #effects}. */
  private static final Object DEACTIVATE = new Object();

  private final JadescriptAgent agent;
  /** What the body did, in order, until its rule's line is written. */
  private final ArrayList<Event> events = new ArrayList<>();
  /** Its effects: a {@link JadescriptBehaviour} activated, or {@link #DEACTIVATE}. */
  private final ArrayList<Object> effects = new ArrayList<>();
  /** JADE's side of the effects of the rule's bodies, in order, until the
      rule is over: a behaviour to add (activated) or to remove (deactivated). */
  private final ArrayList<JadescriptBehaviour> jadeOps = new ArrayList<>();
  private final ArrayList<Boolean> jadeAdds = new ArrayList<>();
  /** The instance whose handler or step runs (null: none, or the agent's own body). */
  JadescriptBehaviour running;
  /** Ids a new instance may not take besides the active ones (D2). */
  List<Integer> reserved = List.of();
  /** {@code on create} of the agent runs: its sends wait (D13), its
      deactivations are only recorded. */
  boolean initPhase;
  private int fuel;
  private int depth;

  Body(JadescriptAgent agent) { this.agent = agent; }

  /** An event of a body (docs/trace-format.md, "Events inside a step"),
      its values already literals: written with the action of the rule that
      ran the body. */
  sealed interface Event permits Log, Invoke, Send, Activate, Deactivate, RunError {
    void write(Trace t, String agent, String action);
  }
  record Log(String text) implements Event {
    public void write(Trace t, String agent, String action) { t.log(agent, action, text); }
  }
  record Invoke(String method, String object, List<String> args, String result) implements Event {
    public void write(Trace t, String agent, String action) { t.invoke(agent, action, method, object, args, result); }
  }
  record Send(String performative, String content, List<String> to) implements Event {
    public void write(Trace t, String agent, String action) { t.send(agent, action, performative, content, to); }
  }
  record Activate(String behaviour) implements Event {
    public void write(Trace t, String agent, String action) { t.activate(agent, action, behaviour); }
  }
  record Deactivate(int instance) implements Event {
    public void write(Trace t, String agent, String action) { t.deactivate(agent, action, instance); }
  }
  record RunError(String at, String message) implements Event {
    public void write(Trace t, String agent, String action) { t.error(agent, action, at, message); }
  }

  // ------------------------------------------------------------ fuel and depth (R7)

  void tick(String at) {
    if (--fuel < 0)
      throw JadescriptError.at(at, "step budget exhausted: more than " + agent.cfg.fuel
          + " statements in one handler or step (--fuel)");
  }

  void enterCall(String at) {
    if (depth >= JadescriptAgent.MAX_CALL_DEPTH)
      throw JadescriptError.at(at, "recursion too deep: more than " + JadescriptAgent.MAX_CALL_DEPTH
          + " nested calls of functions and procedures");
    depth++;
  }

  void exitCall() { depth--; }

  void freshFuel() { fuel = agent.cfg.fuel; }

  // ------------------------------------------------------------ what a body does

  void log(Object v) { events.add(new Log(Text.text(v))); }

  Object invoke(String at, String methodAt, String targetAt, Object target, String method, Object[] args) {
    if (!"any".equals(Text.typeName(target)))
      throw JadescriptError.at(targetAt, "invoke needs a host object (any), not a " + Text.typeName(target));
    String cls = Text.hostClass(target);
    Method m = null;
    boolean varargs = false;
    for (Method c : hostMethods(target, method))
      if (c.getParameterCount() == args.length && !c.isVarArgs()) { m = c; break; }
    if (m == null)
      for (Method c : hostMethods(target, method))
        if (c.isVarArgs() && c.getParameterCount() == 1) { m = c; varargs = true; break; }
    if (m == null) throw JadescriptError.at(methodAt, cls + " has no method \"" + method + "\"");
    Object result;
    try {
      result = varargs ? m.invoke(target, (Object) args) : m.invoke(target, args);
    } catch (InvocationTargetException e) {
      Throwable c = e.getCause();
      if (c instanceof JadescriptError je) throw je;
      throw JadescriptError.at(at, cls + "." + method + " failed: " + c);
    } catch (IllegalAccessException | IllegalArgumentException e) {
      throw JadescriptError.at(at, cls + "." + method + " failed: " + e.getMessage());
    }
    if (result == null || m.getReturnType() == void.class) result = Nothing.NOTHING;
    List<String> lits = new ArrayList<>();
    for (Object a : args) lits.add(Text.literal(a));
    events.add(new Invoke(method, cls, lits, Text.literal(result)));
    return result;
  }

  /** The methods a host object offers by this name: its public instance
      methods, not those of {@code java.lang.Object}. */
  private static List<Method> hostMethods(Object target, String name) {
    List<Method> l = new ArrayList<>();
    for (Method c : target.getClass().getMethods())
      if (c.getName().equals(name) && c.getDeclaringClass() != Object.class
          && !java.lang.reflect.Modifier.isStatic(c.getModifiers())) l.add(c);
    return l;
  }

  void send(String performative, Object content, List<String> receivers) {
    agent.messaging.post(performative, content, receivers, initPhase);
    events.add(new Send(performative, Text.literal(content), new ArrayList<>(receivers)));
  }

  void activate(String at, JadescriptBehaviour b, String[] names, Object[] values) {
    if (agent.active.size() >= JadescriptAgent.MAX_BEHAVIOURS)   // D19
      throw JadescriptError.at(at, "too many behaviours: an agent has at most " + JadescriptAgent.MAX_BEHAVIOURS
          + " active behaviour instances");
    b.bind(agent, UIDS.incrementAndGet());
    b.initProperties();
    b.onCreate(names, values);
    effects.add(b);
    events.add(new Activate(b.typeName()));
    b.setId(newId());
    agent.active.add(b);
    b.jsActive = true;
    jadeOps.add(b);
    jadeAdds.add(true);
  }

  void deactivate(JadescriptBehaviour self) {
    if (effects.contains(DEACTIVATE)) return;
    effects.add(DEACTIVATE);
    events.add(new Deactivate(self.id()));
    if (initPhase) return;   // create_agent keeps only the activations
    JadescriptBehaviour target = running;
    if (target != null && agent.active.remove(target)) {
      target.jsActive = false;
      jadeOps.add(target);
      jadeAdds.add(false);
    }
  }

  /** Has the rule's body changed the active behaviours (JADE's lists still
      to change)? @return true if so */
  boolean hasJadeEffects() { return !jadeOps.isEmpty(); }

  /** The rule is over: JADE's lists follow its bodies' effects, in order
      ({@code addBehaviour}: the end of the ready list, R5g;
      {@code removeBehaviour}: JADE's {@code Scheduler.remove}, R5f). The
      caller holds the message queue's and the scheduler's monitors. */
  void applyJade() {
    for (int i = 0; i < jadeOps.size(); i++) {
      if (jadeAdds.get(i)) agent.addBehaviour(jadeOps.get(i));
      else agent.removeBehaviour(jadeOps.get(i));
    }
    jadeOps.clear();
    jadeAdds.clear();
  }

  void recordError(JadescriptError e) { events.add(new RunError(e.at(), e.message())); }

  void recordTooDeep() { events.add(new RunError(":0:0", "recursion too deep")); }

  // ------------------------------------------------------------ effects and ids

  /** Forget the effects recorded so far (a new body begins). */
  void clearEffects() { effects.clear(); }

  /** The effects recorded since {@link #clearEffects}, as the trace writes
      them. @return {@code "activate B"} and {@code "deactivate"}, in order */
  List<String> describeEffects() {
    List<String> l = new ArrayList<>();
    for (Object e : effects)
      l.add(e == DEACTIVATE ? TraceFormat.Effect.DEACTIVATE
          : TraceFormat.Effect.activate(((JadescriptBehaviour) e).typeName()));
    return l;
  }

  /** The types of the behaviours activated since {@link #clearEffects}, in order.
      @return the type names */
  List<String> activatedTypes() {
    List<String> l = new ArrayList<>();
    for (Object e : effects) if (e instanceof JadescriptBehaviour b) l.add(b.typeName());
    return l;
  }

  /** NewId: the smallest positive id neither active nor reserved (D2).
      Fewer than n ids are used, so one of 1..n is free: marked in one pass
      over each collection, as Machine.new_id (D19). */
  private int newId() {
    int n = agent.active.size() + reserved.size() + 1;
    boolean[] used = new boolean[n + 1];
    for (JadescriptBehaviour b : agent.active) if (b.id() >= 1 && b.id() <= n) used[b.id()] = true;
    for (Integer k : reserved) if (k != null && k >= 1 && k <= n) used[k] = true;
    int i = 1;
    while (used[i]) i++;
    return i;
  }

  // ------------------------------------------------------------ the events, written

  /** Write the events of the body that ran, with the action of its rule:
      each {@code log} also on the output, each {@code error} also on the
      error stream (R7, D15). @param action the rule's action */
  void flush(String action) {
    if (events.isEmpty()) return;
    String name = agent.name();
    Trace t = agent.cfg.trace;
    for (Event e : events) {
      if (e instanceof Log l) agent.cfg.log(name, l.text());
      else if (e instanceof RunError r) agent.cfg.error(r.at(), r.message());
      e.write(t, name, action);
    }
    events.clear();
  }
}
