package jsbench;

import jade.core.Profile;
import jade.core.ProfileImpl;
import jade.wrapper.AgentController;
import jade.wrapper.ContainerController;

import javax.management.NotificationEmitter;
import java.lang.management.GarbageCollectorMXBean;
import java.lang.management.ManagementFactory;
import java.lang.management.MemoryMXBean;
import java.lang.management.MemoryUsage;
import java.net.ServerSocket;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import java.util.Map;
import java.util.logging.Handler;
import java.util.logging.Level;
import java.util.logging.Logger;

/**
 * Host side of the baseline: boots a JADE main container in this JVM, starts
 * one PerceptAgent and notifies percepts to it through the O2A interface.
 *
 *   steady N [batch]          host notifies batches of `batch` (1024) and waits until
 *                             each batch is handled, until N percepts are handled
 *   flood N mode cap window   host notifies N percepts as fast as it can; mode
 *                             "before": the agent's transfer is held until all N are
 *                             in the O2A queue; "concurrent": the agent drains while
 *                             the host notifies. Stops after `cap` seconds if not done.
 *   sweep n1,n2,...           "before" floods of each size, drained to the end: the
 *                             drain time as a function of the backlog
 * Option (any position): put=controller (default: AgentController.putO2AObject, the
 * host API), put=direct (Agent.putO2AObject), put=control (a ConcurrentLinkedQueue
 * and the same O2A-manager restart: JADE's scheduler, no O2A list), put=native10
 * (Jadescript 1.0's path: each percept becomes an INFORM message posted to the
 * agent's own mailbox, Agent.postMessage, handled first in, first out by a cyclic
 * behaviour with receive(): no priorities).
 */
public final class Bench {
    static Probe probe;
    static AgentController controller;
    static PerceptAgent agent;
    static String put = "controller";
    static String tag = "JADE";
    static String name = null; // overrides the scenario word of the result line
    static long seq; // per-agent arrival counter (R2b), host side

    public static void main(String[] argv) throws Exception {
        Locale.setDefault(Locale.ROOT);
        List<String> args = new ArrayList<>();
        for (String a : argv) {
            if (a.startsWith("put=")) put = a.substring(4);
            else if (a.startsWith("name=")) name = a.substring(5);
            else args.add(a);
        }
        if (put.equals("control")) tag = "CONTROL";
        if (put.equals("native10")) tag = "NATIVE10";
        if (args.get(0).equals("listcost")) { listCost(); return; }
        quietLogging();
        probe = new Probe(put.equals("control"));
        probe.nativeMailbox = put.equals("native10");
        boot();
        Mem.install();
        switch (args.get(0)) {
            case "steady" -> steady(Long.parseLong(args.get(1)), args.size() > 2 ? Integer.parseInt(args.get(2)) : 1024);
            case "flood" -> flood(Long.parseLong(args.get(1)), args.get(2), Double.parseDouble(args.get(3)),
                    Long.parseLong(args.get(4)));
            case "sweep" -> sweep(args.get(1));
            default -> throw new IllegalArgumentException(args.get(0));
        }
        System.out.flush();
        Runtime.getRuntime().halt(0); // JADE's threads need not be shut down cleanly
    }

    // ------------------------------------------------------------------ JADE

    static void quietLogging() {
        Logger root = Logger.getLogger("");
        root.setLevel(Level.WARNING);
        for (Handler h : root.getHandlers()) h.setLevel(Level.WARNING);
    }

    static void boot() throws Exception {
        int port;
        try (ServerSocket s = new ServerSocket(0, 1, java.net.InetAddress.getLoopbackAddress())) {
            port = s.getLocalPort(); // a free port, so parallel runs do not collide on 1099
        }
        jade.core.Runtime rt = jade.core.Runtime.instance();
        rt.setCloseVM(false);
        Profile p = new ProfileImpl();
        p.setParameter(Profile.MAIN, "true");
        p.setParameter(Profile.GUI, "false");
        p.setParameter(Profile.NO_MTP, "true");           // no HTTP MTP (port 7778)
        p.setParameter(Profile.LOCAL_HOST, "127.0.0.1");  // IMTP on loopback only
        p.setParameter(Profile.LOCAL_PORT, Integer.toString(port));
        // JADE 4.3's IMTP is LEAP/JICP; without this its server socket binds every
        // interface (LOCAL_HOST alone only sets the advertised address).
        p.setParameter("jade_imtp_leap_JICP_JICPServer_acceptlocalhostonly", "true");
        p.setParameter(Profile.PLATFORM_ID, "jsbench");
        // JADE writes APDescription.txt at boot; keep it out of the source tree.
        java.io.File dir = new java.io.File(System.getProperty("jsbench.filedir", "target/jade-files"));
        dir.mkdirs();
        p.setParameter(Profile.FILE_DIR, dir.getPath() + java.io.File.separator);
        ContainerController cc = rt.createMainContainer(p);
        controller = cc.createNewAgent("percepts", PerceptAgent.class.getName(), new Object[] { probe });
        controller.start();
        probe.ready.await();
        agent = probe.agent;
        System.out.println("# JADE " + jade.core.Runtime.getVersionInfo() + " main container up, IMTP port "
                + port + " on 127.0.0.1, no MTP, no GUI; host put path: " + put
                + "; Java " + System.getProperty("java.version") + ", " + java.lang.Runtime.getRuntime().availableProcessors()
                + " cpus, max heap " + (java.lang.Runtime.getRuntime().maxMemory() >> 20) + " MB");
    }

