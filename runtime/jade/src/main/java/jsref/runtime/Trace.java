package jsref.runtime;

import java.io.BufferedOutputStream;
import java.io.IOException;
import java.io.OutputStream;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import jsref.runtime.TraceFormat.Action;
import jsref.runtime.TraceFormat.Event;
import jsref.runtime.TraceFormat.Field;
import jsref.runtime.TraceFormat.Header;
import jsref.runtime.TraceFormat.Value;
import jsref.values.Text;

/** The trace writer (docs/trace-format.md, version 2): one method per event,
    each writing one line with the fields of its event in the order of the
    OCaml owner of the format ({@code lib/trace/trace.ml}), the names taken
    from {@link TraceFormat}; values are written as Jadescript literals
    ({@link Text#literal}). The header comes first; every event gets its
    {@code step} number (its position in the trace, from 1) in front of its
    other fields.

    <p>At the level {@code observable} (docs/trace-format.md, "Observable
    traces"; {@link #observable}) the loop's own steps write nothing:
    transfer, transfer_one, transfer_spin, transfer_end, dequeue, skip,
    end_dispatch (a discard is written), next_iteration and idle, as
    {@code Trace.observable} of {@code lib/trace} says; the events of the
    bodies they ran are written all the same.

    <p>Shared by every agent of a run; each line is written under the
    writer's lock. A trace that writes nowhere ({@link #writes()} false)
    builds nothing. A forwarding trace (a peripheral container's, docs/jade.md
    "Two containers") hands its events without step numbers to the harness,
    which numbers and writes them ({@link #event}). */
public final class Trace {
  private final OutputStream out;
  private final java.util.function.Consumer<Json.Obj> sink;
  private volatile Runnable syncHook;
  private int events;
  /** The level {@code observable}: the loop's own steps are not written. */
  private volatile boolean observable;

  /** A trace to a stream, or to nowhere. @param out the stream, or null */
  public Trace(OutputStream out) {
    this.out = out == null ? null : new BufferedOutputStream(out, 1 << 16);
    this.sink = null;
  }

  private Trace(java.util.function.Consumer<Json.Obj> sink) {
    this.out = null;
    this.sink = sink;
  }

  /** A trace whose events (without their step numbers) go to another
      writer: a peripheral container's, sent to the harness, which numbers
      and writes them (docs/jade.md, "Two containers").
      @param sink where each event goes @return the trace */
  public static Trace forwardingTo(java.util.function.Consumer<Json.Obj> sink) { return new Trace(sink); }

  /** What {@link #sync} does besides flushing (a forwarding trace: wait until
      the harness has written every event sent so far). @param hook the action */
  public void onSync(Runnable hook) { syncHook = hook; }

  /** Before a message leaves the agent: every event before it is written. */
  public void sync() {
    flush();
    Runnable h = syncHook;
    if (h != null) h.run();
  }

  /** @return does this trace write its events anywhere (a file, or another
      JVM's harness)? Without, the runtime does not build them. */
  public boolean writes() { return out != null || sink != null; }

  /** Write the loop's own steps or not (the level of the header,
      {@link #header}). @param yes true for the level {@code observable} */
  public void observable(boolean yes) { observable = yes; }

  /** @return does this trace write a line for the loop's own steps? */
  private boolean loopSteps() { return writes() && !observable; }

  // ------------------------------------------------------------ the header

