package jsref.runtime;

import jade.core.AID;
import jade.core.JsrefMessageQueue;
import jade.core.JsrefScheduler;
import jade.core.MessageQueue;
import jade.core.behaviours.Behaviour;
import jade.lang.acl.ACLMessage;
import jade.lang.acl.MessageTemplate;
import java.lang.reflect.Field;
import java.lang.reflect.InvocationTargetException;
import java.lang.reflect.Method;
import java.util.ArrayList;
import java.util.Collections;
import java.util.HashMap;
import java.util.IdentityHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicLong;
import jsref.values.JadescriptError;
import jsref.values.Nothing;
import jsref.values.Ops;
import jsref.values.Schema;
import jsref.values.Text;
import jsref.values.Type;

/** The base class of every generated agent class: a JADE agent running the
    Jadescript agent loop of the rulings (R3) on JADE's own machinery.

    <h2>The loop on JADE (docs/jade.md)</h2>
    <ul>
    <li><b>Behaviours</b> are JADE behaviours: {@code activate} is
    {@code addBehaviour} (the end of JADE's ready list), {@code deactivate} is
    {@code removeBehaviour} (JADE's {@code Scheduler.remove}, whose index rule
    is R5f), a behaviour step that took nothing calls {@code block()} and JADE
    moves it to its blocked list (R5d), a message's arrival restarts the blocked
    ones through JADE's {@code postMessage}/{@code restartAll} (ready then
    blocked, in blocking order), and a one-shot is {@code done()} after its step
    and JADE removes it (R5c, D1). The round robin (R5a) is JADE's
    {@code Scheduler.schedule()}.</li>
    <li><b>The percept phase</b> runs in front of every JADE schedule: the
    agent's scheduler is a {@link JsrefScheduler} (JADE's scheduler with
    {@code schedule()} overridden), installed by reflection when the agent is
    constructed. Its {@code schedule()} runs one loop iteration up to the
    behaviour step: Transfer, then Dequeue, Handle/Skip per registered handler
    and EndDispatch per percept (R3a, R3b, R4), then asks JADE's round robin
    for the behaviour to step; with no behaviour ready it takes NextIteration
    or Idle (R3e) and waits, as JADE's scheduler waits, on the scheduler's
    monitor. JADE's agent thread then runs the step ({@code action()}) and
    blocks or removes the behaviour as JADE does.</li>
    <li><b>Percepts</b> travel through JADE's O2A queue ({@code putO2AObject});
    the transfer takes the percepts out of it under JADE's own lock and leaves
    the other objects there, in order (R3a). The capacity (R2d) is checked
    before putting (JADE's queue would drop its oldest object).</li>
    <li><b>Messages</b> are ACL messages sent with JADE's {@code send} and
    taken with {@code receive(MessageTemplate)} from JADE's queue; a message
    handler's pattern and {@code when} are the template. Sends are delivered
    when the step that made them is over (R5e).</li>
    </ul>

    <p>With {@link RunConfig#lockStep} the host runs each agent one loop
    iteration at a time ({@link #runIteration}), which makes runs
    deterministic (R6); otherwise the agents run freely on their JADE threads.
    Every rule taken is written to the trace (docs/trace-format.md). */
public abstract class JadescriptAgent extends jade.core.Agent implements JadeHooks, HostedAgent {
  private static final long serialVersionUID = 1L;

  /** Behaviour instance numbers ({@code uid}), one counter per JVM as the
      interpreter's. */
  private static final AtomicInteger UIDS = new AtomicInteger();
  /** Ids of the runtime's own messages. */
  private static final AtomicLong MESSAGE_IDS = new AtomicLong();
  /** Two containers (docs/jade.md): called with the id of a message that
      arrived here from a sender in another JVM, whose delivery that JVM awaits. */
  private static volatile java.util.function.LongConsumer remoteArrival;
  /** Percepts dequeued by this agent so far (the bench's windows). */
  private final AtomicLong dequeued = new AtomicLong();
  /** Message contents by message id (shared by reference, as the interpreter does). */
  private static final Map<Long, Object> CONTENTS = new ConcurrentHashMap<>();
  /** Percepts moved to the message queue (native), by message id. */
  private static final Map<Long, PerceptEntry> PERCEPTS = new ConcurrentHashMap<>();
  /** Sends not yet delivered nor refused, by message id. */
  private static final Map<Long, Outgoing> PENDING = new ConcurrentHashMap<>();

  static final String P_ID = "jsref-id";
  static final String P_PERF = "jsref-performative";
  static final String P_FROM = "jsref-from";
  static final String P_PERCEPT = "jsref-percept";
  static final String P_SERIAL = "jsref-serialized";

  // ------------------------------------------------------------ configuration
  private transient RunConfig cfg;
  private transient JsrefScheduler sched;
  private transient JsrefMessageQueue queue;
  private transient jade.util.leap.List o2a;

  // ------------------------------------------------------------ loop state
  private final transient PerceptQueue pq = new PerceptQueue();
  private final transient Object hostLock = new Object();
  private int nextSeq;                 // host side, under hostLock
  private int puts;                    // host side, under hostLock
  private int msgSeq;                  // arrivals, under the message queue's lock
  private final transient ArrayList<JadescriptBehaviour> active = new ArrayList<>();
  private volatile boolean idle;
  private volatile boolean parked;     // free running, --max-steps spent
  private int dispatched;
  private final transient AtomicInteger nativePercepts = new AtomicInteger();   // native: percepts in the message queue
  private final transient HashMap<Integer, String> known = new HashMap<>();
  private final transient Map<ACLMessage, Arrived> arrivals =
      Collections.synchronizedMap(new IdentityHashMap<>());
  private boolean stepInProgress;
  private boolean createFlushed;
  private volatile boolean setUp;
  private transient volatile String setupError;