    static void notifyPercept(long i) throws Exception {
        Percept p = Percept.make(i);
        Notified n = new Notified(p, p.defaultPriority(), ++seq); // notify(agent, p): default priority
        switch (put) {
            case "controller" -> controller.putO2AObject(n, AgentController.ASYNC);
            case "direct" -> agent.putO2AObject(n, false);
            case "native10" -> agent.postNative(n);
            default -> agent.controlPut(n);
        }
    }

    /** Spin briefly, then yield: on a loaded 2-core machine a pure spin steals the agent's core. */
    static void awaitHandled(long target) {
        int spins = 0;
        while (probe.handled.get() < target) {
            if (++spins < 2_000) Thread.onSpinWait(); else Thread.yield();
        }
    }

    // ---------------------------------------------------------------- steady

    static void steady(long n, int batch) throws Exception {
        // Warm-up (JIT), not measured: 200 batches.
        long i = 0;
        for (int b = 0; b < 200; b++) {
            for (int k = 0; k < batch; k++) notifyPercept(i++);
            awaitHandled(i);
        }
        System.gc();
        Mem.reset();
        long h0 = probe.handled.get(), l0 = probe.loopSteps.get();
        long c0 = processCpuNanos();
        long t0 = System.nanoTime();
        long sent = 0;
        while (sent < n) {
            int b = (int) Math.min(batch, n - sent);
            for (int k = 0; k < b; k++) notifyPercept(i++);
            sent += b;
            awaitHandled(h0 + sent);
        }
        long t1 = System.nanoTime();
        long c1 = processCpuNanos();
        long handled = probe.handled.get() - h0;
        double s = (t1 - t0) / 1e9;
        long loops = probe.loopSteps.get() - l0;
        System.out.printf("# steady: %d percepts in batches of %d (host notifies a batch, waits until handled), "
                + "%d loop-behaviour steps (%.1f percepts per step)%n", handled, batch, loops, (double) handled / loops);
        System.out.printf("# steady: peak live heap after GC %.1f MB; %s%n", Mem.peakLiveMb(), Mem.gcSummary());
        // cpu_seconds: the process's processor time over the measured window,
        // every thread (host, agent, JIT compiler, collector); -1 if unknown
        System.out.printf("%s %s percepts_per_second=%.1f handled=%d seconds=%.3f peak_mb=%.1f cpu_seconds=%.3f%n",
                tag, name == null ? "steady" : name, handled / s, handled, s, Mem.peakMb(),
                c0 < 0 || c1 < 0 ? -1.0 : (c1 - c0) / 1e9);
    }

    /** The JVM process's processor time so far, in nanoseconds, or -1. */
    static long processCpuNanos() {
        java.lang.management.OperatingSystemMXBean os = java.lang.management.ManagementFactory.getOperatingSystemMXBean();
        if (os instanceof com.sun.management.OperatingSystemMXBean sun) return sun.getProcessCpuTime();
        return -1;
    }

    // ----------------------------------------------------------------- flood

