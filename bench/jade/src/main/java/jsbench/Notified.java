package jsbench;

import java.util.Comparator;

/**
 * The entry that notify(agent, p) puts in the O2A queue (R2b): the percept,
 * its effective priority and a per-agent arrival counter. Deliberately a plain
 * class (identity equals/hashCode): JADE's getO2AObject looks every object up
 * in its o2aLocks map, and identity hashing keeps that lookup cheap.
 */
public final class Notified {
    final Percept percept;
    final int priority;
    final long seq;

    Notified(Percept percept, int priority, long seq) {
        this.percept = percept;
        this.priority = priority;
        this.seq = seq;
    }

    /** Highest priority first; equal priorities by arrival (smaller seq first), R3b. */
    static final Comparator<Notified> ORDER = (a, b) ->
        a.priority != b.priority ? Integer.compare(b.priority, a.priority) : Long.compare(a.seq, b.seq);
}
