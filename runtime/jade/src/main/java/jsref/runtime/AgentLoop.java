package jsref.runtime;

import jade.core.JsrefScheduler;
import jade.core.behaviours.Behaviour;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.concurrent.atomic.AtomicLong;
import jsref.runtime.TraceFormat.Action;

/** The agent loop of the rulings (R3; docs/semantics.md "Agent rules"), one
    method per rule of spec/AgentLoop.tla, on JADE's own machinery: an
    iteration runs where JADE's scheduler picks the next behaviour
    ({@link #iteration}, called through {@link SchedulerHooks}): Transfer
    (R3a; TransferOne/TransferSpin/TransferEnd in {@code printed}; into the
    message queue in {@code native}), then per percept Dequeue, Handle or
    Skip per registered handler and EndDispatch (R3b, R4), then JADE's round
    robin picks the behaviour whose step (BehaviourStep, R5a-R5d) JADE's
    thread then runs ({@link #step}); with no behaviour ready, NextIteration
    or Idle (R3e). Each rule waits for its turn ({@link LockStep#rule}) and
    is written to the trace, then the events of the bodies it ran. */
final class AgentLoop {
  private final JadescriptAgent agent;
  /** The priority queue of percepts (R3b). */
  private final PerceptQueue pq = new PerceptQueue();
  /** Percepts dequeued since the last Transfer (the budget of {@code budgeted}). */
  private int dispatched;
  /** {@code native}: the behaviour step in progress took a percept from
      the message queue, whose room in the O2A queue (D6) it gives back with
      its line (the agent's own thread only). */
  private boolean nativeTaken;
  /** Percepts dequeued by this agent so far (the bench's windows). */
  final AtomicLong dequeued = new AtomicLong();
  /** The behaviour step JADE is about to run, or ran: in lock step its
      sends go when the next iteration starts (R5e: at the end of the step,
      outside the agent's monitors). */
  private boolean stepInProgress;
  /** Running freely, the first iteration has waited for every agent to exist (D13). */
  private boolean started;
  /** The types of the instances the trace has seen, by id: a skip or a step
      of an instance deactivated since still names its type. */
  private final HashMap<Integer, String> known = new HashMap<>();
  /** The registered handlers of the dispatch in progress (R4a), reused from
      one percept to the next: instances and handler numbers. */
  private JadescriptBehaviour[] snapB = new JadescriptBehaviour[16];
  private int[] snapH = new int[16];

  AgentLoop(JadescriptAgent agent) { this.agent = agent; }

  /** The loop: one iteration up to the behaviour step, run where JADE's
      scheduler picks the next behaviour. @param s JADE's scheduler of the agent
      @return the behaviour whose step JADE runs next
      @throws InterruptedException on JADE's deletion */
  Behaviour iteration(JsrefScheduler s) throws InterruptedException {
    RunConfig cfg = agent.cfg;
    SchedulerHooks hooks = agent.hooks;
    if (stepInProgress) {
      stepInProgress = false;
      if (cfg.lockStep) {
        // as the reference: the events lines' messages held for this step
        // arrive during it (D42, SendInStep), then the step's sends leave as
        // it ends, each awaited (R5e, D44), then the window of R5d revised
        // closes
        agent.messaging.postHeld(true);
        agent.messaging.deliverSent();
        synchronized (hooks.queue) { agent.inStep.close(); }
      }
    }
    if (!cfg.lockStep && !started) {   // D13: the host sends on create's messages first
      started = true;
      cfg.awaitAllCreated();
    }
    while (true) {
      agent.lockStep.awaitTurn();
      try {
        switch (cfg.variant) {
          case PRINTED -> transferPrinted();
          case NATIVE -> transferNative();
          default -> transfer();
        }
        if (cfg.variant != Variant.NATIVE) dispatch();
      } catch (RuntimeException | StackOverflowError e) {
        agent.internalError(e);
      }
      agent.lockStep.rule();
      // BehaviourStep, Idle or NextIteration: decided with no message half
      // posted (JADE's postMessage holds the queue's monitor from the arrival
      // to restartAll) and no behaviour half restarted (the scheduler's), so
      // that a Send is wholly before the decision or wholly after it
      synchronized (hooks.queue) {
        synchronized (s) {
          if (s.readyCount() > 0) {
            stepInProgress = true;
            JadescriptBehaviour b = (JadescriptBehaviour) s.pick();
            agent.messaging.pickedNow();
            agent.inStep.start(b);
            return b;
          }
          synchronized (hooks.o2a) {   // and no notify half done (its line and its put)
            if (cfg.variant != Variant.PRINTED && idleCondition(s)) {
              hooks.idle = true;
              cfg.trace.idle(agent.name());
              ruleWritten(Action.IDLE);
              continue;
            }
            cfg.trace.nextIteration(agent.name());
            ruleWritten(Action.NEXT_ITERATION);
          }
        }
      }
    }
  }