    static void flood(long n, String mode, double capSeconds, long window) throws Exception {
        // Warm-up (JIT) with a bounded backlog, not measured.
        long i = 0;
        for (int b = 0; b < 200; b++) {
            for (int k = 0; k < 1024; k++) notifyPercept(i++);
            awaitHandled(i);
        }
        System.gc();
        Mem.reset();
        boolean before = mode.equals("before");
        probe.arm(window, n);
        final long h0 = probe.handled.get(), tr0 = probe.transferred.get();
        final long[] notified = new long[1];
        if (before) probe.gateOpen = false;
        final long t0 = System.nanoTime();
        final long deadline = t0 + (long) (capSeconds * 1e9);
        // Progress sampler: one line a second.
        Thread sampler = new Thread(() -> {
            long next = t0 + 1_000_000_000L;
            while (!Thread.currentThread().isInterrupted()) {
                long now = System.nanoTime();
                if (now < next) { try { Thread.sleep(Math.max(1, (next - now) / 1_000_000)); } catch (InterruptedException e) { return; } continue; }
                next += 1_000_000_000L;
                long tr = probe.transferred.get() - tr0, hd = probe.handled.get() - h0, nt;
                synchronized (notified) { nt = notified[0]; }
                System.out.printf("# flood t=%5.1fs notified=%d transferred=%d handled=%d o2a_backlog=%d heap_mb=%.0f%n",
                        (now - t0) / 1e9, nt, tr, hd, nt - tr, Mem.usedMb());
            }
        }, "progress");
        sampler.setDaemon(true);
        sampler.start();
        long pushed = 0;
        boolean capped = false;
        while (pushed < n) {
            notifyPercept(i++);
            pushed++;
            if ((pushed & 4095) == 0) {
                synchronized (notified) { notified[0] = pushed; }
                if (System.nanoTime() > deadline) { capped = true; break; }
            }
        }
        synchronized (notified) { notified[0] = pushed; }
        long tNotified = System.nanoTime();
        probe.gateOpen = true;
        while (probe.handled.get() - h0 < pushed) {
            if (System.nanoTime() > deadline) { capped = true; break; }
            Thread.sleep(0, 100_000);
        }
        long t1 = System.nanoTime();
        sampler.interrupt();
        long handled = probe.handled.get() - h0, transferred = probe.transferred.get() - tr0;
        double s = (t1 - t0) / 1e9;
        System.out.printf("# flood (%s): host notified %d percepts in %.3f s (%.0f notifies/s)%s%n", mode, pushed,
                (tNotified - t0) / 1e9, pushed / ((tNotified - t0) / 1e9), before ? "; agent transfer held until then" : "");
        System.out.printf("# flood (%s): transferred %d, handled %d in %.3f s%s; peak priority queue %d; peak live heap after GC %.1f MB; %s%n",
                mode, transferred, handled, s, capped ? " -- STOPPED AT THE " + capSeconds + " s CAP, not drained" : "",
                probe.peakPriorityQueue, Mem.peakLiveMb(), Mem.gcSummary());
        String tw = windows(probe.markTransferred, t0, transferred, t1, window);
        String hw = windows(probe.markHandled, t0, handled, t1, window);
        System.out.printf("# flood (%s): transfer (O2A -> priority queue) rate per %d-percept window: %s%n", mode, window, tw);
        System.out.printf("# flood (%s): handled rate per %d-percept window (from the first notify): %s%n", mode, window, hw);
        if (capped) System.out.println("# flood: the last window is partial (cap reached)");
        System.out.printf("%s %s percepts_per_second=%.1f handled=%d seconds=%.3f peak_mb=%.1f windows=%s%n",
                tag, name == null ? "flood" : name, handled / s, handled, s, Mem.peakMb(), hw);
    }

    /** Rates (percepts/s) of successive windows; the last one partial if count is not a multiple. */
    static String windows(long[] marks, long t0, long count, long tEnd, long window) {
        StringBuilder sb = new StringBuilder();
        long prev = t0;
        long full = count / window;
        for (int k = 0; k < full && k < marks.length; k++) {
            if (marks[k] == 0) break;
            if (sb.length() > 0) sb.append(',');
            sb.append(String.format("%.1f", window / ((marks[k] - prev) / 1e9)));
            prev = marks[k];
        }
        long rest = count - full * window;
        if (rest > 0 || full == 0) {
            if (sb.length() > 0) sb.append(',');
            sb.append(String.format("%.1f", rest / ((tEnd - prev) / 1e9)));
        }
        return sb.toString();
    }

    // ----------------------------------------------------------------- sweep

    static void sweep(String sizes) throws Exception {
        long i = 0;
        for (int b = 0; b < 200; b++) {
            for (int k = 0; k < 1024; k++) notifyPercept(i++);
            awaitHandled(i);
        }
        for (String sz : sizes.split(",")) {
            long n = Long.parseLong(sz);
            long h0 = probe.handled.get();
            probe.gateOpen = false;
            long t0 = System.nanoTime();
            for (long k = 0; k < n; k++) notifyPercept(i++);
            long t1 = System.nanoTime();
            probe.gateOpen = true;
            awaitHandled(h0 + n);
            long t2 = System.nanoTime();
            double drain = (t2 - t1) / 1e9;
            System.out.printf("# sweep backlog=%d notify_s=%.3f drain_s=%.3f drain_rate=%.0f/s drain_ns_per_percept=%.0f ns_per_element_shifted=%.3f%n",
                    n, (t1 - t0) / 1e9, drain, n / drain, drain * 1e9 / n, drain * 1e9 / (n * (n - 1) / 2.0));
            System.out.printf("%s sweep backlog=%d drain_seconds=%.3f%n", tag, n, drain);
        }
    }

