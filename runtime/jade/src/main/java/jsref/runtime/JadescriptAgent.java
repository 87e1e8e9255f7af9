package jsref.runtime;

import jade.core.MessageQueue;
import java.util.ArrayList;
import java.util.List;
import jsref.runtime.TraceFormat.Action;
import jsref.values.JadescriptError;
import jsref.values.Ops;
import jsref.values.Text;
import jsref.values.Type;

/** The base class of every generated agent class: a JADE agent running the
    Jadescript agent loop of the rulings (R3) on JADE's own machinery
    (docs/jade.md). This class is what generated code extends and calls
    (CONTRACT.md), what JADE's life cycle calls (setup: {@code on create} and
    the {@code create} line; the end of the run: {@code on destroy}), and what
    the host drives ({@link HostedAgent}). The rest is one idea per class:

    <ul>
    <li>{@link AgentLoop}: the rules of the loop, run where JADE's scheduler
    picks the next behaviour, and the behaviour step JADE's thread runs;</li>
    <li>{@link SchedulerHooks}: where JADE calls in (its scheduler and message
    queue, replaced), JADE's O2A list, the sleep while idle (R3e);</li>
    <li>{@link HostRules}: Notify, NotifyWith and Put on JADE's O2A queue (R2);</li>
    <li>{@link Messaging}: sends, deliveries and the handlers' templates (R5b, R5e);</li>
    <li>{@link LockStep}: the host's grants of one iteration at a time (R6);</li>
    <li>{@link InStep}: the messages that reach the agent during a behaviour
    step (R5d revised);</li>
    <li>{@link Body}: the body being run and the services it calls (R5g, R5h, R7);</li>
    <li>{@link Trace}: the trace writer, one method per event, with the names of
    {@link TraceFormat}.</li>
    </ul>

    <p>With {@link RunConfig#lockStep} the host runs each agent one loop
    iteration at a time ({@link #runIteration}), which makes runs
    deterministic (R6); otherwise the agents run freely on their JADE threads.
    Every rule taken is written to the trace (docs/trace-format.md). */
public abstract class JadescriptAgent extends jade.core.Agent implements HostedAgent {
  private static final long serialVersionUID = 1L;

  /** At most this many nested calls of functions, procedures and
      {@code on create} (Eval.max_call_depth): a deeper one is an exhaustion
      error at its call, never a JVM stack overflow. */
  public static final int MAX_CALL_DEPTH = 200;

  /** D19: active behaviour instances one agent may have (Eval.max_behaviours). */
  public static final int MAX_BEHAVIOURS = 10_000;

  /** The run's configuration, from JADE's first argument (set in {@link #setup}). */
  transient RunConfig cfg;
  /** The active behaviour instances, in activation order (R4a, R5a). */
  final transient ArrayList<JadescriptBehaviour> active = new ArrayList<>();

  final transient SchedulerHooks hooks;
  final transient AgentLoop loop = new AgentLoop(this);
  final transient HostRules host = new HostRules(this);
  final transient Messaging messaging = new Messaging(this);
  final transient LockStep lockStep = new LockStep(this);
  final transient InStep inStep = new InStep(this);
  final transient Body body = new Body(this);

  private volatile boolean setUp;
  private transient volatile String setupError;

  /** Installs the runtime's scheduler in place of JADE's own. */
  protected JadescriptAgent() {
    super();
    hooks = new SchedulerHooks(this);
  }

  /** JADE's own message queue, with the runtime's arrival hook. */
  @Override
  protected MessageQueue createMessageQueue() {
    return hooks.messageQueue();
  }

  // ======================================================== generated code

  /** The agent type's name. @return the name */
  public abstract String typeName();

  /** Property initialisers, inherited first. */
  protected void initProperties() {}

  /** The names of {@code on create}'s parameters. @return the names */
  public String[] createParamNames() { return new String[0]; }

  /** The types of {@code on create}'s parameters. @return the types */
  public Type[] createParamTypes() { return new Type[0]; }

  /** {@code on create}, with the arguments converted to the parameter types.
      @param args the arguments */
  protected void onCreate(Object[] args) {}

  /** {@code on destroy}. */
  protected void onDestroy() {}

  // ======================================================== services (Body)

  /** Fuel (R7): one statement, loop round or call. @param at the position */
  public final void tick(String at) { body.tick(at); }

