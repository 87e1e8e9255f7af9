package jsref.values;

/** An agent identifier ({@code aid}): the agent's name. Compared by name;
    shown as {@code aid("name")}. */
public final class Aid implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  /** The agent's name. */
  private final String name;

  /** The identifier of the agent with this name.
      @param name the agent's (local) name */
  public Aid(String name) { this.name = name; }

  /** The agent's name.
      @return the name */
  public String name() { return name; }

  /** Same name. */
  @Override public boolean equals(Object o) { return o instanceof Aid && ((Aid) o).name.equals(name); }

  /** Consistent with {@link #equals}. */
  @Override public int hashCode() { return name.hashCode(); }

  /** {@code aid("name")}, as {@link Text#literal}. */
  @Override public String toString() { return Text.literal(this); }
}
