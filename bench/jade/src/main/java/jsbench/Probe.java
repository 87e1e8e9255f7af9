package jsbench;

import java.util.concurrent.ConcurrentLinkedQueue;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.atomic.AtomicLong;

/**
 * What the host (bench) thread and the agent thread share: progress counters
 * written by the agent only (published with lazySet, a plain store on x86),
 * the time at which each window of percepts was transferred / handled, the
 * gate that holds the transfer back during a "notify everything first" flood,
 * and the queue used by the control runs in place of JADE's O2A queue.
 */
final class Probe {
    final CountDownLatch ready = new CountDownLatch(1);
    volatile PerceptAgent agent;

    /** true: percepts travel through a ConcurrentLinkedQueue instead of O2A (control). */
    final boolean controlQueue;
    final ConcurrentLinkedQueue<Object> control = new ConcurrentLinkedQueue<>();

    /** While false the loop behaviour does not transfer (flood "before" mode). */
    volatile boolean gateOpen = true;
    /** put=native10: percepts arrive as INFORM messages in the mailbox (Jadescript 1.0). */
    volatile boolean nativeMailbox;

    final AtomicLong transferred = new AtomicLong();
    final AtomicLong handled = new AtomicLong();
    final AtomicLong loopSteps = new AtomicLong();
    final AtomicLong otherSteps = new AtomicLong();
    volatile int peakPriorityQueue;

    // Window marks: markX[k] = System.nanoTime() when counter X reached base + (k+1)*window.
    long window = Long.MAX_VALUE;
    long base;
    long[] markTransferred = new long[0];
    long[] markHandled = new long[0];

    Probe(boolean controlQueue) { this.controlQueue = controlQueue; }

    /** Arm the window marks for a run that starts with the counters at their current values. */
    void arm(long window, long expected) {
        long t = transferred.get(), h = handled.get();
        if (t != h) throw new IllegalStateException("arm with percepts in flight");
        int n = (int) (expected / window) + 1;
        markTransferred = new long[n];
        markHandled = new long[n];
        base = h;
        this.window = window;
    }
}
