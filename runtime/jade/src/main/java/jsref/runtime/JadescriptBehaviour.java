package jsref.runtime;

/** SKELETON (to be filled in by the runtime): the base class of every
    generated behaviour class. See runtime/jade/CONTRACT.md. */
public abstract class JadescriptBehaviour extends jade.core.behaviours.Behaviour {
  private static final long serialVersionUID = 1L;

  // --- overridden by the generated behaviour class ---
  public abstract String typeName();
  public abstract boolean isCyclic();
  public boolean hasAction() { return false; }
  protected void actionBlock() {}
  public int perceptHandlerCount() { return 0; }
  public int messageHandlerCount() { return 0; }
  public boolean perceptHandler(int h, Object content) { return false; }
  public String messagePerformative(int h) { return null; }
  public boolean messageAccepts(int h, Message m) { return true; }
  public void messageHandler(int h, Message m) {}
  protected void initProperties() {}
  protected void onCreate(String[] names, Object[] values) {}

  // --- services ---
  public final JadescriptAgent agent() { return (JadescriptAgent) myAgent; }
  public final int uid() { throw new UnsupportedOperationException("skeleton"); }

  // JADE's side: filled in by the runtime
  @Override public void action() { throw new UnsupportedOperationException("skeleton"); }
  @Override public boolean done() { return false; }
}