  /** A call of a function, procedure or behaviour's {@code on create}
      begins (after its tick): more than {@link #MAX_CALL_DEPTH} nested is an
      error. @param at the call */
  public final void enterCall(String at) { body.enterCall(at); }

  /** The call begun by {@link #enterCall} is over. */
  public final void exitCall() { body.exitCall(); }

  /** A fresh budget for a new body. */
  public final void freshFuel() { body.freshFuel(); }

  /** {@code log v}. @param v the value */
  public final void log(Object v) { body.log(v); }

  /** {@code invoke "method" on target with args}: calls a public method of a
      host object by name and arity. @param at the statement @param methodAt the
      method's name @param targetAt the target expression @param target the
      object @param method the method's name @param args the arguments
      @return the result ({@link jsref.values.Nothing#NOTHING} for a void method) */
  public final Object invoke(String at, String methodAt, String targetAt,
                             Object target, String method, Object[] args) {
    return body.invoke(at, methodAt, targetAt, target, method, args);
  }

  /** {@code send performative content to receivers}: one message per
      receiver, delivered when the running step is over (R5e).
      @param performative as written @param content the content
      @param receivers the receivers' names */
  public final void send(String performative, Object content, List<String> receivers) {
    body.send(performative, content, receivers);
  }

  /** {@code activate behaviour B(...)} (R5g): the instance's properties and
      {@code on create} run now (their errors propagate to the activating
      body); then it joins the active behaviours and JADE's ready list.
      @param at the statement @param b the new instance @param names the
      arguments' names @param values their values */
  public final void activate(String at, JadescriptBehaviour b, String[] names, Object[] values) {
    body.activate(at, b, names, values);
  }

  /** {@code deactivate this} (R5h): the running instance leaves the active
      behaviours and JADE's lists at once; the rest of the body still runs. A
      second one in the same body does nothing (D16). @param self the
      behaviour whose code runs */
  public final void deactivate(JadescriptBehaviour self) { body.deactivate(self); }

  /** A run-time error (R7), recorded now. @param e the error */
  public final void recordError(JadescriptError e) { body.recordError(e); }

  /** A stack overflow in a body: the error "recursion too deep". */
  public final void recordTooDeep() { body.recordTooDeep(); }

  /** The agent's name as written, decoded once from JADE's (D48; JADE
      holds it as {@link Names#jade}); every trace line asks for it. Set by
      whichever thread asks first: the same string whichever it is.
      @return the name */
  public final String name() {
    String n = name;
    if (n == null) name = n = Names.jadescript(getLocalName());
    return n;
  }

  private volatile String name;

  /** The run's configuration. @return it */
  public final RunConfig config() { return cfg; }

  /** A failure of the runtime or of generated code (not a Jadescript error):
      reported on the error stream as one line, counted as a run-time error;
      the agent carries on. @param e what was thrown */
  final void internalError(Throwable e) {
    cfg.error(null, "internal error in agent " + name() + ": " + e);
  }

  // ======================================================== JADE life cycle

  /** JADE's setup: the run's configuration (the first argument), then the
      agent's properties and {@code on create} with the other arguments
      (converted to the parameter types), the {@code create} event, and the
      behaviours it activated, with ids 1, 2, ... in activation order. */
  @Override
  protected final void setup() {
    Object[] a = getArguments();
    cfg = (RunConfig) a[0];
    Object[] given = new Object[a.length - 1];
    System.arraycopy(a, 1, given, 0, given.length);
    hooks.enableO2A(cfg.o2aCapacity);
    String[] pn = createParamNames();
    Type[] pt = createParamTypes();
    if (pn.length != given.length) {
      setupError = "agent type " + typeName() + " takes " + pn.length + " creation argument"
          + (pn.length == 1 ? "" : "s") + ", not " + given.length;
      setUp = true;
      cfg.register(this);
      return;
    }
    Object[] args = new Object[given.length];
    for (int i = 0; i < given.length; i++) {
      Object v = Ops.coerceParam(pt[i], given[i]);
      if (v == null) {
        setupError = "creation argument " + pn[i] + " of " + typeName() + " is a " + pt[i]
            + ", not a " + Text.typeName(given[i]);
        setUp = true;
        cfg.register(this);
        return;
      }
      args[i] = v;
    }
    body.initPhase = true;
    body.running = null;
    body.reserved = List.of();
    body.clearEffects();
    body.freshFuel();
    try {
      initProperties();
      onCreate(args);
    } catch (JadescriptError e) {
      recordError(e);
    } catch (StackOverflowError e) {
      recordTooDeep();
    }
    body.initPhase = false;
    List<String> behs = body.activatedTypes();
    body.clearEffects();
    cfg.trace.create(name(), typeName(), given, behs);
    body.flush(Action.INIT);
    body.applyJade();   // the behaviours it activated join JADE's ready list
    setUp = true;
    cfg.register(this);
  }