    // -------------------------------------------------------------- listcost

    /**
     * JADE's o2aQueue is a jade.util.leap.ArrayList over a java.util.ArrayList and
     * getO2AObject() calls remove(0) on it. This times that call alone (no JADE)
     * at several sizes: the cost of shifting the whole backing array by one slot.
     */
    static void listCost() {
        Object x = new Object();
        for (int size : new int[] { 1_024, 100_000, 1_000_000, 10_000_000 }) {
            java.util.ArrayList<Object> list = new java.util.ArrayList<>(size + 1);
            for (int k = 0; k < size; k++) list.add(x);
            int reps = size >= 1_000_000 ? 300 : 20_000;
            long best = Long.MAX_VALUE;
            for (int round = 0; round < 5; round++) {
                long t0 = System.nanoTime();
                for (int r = 0; r < reps; r++) { list.remove(0); list.add(x); }
                best = Math.min(best, System.nanoTime() - t0);
            }
            double ns = (double) best / reps;
            System.out.printf("# listcost: java.util.ArrayList.remove(0) with %,d elements: %.1f us per call (%.2f ns per element shifted) -> at most %.0f dequeues/s%n",
                    size, ns / 1e3, ns / size, 1e9 / ns);
        }
    }

    // ---------------------------------------------------------------- memory

    /** Peak heap: sampled used heap (every 2 ms) and live heap after each GC. */
    static final class Mem {
        static final MemoryMXBean MX = ManagementFactory.getMemoryMXBean();
        static volatile long peakUsed, peakLive;
        static long gcCount0, gcTime0;

        static void install() {
            Thread t = new Thread(() -> {
                for (;;) {
                    long u = MX.getHeapMemoryUsage().getUsed();
                    if (u > peakUsed) peakUsed = u;
                    try { Thread.sleep(2); } catch (InterruptedException e) { return; }
                }
            }, "mem-sampler");
            t.setDaemon(true);
            t.start();
            for (GarbageCollectorMXBean gc : ManagementFactory.getGarbageCollectorMXBeans()) {
                if (!(gc instanceof NotificationEmitter em)) continue;
                em.addNotificationListener((notif, hb) -> {
                    if (!notif.getType().equals("com.sun.management.gc.notification")) return;
                    var info = com.sun.management.GarbageCollectionNotificationInfo.from(
                            (javax.management.openmbean.CompositeData) notif.getUserData());
                    long after = 0, beforeGc = 0;
                    for (Map.Entry<String, MemoryUsage> e : info.getGcInfo().getMemoryUsageAfterGc().entrySet())
                        if (!isNonHeap(e.getKey())) after += e.getValue().getUsed();
                    for (Map.Entry<String, MemoryUsage> e : info.getGcInfo().getMemoryUsageBeforeGc().entrySet())
                        if (!isNonHeap(e.getKey())) beforeGc += e.getValue().getUsed();
                    if (after > peakLive) peakLive = after;
                    if (beforeGc > peakUsed) peakUsed = beforeGc;
                }, null, null);
            }
        }

        static boolean isNonHeap(String pool) {
            return pool.contains("Metaspace") || pool.contains("Code") || pool.contains("Compressed Class");
        }

        static void reset() {
            peakUsed = MX.getHeapMemoryUsage().getUsed();
            peakLive = 0;
            gcCount0 = gcCount();
            gcTime0 = gcTime();
        }

        static long gcCount() { long c = 0; for (var g : ManagementFactory.getGarbageCollectorMXBeans()) c += g.getCollectionCount(); return c; }
        static long gcTime() { long c = 0; for (var g : ManagementFactory.getGarbageCollectorMXBeans()) c += g.getCollectionTime(); return c; }
        static String gcSummary() { return String.format("%d GCs, %.2f s in GC", gcCount() - gcCount0, (gcTime() - gcTime0) / 1e3); }
        static double usedMb() { return MX.getHeapMemoryUsage().getUsed() / 1048576.0; }
        static double peakMb() { return Math.max(peakUsed, MX.getHeapMemoryUsage().getUsed()) / 1048576.0; }
        static double peakLiveMb() { return peakLive / 1048576.0; }
    }
}
