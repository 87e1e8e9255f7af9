package jade.core;

import jade.core.behaviours.Behaviour;
import jsref.runtime.JadeHooks;

/** JADE's own behaviour scheduler, with the Jadescript percept phase in
    front of it (docs/jade.md). It lives in package {@code jade.core} because
    JADE's {@link Scheduler} is package-private; the runtime installs one in
    each Jadescript agent (by reflection, in place of the agent's own).

    <p>Everything about behaviours stays JADE's: the ready and blocked lists,
    the round-robin index, {@code add}, {@code block}, {@code restart},
    {@code restartAll} and {@code remove} (with {@code removeFromReady}'s
    position rule, R5f) are the inherited ones. Only {@link #schedule()}
    changes: JADE's agent thread calls it before every behaviour step, and it
    hands control to the runtime's loop ({@link JadeHooks#schedule}), which runs
    the percept phase (Transfer, then Dequeue, Handle/Skip, EndDispatch per
    percept), and then asks JADE's own round robin for the behaviour to step
    ({@link #pick()}), or takes NextIteration or Idle when no behaviour is
    ready (R3e) and waits. And {@link #restartAll()}, JADE's wake-up of the
    blocked behaviours when a message arrives, asks the runtime first
    ({@link JadeHooks#restartAll}): during a behaviour step it waits for the
    end of the step (R5d revised: the message reached the agent during the
    step, after the step's handlers looked).

    <p>The runtime blocks a behaviour itself, at the end of its step
    ({@link #block(Behaviour)}, JADE's own), and {@link #wakeBlocked()}
    restarts only the blocked behaviours: JADE's {@code restartAll} restarts
    the ready ones too, which bumps the running behaviour's restart counter
    and keeps it runnable whatever the runtime decided (docs/jade.md,
    "Running freely"). */
public class JsrefScheduler extends Scheduler {
  private static final long serialVersionUID = 1L;
  private final transient Agent agent;
  private final transient JadeHooks hooks;

  /** A scheduler for an agent. @param a the agent @param hooks its loop */
  public JsrefScheduler(Agent a, JadeHooks hooks) {
    super(a);
    this.agent = a;
    this.hooks = hooks;
  }

  /** Not synchronized as JADE's is: the percept phase runs handler bodies,
      and hosts must be able to notify meanwhile. JADE's own pick
      ({@link #pick}) and waits ({@link #idleWait}) take the scheduler's
      monitor as JADE does. */
  @Override
  public Behaviour schedule() throws InterruptedException {
    return hooks.schedule(this);
  }

  /** JADE's round robin: the behaviour at the current index of the ready
      list; the index moves on (wrapping). The ready list must not be empty.
      @return the behaviour to step @throws InterruptedException if the agent is
      interrupted (JADE's deletion) */
  public Behaviour pick() throws InterruptedException {
    return super.schedule();
  }

  /** JADE's wake-up of every behaviour (a message arrived, JADE's
      {@code Agent.doWake}): the runtime decides when ({@link JadeHooks#restartAll}). */
  @Override
  public synchronized void restartAll() {
    hooks.restartAll(this);
  }

  /** Restart every blocked behaviour, in the order they blocked: each joins
      the end of the ready list (R5d: ready @ blocked), through JADE's
      {@code Behaviour.restart} and {@code Scheduler.restart}. */
  public synchronized void wakeBlocked() {
    Object[] bs = blockedBehaviours.toArray();
    for (Object b : bs) ((Behaviour) b).restart();
  }

  /** Is this behaviour in JADE's ready list? @param b a behaviour @return true if it is */
  public synchronized boolean isReady(Behaviour b) {
    return readyBehaviours.contains(b);
  }

  /** How many behaviours are ready. @return the size of JADE's ready list */
  public synchronized int readyCount() {
    return readyBehaviours.size();
  }

  /** How many behaviours are blocked. @return the size of JADE's blocked list */
  public synchronized int blockedCount() {
    return blockedBehaviours.size();
  }

  /** Wait as JADE's scheduler waits for work: the agent goes to state
      {@code IDLE} and sleeps on the scheduler's monitor until notified
      ({@code add}, {@code restart}, or {@link #wake()}). The caller holds the
      monitor. @throws InterruptedException on JADE's deletion */
  public void idleWait() throws InterruptedException {
    agent.idle();
  }

  /** Wake the agent if it sleeps in {@link #idleWait()}. */
  public synchronized void wake() {
    notifyAll();
  }
}
