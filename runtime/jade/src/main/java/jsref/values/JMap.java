package jsref.values;

import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;

/** A Jadescript map ({@code map of K:V}): mutable, shared by reference,
    keeping insertion order, with keys compared structurally
    ({@link Ops#equal}: {@code 1} and {@code 1.0} are the same key, a percept
    is a key, R1c). Setting an existing key keeps the key first inserted and
    its position, as the interpreter's map does. */
public final class JMap implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;

  /** A key under structural equality. */
  private static final class Key implements java.io.Serializable {
    /** The version of the serial form. */
    private static final long serialVersionUID = 1L;
    /** The key. */
    final Object v;
    /** Its structural hash. */
    final int h;
    Key(Object v) { this.v = v; this.h = Ops.hash(v); }
    @Override public boolean equals(Object o) { return o instanceof Key && Ops.equal(v, ((Key) o).v); }
    @Override public int hashCode() { return h; }
  }

  /** The bindings, by structural key, in insertion order. */
  private final LinkedHashMap<Key, Object> table = new LinkedHashMap<>();

  /** An empty map. */
  public JMap() {}

  /** A map from alternating values and keys, in the order the interpreter
      evaluates a map literal ({@code {k1: v1, k2: v2}}: {@code v1, k1, v2, k2}).
      A comparison or hash of a key past {@link Ops#MAX_VISITS} is an error
      at the literal (D37).
      @param at position of the literal
      @param valueKeys {@code v1, k1, v2, k2, ...}
      @return the new map */
  public static JMap ofValueKeyAt(String at, Object... valueKeys) {
    try { return ofValueKey(valueKeys); }
    catch (Ops.TooLarge e) { throw Ops.tooLargeToCompare(at); }
  }

  /** A map literal without a position (host values).
      @param valueKeys value, key, value, key, ...
      @return the map */
  public static JMap ofValueKey(Object... valueKeys) {
    JMap m = new JMap();
    for (int i = 0; i + 1 < valueKeys.length; i += 2) m.put(valueKeys[i + 1], valueKeys[i]);
    return m;
  }

  /** The number of keys.
      @return the size */
  public int size() { return table.size(); }

  /** The value of a key.
      @param k the key
      @return the value, or null when the key is absent */
  public Object get(Object k) { return table.get(new Key(k)); }

  /** Is the key present?
      @param k the key
      @return true if it is */
  public boolean containsKey(Object k) { return table.containsKey(new Key(k)); }

  /** Sets a key's value (a new key goes last).
      @param k the key
      @param v the value */
  public void put(Object k, Object v) { table.put(new Key(k), v); }

  /** The keys, in insertion order (a copy).
      @return a new Java list */
  public List<Object> keys() {
    ArrayList<Object> r = new ArrayList<>(table.size());
    for (Key k : table.keySet()) r.add(k.v);
    return r;
  }

  /** The values, in the keys' insertion order (a copy).
      @return a new Java list */
  public List<Object> values() { return new ArrayList<>(table.values()); }

  /** The bindings in insertion order (a copy).
      @return key-value pairs */
  public List<Map.Entry<Object, Object>> entries() {
    ArrayList<Map.Entry<Object, Object>> r = new ArrayList<>(table.size());
    for (Map.Entry<Key, Object> e : table.entrySet()) r.add(Map.entry(e.getKey().v, e.getValue()));
    return r;
  }

  /** Structural, bindings in order: {@link Ops#equal}. */
  @Override public boolean equals(Object o) { return Ops.equal(this, o); }

  /** Consistent with {@link #equals}. */
  @Override public int hashCode() { return Ops.hash(this); }

  /** As a literal: {@code {"a": 1}}. */
  @Override public String toString() { return Text.literal(this); }
}