  /** A rule's line, then the events of the bodies it ran (a Skip's: the
      error of its {@code when}, R3b), all at once in the trace (its
      monitor): running freely, the host's thread writes its own lines (a
      notify, a put) whenever they happen, and one between a rule's line and
      its body's events is a run no rule explains (the judge rejects it:
      docs/jade.md, "Running freely"). @param action the rule's action
      @param line writes the rule's line, or null */
  private void written(String action, Runnable line) {
    synchronized (agent.cfg.trace) {
      if (line != null) line.run();
      ruleWritten(action);
    }
  }

  /** The rule's line is written: remember the instances' types, then write
      the events of the bodies it ran. */
  private void ruleWritten(String action) {
    if (agent.cfg.trace.writes()) for (JadescriptBehaviour b : agent.active) known.put(b.id(), b.typeName());
    agent.body.flush(action);
  }

  /** The end of a rule whose bodies may have changed the active behaviours
      or sent messages: its line ({@code line}, null for none), its bodies'
      events, then JADE's lists (the effects, {@link Body#applyJade}), all at
      once with respect to a message's arrival (which holds the message
      queue's monitor): the arrival's line and its wake-up of the blocked
      behaviours are both before the rule's or both after. Running freely,
      the messages the bodies sent then go to JADE ({@link #finish}). A rule
      with neither writes its lines with no monitor. @param action the
      rule's action @param line writes the rule's line */
  private void commit(String action, Runnable line) {
    boolean sends = !agent.cfg.lockStep && agent.messaging.hasSent();
    if (!sends && !agent.body.hasJadeEffects()) {
      written(action, line);
      return;
    }
    finish(action, line, sends, null);
  }

  /** A rule's end, at once with respect to arrivals (the message queue's
      and the scheduler's monitors): its line, its bodies' events, the
      {@code undeliverable} lines of its sends (R5e), JADE's lists, then
      {@code then}. Running freely with sends, all of it holding
      {@link Messaging#SENDS}, and then JADE's sends, still holding it (so
      that messages enter JADE's delivery queues in the order of their send
      lines) but no longer the agent's monitors: JADE's {@code send} takes
      the sender's entry in the container's table of agents, which a
      delivery to the sender holds while it waits for the sender's message
      queue (holding the queue there deadlocks with the AMS's failure for an
      earlier send of the same step). Lock order: SENDS, the message queue,
      the scheduler. @param action the rule's action @param line writes the
      rule's line @param sends running freely, the bodies sent messages
      @param then runs last under the monitors, or null */
  private void finish(String action, Runnable line, boolean sends, Runnable then) {
    if (!sends) { atOnce(action, line, null, then); return; }
    synchronized (Messaging.SENDS) {
      List<Messaging.Prepared> out = new ArrayList<>();
      atOnce(action, line, out, then);
      agent.messaging.post(out);
    }
  }

  private void atOnce(String action, Runnable line, List<Messaging.Prepared> out, Runnable then) {
    synchronized (agent.hooks.queue) {
      synchronized (agent.hooks.sched) {
        if (nativeTaken) {
          // D6: the percept a native step took leaves the O2A queue's room
          // with the step's line, at once with respect to the host's check
          // and line (HostRules, under the O2A's lock): a put or notify is
          // wholly before the step, and finds the percept still counted, or
          // wholly after it
          nativeTaken = false;
          synchronized (agent.hooks.o2a) {
            written(action, line);
            agent.host.nativePercepts.decrementAndGet();
          }
        } else written(action, line);
        if (out != null) out.addAll(agent.messaging.prepareSent());
        agent.body.applyJade();
        if (then != null) then.run();
      }
    }
  }

  /** IdleCondition (R3e): nothing ready, no percept to transfer or dispatch. */
  private boolean idleCondition(JsrefScheduler s) {
    if (s.readyCount() > 0 || !pq.isEmpty()) return false;
    jade.util.leap.List o2a = agent.hooks.o2a;
    synchronized (o2a) {
      for (int i = 0; i < o2a.size(); i++) if (o2a.get(i) instanceof PerceptEntry) return false;
    }
    return true;
  }

  // ------------------------------------------------------------ transfer

