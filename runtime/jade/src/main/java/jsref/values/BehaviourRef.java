package jsref.values;

/** The value of {@code this} in a behaviour: the behaviour instance, by its
    unique number. Shown as {@code behaviour #N}. */
public final class BehaviourRef implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  /** The instance's number. */
  private final int uid;

  /** A reference to the behaviour instance with this number.
      @param uid the instance's number */
  public BehaviourRef(int uid) { this.uid = uid; }

  /** The instance's number.
      @return the number */
  public int uid() { return uid; }

  /** Same instance. */
  @Override public boolean equals(Object o) { return o instanceof BehaviourRef && ((BehaviourRef) o).uid == uid; }

  /** Consistent with {@link #equals}. */
  @Override public int hashCode() { return uid; }

  /** {@code behaviour #N}. */
  @Override public String toString() { return "behaviour #" + uid; }
}
