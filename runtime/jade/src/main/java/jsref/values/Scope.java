package jsref.values;

/** What the code running in an agent or a behaviour can reach by name, for
    {@code x of agent}, {@code x of this} and their assignments
    ({@link Ops#of}, {@link Ops#setOf}). Generated agent and behaviour classes
    implement it; a property that does not exist (or is not initialised yet)
    answers null or false. */
public interface Scope {
  /** The current value of a property of the agent running the code.
      @param name the property
      @return its value, or null if there is none */
  Object jsAgentProperty(String name);

  /** Sets a property of the agent running the code, converted to its declared
      type.
      @param name the property
      @param v the value
      @return false if there is none */
  boolean jsSetAgentProperty(String name, Object v);

  /** The number of the behaviour instance whose code runs, or -1 in an agent's
      own code (routines of the agent included).
      @return the number */
  int jsBehaviourUid();

  /** The current value of a property of the running behaviour.
      @param name the property
      @return its value, or null if there is none */
  Object jsBehaviourProperty(String name);

  /** Sets a property of the running behaviour, converted to its declared type.
      @param name the property
      @param v the value
      @return false if there is none */
  boolean jsSetBehaviourProperty(String name, Object v);
}
