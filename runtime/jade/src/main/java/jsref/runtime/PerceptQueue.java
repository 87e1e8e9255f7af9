package jsref.runtime;

import java.util.ArrayDeque;
import java.util.Iterator;
import java.util.Map;
import java.util.TreeMap;

/** The stable priority queue of R3b: entries leave highest priority first
    and, among equal priorities, smallest seq first. One first-in first-out
    bucket per priority present, in a map ordered from the highest priority
    down (as {@code lib/semantics/pqueue.ml}). Seqs grow with every notify and
    the transfer moves percepts in notify order, so an insert almost always
    goes at the back of its bucket; any other insert is placed after every
    entry of a smaller or equal seq. Not thread-safe: only the agent's thread
    uses it. */
public final class PerceptQueue {
  private final TreeMap<Integer, ArrayDeque<PerceptEntry>> buckets =
      new TreeMap<>(java.util.Comparator.reverseOrder());
  private int size;

  /** Add an entry. @param e the entry */
  public void insert(PerceptEntry e) {
    ArrayDeque<PerceptEntry> b = buckets.computeIfAbsent(e.priority(), k -> new ArrayDeque<>());
    if (b.isEmpty() || b.peekLast().seq() <= e.seq()) b.addLast(e);
    else {
      // rare: place after every entry of seq <= e.seq, keeping the others behind
      ArrayDeque<PerceptEntry> nb = new ArrayDeque<>(b.size() + 1);
      boolean placed = false;
      for (PerceptEntry x : b) {
        if (!placed && x.seq() > e.seq()) { nb.addLast(e); placed = true; }
        nb.addLast(x);
      }
      if (!placed) nb.addLast(e);
      buckets.put(e.priority(), nb);
    }
    size++;
  }

  /** The entry that leaves first, removed; null when empty. @return the entry */
  public PerceptEntry pop() {
    Map.Entry<Integer, ArrayDeque<PerceptEntry>> top = buckets.firstEntry();
    if (top == null) return null;
    PerceptEntry e = top.getValue().pollFirst();
    if (top.getValue().isEmpty()) buckets.remove(top.getKey());
    size--;
    return e;
  }

  /** The entry that leaves first, not removed; null when empty. @return the entry */
  public PerceptEntry peek() {
    Map.Entry<Integer, ArrayDeque<PerceptEntry>> top = buckets.firstEntry();
    return top == null ? null : top.getValue().peekFirst();
  }

  /** @return true when no entry waits */
  public boolean isEmpty() { return size == 0; }

  /** @return how many entries wait */
  public int size() { return size; }

  /** The entries in leaving order (for tests). @return an iterator */
  public Iterator<PerceptEntry> inOrder() {
    java.util.List<PerceptEntry> l = new java.util.ArrayList<>(size);
    for (ArrayDeque<PerceptEntry> b : buckets.values()) l.addAll(b);
    return l.iterator();
  }
}
