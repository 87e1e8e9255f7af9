package jsref.values;

/** A value of an ontology schema (concept, predicate, proposition, action, or
    percept type): a record of slots. Generated classes extend it (or the class
    of their super schema) with one public field per slot; this class gives the
    slots by name and position to the runtime and to host code.

    <p>Equality and hashing are structural ({@link Ops#equal}, {@link Ops#hash}):
    same schema name and equal slots, numbers compared by value, so that
    schema values work as map keys (R1c). Slots are mutable ({@code x of p = v}),
    as in the interpreter; a value mutated while it is a map key is not found
    again, also as in the interpreter. */
public abstract class Schema implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;

  /** For subclasses. */
  protected Schema() {}

  /** The schema's name as the program declares it.
      @return the name */
  public abstract String schemaName();

  /** Every slot's name, inherited slots first, in declaration order (an
      overriding slot keeps its inherited position).
      @return a fresh array */
  public abstract String[] slotNames();

  /** Every slot's value, in the order of {@link #slotNames}.
      @return a fresh array */
  public abstract Object[] slotValues();

  /** A slot's value.
      @param slot the slot's name
      @return its value, or null
      when the schema has no such slot */
  public abstract Object get(String slot);

  /** Sets a slot (no conversion: the interpreter stores the value as given).
      @param slot the slot's name
      @param v the value
      @return false when the
      schema has no such slot */
  public abstract boolean set(String slot, Object v);

  /** Does the schema extend {@code percept} (maybe indirectly)?
      @return true for percept types */
  public boolean isPercept() { return false; }

  /** The default priority of a percept type (R1a: its own, else its parent's,
      else 0); 0 for the other schemas.
      @return the priority */
  public int defaultPriority() { return 0; }

  /** Structural: {@link Ops#equal}. */
  @Override public final boolean equals(Object o) { return Ops.equal(this, o); }

  /** Consistent with {@link #equals}: {@link Ops#hash}. */
  @Override public final int hashCode() { return Ops.hash(this); }

  /** As a literal: {@code position(1.0, 2.0)}, {@code stop} ({@link Text#literal}). */
  @Override public final String toString() { return Text.literal(this); }
}
