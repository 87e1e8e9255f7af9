package jsref.runtime;

import jade.core.JsrefScheduler;
import jade.core.behaviours.Behaviour;
import jade.lang.acl.ACLMessage;

/** What the runtime's classes inside package {@code jade.core} call back:
    the agent loop and the arrival of messages. Implemented by
    {@link SchedulerHooks}; not for generated code. */
public interface JadeHooks {
  /** The loop, run by JADE's agent thread where JADE's scheduler picks the
      next behaviour. @param s the scheduler @return the behaviour to step
      @throws InterruptedException on the agent's deletion */
  Behaviour schedule(JsrefScheduler s) throws InterruptedException;

  /** A message is about to join the queue. @param m the message
      @return false to keep it out (the runtime consumed it) */
  boolean arriving(ACLMessage m);

  /** A message joined the queue. @param m the message */
  void arrived(ACLMessage m);

  /** JADE would restart every behaviour now (a message arrived): the
      runtime restarts the blocked ones now, or at the end of the behaviour
      step in progress ({@link JsrefScheduler#wakeBlocked}). Called holding
      the scheduler's monitor. @param s the scheduler */
  void restartAll(JsrefScheduler s);
}