  // ------------------------------------------------------------ bodies
  private final transient ArrayList<Json.Obj> bodyEvents = new ArrayList<>();
  private final transient ArrayList<Object> effects = new ArrayList<>();   // JadescriptBehaviour or DEACTIVATE
  private static final Object DEACTIVATE = new Object();
  private final transient ArrayList<Outgoing> outbox = new ArrayList<>();
  private final transient ArrayList<Outgoing> createOutbox = new ArrayList<>();
  private transient JadescriptBehaviour running;
  private transient List<Integer> reserved = List.of();
  private boolean initPhase;
  private int fuel;

  // ------------------------------------------------------------ lock step
  private final transient Object gate = new Object();
  private boolean granted;
  private boolean inIteration;
  private int grant;
  private int used;

  /** A message that arrived in JADE's queue: a Jadescript message with its
      seq, or a percept moved there (native). */
  private record Arrived(Message msg, int seq, PerceptEntry percept) {}

  /** A send waiting for its delivery. */
  static final class Outgoing {
    final long id;
    final String sender;
    final String receiver;
    final Message message;
    final CountDownLatch done = new CountDownLatch(1);
    volatile Object barrier;
    Outgoing(long id, String sender, String receiver, Message message) {
      this.id = id; this.sender = sender; this.receiver = receiver; this.message = message;
    }
  }

  /** Installs the runtime's scheduler in place of JADE's own. */
  protected JadescriptAgent() {
    super();
    try {
      Field f = jade.core.Agent.class.getDeclaredField("myScheduler");
      f.setAccessible(true);
      sched = new JsrefScheduler(this, this);
      f.set(this, sched);
    } catch (ReflectiveOperationException e) {
      throw new IllegalStateException("cannot install the Jadescript scheduler in JADE's agent", e);
    }
  }