  /** The percepts of the O2A queue, oldest first, taken out of it; the other
      objects stay, in order (R3a). The caller holds JADE's O2A lock, so that
      its trace line is written before any later notify's. */
  private List<PerceptEntry> takePercepts() {
    jade.util.leap.List o2a = agent.hooks.o2a;
    List<PerceptEntry> moved = new ArrayList<>();
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
    return moved;
  }

  /** Transfer (R3a). */
  private void transfer() throws InterruptedException {
    agent.lockStep.rule();
    synchronized (agent.hooks.o2a) {
      List<PerceptEntry> moved = takePercepts();
      for (PerceptEntry e : moved) pq.insert(e);
      dispatched = 0;
      agent.cfg.trace.transfer(agent.name(), moved.size());
      ruleWritten(Action.TRANSFER);
    }
  }

  /** TransferOne / TransferSpin / TransferEnd (printed, Algorithm 1). */
  private void transferPrinted() throws InterruptedException {
    jade.util.leap.List o2a = agent.hooks.o2a;
    Trace trace = agent.cfg.trace;
    while (true) {
      agent.lockStep.rule();
      synchronized (o2a) {
        Object head = o2a.isEmpty() ? null : o2a.get(0);
        if (head == null) {
          dispatched = 0;
          trace.transferEnd(agent.name());
          ruleWritten(Action.TRANSFER_END);
          return;
        }
        if (head instanceof PerceptEntry e) {
          o2a.remove(0);
          pq.insert(e);
          trace.transferOne(agent.name(), e);
          ruleWritten(Action.TRANSFER_ONE);
        } else {
          trace.transferSpin(agent.name(), head instanceof PutObject po ? po.value() : head);
          ruleWritten(Action.TRANSFER_SPIN);
        }
      }
    }
  }

  /** Transfer (native): the percepts go to the end of JADE's message queue,
      through {@code postMessage} (which restarts the blocked behaviours). */
  private void transferNative() throws InterruptedException {
    agent.lockStep.rule();
    synchronized (agent.hooks.queue) {   // the percepts join the message queue together
      List<PerceptEntry> moved;
      synchronized (agent.hooks.o2a) {
        moved = takePercepts();
        agent.host.nativePercepts.addAndGet(moved.size());   // still the O2A's room (D6)
        dispatched = 0;
        agent.cfg.trace.transfer(agent.name(), moved.size());
        ruleWritten(Action.TRANSFER);
      }
      for (PerceptEntry e : moved) agent.messaging.postPercept(e);
    }
  }

  // ------------------------------------------------------------ dispatch

  /** Dequeue, Handle/Skip per handler of the snapshot, EndDispatch (R3b, R4). */
  private void dispatch() throws InterruptedException {
    RunConfig cfg = agent.cfg;
    Trace trace = cfg.trace;
    Body body = agent.body;
    String name = agent.name();
    while (!pq.isEmpty() && !(cfg.variant == Variant.BUDGETED && dispatched >= cfg.budget)) {
      agent.lockStep.rule();
      PerceptEntry e = pq.pop();
      dispatched++;
      dequeued.lazySet(dequeued.get() + 1);
      trace.dequeue(name, e);
      ruleWritten(Action.DEQUEUE);
      // the registered handlers (R4a): active instances in activation order,
      // each one's handlers in declaration order (inherited first)
      int n = 0;
      for (JadescriptBehaviour b : agent.active) n += b.perceptHandlerCount();
      if (snapB.length < n) { snapB = new JadescriptBehaviour[2 * n]; snapH = new int[2 * n]; }
      final JadescriptBehaviour[] insts = snapB;
      final int[] hs = snapH;
      n = 0;
      for (JadescriptBehaviour b : agent.active)
        for (int h = 1; h <= b.perceptHandlerCount(); h++) { insts[n] = b; hs[n] = h; n++; }
      boolean applied = false;
      for (int k = 0; k < n; k++) {
        agent.lockStep.rule();
        JadescriptBehaviour b = insts[k];
        int h = hs[k];
        if (!b.jsActive) {   // R4b: deactivated since the snapshot
          skip(b, h);
          continue;
        }
        body.reserved = new SnapshotIds(insts, k, n);   // the snapshot's ids from here on (D2)
        body.running = b;
        body.clearEffects();
        body.freshFuel();
        boolean ran;
        try {
          ran = b.perceptHandler(h, e.percept());
        } finally {
          body.running = null;
          body.reserved = List.of();
        }
        if (ran) {
          applied = true;
          final int hh = h;
          commit(Action.HANDLE, !trace.writes() ? null
              : () -> trace.handle(name, b.id(), b.typeName(), hh, e.percept(), e.seq(), body.describeEffects()));
        } else {
          skip(b, h);
        }
        body.clearEffects();
        if (cfg.lockStep) agent.messaging.deliverSent();
      }
      agent.lockStep.rule();
      trace.endDispatch(name, e.seq(), !applied);
      ruleWritten(Action.END_DISPATCH);
    }
  }

