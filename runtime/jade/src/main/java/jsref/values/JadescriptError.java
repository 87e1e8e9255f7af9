package jsref.values;

/** A run-time error of a Jadescript program (R7): a message, with the wording
    of the reference interpreter, at a source position {@code FILE:LINE:COL}
    (exactly as {@code Source.string_of_region}; {@code ":0:0"} when the error
    has no place in the program). It stops the body that raised it; the
    runtime records it and the agent carries on. No stack trace is filled in:
    these are ordinary outcomes, and cheap. */
public class JadescriptError extends RuntimeException {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  /** Where. */
  private final String at;

  /** An error.
      @param at {@code FILE:LINE:COL}
      @param message the interpreter's message */
  public JadescriptError(String at, String message) { super(message, null, false, false); this.at = at; }

  /** An error.
      @param at {@code FILE:LINE:COL}
      @param message the interpreter's message
      @return the new error (to be thrown) */
  public static JadescriptError at(String at, String message) { return new JadescriptError(at, message); }

  /** Where: {@code FILE:LINE:COL}.
      @return the position */
  public String at() { return at; }

  /** What: the interpreter's message.
      @return the message */
  public String message() { return getMessage(); }

  /** {@code FILE:LINE:COL: error: message}, as the command line reports it. */
  @Override public String toString() { return at + ": error: " + getMessage(); }
}
