package jsref.values;

import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;

/** A Jadescript list ({@code list of T}): mutable, shared by reference, as in
    the interpreter. Equality and hashing are structural ({@link Ops#equal}). */
public final class JList implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  /** The items. */
  private final ArrayList<Object> items;

  /** An empty list. */
  public JList() { items = new ArrayList<>(); }

  private JList(ArrayList<Object> items) { this.items = items; }

  /** A list of these items, in order.
      @param items the items
      @return the new list */
  public static JList of(Object... items) { return new JList(new ArrayList<>(Arrays.asList(items))); }

  /** A list of a copy of these items.
      @param items the items
      @return the new list */
  public static JList copyOf(List<?> items) { return new JList(new ArrayList<Object>(items)); }

  /** The number of items.
      @return the size */
  public int size() { return items.size(); }

  /** An item (no bounds check beyond Java's: see {@link Ops#index}).
      @param i the index from 0
      @return the item */
  public Object get(int i) { return items.get(i); }

  /** Replaces an item.
      @param i the index from 0
      @param v the new item */
  public void set(int i, Object v) { items.set(i, v); }

  /** Appends an item (for host code).
      @param v the item */
  public void add(Object v) { items.add(v); }

  /** A copy of the items, in order.
      @return a new Java list */
  public List<Object> items() { return new ArrayList<>(items); }

  /** Structural: {@link Ops#equal}. */
  @Override public boolean equals(Object o) { return Ops.equal(this, o); }

  /** Consistent with {@link #equals}. */
  @Override public int hashCode() { return Ops.hash(this); }

  /** As a literal: {@code [1, 2]}. */
  @Override public String toString() { return Text.literal(this); }
}