  /** The header line (docs/trace-format.md, "The header"), at the level
      {@code full} or, when {@link #observable} was set, {@code observable}.
      @param variant the loop's name @param budget the budget
      @param o2aCapacity the capacity, or null for unbounded @param seed the seed, or null
      @param agents the agents' names and types, in creation order
      @param containers the agents outside the main container, with their
      container's name (written only when not empty: D47, R5e's order of
      the sends holds per container)
      @param behaviours every behaviour type @param percepts every percept type
      with its default priority */
  public synchronized void header(String variant, int budget, Integer o2aCapacity, Integer seed,
                                  Map<String, String> agents, Map<String, String> containers,
                                  List<BehaviourInfo> behaviours,
                                  Map<String, Integer> percepts) {
    List<Object> as = new ArrayList<>();
    for (Map.Entry<String, String> a : agents.entrySet())
      as.add(new Json.Obj().put(Header.NAME, a.getKey()).put(Field.TYPE, a.getValue()));
    List<Object> bs = new ArrayList<>();
    for (BehaviourInfo b : behaviours)
      bs.add(new Json.Obj().put(Header.NAME, b.name()).put(Header.KIND, b.kind()).put(Field.ACTION, b.action())
          .put(Header.PERCEPT_HANDLERS, b.perceptHandlers()).put(Header.MESSAGE_HANDLERS, b.messageHandlers()));
    Json.Obj ps = new Json.Obj();
    for (Map.Entry<String, Integer> e : percepts.entrySet()) ps.put(e.getKey(), e.getValue());
    Json.Obj h = new Json.Obj().put(Header.TRACE, Value.FORMAT).put(Header.VERSION, Value.VERSION)
        .put(Header.VARIANT, variant).put(Header.TIE_POLICY, Value.STABLE).put(Header.BUDGET, budget)
        .put(Header.O2A_CAPACITY, o2aCapacity).put(Header.SEED, seed).put(Header.LEVEL, observable ? Value.OBSERVABLE : Value.FULL).put(Header.AGENTS, as);
    if (!containers.isEmpty()) {
      Json.Obj cs = new Json.Obj();
      for (Map.Entry<String, String> c : containers.entrySet()) cs.put(c.getKey(), c.getValue());
      h.put(Header.CONTAINERS, cs);
    }
    line(h.put(Header.PROGRAM, new Json.Obj().put(Field.BEHAVIOURS, bs).put(Header.PERCEPTS, ps)).toString());
  }

  // ------------------------------------------------------------ steps of the loop

  /** {@code create} (Init): the agent exists, its {@code on create} ran.
      @param agent the agent @param type its type @param args its creation
      arguments @param behaviours the types its {@code on create} activated, in order */
  public void create(String agent, String type, Object[] args, List<String> behaviours) {
    if (!writes()) return;
    List<Object> lits = new ArrayList<>();
    for (Object v : args) lits.add(Text.literal(v));
    event(start(agent, Event.CREATE, Action.INIT).put(Field.TYPE, type).put(Field.ARGS, lits)
        .put(Field.BEHAVIOURS, new ArrayList<Object>(behaviours)));
  }

  /** {@code notify} (Notify, or NotifyWith when the host gave the priority, R2a).
      @param agent the agent @param e the entry @param overridden the priority was given */
  public void notify(String agent, PerceptEntry e, boolean overridden) {
    if (!writes()) return;
    event(entry(start(agent, Event.NOTIFY, overridden ? Action.NOTIFY_WITH : Action.NOTIFY), e));
  }

  /** {@code put} (Put, R2c). @param agent the agent @param object the object
      @param index its index (1 for the agent's first) */
  public void put(String agent, Object object, int index) {
    if (!writes()) return;
    event(start(agent, Event.PUT, Action.PUT).put(Field.OBJECT, Text.literal(object)).put(Field.INDEX, index));
  }

  /** {@code deliver} (Send, R5e): a message reached the agent; or
      (SendInStep, R5d revised) it reached the agent during its last
      behaviour step, after the step's handlers looked.
      @param agent the receiver @param m the message @param seq its seq there
      @param inStep during the agent's last behaviour step */
  public void deliver(String agent, Message m, int seq, boolean inStep) {
    if (!writes()) return;
    event(message(start(agent, Event.DELIVER, inStep ? Action.SEND_IN_STEP : Action.SEND), m).put(Field.SEQ, seq));
  }

  /** {@code transfer} (Transfer, R3a). @param agent the agent @param moved how many percepts moved */
  public void transfer(String agent, int moved) {
    if (!loopSteps()) return;
    event(start(agent, Event.TRANSFER, Action.TRANSFER).put(Field.MOVED, moved));
  }

  /** {@code transfer_one} (TransferOne, printed). @param agent the agent @param e the percept moved */
  public void transferOne(String agent, PerceptEntry e) {
    if (!loopSteps()) return;
    event(entry(start(agent, Event.TRANSFER_ONE, Action.TRANSFER_ONE), e));
  }

  /** {@code transfer_spin} (TransferSpin, printed). @param agent the agent
      @param object the object peeked at */
  public void transferSpin(String agent, Object object) {
    if (!loopSteps()) return;
    event(start(agent, Event.TRANSFER_SPIN, Action.TRANSFER_SPIN).put(Field.OBJECT, Text.literal(object)));
  }

  /** {@code transfer_end} (TransferEnd, printed). @param agent the agent */
  public void transferEnd(String agent) {
    if (!loopSteps()) return;
    event(start(agent, Event.TRANSFER_END, Action.TRANSFER_END));
  }

