package jsref.values;

/** SKELETON (to be filled in with the back end): a run-time error (R7) at a
    source position, {@code FILE:LINE:COL}. */
public class JadescriptError extends RuntimeException {
  private static final long serialVersionUID = 1L;
  private final String at;

  public JadescriptError(String at, String message) { super(message, null, false, false); this.at = at; }

  public static JadescriptError at(String at, String message) { return new JadescriptError(at, message); }

  public String at() { return at; }

  public String message() { return getMessage(); }
}
