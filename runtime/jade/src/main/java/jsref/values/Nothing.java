package jsref.values;

/** The absence of a value: what a procedure or a host method returns
    ({@code Value.Unit}, shown as {@code nothing}). There is one instance. */
public final class Nothing implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;

  /** The only instance. */
  public static final Nothing NOTHING = new Nothing();

  private Nothing() {}

  /** Keeps the instance unique across serialisation.
      @return {@link #NOTHING} */
  private Object readResolve() { return NOTHING; }

  /** {@code nothing}. */
  @Override public String toString() { return "nothing"; }
}