  /** {@code dequeue} (Dequeue, R3b). @param agent the agent @param e the percept taken */
  public void dequeue(String agent, PerceptEntry e) {
    if (!loopSteps()) return;
    event(entry(start(agent, Event.DEQUEUE, Action.DEQUEUE), e));
  }

  /** {@code handle} (Handle, R3b, R4). @param agent the agent @param instance
      the instance @param behaviour its type @param handler the handler (from 1)
      @param percept the percept @param seq its seq @param effects the body's
      effects ({@link TraceFormat.Effect}) */
  public void handle(String agent, int instance, String behaviour, int handler, Object percept, int seq,
                     List<String> effects) {
    if (!writes()) return;
    event(start(agent, Event.HANDLE, Action.HANDLE).put(Field.INSTANCE, instance).put(Field.BEHAVIOUR, behaviour)
        .put(Field.HANDLER, handler).put(Field.PERCEPT, Text.literal(percept)).put(Field.SEQ, seq)
        .put(Field.EFFECTS, new ArrayList<Object>(effects)));
  }

  /** {@code skip} (Skip, R4b). @param agent the agent @param instance the
      instance @param behaviour its type @param handler the handler (from 1) */
  public void skip(String agent, int instance, String behaviour, int handler) {
    if (!loopSteps()) return;
    event(start(agent, Event.SKIP, Action.SKIP).put(Field.INSTANCE, instance).put(Field.BEHAVIOUR, behaviour)
        .put(Field.HANDLER, handler));
  }

  /** {@code end_dispatch}, or {@code discard} when no handler applied (EndDispatch, R3b).
      @param agent the agent @param seq the percept's seq @param discarded no handler applied */
  public void endDispatch(String agent, int seq, boolean discarded) {
    if (discarded ? !writes() : !loopSteps()) return;
    event(start(agent, discarded ? Event.DISCARD : Event.END_DISPATCH, Action.END_DISPATCH).put(Field.SEQ, seq));
  }

  /** {@code behaviour_step} (BehaviourStep, R5a-R5d). At most one of
      {@code message} and {@code percept} is given: what the step took.
      @param agent the agent @param instance the instance @param behaviour its type
      @param message the message taken, or null @param seq its seq
      @param percept the percept taken ({@code native}), or null
      @param actionEffects the action block's effects, or null when it has none
      @param handler the handler that took it, or null @param effects that handler's effects */
  public void behaviourStep(String agent, int instance, String behaviour, Message message, int seq,
                            PerceptEntry percept, List<String> actionEffects, Integer handler,
                            List<String> effects) {
    if (!writes()) return;
    Object taken = message != null ? message(new Json.Obj(), message).put(Field.SEQ, seq)
        : percept != null ? entry(new Json.Obj(), percept) : null;
    Json.Obj o = start(agent, Event.BEHAVIOUR_STEP, Action.BEHAVIOUR_STEP).put(Field.INSTANCE, instance)
        .put(Field.BEHAVIOUR, behaviour).put(Field.MESSAGE, taken);
    if (actionEffects != null) o.put(Field.ACTION_EFFECTS, new ArrayList<Object>(actionEffects));
    if (handler != null) o.put(Field.HANDLER, handler).put(Field.EFFECTS, new ArrayList<Object>(effects));
    event(o);
  }

  /** {@code next_iteration} (NextIteration). @param agent the agent */
  public void nextIteration(String agent) {
    if (!loopSteps()) return;
    event(start(agent, Event.NEXT_ITERATION, Action.NEXT_ITERATION));
  }

  /** {@code idle} (Idle, R3e). @param agent the agent */
  public void idle(String agent) {
    if (!loopSteps()) return;
    event(start(agent, Event.IDLE, Action.IDLE));
  }

  // ------------------------------------------------------------ inside a step

  /** {@code log}. @param agent the agent @param action the step's action @param text the text */
  public void log(String agent, String action, String text) {
    if (!writes()) return;
    event(start(agent, Event.LOG, action).put(Field.TEXT, text));
  }

  /** {@code invoke}: a method of a host object. @param agent the agent
      @param action the step's action @param method the method @param object
      the object's class @param args the arguments' literals @param result the result's literal */
  public void invoke(String agent, String action, String method, String object, List<String> args,
                     String result) {
    if (!writes()) return;
    event(start(agent, Event.INVOKE, action).put(Field.METHOD, method).put(Field.OBJECT, object)
        .put(Field.ARGS, new ArrayList<Object>(args)).put(Field.RESULT, result));
  }

