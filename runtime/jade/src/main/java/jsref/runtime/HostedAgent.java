package jsref.runtime;

/** An agent as the host harness drives it: a {@link JadescriptAgent} of this
    JVM, or a {@link RemoteAgent} living in a peripheral container of another
    JVM (docs/jade.md, "Two containers"). The methods are the host's API of
    the paper (notifyEvent) and the lock-step controls of the harness. */
public interface HostedAgent {
  /** @return the agent's name as written (D48) */
  String name();

  /** @return is the agent idle (R3e)? */
  boolean isIdle();

  /** @return running freely: asleep with nothing ready and no message on its way */
  boolean isQuiet();

  /** One loop iteration in lock step. @param maxRules the most rules to take
      @return how many rules it took @throws InterruptedException if interrupted */
  int runIteration(int maxRules) throws InterruptedException;

  /** {@code notifyEvent(p)} (R2b). @param p the percept @return false when refused (R2d) */
  boolean notifyEvent(Object p);

  /** {@code notifyEvent(p, k)} (R2a). @param p the percept @param k the priority
      @return false when refused (R2d) */
  boolean notifyEvent(Object p, int k);

  /** A non-percept object into the O2A queue (R2c). @param o the object
      @return false when refused (R2d) */
  boolean put(Object o);

  /** A message from the host (R5e). @param performative as written @param content the content */
  void hostMessage(String performative, Object content);

  /** An events line's message for the agent's next behaviour step (D42).
      @param performative as written @param content the content */
  void hostMessageDuringStep(String performative, Object content);

  /** The messages held for a step that did not come arrive now (D42).
      @return were there any */
  boolean releaseHeld();

  /** Deliver what {@code on create} sent (D13). */
  void deliverCreateMessages();

  /** {@code on destroy} and the {@code destroy} event (D14). */
  void finishRun();
}
