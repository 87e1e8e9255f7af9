package jsref.runtime;

import jade.core.JsrefScheduler;
import java.util.ArrayList;
import java.util.List;

/** R5d revised on JADE: the messages that reach an agent while one of its
    behaviour steps is in progress, or right after it (docs/jade.md,
    "Messages during a step"). Its state is read and changed holding the
    agent's message queue's monitor (JADE's {@code postMessage} holds it for a
    whole arrival) and, where JADE's lists change, the scheduler's too.

    <p><b>Running freely</b> the window is the step itself: it opens when
    JADE's scheduler picks the behaviour ({@link #start}) and closes when the
    step is over ({@link #commitFree}). A message that arrives in it is not
    seen by the step's handlers (they look at the messages that had arrived
    when the behaviour was picked), its {@code deliver} line waits for the
    step's line and body lines and is then written with the action
    {@code SendInStep}, and the wake-up of the blocked behaviours it causes
    waits for the step's effects on behaviours; the behaviour, if its step
    took nothing, stays ready at its place (JADE's restart counter) instead
    of blocking. So a step is, to the other agents' messages, atomic up to
    the look of its handlers, and each message that comes during it comes
    after that look, as the ruling's SendInStep says.

    <p><b>In lock step</b> no message arrives during a step; the host's
    messages of an events line {@code "during": "step"} (D42) do, right after
    the step's own sends are delivered, as the reference delivers them: the
    window opens at the end of a step that would block its behaviour and
    some such message waits ({@link #commitLockStep}); a plain message
    arriving first closes it (the behaviour blocks, then wakes as any
    blocked one); the agent's next rule closes it too ({@link #close}). */
final class InStep {
  /** Where the agent is with respect to its behaviour steps. */
  enum Phase {
    /** No step in progress, no window open. */
    NONE,
    /** Running freely: a step is in progress. */
    STEP,
    /** In lock step: a step is over and its behaviour's block waits. */
    OPEN
  }

  private final JadescriptAgent agent;
  Phase phase = Phase.NONE;
  /** The behaviour whose step is in progress, or whose block waits. */
  private JadescriptBehaviour stepping;
  /** In lock step, the step took nothing and would block its behaviour. */
  private boolean wantsBlock;
  /** A message reached the agent in the window. */
  private boolean arrived;
  /** A wake-up of the blocked behaviours waits for the end of the step. */
  private boolean wake;
  /** Deliveries in the window, their lines waiting for the step's. */
  private final List<Messaging.Arrived> lines = new ArrayList<>();

  InStep(JadescriptAgent agent) { this.agent = agent; }

  /** Running freely, JADE's scheduler picked the behaviour: its step begins.
      @param b the behaviour */
  void start(JadescriptBehaviour b) {
    if (agent.cfg.lockStep) return;
    phase = Phase.STEP;
    stepping = b;
    arrived = false;
    wake = false;
    lines.clear();
  }

  /** When a delivery's line is written. */
  enum Line {
    /** Now, a Send. */
    SEND,
    /** Now, a SendInStep. */
    SEND_IN_STEP,
    /** With the step's, at its end, a SendInStep. */
    LATER
  }

  /** A message arrived (its seq given): where its line goes. Holding the
      message queue's monitor. @param a the arrival @param duringStep an
      events line's message for the agent's next behaviour step (D42)
      @return when its line is written */
  Line arriving(Messaging.Arrived a, boolean duringStep) {
    switch (phase) {
      case STEP -> {
        arrived = true;
        lines.add(a);
        return Line.LATER;
      }
      case OPEN -> {
        if (duringStep) { arrived = true; return Line.SEND_IN_STEP; }
        close();   // a plain Send ends the window: the behaviour blocks first
        return Line.SEND;
      }
      default -> { return Line.SEND; }
    }
  }

  /** JADE's {@code restartAll} (a message arrived, holding the scheduler's
      monitor): during a step it waits for the step's end.
      @param s the scheduler @return true if the blocked behaviours wake now */
  boolean restartNow(JsrefScheduler s) {
    if (phase == Phase.STEP) { wake = true; return false; }
    return true;
  }

  /** Running freely, the step is over (its line and body lines written,
      JADE's lists changed by its effects): the behaviour blocks unless a
      message came during the step; then the lines of those messages, and the
      wake-up of the blocked behaviours. Holding the message queue's and the
      scheduler's monitors. @param s the scheduler @param blocks the step took
      nothing and would block its behaviour (R5d) */
  void commitFree(JsrefScheduler s, boolean blocks) {
    JadescriptBehaviour b = stepping;
    phase = Phase.NONE;
    stepping = null;
    if (blocks && !arrived) block(s, b);
    for (Messaging.Arrived a : lines)
      if (a.msg() != null) agent.cfg.trace.deliver(agent.name(), a.msg(), a.seq(), true);
    lines.clear();
    if (wake) s.wakeBlocked();
    wake = false;
    arrived = false;
  }

  /** In lock step, the step is over: a behaviour that would block blocks
      now, unless an events line's message waits for this step (D42): then
      the window opens until the agent's next rule, or a plain message
      arrives first (the reference's SendInStep is enabled after any
      behaviour step: a step that blocked nothing makes it a Send with the
      action SendInStep). Holding the scheduler's monitor.
      @param s the scheduler @param b the behaviour @param blocks it would block
      @param held messages wait for the agent's behaviour step */
  void commitLockStep(JsrefScheduler s, JadescriptBehaviour b, boolean blocks, boolean held) {
    if (!held) {
      if (blocks) block(s, b);
      return;
    }
    phase = Phase.OPEN;
    stepping = b;
    wantsBlock = blocks;
    arrived = false;
  }

  /** In lock step, the window closes (a plain message, or the agent's next
      rule): the behaviour blocks unless a message came during its step.
      Holding the message queue's monitor. */
  void close() {
    if (phase != Phase.OPEN) return;
    phase = Phase.NONE;
    JsrefScheduler s = agent.hooks.sched;
    synchronized (s) {
      if (wantsBlock && !arrived) block(s, stepping);
    }
    stepping = null;
    wantsBlock = false;
    arrived = false;
  }

  /** Block the behaviour (R5d), as JADE's agent thread blocks one after a
      step that called {@code block()}: its flag, then JADE's
      {@code Scheduler.block} (R5f's index rule). */
  private static void block(JsrefScheduler s, JadescriptBehaviour b) {
    if (b == null || !b.jsActive || !s.isReady(b)) return;
    b.block();
    s.block(b);
  }
}
