package jsref.runtime;

import jsref.values.JadescriptError;
import jsref.values.Type;

/** SKELETON (to be filled in by the runtime): the base class of every
    generated agent class. See runtime/jade/CONTRACT.md. */
public abstract class JadescriptAgent extends jade.core.Agent {
  private static final long serialVersionUID = 1L;

  // --- overridden by the generated agent class ---
  public abstract String typeName();
  protected void initProperties() {}
  public String[] createParamNames() { return new String[0]; }
  public Type[] createParamTypes() { return new Type[0]; }
  protected void onCreate(Object[] args) {}
  protected void onDestroy() {}

  // --- services for generated code ---
  public final void tick(String at) { throw new UnsupportedOperationException("skeleton"); }
  public final void log(Object v) { throw new UnsupportedOperationException("skeleton"); }
  public final Object invoke(String at, String methodAt, String targetAt,
                             Object target, String method, Object[] args) {
    throw new UnsupportedOperationException("skeleton");
  }
  public final void send(String performative, Object content, java.util.List<String> receivers) {
    throw new UnsupportedOperationException("skeleton");
  }
  public final void activate(String at, JadescriptBehaviour b, String[] names, Object[] values) {
    throw new UnsupportedOperationException("skeleton");
  }
  public final void deactivate(JadescriptBehaviour self) { throw new UnsupportedOperationException("skeleton"); }
  public final void recordError(JadescriptError e) { throw new UnsupportedOperationException("skeleton"); }
  public final void recordTooDeep() { throw new UnsupportedOperationException("skeleton"); }
  public final void freshFuel() { throw new UnsupportedOperationException("skeleton"); }
  public final String name() { return getLocalName(); }
}
