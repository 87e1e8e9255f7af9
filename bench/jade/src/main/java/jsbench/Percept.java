package jsbench;

/**
 * The four percept types of the workload. In Jadescript they would be
 * predicates that `extends percept` with `with priority = N` (R1a); here each
 * one is a record with an integer payload, a type tag and a default priority.
 */
public sealed interface Percept permits Percept.Obstacle, Percept.Position, Percept.Battery, Percept.Tick {
    int payload();
    int tag();
    int defaultPriority();

    record Obstacle(int payload) implements Percept {
        public int tag() { return 0; }
        public int defaultPriority() { return 10; }
    }

    record Position(int payload) implements Percept {
        public int tag() { return 1; }
        public int defaultPriority() { return 8; }
    }

    record Battery(int payload) implements Percept {
        public int tag() { return 2; }
        public int defaultPriority() { return 4; }
    }

    record Tick(int payload) implements Percept {
        public int tag() { return 3; }
        public int defaultPriority() { return 2; }
    }

    /** The i-th percept the host produces: types in rotation, a scrambled payload. */
    static Percept make(long i) {
        int payload = (int) ((i * 2654435761L) >>> 7);
        switch ((int) (i & 3)) {
            case 0: return new Obstacle(payload);
            case 1: return new Position(payload);
            case 2: return new Battery(payload);
            default: return new Tick(payload);
        }
    }
}