  /** JADE's own message queue, with the runtime's arrival hook. */
  @Override
  protected MessageQueue createMessageQueue() {
    queue = new JsrefMessageQueue(this, this);
    return queue;
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

  // ======================================================== services

  /** Fuel (R7): one statement, loop round or call. @param at the position */
  public final void tick(String at) {
    if (--fuel < 0)
      throw JadescriptError.at(at, "step budget exhausted: more than " + cfg.fuel
          + " statements in one handler or step (--fuel)");
  }

  /** At most this many nested calls of functions, procedures and
      {@code on create} (Eval.max_call_depth): a deeper one is an exhaustion
      error at its call, never a JVM stack overflow. */
  public static final int MAX_CALL_DEPTH = 200;
  private int depth;

  /** A call of a function, procedure or behaviour's {@code on create}
      begins (after its tick). @param at the call */
  public final void enterCall(String at) {
    if (depth >= MAX_CALL_DEPTH)
      throw JadescriptError.at(at, "recursion too deep: more than " + MAX_CALL_DEPTH
          + " nested calls of functions and procedures");
    depth++;
  }

  /** The call begun by {@link #enterCall} is over. */
  public final void exitCall() { depth--; }

  /** A fresh budget for a new body. */
  public final void freshFuel() { fuel = cfg.fuel; }

  /** {@code log v}. @param v the value */
  public final void log(Object v) {
    bodyEvents.add(new Json.Obj().put("event", "log").put("text", Text.text(v)));
  }

  /** {@code invoke "method" on target with args}: calls a public method of a
      host object by name and arity. @param at the statement @param methodAt the
      method's name @param targetAt the target expression @param target the
      object @param method the method's name @param args the arguments
      @return the result ({@link Nothing#NOTHING} for a void method) */
  public final Object invoke(String at, String methodAt, String targetAt,
                             Object target, String method, Object[] args) {
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
    List<Object> lits = new ArrayList<>();
    for (Object a : args) lits.add(Text.literal(a));
    bodyEvents.add(new Json.Obj().put("event", "invoke").put("method", method).put("object", cls)
        .put("args", lits).put("result", Text.literal(result)));
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

  /** {@code send performative content to receivers}: one message per
      receiver, delivered when the running step is over (R5e).
      @param performative as written @param content the content
      @param receivers the receivers' names */
  public final void send(String performative, Object content, List<String> receivers) {
    List<Object> to = new ArrayList<>(receivers);
    for (String r : receivers) {
      Outgoing o = new Outgoing(MESSAGE_IDS.incrementAndGet(), getLocalName(), r,
          new Message(performative, content, getLocalName()));
      (initPhase ? createOutbox : outbox).add(o);
    }
    bodyEvents.add(new Json.Obj().put("event", "send").put("performative", performative)
        .put("content", Text.literal(content)).put("to", to));
  }

  /** {@code activate behaviour B(...)} (R5g): the instance's properties and
      {@code on create} run now (their errors propagate to the activating
      body); then it joins the active behaviours and JADE's ready list.
      @param at the statement @param b the new instance @param names the
      arguments' names @param values their values */
  public final void activate(String at, JadescriptBehaviour b, String[] names, Object[] values) {
    if (active.size() >= MAX_BEHAVIOURS)   // D19
      throw JadescriptError.at(at, "too many behaviours: an agent has at most " + MAX_BEHAVIOURS
          + " active behaviour instances");
    b.bind(this, UIDS.incrementAndGet());
    b.initProperties();
    b.onCreate(names, values);
    effects.add(b);
    bodyEvents.add(new Json.Obj().put("event", "activate").put("behaviour", b.typeName()));
    b.setId(newId());
    active.add(b);
    b.jsActive = true;
    addBehaviour(b);
  }

  /** {@code deactivate this} (R5h): the running instance leaves the active
      behaviours and JADE's lists at once; the rest of the body still runs. A
      second one in the same body does nothing (D16). @param self the
      behaviour whose code runs */
  public final void deactivate(JadescriptBehaviour self) {
    if (effects.contains(DEACTIVATE)) return;
    effects.add(DEACTIVATE);
    bodyEvents.add(new Json.Obj().put("event", "deactivate").put("instance", self.id()));
    if (initPhase) return;   // create_agent keeps only the activations
    JadescriptBehaviour target = running;
    if (target != null && active.remove(target)) { target.jsActive = false; removeBehaviour(target); }
  }

  /** A run-time error (R7), recorded now. @param e the error */
  public final void recordError(JadescriptError e) {
    bodyEvents.add(new Json.Obj().put("event", "error").put("at", e.at()).put("message", e.message()));
  }

  /** A stack overflow in a body: the error "recursion too deep". */
  public final void recordTooDeep() {
    bodyEvents.add(new Json.Obj().put("event", "error").put("at", ":0:0").put("message", "recursion too deep"));
  }

  /** The agent's local name. @return the name */
  public final String name() { return getLocalName(); }

  /** The run's configuration. @return it */
  public final RunConfig config() { return cfg; }

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
    setEnabledO2ACommunication(true, cfg.o2aCapacity == null ? 0 : cfg.o2aCapacity);
    setO2AManager(new Dormant());
    try {
      Field f = jade.core.Agent.class.getDeclaredField("o2aQueue");
      f.setAccessible(true);
      o2a = (jade.util.leap.List) f.get(this);
    } catch (ReflectiveOperationException e) {
      throw new IllegalStateException("cannot reach JADE's O2A queue", e);
    }
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
    initPhase = true;
    running = null;
    reserved = List.of();
    effects.clear();
    freshFuel();
    try {
      initProperties();
      onCreate(args);
    } catch (JadescriptError e) {
      recordError(e);
    } catch (StackOverflowError e) {
      recordTooDeep();
    }
    initPhase = false;
    List<Object> lits = new ArrayList<>();
    for (Object v : given) lits.add(Text.literal(v));
    List<Object> behs = new ArrayList<>();
    for (Object e : effects) if (e instanceof JadescriptBehaviour b) behs.add(b.typeName());
    effects.clear();
    cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "create").put("action", "Init")
        .put("type", typeName()).put("args", lits).put("behaviours", behs));
    flushBody("Init");
    setUp = true;
    cfg.register(this);
  }

  /** The error that stopped the agent's creation (wrong arguments), or null.
      @return the interpreter's message */
  public final String setupError() { return setupError; }

  /** Has {@link #setup} finished? @return true once it has */
  public final boolean isSetUp() { return setUp; }

  /** An O2A manager that is never scheduled: JADE restarts it (instead of
      every behaviour) when an object is put into the O2A queue; the runtime
      wakes the loop itself, for percepts only (D3). */
  private static final class Dormant extends Behaviour {
    private static final long serialVersionUID = 1L;
    @Override public void action() { block(); }
    @Override public boolean done() { return false; }
  }

  // ======================================================== host side

  /** {@code notifyEvent(p)} (R2b): the percept with its type's default
      priority (R1a). Safe from any thread. @param p a percept value
      @return false when refused (the O2A queue is full, R2d) */
  public final boolean notifyEvent(Object p) {
    int prio = p instanceof Schema s ? s.defaultPriority() : 0;
    return notifyInternal(p, prio, false);
  }

  /** {@code notifyEvent(p, k)} (R2a): the percept with priority k. Safe from
      any thread. @param p a percept value @param k a natural number
      @return false when refused (R2d) */
  public final boolean notifyEvent(Object p, int k) {
    if (k < 0) throw new IllegalArgumentException("priority " + k + " is negative (R2a)");
    return notifyInternal(p, k, true);
  }

  private boolean notifyInternal(Object p, int prio, boolean with) {
    synchronized (hostLock) {
      if (!o2aHasRoom()) {
        cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "refused").put("action", null)
            .put("percept", Text.literal(p)).put("reason", "the O2A queue is full (R2d)"));
        return false;
      }
      int seq = ++nextSeq;
      PerceptEntry e = new PerceptEntry(p, prio, seq);
      // the line, the put and the wake-up at once (R2b, R3e): a loop running
      // meanwhile sees all of the notify or none of it
      synchronized (sched) {
        synchronized (o2a) {
          if (cfg.trace.writes())
            cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "notify")
                .put("action", with ? "NotifyWith" : "Notify").putAll(entryFields(e)));
          try {
            putO2AObject(e, false);
          } catch (InterruptedException x) {
            Thread.currentThread().interrupt();
          }
        }
        wakeUp();
      }
      return true;
    }
  }

  /** Put a non-percept object into the O2A queue (R2c); it does not wake an
      idle agent (D3). Safe from any thread. @param o the object
      @return false when refused (R2d) */
  public final boolean put(Object o) {
    synchronized (hostLock) {
      if (!o2aHasRoom()) {
        // R2d, D24: a refused put is in the trace, with its object
        cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "refused").put("action", null)
            .put("object", Text.literal(o)).put("reason", "the O2A queue is full (R2d)"));
        return false;
      }
      int k = ++puts;
      synchronized (o2a) {
        cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "put").put("action", "Put")
            .put("object", Text.literal(o)).put("index", k));
        try {
          putO2AObject(new PutObject(o, k), false);
        } catch (InterruptedException x) {
          Thread.currentThread().interrupt();
        }
      }
      return true;
    }
  }

  /** A message from the host (sender {@code host}, R5e), posted into JADE's
      message queue of this agent. @param performative as written @param content the content */
  public final void hostMessage(String performative, Object content) {
    Outgoing o = new Outgoing(MESSAGE_IDS.incrementAndGet(), "host", getLocalName(),
        new Message(performative, content, "host"));
    ACLMessage acl = encode(o, new AID("host", AID.ISLOCALNAME));
    postMessage(acl);
  }

  private boolean o2aHasRoom() {
    if (cfg.o2aCapacity == null) return true;
    int used;
    synchronized (o2a) { used = o2a.size(); }
    if (cfg.variant == Variant.NATIVE) used += nativePercepts.get();   // D6
    return used < cfg.o2aCapacity;
  }

  /** R3e: a notification or a message wakes an idle agent. The loop sets
      {@code idle} holding the scheduler's monitor, after finding nothing to
      do, so a wake-up that finds the agent not idle has nothing to notify. */
  private void wakeUp() {
    synchronized (sched) {
      if (idle) {
        idle = false;
        sched.notifyAll();
      }
    }
  }

  /** Is the agent idle (R3e: it took Idle and nothing woke it since)? @return true if idle */
  public final boolean isIdle() { return idle; }

  /** How many percepts this agent has dequeued (R3b) since it started: the
      bench reads it from the host thread. @return the count */
  public final long perceptsDispatched() { return dequeued.get(); }

  // ======================================================== two containers

  /** Message ids of this JVM start after {@code base}, so that they differ
      from another JVM's (a split run's peripheral container). @param base the base */
  static void messageIdBase(long base) { MESSAGE_IDS.set(base); }

  /** What to do when a message from another JVM's sender has arrived here
      (tell that JVM, whose sender awaits the delivery). @param f the action, with the message id */
  static void onRemoteArrival(java.util.function.LongConsumer f) { remoteArrival = f; }

  /** A message sent from this JVM arrived in another JVM: its sender may go
      on (lock step, R5e). @param id the message id */
  static void remoteDelivered(long id) {
    Outgoing o = PENDING.remove(id);
    if (o != null) o.done.countDown();
  }

  /** Running freely: is the agent asleep, with nothing ready and no message
      of the run on its way anywhere? @return true if so */
  public final boolean isQuiet() {
    if (parked) return true;
    synchronized (sched) { return idle && sched.readyCount() == 0 && PENDING.isEmpty(); }
  }

  // ======================================================== lock step

  /** Run one loop iteration (lock step): the agent takes rules until its
      iteration ends (BehaviourStep, NextIteration or Idle) or it has taken
      {@code maxRules}; a later call goes on from there. Call from the host's
      thread only. @param maxRules the most rules to take (positive)
      @return how many rules it took @throws InterruptedException if interrupted */
  public final int runIteration(int maxRules) throws InterruptedException {
    synchronized (gate) {
      grant = maxRules;
      used = 0;
      granted = true;
      gate.notifyAll();
      while (granted) gate.wait();
      return used;
    }
  }

  /** The start of an iteration: in lock step, report the end of the last one
      and wait for the host; running freely, sleep while idle. */
  private void awaitTurn() throws InterruptedException {
    if (cfg.lockStep) {
      synchronized (gate) {
        if (inIteration) { inIteration = false; granted = false; gate.notifyAll(); }
        while (!granted) gate.wait();
        inIteration = true;
      }
    } else {
      // asleep while idle and nothing is ready: a message's arrival wakes
      // the loop before JADE's restartAll makes its behaviours ready, so the
      // ready list is part of the condition (JADE's scheduler notifies)
      synchronized (sched) {
        while (idle && sched.readyCount() == 0) sched.idleWait();
        idle = false;
      }
    }
  }

  /** One rule is about to be taken: in lock step, within the host's grant. */
  private void rule() throws InterruptedException {
    if (!cfg.lockStep) {
      if (cfg.freeSteps.decrementAndGet() < 0) {   // --max-steps spent: stop here for good
        parked = true;
        synchronized (gate) { while (true) gate.wait(); }
      }
      return;
    }
    synchronized (gate) {
      while (grant == 0) {
        granted = false;
        gate.notifyAll();
        while (!granted) gate.wait();
      }
      grant--;
      used++;
    }
  }

  // ======================================================== the loop

  /** The loop (see the class comment): one iteration up to the behaviour
      step, run where JADE's scheduler picks the next behaviour. */
  @Override
  public final Behaviour schedule(JsrefScheduler s) throws InterruptedException {
    if (stepInProgress) {
      stepInProgress = false;
      deliver(outbox);
    }
    if (!createFlushed && !cfg.lockStep) {
      createFlushed = true;
      cfg.awaitAllCreated();   // D13
      deliver(createOutbox);
    }
    while (true) {
      awaitTurn();
      try {
        switch (cfg.variant) {
          case PRINTED -> transferPrinted();
          case NATIVE -> transferNative();
          default -> transfer();
        }
        if (cfg.variant != Variant.NATIVE) dispatch();
      } catch (RuntimeException | StackOverflowError e) {
        internalError(e);
      }
      rule();
      // BehaviourStep, Idle or NextIteration: decided with no message half
      // posted (JADE's postMessage holds the queue's monitor from the arrival
      // to restartAll) and no behaviour half restarted (the scheduler's), so
      // that a Send is wholly before the decision or wholly after it
      synchronized (queue) {
        synchronized (s) {
          if (s.readyCount() > 0) {
            stepInProgress = true;
            return s.pick();
          }
          synchronized (o2a) {   // and no notify half done (its line and its put)
            if (cfg.variant != Variant.PRINTED && idleCondition(s)) {
              idle = true;
              writeRule("idle", "Idle", () -> new Json.Obj());
              continue;
            }
            writeRule("next_iteration", "NextIteration", () -> new Json.Obj());
          }
        }
      }
    }
  }

  /** A failure of the runtime or of generated code (not a Jadescript error):
      reported on the error stream as one line, counted as a run-time error;
      the agent carries on. @param e what was thrown */
  final void internalError(Throwable e) {
    cfg.error(null, "internal error in agent " + getLocalName() + ": " + e);
  }

  private boolean idleCondition(JsrefScheduler s) {
    if (s.readyCount() > 0 || !pq.isEmpty()) return false;
    synchronized (o2a) {
      for (int i = 0; i < o2a.size(); i++) if (o2a.get(i) instanceof PerceptEntry) return false;
    }
    return true;
  }

  /** The percepts of the O2A queue, oldest first, taken out of it; the other
      objects stay, in order (R3a). The caller holds JADE's O2A lock, so that
      its trace line is written before any later notify's. */
  private List<PerceptEntry> takePercepts() {
    List<PerceptEntry> moved = new ArrayList<>();
    {
      int n = o2a.size();
      boolean objects = false;
      for (int i = 0; i < n; i++) {
        Object x = o2a.get(i);
        if (x instanceof PerceptEntry e) moved.add(e); else objects = true;
      }
      if (!moved.isEmpty()) {
        if (!objects) o2a.clear();
        else for (int i = n - 1; i >= 0; i--) if (o2a.get(i) instanceof PerceptEntry) o2a.remove(i);
      }
    }
    return moved;
  }

  /** Transfer (R3a). */
  private void transfer() throws InterruptedException {
    rule();
    synchronized (o2a) {
      List<PerceptEntry> moved = takePercepts();
      for (PerceptEntry e : moved) pq.insert(e);
      dispatched = 0;
      writeRule("transfer", "Transfer", () -> new Json.Obj().put("moved", moved.size()));
    }
  }

  /** TransferOne / TransferSpin / TransferEnd (printed, Algorithm 1). */
  private void transferPrinted() throws InterruptedException {
    while (true) {
      rule();
      synchronized (o2a) {
        Object head = o2a.isEmpty() ? null : o2a.get(0);
        if (head == null) {
          dispatched = 0;
          writeRule("transfer_end", "TransferEnd", () -> new Json.Obj());
          return;
        }
        if (head instanceof PerceptEntry e) {
          o2a.remove(0);
          pq.insert(e);
          writeRule("transfer_one", "TransferOne", () -> entryFields(e));
        } else {
          Object v = head instanceof PutObject po ? po.value() : head;
          writeRule("transfer_spin", "TransferSpin", () -> new Json.Obj().put("object", Text.literal(v)));
        }
      }
    }
  }

  /** Transfer (native): the percepts go to the end of JADE's message queue,
      through {@code postMessage} (which restarts the blocked behaviours). */
  private void transferNative() throws InterruptedException {
    rule();
    synchronized (queue) {   // the percepts join the message queue together
      List<PerceptEntry> moved;
      synchronized (o2a) {
        moved = takePercepts();
        nativePercepts.addAndGet(moved.size());   // still the O2A's room (D6)
        dispatched = 0;
        writeRule("transfer", "Transfer", () -> new Json.Obj().put("moved", moved.size()));
      }
      for (PerceptEntry e : moved) {
        long id = MESSAGE_IDS.incrementAndGet();
        PERCEPTS.put(id, e);
        ACLMessage m = new ACLMessage(ACLMessage.INFORM);
        m.setSender(getAID());
        m.addReceiver(getAID());
        m.addUserDefinedParameter(P_PERCEPT, Long.toString(id));
        m.setContent(Text.literal(e.percept()));
        postMessage(m);
      }
    }
  }

  /** Dequeue, Handle/Skip per handler of the snapshot, EndDispatch (R3b, R4). */
  private void dispatch() throws InterruptedException {
    while (!pq.isEmpty() && !(cfg.variant == Variant.BUDGETED && dispatched >= cfg.budget)) {
      rule();
      PerceptEntry e = pq.pop();
      dispatched++;
      dequeued.lazySet(dequeued.get() + 1);
      writeRule("dequeue", "Dequeue", () -> entryFields(e));
      // the registered handlers (R4a): active instances in activation order,
      // each one's handlers in declaration order (inherited first)
      int n = 0;
      for (JadescriptBehaviour b : active) n += b.perceptHandlerCount();
      if (snapB.length < n) { snapB = new JadescriptBehaviour[2 * n]; snapH = new int[2 * n]; }
      final JadescriptBehaviour[] insts = snapB;
      final int[] hs = snapH;
      n = 0;
      for (JadescriptBehaviour b : active)
        for (int h = 1; h <= b.perceptHandlerCount(); h++) { insts[n] = b; hs[n] = h; n++; }
      boolean applied = false;
      for (int k = 0; k < n; k++) {
        rule();
        JadescriptBehaviour b = insts[k];
        int h = hs[k];
        if (!b.jsActive) {   // R4b: deactivated since the snapshot
          writeRule("skip", "Skip", () -> skipFields(b, h));
          continue;
        }
        reserved = new SnapshotIds(insts, k, n);   // the snapshot's ids from here on (D2)
        running = b;
        effects.clear();
        freshFuel();
        boolean ran;
        try {
          ran = b.perceptHandler(h, e.percept());
        } finally {
          running = null;
          reserved = List.of();
        }
        if (ran) {
          applied = true;
          writeRule("handle", "Handle", () -> new Json.Obj().put("instance", b.id()).put("behaviour", b.typeName())
              .put("handler", h).put("percept", Text.literal(e.percept())).put("seq", e.seq())
              .put("effects", describe(effects)));
        } else {
          writeRule("skip", "Skip", () -> skipFields(b, h));
        }
        effects.clear();
        deliver(outbox);
      }
      rule();
      writeRule(applied ? "end_dispatch" : "discard", "EndDispatch", () -> new Json.Obj().put("seq", e.seq()));
    }
  }

  private Json.Obj skipFields(JadescriptBehaviour b, int h) {
    return new Json.Obj().put("instance", b.id()).put("behaviour", known.getOrDefault(b.id(), "?")).put("handler", h);
  }

  /** BehaviourStep (R5a-R5d): run by JADE's agent thread in the behaviour's
      {@code action()}. */
  final void step(JadescriptBehaviour b) {
    // the step is atomic with respect to arrivals (R6): JADE's postMessage
    // holds the queue's monitor, so a message arrives wholly before the step
    // (and may be taken by it) or after it. (Plain JADE lets a message
    // arrive during a step; see JadeRestartDuringStep.)
    synchronized (queue) { stepAtomically(b); }
  }

  private void stepAtomically(JadescriptBehaviour b) {
    int id = b.id();
    reserved = List.of(id);
    running = b;
    String lastBehaviour = "";
    List<Object> actionEffects = null;
    Integer handler = null;
    List<Object> handlerEffects = null;
    Object msgField = null;
    boolean taken = false;
    try {
      if (b.hasAction()) {
        lastBehaviour = b.typeName();
        effects.clear();
        freshFuel();
        b.actionBlock();
        actionEffects = describe(effects);
        effects.clear();
      }
      if (cfg.variant == Variant.NATIVE) {
        for (int h = 1; h <= b.perceptHandlerCount() && !taken; h++) {
          effects.clear();
          HandlerMatch pm = new HandlerMatch(this, b, h, true);
          ACLMessage m = receive(new MessageTemplate(pm));
          if (m != null) {
            Arrived a = arrivals.remove(m);
            nativePercepts.decrementAndGet();
            taken = true;
            lastBehaviour = b.typeName();
            handler = h;
            handlerEffects = describe(effects);
            msgField = entryFields(a.percept());
          }
        }
      }
      for (int h = 1; h <= b.messageHandlerCount() && !taken; h++) {
        ACLMessage m = receive(new MessageTemplate(new HandlerMatch(this, b, h, false)));
        if (m != null) {
          Arrived a = arrivals.remove(m);
          taken = true;
          lastBehaviour = b.typeName();
          effects.clear();
          freshFuel();
          b.messageHandler(h, a.msg());
          handler = h;
          handlerEffects = describe(effects);
          msgField = messageFields(a.msg()).put("seq", a.seq());
        }
      }
    } finally {
      running = null;
      reserved = List.of();
      effects.clear();
    }
    if (!b.isCyclic()) { active.remove(b); b.jsActive = false; }   // JADE removes it: done() (R5c, D1)
    else if (!b.hasAction() && !taken && b.jsActive) b.block();   // JADE blocks it (R5d)
    Json.Obj f = new Json.Obj().put("instance", id)
        .put("behaviour", lastBehaviour.isEmpty() ? known.getOrDefault(id, "?") : lastBehaviour)
        .put("message", msgField);
    if (actionEffects != null) f.put("action_effects", actionEffects);
    if (taken) f.put("handler", handler).put("effects", handlerEffects);
    writeRule("behaviour_step", "BehaviourStep", () -> f);
  }

  /** A handler as a JADE message template. A percept handler (native): the
      percept messages in arrival order; the first whose handler applies is
      taken, and its body has run. A message handler: its performative,
      pattern and {@code when} (R5b). One class for both, as they differ only
      in what they look at. */
  private static final class HandlerMatch implements MessageTemplate.MatchExpression {
    private static final long serialVersionUID = 1L;
    private final transient JadescriptAgent agent;
    private final transient JadescriptBehaviour b;
    private final int h;
    private final boolean percept;
    HandlerMatch(JadescriptAgent agent, JadescriptBehaviour b, int h, boolean percept) {
      this.agent = agent; this.b = b; this.h = h; this.percept = percept;
    }
    @Override public boolean match(ACLMessage m) {
      Arrived a = agent.arrivals.get(m);
      if (a == null) return false;
      if (percept) {
        if (a.percept() == null) return false;
        agent.freshFuel();
        return b.perceptHandler(h, a.percept().percept());
      }
      if (a.msg() == null) return false;
      String perf = b.messagePerformative(h);
      if (perf != null && !perf.equals(a.msg().performative())) return false;
      agent.freshFuel();
      return b.messageAccepts(h, a.msg());
    }
  }

  // ======================================================== effects and ids

  /** The ids of a dispatch snapshot's instances from position {@code from}
      on: the reserved ids of D2, read only when an activation asks. */
  private static final class SnapshotIds extends java.util.AbstractList<Integer> {
    private final JadescriptBehaviour[] insts;
    private final int from;
    private final int to;
    SnapshotIds(JadescriptBehaviour[] insts, int from, int to) { this.insts = insts; this.from = from; this.to = to; }
    @Override public Integer get(int i) { return insts[from + i].id(); }
    @Override public int size() { return to - from; }
  }

  /** The registered handlers of the dispatch in progress (R4a), reused from
      one percept to the next: instances and handler numbers. */
  private transient JadescriptBehaviour[] snapB = new JadescriptBehaviour[16];
  private transient int[] snapH = new int[16];

  /** D19: active behaviour instances one agent may have (Eval.max_behaviours). */
  public static final int MAX_BEHAVIOURS = 10_000;

  /** NewId: the smallest positive id neither active nor reserved (D2).
      Fewer than n ids are used, so one of 1..n is free: marked in one pass
      over each collection, as Machine.new_id (D19). */
  private int newId() {
    int n = active.size() + reserved.size() + 1;
    boolean[] used = new boolean[n + 1];
    for (JadescriptBehaviour b : active) if (b.id() >= 1 && b.id() <= n) used[b.id()] = true;
    for (Integer k : reserved) if (k != null && k >= 1 && k <= n) used[k] = true;
    int i = 1;
    while (used[i]) i++;
    return i;
  }

  private static List<Object> describe(List<Object> effs) {
    List<Object> l = new ArrayList<>();
    for (Object e : effs)
      l.add(e == DEACTIVATE ? "deactivate" : "activate " + ((JadescriptBehaviour) e).typeName());
    return l;
  }

  // ======================================================== trace

  private static Json.Obj entryFields(PerceptEntry e) {
    return new Json.Obj().put("percept", Text.literal(e.percept())).put("priority", e.priority()).put("seq", e.seq());
  }

  private static Json.Obj messageFields(Message m) {
    return new Json.Obj().put("performative", m.performative()).put("content", Text.literal(m.content()))
        .put("from", m.sender());
  }

  /** Write the line of a rule, remember the instances' types, then the events
      of the bodies it ran. */
  private void writeRule(String event, String action, java.util.function.Supplier<Json.Obj> fields) {
    if (cfg.trace.writes()) {
      cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", event).put("action", action)
          .putAll(fields.get()));
      for (JadescriptBehaviour b : active) known.put(b.id(), b.typeName());
    }
    flushBody(action);
  }

  private void flushBody(String action) {
    if (bodyEvents.isEmpty()) return;
    for (Json.Obj e : bodyEvents) {
      Json.Obj line = new Json.Obj().put("agent", getLocalName()).put("event", e.get("event")).put("action", action);
      String ev = (String) e.get("event");
      switch (ev) {
        case "log" -> { line.put("text", e.get("text")); cfg.log(getLocalName(), (String) e.get("text")); }
        case "invoke" -> line.put("method", e.get("method")).put("object", e.get("object"))
            .put("args", e.get("args")).put("result", e.get("result"));
        case "send" -> line.put("performative", e.get("performative")).put("content", e.get("content"))
            .put("to", e.get("to"));
        case "activate" -> line.put("behaviour", e.get("behaviour"));
        case "deactivate" -> line.put("instance", e.get("instance"));
        case "error" -> {
          line.put("at", e.get("at")).put("message", e.get("message"));
          cfg.error((String) e.get("at"), (String) e.get("message"));
        }
        default -> throw new IllegalStateException(ev);
      }
      cfg.trace.event(line);
    }
    bodyEvents.clear();
  }

  /** The end of the run (D14): {@code on destroy}, then the {@code destroy}
      event and its body's events. Called by the host when the agent's loop is
      parked (lock step) or over. */
  public final void finishRun() {
    running = null;
    effects.clear();
    freshFuel();
    try {
      onDestroy();
    } catch (JadescriptError e) {
      recordError(e);
    } catch (StackOverflowError e) {
      recordTooDeep();
    }
    effects.clear();
    cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "destroy").put("action", null));
    flushBody("destroy");
    outbox.clear();
  }

  // ======================================================== messages

  /** Deliver the messages sent by {@code on create} (D13); the host calls it
      for every agent, in creation order, once all exist. */
  public final void deliverCreateMessages() {
    createFlushed = true;
    deliver(createOutbox);
  }

  private ACLMessage encode(Outgoing o, AID sender) {
    Message m = o.message;
    int perf = ACLMessage.getInteger(m.performative().toUpperCase(java.util.Locale.ROOT));
    ACLMessage acl = new ACLMessage(perf < 0 ? ACLMessage.UNKNOWN : perf);
    acl.setSender(sender);
    acl.addReceiver(new AID(o.receiver, AID.ISLOCALNAME));
    acl.addUserDefinedParameter(P_ID, Long.toString(o.id));
    acl.addUserDefinedParameter(P_PERF, m.performative());
    acl.addUserDefinedParameter(P_FROM, m.sender());
    acl.setConversationId("jsref-" + o.id);
    acl.setReplyWith("jsref-" + o.id);
    acl.setContent(Text.literal(m.content()));
    CONTENTS.put(o.id, m.content() == null ? Nothing.NOTHING : m.content());
    return acl;
  }

  /** Send each message through JADE, in order; in lock step, wait for each
      to arrive (or for the AMS to refuse it) before the next (R5e, R6). */
  private void deliver(List<Outgoing> out) {
    if (out.isEmpty()) return;
    List<Outgoing> l = new ArrayList<>(out);
    out.clear();
    for (Outgoing o : l) {
      boolean platformAgent = !cfg.isRunAgent(o.receiver)
          && ("ams".equalsIgnoreCase(o.receiver) || "df".equalsIgnoreCase(o.receiver));
      if (!platformAgent) PENDING.put(o.id, o);
      ACLMessage acl = encode(o, getAID());
      if (!cfg.hasAgent(o.receiver) && o.message.content() instanceof java.io.Serializable ser) {
        // to another JVM (two containers): the content travels serialized
        try {
          acl.setContentObject(ser);
          acl.addUserDefinedParameter(P_SERIAL, "1");
        } catch (java.io.IOException e) {
          // not serializable after all: the receiver reads the literal
        }
      }
      cfg.trace.sync();   // two containers: every event before the send is written first
      send(acl);
      if (platformAgent) {
        // JADE's own AMS or DF: delivered, but not to a Jadescript agent (no
        // deliver event); the reference has no such agents (undeliverable)
        CONTENTS.remove(o.id);
        continue;
      }
      if (cfg.lockStep) {
        try {
          if (!o.done.await(20, TimeUnit.SECONDS))
            System.err.println("jsref: no delivery of a message to " + o.receiver + " after 20 s");
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
          return;
        }
        Object barrier = o.barrier;
        if (barrier != null) synchronized (barrier) { /* JADE's postMessage is over */ }
      }
    }
  }

  /** {@inheritDoc} */
  @Override
  public final boolean arriving(ACLMessage m) {
    if (m.getPerformative() == ACLMessage.FAILURE && m.getSender() != null
        && "ams".equalsIgnoreCase(m.getSender().getLocalName())) {
      Long id = idOf(m.getInReplyTo());
      if (id == null) id = idOf(m.getConversationId());
      Outgoing o = id == null ? null : PENDING.remove(id);
      if (o != null) {
        CONTENTS.remove(o.id);
        cfg.trace.event(new Json.Obj().put("agent", o.sender).put("event", "undeliverable").put("action", null)
            .put("to", o.receiver).put("performative", o.message.performative())
            .put("content", Text.literal(o.message.content())));
        o.barrier = queue;
        o.done.countDown();
        return false;
      }
      return true;
    }
    String pid = m.getUserDefinedParameter(P_PERCEPT);
    if (pid != null) {
      PerceptEntry e = PERCEPTS.remove(Long.parseLong(pid));
      if (e == null) return false;
      arrivals.put(m, new Arrived(null, 0, e));
      return true;
    }
    String sid = m.getUserDefinedParameter(P_ID);
    if (sid == null) return true;   // not a Jadescript message: JADE keeps it; no handler takes it
    long id = Long.parseLong(sid);
    Object content = CONTENTS.remove(id);
    if (content == null) content = remoteContent(m);
    Message msg = new Message(m.getUserDefinedParameter(P_PERF), content, m.getUserDefinedParameter(P_FROM));
    int seq = ++msgSeq;
    arrivals.put(m, new Arrived(msg, seq, null));
    cfg.trace.event(new Json.Obj().put("agent", getLocalName()).put("event", "deliver").put("action", "Send")
        .putAll(messageFields(msg)).put("seq", seq));
    return true;
  }

  /** {@inheritDoc} */
  @Override
  public final void arrived(ACLMessage m) {
    if (m.getUserDefinedParameter(P_PERCEPT) != null) return;
    String sid = m.getUserDefinedParameter(P_ID);
    if (sid == null) return;
    wakeUp();
    Outgoing o = PENDING.remove(Long.parseLong(sid));
    if (o != null) {
      o.barrier = queue;
      o.done.countDown();
    } else if (remoteArrival != null && !"host".equals(m.getUserDefinedParameter(P_FROM))) {
      remoteArrival.accept(Long.parseLong(sid));
    }
  }

  /** The content of a message from another JVM: the serialized value, else
      the literal read back with the program's ontologies. */
  private Object remoteContent(ACLMessage m) {
    if ("1".equals(m.getUserDefinedParameter(P_SERIAL))) {
      try {
        Object v = m.getContentObject();
        if (v != null) return v;
      } catch (jade.lang.acl.UnreadableException e) {
        // fall back to the literal
      }
    }
    String lit = m.getContent();
    try {
      return jsref.values.Literals.parse(lit, cfg.program, "message");
    } catch (jsref.values.LiteralError e) {
      return lit;
    }
  }

  private static Long idOf(String s) {
    if (s == null || !s.startsWith("jsref-")) return null;
    try { return Long.parseLong(s.substring(6)); } catch (NumberFormatException e) { return null; }
  }
}
