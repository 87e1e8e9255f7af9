package jsref.runtime;

/** The base class of every generated behaviour class: a JADE behaviour.
    Activated, it is added to its agent with JADE's {@code addBehaviour};
    JADE's scheduler picks it in round robin; each {@code action()} is one
    behaviour step of the rulings (R5a-R5d), run by {@link AgentLoop#step}:
    the {@code do} block, then at most one message taken from JADE's queue by
    the first message handler that has a matching one. A cyclic behaviour is
    never {@code done()}; a one-shot one is done after its step, and JADE
    removes it (R5c, D1). A step that took nothing, in a behaviour without a
    {@code do} block, ends with JADE's {@code block()} (R5d). */
public abstract class JadescriptBehaviour extends jade.core.behaviours.Behaviour {
  /** Is the instance among the agent's active behaviours (R4b)? Kept by the
      runtime beside its list of active instances, so that a dispatch asks in
      one read. */
  transient boolean jsActive;

  private static final long serialVersionUID = 1L;
  private transient JadescriptAgent owner;
  private int uid;
  private int id;

  /** For generated subclasses. */
  protected JadescriptBehaviour() { super(); }

  // --- overridden by the generated behaviour class ---

  /** The behaviour type's name. @return the name */
  public abstract String typeName();

  /** Cyclic or one shot. @return true for a cyclic behaviour */
  public abstract boolean isCyclic();

  /** Does it have a {@code do} block? @return true if it has */
  public boolean hasAction() { return false; }

  /** The {@code do} block (its errors are caught and recorded by generated code). */
  protected void actionBlock() {}

  /** How many {@code on percept} handlers, inherited ones first. @return the count */
  public int perceptHandlerCount() { return 0; }

  /** How many message handlers. @return the count */
  public int messageHandlerCount() { return 0; }

  /** Percept handler h (from 1): pattern and {@code when} (errors recorded,
      then false); if they hold, {@code freshFuel()} and the body (errors
      recorded), then true. @param h the handler @param content the percept
      @return true if the body ran */
  public boolean perceptHandler(int h, Object content) { return false; }

  /** The performative of message handler h, or null for any.
      @param h the handler @return the performative, lower case */
  public String messagePerformative(int h) { return null; }

  /** Message handler h's pattern and {@code when} on a message (errors
      recorded, then false). @param h the handler @param m the message
      @return true if it accepts the message */
  public boolean messageAccepts(int h, Message m) { return true; }

  /** Message handler h: the guard again (for its bindings), then the body;
      errors recorded. @param h the handler @param m the message */
  public void messageHandler(int h, Message m) {}

  /** Property initialisers. */
  protected void initProperties() {}

  /** {@code on create}, with named arguments. @param names the names @param values the values */
  protected void onCreate(String[] names, Object[] values) {}

  // --- services ---

  /** The agent it runs in. @return the agent */
  public final JadescriptAgent agent() { return owner; }

  /** Its number ({@code this} as a value, {@code behaviour #N}): from 1, one
      counter per run. @return the number */
  public final int uid() { return uid; }

  /** Its instance id in the agent loop (R4a, D2), 0 before it is active.
      @return the id */
  public final int id() { return id; }

  final void bind(JadescriptAgent a, int uid) { this.owner = a; this.uid = uid; }

  final void setId(int id) { this.id = id; }

  // --- JADE's side ---

  /** One behaviour step, run by JADE's agent thread. */
  @Override
  public final void action() {
    try {
      owner.loop.step(this);
    } catch (RuntimeException | Error e) {
      owner.internalError(e);
    }
  }

  /** A one-shot behaviour is done after its step. */
  @Override
  public final boolean done() {
    return !isCyclic();
  }
}