  /** {@code send}. @param agent the sender @param action the step's action
      @param performative as written @param content the content's literal @param to the receivers */
  public void send(String agent, String action, String performative, String content, List<String> to) {
    if (!writes()) return;
    event(start(agent, Event.SEND, action).put(Field.PERFORMATIVE, performative).put(Field.CONTENT, content)
        .put(Field.TO, new ArrayList<Object>(to)));
  }

  /** {@code activate} (R5g). @param agent the agent @param action the step's
      action @param behaviour the new instance's type */
  public void activate(String agent, String action, String behaviour) {
    if (!writes()) return;
    event(start(agent, Event.ACTIVATE, action).put(Field.BEHAVIOUR, behaviour));
  }

  /** {@code deactivate} (R5h). @param agent the agent @param action the step's
      action @param instance the instance */
  public void deactivate(String agent, String action, int instance) {
    if (!writes()) return;
    event(start(agent, Event.DEACTIVATE, action).put(Field.INSTANCE, instance));
  }

  /** {@code error} (R7). @param agent the agent @param action the step's action
      @param at {@code FILE:LINE:COL} @param message the message */
  public void error(String agent, String action, String at, String message) {
    if (!writes()) return;
    event(start(agent, Event.ERROR, action).put(Field.AT, at).put(Field.MESSAGE, message));
  }

  // ------------------------------------------------------------ outside the spec

  /** {@code refused}: a notify the agent refused (R2d). @param agent the agent
      @param percept the percept */
  public void refused(String agent, Object percept) {
    if (!writes()) return;
    event(start(agent, Event.REFUSED, null).put(Field.PERCEPT, Text.literal(percept))
        .put(Field.REASON, TraceFormat.Value.O2A_FULL));
  }

  /** {@code refused}: a put the agent refused (R2d, D24). @param agent the
      agent @param object the object */
  public void refusedPut(String agent, Object object) {
    if (!writes()) return;
    event(start(agent, Event.REFUSED, null).put(Field.OBJECT, Text.literal(object))
        .put(Field.REASON, TraceFormat.Value.O2A_FULL));
  }

  /** {@code undeliverable} (R5e): on the sender's line. @param agent the
      sender @param to the receiver @param performative as written @param content the content */
  public void undeliverable(String agent, String to, String performative, Object content) {
    if (!writes()) return;
    event(start(agent, Event.UNDELIVERABLE, null).put(Field.TO, to).put(Field.PERFORMATIVE, performative)
        .put(Field.CONTENT, Text.literal(content)));
  }

  /** {@code destroy} (D14): the agent's {@code on destroy} runs next. @param agent the agent */
  public void destroy(String agent) {
    if (!writes()) return;
    event(start(agent, Event.DESTROY, null));
  }

  // ------------------------------------------------------------ lines

  private static Json.Obj start(String agent, String event, String action) {
    return new Json.Obj().put(Field.AGENT, agent).put(Field.EVENT, event).put(Field.ACTION, action);
  }

  private static Json.Obj entry(Json.Obj o, PerceptEntry e) {
    return o.put(Field.PERCEPT, Text.literal(e.percept())).put(Field.PRIORITY, e.priority()).put(Field.SEQ, e.seq());
  }

  private static Json.Obj message(Json.Obj o, Message m) {
    return o.put(Field.PERFORMATIVE, m.performative()).put(Field.CONTENT, Text.literal(m.content()))
        .put(Field.FROM, m.sender());
  }

  /** Write one event: {@code step}, then its fields (a forwarding trace:
      the fields alone). The harness writes the events a peripheral
      container forwards with this. @param fields the event's fields, {@code agent} first */
  public synchronized void event(Json.Obj fields) {
    events++;
    if (sink != null) { sink.accept(fields); return; }
    if (out == null) return;
    Json.Obj o = new Json.Obj().put(Field.STEP, events).putAll(fields);
    line(o.toString());
  }

  /** @return how many events were written */
  public synchronized int events() { return events; }

  private void line(String s) {
    if (out == null) return;
    try {
      out.write(s.getBytes(StandardCharsets.UTF_8));
      out.write('\n');
    } catch (IOException e) {
      throw new java.io.UncheckedIOException(e);
    }
  }

  /** Flush what was written. */
  public synchronized void flush() {
    if (out == null) return;
    try { out.flush(); } catch (IOException e) { throw new java.io.UncheckedIOException(e); }
  }

  /** Flush and close. */
  public synchronized void close() {
    if (out == null) return;
    try { out.close(); } catch (IOException e) { throw new java.io.UncheckedIOException(e); }
  }
}
