package jsref.values;

/** The value of {@code agent} (and of {@code this} in an agent's own code):
    the agent, by name. Shown as {@code agent NAME}. Properties read and set
    through it ({@code x of agent}) are those of the agent running the code. */
public final class AgentRef implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  /** The agent's name. */
  private final String name;

  /** A reference to the agent of this name.
      @param name the agent's local name */
  public AgentRef(String name) { this.name = name; }

  /** The agent's name.
      @return the name */
  public String name() { return name; }

  /** Same name. */
  @Override public boolean equals(Object o) { return o instanceof AgentRef && ((AgentRef) o).name.equals(name); }

  /** Consistent with {@link #equals}. */
  @Override public int hashCode() { return name.hashCode(); }

  /** {@code agent NAME}. */
  @Override public String toString() { return "agent " + name; }
}
