package jsref.runtime;

/** How the host paces an agent's loop (R6, docs/jade.md "Lock step and free
    running"). In lock step the host grants one loop iteration at a time
    ({@link #runIteration}), counting rules against {@code --max-steps}: the
    agent's thread waits at the start of each iteration for the host's grant,
    and before each rule for room in it, so that an iteration may pause in
    the middle and go on at the next grant ({@code Runtime.iterate}). Running
    freely, the agent's thread sleeps only while idle (R3e), and stops for
    good when the run's rules ({@code --max-steps}) are spent. */
final class LockStep {
  private final JadescriptAgent agent;
  private final Object gate = new Object();
  /** The host has granted rules that the agent has not given back. */
  private boolean granted;
  /** Between the start of an iteration and its end (lock step). */
  private boolean inIteration;
  /** Rules left in the grant, and rules taken in it. */
  private int grant;
  private int used;
  /** Running freely, {@code --max-steps} spent: the agent stopped for good. */
  private volatile boolean parked;

  LockStep(JadescriptAgent agent) { this.agent = agent; }

  /** Run one loop iteration (lock step): the agent takes rules until its
      iteration ends (BehaviourStep, NextIteration or Idle) or it has taken
      {@code maxRules}; a later call goes on from there. Called from the host's
      thread only. @param maxRules the most rules to take (positive)
      @return how many rules it took @throws InterruptedException if interrupted */
  int runIteration(int maxRules) throws InterruptedException {
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
      and wait for the host; running freely, sleep while idle.
      @throws InterruptedException on JADE's deletion */
  void awaitTurn() throws InterruptedException {
    if (agent.cfg.lockStep) {
      synchronized (gate) {
        if (inIteration) { inIteration = false; granted = false; gate.notifyAll(); }
        while (!granted) gate.wait();
        inIteration = true;
      }
    } else {
      agent.hooks.sleepWhileIdle();
    }
  }

  /** One rule is about to be taken: in lock step, within the host's grant.
      @throws InterruptedException on JADE's deletion */
  void rule() throws InterruptedException {
    RunConfig cfg = agent.cfg;
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

  /** @return running freely, has the agent stopped for good ({@code --max-steps})? */
  boolean parked() { return parked; }
}