  /** The error that stopped the agent's creation (wrong arguments), or null.
      @return the interpreter's message */
  public final String setupError() { return setupError; }

  /** Has {@link #setup} finished? @return true once it has */
  public final boolean isSetUp() { return setUp; }

  /** The end of the run (D14): {@code on destroy}, then the {@code destroy}
      event and its body's events. Called by the host when the agent's loop is
      parked (lock step) or over. */
  public final void finishRun() {
    body.running = null;
    body.clearEffects();
    body.freshFuel();
    try {
      onDestroy();
    } catch (JadescriptError e) {
      recordError(e);
    } catch (StackOverflowError e) {
      recordTooDeep();
    }
    body.clearEffects();
    cfg.trace.destroy(name());
    body.flush(Action.DESTROY);
    body.applyJade();
    messaging.dropSent();
  }

  // ======================================================== the host's side (HostedAgent)

  /** {@code notifyEvent(p)} (R2b): the percept with its type's default
      priority (R1a). Safe from any thread. @param p a percept value
      @return false when refused (the O2A queue is full, R2d) */
  public final boolean notifyEvent(Object p) { return host.notifyEvent(p); }

  /** {@code notifyEvent(p, k)} (R2a): the percept with priority k. Safe from
      any thread. @param p a percept value @param k a natural number
      @return false when refused (R2d) */
  public final boolean notifyEvent(Object p, int k) { return host.notifyEvent(p, k); }

  /** Put a non-percept object into the O2A queue (R2c); it does not wake an
      idle agent (D3). Safe from any thread. @param o the object
      @return false when refused (R2d) */
  public final boolean put(Object o) { return host.put(o); }

  /** A message from the host (sender {@code host}, R5e), posted into JADE's
      message queue of this agent. @param performative as written @param content the content */
  public final void hostMessage(String performative, Object content) { messaging.hostMessage(performative, content); }

  /** Deliver the messages sent by {@code on create} (D13); the host calls it
      for every agent, in creation order, once all exist. */
  public final void deliverCreateMessages() { messaging.deliverCreateMessages(); }

  /** An events line's message for the agent's next behaviour step (D42):
      held until then. @param performative as written @param content the content */
  public final void hostMessageDuringStep(String performative, Object content) {
    messaging.holdForStep(performative, content);
  }

  /** The messages held for a behaviour step that did not come reach the
      agent now, as plain messages (D42: at the end of the run's rounds).
      @return were there any */
  public final boolean releaseHeld() { return messaging.postHeld(false); }

  /** Run one loop iteration (lock step): the agent takes rules until its
      iteration ends (BehaviourStep, NextIteration or Idle) or it has taken
      {@code maxRules}; a later call goes on from there. Call from the host's
      thread only. @param maxRules the most rules to take (positive)
      @return how many rules it took @throws InterruptedException if interrupted */
  public final int runIteration(int maxRules) throws InterruptedException { return lockStep.runIteration(maxRules); }

  /** Is the agent idle (R3e: it took Idle and nothing woke it since)? @return true if idle */
  public final boolean isIdle() { return hooks.idle; }

  /** Running freely: is the agent asleep, with nothing ready and no message
      of the run on its way anywhere? @return true if so */
  public final boolean isQuiet() {
    // stopped for good (--max-steps), it still receives: what was sent to it
    // and the platform's failures for its sends arrive before the run ends (D26)
    if (lockStep.parked()) return Messaging.noneOnItsWay();
    synchronized (hooks.sched) { return hooks.idle && hooks.sched.readyCount() == 0 && Messaging.noneOnItsWay(); }
  }

  /** How many percepts this agent has dequeued (R3b) since it started: the
      bench reads it from the host thread. @return the count */
  public final long perceptsDispatched() { return loop.dequeued.get(); }
}