  /** Skip (R4b): the line names the instance's type even when it was
      deactivated since. */
  private void skip(JadescriptBehaviour b, int h) {
    Trace trace = agent.cfg.trace;
    written(Action.SKIP, !trace.writes() ? null
        : () -> trace.skip(agent.name(), b.id(), known.getOrDefault(b.id(), "?"), h));
  }

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

  // ------------------------------------------------------------ the behaviour step

  /** BehaviourStep (R5a-R5d): run by JADE's agent thread in the behaviour's
      {@code action()}. The step holds no monitor while its bodies run: a
      message may arrive meanwhile, as on JADE; it is not seen by the step's
      handlers, which look at the messages that had arrived when JADE's
      scheduler picked the behaviour, and it comes after the step
      ({@link InStep}: R5d revised, SendInStep). The look of the handlers is
      atomic (under the message queue's monitor), and so is the end of the
      step ({@link #commit}'s monitors): its line, its bodies' events, JADE's
      lists, and its behaviour blocked (R5d) unless a message came during the
      step. @param b the behaviour JADE picked */
  void step(JadescriptBehaviour b) {
    RunConfig cfg = agent.cfg;
    Body body = agent.body;
    SchedulerHooks hooks = agent.hooks;
    if (!cfg.lockStep) agent.messaging.postHeld(true);   // D42: they arrive during this step
    int id = b.id();
    body.reserved = List.of(id);
    body.running = b;
    String lastBehaviour = "";
    List<String> actionEffects = null;
    Integer handler = null;
    List<String> handlerEffects = null;
    Messaging.Arrived taken = null;
    try {
      if (b.hasAction()) {
        lastBehaviour = b.typeName();
        body.clearEffects();
        body.freshFuel();
        b.actionBlock();
        actionEffects = body.describeEffects();
        body.clearEffects();
      }
      Messaging.Arrived found = null;
      int foundBy = 0;
      synchronized (hooks.queue) {   // the handlers look (R5b), at once
        if (cfg.variant == Variant.NATIVE) {
          for (int h = 1; h <= b.perceptHandlerCount() && taken == null; h++) {
            body.clearEffects();
            Messaging.Arrived a = agent.messaging.take(b, h, true);   // its handler has run
            if (a != null) {
              nativeTaken = true;   // its room is given back with the step's line (atOnce)
              taken = a;
              lastBehaviour = b.typeName();
              handler = h;
              handlerEffects = body.describeEffects();
            }
          }
        }
        for (int h = 1; h <= b.messageHandlerCount() && taken == null && found == null; h++) {
          found = agent.messaging.take(b, h, false);
          foundBy = h;
        }
      }
      if (found != null) {
        taken = found;
        lastBehaviour = b.typeName();
        body.clearEffects();
        body.freshFuel();
        b.messageHandler(foundBy, found.msg());
        handler = foundBy;
        handlerEffects = body.describeEffects();
      }
    } finally {
      body.running = null;
      body.reserved = List.of();
      body.clearEffects();
    }
    // R5d: a cyclic step that took nothing, in a behaviour without a do
    // block that is still active, blocks it (unless a message came during it)
    boolean blocks = b.isCyclic() && !b.hasAction() && taken == null && b.jsActive;
    if (!b.isCyclic()) { agent.active.remove(b); b.jsActive = false; }   // JADE removes it: done() (R5c, D1)
    final Messaging.Arrived t = taken;
    final String shown = lastBehaviour.isEmpty() ? known.getOrDefault(id, "?") : lastBehaviour;
    final List<String> ae = actionEffects;
    final Integer hd = handler;
    final List<String> he = handlerEffects;
    Runnable line = () -> cfg.trace.behaviourStep(agent.name(), id, shown,
        t == null ? null : t.msg(), t == null ? 0 : t.seq(), t == null ? null : t.percept(), ae, hd, he);
    boolean sends = !cfg.lockStep && agent.messaging.hasSent();
    finish(Action.BEHAVIOUR_STEP, line, sends, () -> {
      if (cfg.lockStep) agent.inStep.commitLockStep(hooks.sched, b, blocks, agent.messaging.holds());
      else agent.inStep.commitFree(hooks.sched, blocks);
    });
  }
}
