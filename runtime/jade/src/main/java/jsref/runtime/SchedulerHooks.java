package jsref.runtime;

import jade.core.JsrefMessageQueue;
import jade.core.JsrefScheduler;
import jade.core.behaviours.Behaviour;
import jade.lang.acl.ACLMessage;
import java.lang.reflect.Field;

/** Where JADE's machinery calls into the runtime, and how the runtime
    reaches into JADE (docs/jade.md, "The loop on JADE's scheduler"): the
    agent's scheduler replaced by a {@link JsrefScheduler}, whose
    {@code schedule()} runs the loop ({@link AgentLoop#iteration}); JADE's
    message queue replaced by a {@link JsrefMessageQueue}, whose arrivals go
    to {@link Messaging}; JADE's O2A list, reached by reflection, with an O2A
    manager that is never scheduled (D3); and the agent's sleep while idle
    (R3e) on the scheduler's monitor, as JADE's own scheduler sleeps. */
final class SchedulerHooks implements JadeHooks {
  private final JadescriptAgent agent;
  /** JADE's scheduler of the agent, with the loop in front of it. */
  final JsrefScheduler sched;
  /** JADE's message queue of the agent, once JADE has made it. */
  JsrefMessageQueue queue;
  /** JADE's O2A list of the agent (its own lock guards it), once set up. */
  jade.util.leap.List o2a;
  /** Has the agent taken Idle, with nothing woken it since (R3e)? Set holding
      the scheduler's monitor. */
  volatile boolean idle;

  /** Installs the runtime's scheduler in place of JADE's own (the private
      field {@code Agent.myScheduler}). @param agent the agent being constructed */
  SchedulerHooks(JadescriptAgent agent) {
    this.agent = agent;
    try {
      Field f = jade.core.Agent.class.getDeclaredField("myScheduler");
      f.setAccessible(true);
      sched = new JsrefScheduler(agent, this);
      f.set(agent, sched);
    } catch (ReflectiveOperationException e) {
      throw new IllegalStateException("cannot install the Jadescript scheduler in JADE's agent", e);
    }
  }

  /** JADE's own message queue, with the runtime's arrival hook.
      @return the queue for {@code Agent.createMessageQueue} */
  JsrefMessageQueue messageQueue() {
    queue = new JsrefMessageQueue(agent, this);
    return queue;
  }

  /** Enable JADE's O2A queue (R2d: JADE's own limit is set to the same
      capacity, but the runtime checks it before putting, as JADE would drop
      the oldest object), with the dormant manager, and reach its list.
      @param capacity the capacity, or null for unbounded */
  void enableO2A(Integer capacity) {
    agent.setEnabledO2ACommunication(true, capacity == null ? 0 : capacity);
    agent.setO2AManager(new Dormant());
    try {
      Field f = jade.core.Agent.class.getDeclaredField("o2aQueue");
      f.setAccessible(true);
      o2a = (jade.util.leap.List) f.get(agent);
    } catch (ReflectiveOperationException e) {
      throw new IllegalStateException("cannot reach JADE's O2A queue", e);
    }
  }

  /** An O2A manager that is never scheduled: JADE restarts it (instead of
      every behaviour) when an object is put into the O2A queue; the runtime
      wakes the loop itself, for percepts only (D3). */
  private static final class Dormant extends Behaviour {
    private static final long serialVersionUID = 1L;
    @Override public void action() { block(); }
    @Override public boolean done() { return false; }
  }

  // ------------------------------------------------------------ JADE calls

  /** {@inheritDoc} */
  @Override
  public Behaviour schedule(JsrefScheduler s) throws InterruptedException {
    return agent.loop.iteration(s);
  }

  /** {@inheritDoc} */
  @Override
  public boolean arriving(ACLMessage m) { return agent.messaging.arriving(m); }

  /** {@inheritDoc} */
  @Override
  public void arrived(ACLMessage m) { agent.messaging.arrived(m); }

  /** {@inheritDoc} */
  @Override
  public void restartAll(JsrefScheduler s) {
    if (agent.inStep.restartNow(s)) s.wakeBlocked();
  }

  // ------------------------------------------------------------ sleeping and waking (R3e)

  /** Running freely, the start of an iteration: asleep while idle and
      nothing is ready. A message's arrival wakes the loop before JADE's
      {@code restartAll} makes its behaviours ready, so the ready list is part
      of the condition (JADE's scheduler notifies).
      @throws InterruptedException on JADE's deletion */
  void sleepWhileIdle() throws InterruptedException {
    synchronized (sched) {
      while (idle && sched.readyCount() == 0) sched.idleWait();
      idle = false;
    }
  }

  /** R3e: a notification or a message wakes an idle agent. The loop sets
      {@code idle} holding the scheduler's monitor, after finding nothing to
      do, so a wake-up that finds the agent not idle has nothing to notify. */
  void wakeUp() {
    synchronized (sched) {
      if (idle) {
        idle = false;
        sched.notifyAll();
      }
    }
  }
}
