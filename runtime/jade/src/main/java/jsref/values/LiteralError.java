package jsref.values;

/** A host literal that cannot be read or is not a value the host can give
    ({@link Literals}): the column (from 1) in the literal's text, and the
    interpreter's message. */
public final class LiteralError extends Exception {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  /** The column, from 1. */
  private final int column;

  /** An error.
      @param column the column, from 1
      @param message the message */
  public LiteralError(int column, String message) { super(message, null, false, false); this.column = column; }

  /** The column, from 1.
      @return the column */
  public int column() { return column; }

  /** The message.
      @return the message */
  public String message() { return getMessage(); }
}
