package jsbench;

import jade.core.Agent;
import jade.core.behaviours.CyclicBehaviour;
import jade.lang.acl.ACLMessage;

import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.PriorityQueue;

/**
 * A JADE agent that runs the paper's Algorithm 1 the way a Jadescript-on-JADE
 * runtime can: JADE's own agent loop (Agent.run / Scheduler) cannot be replaced
 * from user code, so the percept part of the loop is a cyclic behaviour added
 * first. Each of its steps
 *   1. Transfer (R3a): drains getO2AObject() until it returns null, moving each
 *      percept entry into a PriorityQueue (priority desc, seq asc);
 *   2. Dispatch (R3b): removes entries in that order and runs every registered
 *      handler applicable to each one;
 * then JADE's round robin runs the agent's three cyclic behaviours, one step
 * each, before the loop behaviour comes round again.
 * The loop behaviour is the agent's O2A manager, so putO2AObject restarts only
 * it (instead of Scheduler.restartAll on every put).
 */
public final class PerceptAgent extends Agent {
    /** An `on percept` handler of an active behaviour (R4). */
    interface PerceptHandler {
        boolean isApplicableTo(Percept p);
        void execute(Notified n);
    }

    private Probe probe;
    private final PriorityQueue<Notified> priorityQueue = new PriorityQueue<>(1024, Notified.ORDER);
    private final List<PerceptHandler> registeredHandlers = new ArrayList<>();

    /** Agent state the handler updates: a map keyed by payload mod 1024, and per-type counts. */
    final HashMap<Integer, Integer> worldMap = new HashMap<>();
    final long[] perType = new long[4];
    private LoopBehaviour loop;

    @Override
    protected void setup() {
        probe = (Probe) getArguments()[0];
        setEnabledO2ACommunication(true, 0); // 0 = unbounded O2A queue
        loop = new LoopBehaviour();
        if (probe.nativeMailbox) addBehaviour(new MailboxBehaviour());
        else { addBehaviour(loop); setO2AManager(loop); }
        Navigator nav = new Navigator();
        addBehaviour(nav);
        registeredHandlers.add(nav);
        addBehaviour(new Explorer());
        addBehaviour(new Reporter());
        probe.agent = this;
        probe.ready.countDown();
    }

    /** Host side of the control runs: same hand-off as putO2AObject, other queue. */
    void controlPut(Object o) {
        probe.control.offer(o);
        loop.restart();
    }

    /** An INFORM message carrying a notified percept by reference (no serialization:
        host and agent share the JVM, as on Jadescript 1.0's Android container). */
    static final class EventMessage extends ACLMessage {
        private static final long serialVersionUID = 1L;
        final transient Notified n;
        EventMessage(Notified n) { super(ACLMessage.INFORM); this.n = n; }
    }

    /** Host side of put=native10: Jadescript 1.0 turns a native event into an INFORM
        message the agent sends itself; JADE's postMessage appends it to the mailbox
        and restarts every behaviour. */
    void postNative(Notified n) {
        EventMessage m = new EventMessage(n);
        m.setSender(getAID());
        postMessage(m);
    }

    /** Jadescript 1.0's native events: every INFORM in the mailbox, first in, first out,
        through the same handlers (no priority queue). */
    private final class MailboxBehaviour extends CyclicBehaviour {
        MailboxBehaviour() { super(PerceptAgent.this); }

        @Override
        public void action() {
            final Probe pr = probe;
            pr.loopSteps.lazySet(pr.loopSteps.get() + 1);
            if (!pr.gateOpen) { block(); return; }
            long h = pr.handled.get();
            long hMark = nextMark(pr, h);
            final List<PerceptHandler> handlers = registeredHandlers;
            ACLMessage m;
            while ((m = myAgent.receive()) != null) {
                if (!(m instanceof EventMessage e)) continue;
                pr.transferred.lazySet(pr.transferred.get() + 1);
                for (int i = 0, k = handlers.size(); i < k; i++) {
                    PerceptHandler hd = handlers.get(i);
                    if (hd.isApplicableTo(e.n.percept)) hd.execute(e.n);
                }
                ++h;
                pr.handled.lazySet(h);
                if (h == hMark) { mark(pr.markHandled, pr, h); hMark = nextMark(pr, h); }
            }
            block();
        }
    }

    private final class LoopBehaviour extends CyclicBehaviour {
        LoopBehaviour() { super(PerceptAgent.this); }

        @Override
        public void action() {
            final Probe pr = probe;
            pr.loopSteps.lazySet(pr.loopSteps.get() + 1);
            if (!pr.gateOpen) return;
            final boolean control = pr.controlQueue;
            final PriorityQueue<Notified> pq = priorityQueue;
            long t = pr.transferred.get();
            long tMark = nextMark(pr, t);
            // 1. Transfer: every object now in the O2A queue. All objects of this
            //    workload are percept entries; a non-percept would have to be kept
            //    aside (JADE's O2A API cannot put it back at the head), see README.
            for (;;) {
                Object o = control ? pr.control.poll() : myAgent.getO2AObject();
                if (o == null) break;
                pq.add((Notified) o);
                ++t;
                pr.transferred.lazySet(t);
                if (t == tMark) { mark(pr.markTransferred, pr, t); tMark = nextMark(pr, t); }
            }
            if (pq.size() > pr.peakPriorityQueue) pr.peakPriorityQueue = pq.size();
            // 2. Dispatch: highest priority first, ties by seq.
            long h = pr.handled.get();
            long hMark = nextMark(pr, h);
            final List<PerceptHandler> handlers = registeredHandlers;
            Notified n;
            while ((n = pq.poll()) != null) {
                for (int i = 0, k = handlers.size(); i < k; i++) {
                    PerceptHandler hd = handlers.get(i);
                    if (hd.isApplicableTo(n.percept)) hd.execute(n);
                }
                ++h;
                pr.handled.lazySet(h);
                if (h == hMark) { mark(pr.markHandled, pr, h); hMark = nextMark(pr, h); }
            }
            // 3. JADE's scheduler now runs the next behaviour in its ready list.
        }
    }

    private static long nextMark(Probe pr, long count) {
        if (pr.window == Long.MAX_VALUE) return Long.MAX_VALUE;
        long done = (count - pr.base) / pr.window;
        return pr.base + (done + 1) * pr.window;
    }

    private static void mark(long[] marks, Probe pr, long count) {
        int k = (int) ((count - pr.base) / pr.window) - 1;
        if (k >= 0 && k < marks.length) marks[k] = System.nanoTime();
    }

    /** User behaviour 1: a cyclic behaviour with a `do` block and the agent's percept handler. */
    private final class Navigator extends CyclicBehaviour implements PerceptHandler {
        long steps;
        Navigator() { super(PerceptAgent.this); }

        @Override public void action() { steps++; probe.otherSteps.lazySet(probe.otherSteps.get() + 1); }

        // on percept when content matches obstacle(x) or position(x) or battery(x) or tick(x)
        @Override public boolean isApplicableTo(Percept p) { return true; }

        @Override public void execute(Notified n) {
            Percept p = n.percept;
            worldMap.merge(p.payload() & 1023, 1, Integer::sum);
            perType[p.tag()]++;
        }
    }

    /** User behaviours 2 and 3: cyclic, always runnable, trivial `do` blocks. */
    private final class Explorer extends CyclicBehaviour {
        long steps;
        Explorer() { super(PerceptAgent.this); }
        @Override public void action() { steps++; }
    }

    private final class Reporter extends CyclicBehaviour {
        long steps;
        Reporter() { super(PerceptAgent.this); }
        @Override public void action() { steps += 2; }
    }
}
