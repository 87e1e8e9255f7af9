import jade.wrapper.ContainerController;
import java.util.List;
import java.util.Locale;
import jsref.runtime.JadescriptAgent;
import jsref.runtime.ProgramInfo;
import jsref.runtime.RunConfig;
import jsref.runtime.Trace;
import jsref.runtime.Variant;

/**
 * The percept throughput of a compiled Jadescript program on JADE (make bench,
 * docs/jade.md "Speed"): bench/programs/percepts.jade compiled by
 * `jadescript-ref compile --target jade`, its Loader agent created in a JADE
 * main container of this JVM and running freely (no lock step, no trace), fed
 * by this host thread through notifyEvent, which hands each percept to JADE's
 * O2A queue (putO2AObject), as the paper's host API does.
 *
 *   steady N   the host notifies a batch of 1,024 percepts and waits until the
 *              agent is idle again (all handled), until N are handled
 *   flood N    the host notifies N percepts as fast as it can while the agent
 *              drains; the rate of each successive window of N/10 handled
 *              percepts shows whether the loop stays flat under the backlog
 *
 * Result lines (parsed by bench/bench.ml):
 *   COMPILED steady percepts_per_second=<f> handled=<n> seconds=<f>
 *   COMPILED flood percepts_per_second=<f> handled=<n> seconds=<f> windows=<r1,r2,...>
 */
public final class CompiledBench {
  static final String[] TYPES = { "falling", "obstacle", "qrCodeRead", "position" };

  public static void main(String[] argv) throws Exception {
    Locale.setDefault(Locale.ROOT);
    ProgramInfo program = (ProgramInfo) Class.forName("jsgen.Program").getDeclaredConstructor().newInstance();
    RunConfig cfg = new RunConfig(program, Variant.REFERENCE, 1, null, 100_000, new Trace(null), false, null, null);
    ContainerController cc = boot();
    cc.createNewAgent("loader", program.agentClass("Loader").getName(), new Object[] { cfg }).start();
    JadescriptAgent agent = cfg.awaitAgent("loader", 60_000);
    if (agent == null) throw new IllegalStateException("JADE did not start the agent");
    long n = Long.parseLong(argv[1]);
    Object[] percepts = new Object[4096];   // built once: the bench measures the loop, not construction
    for (int i = 0; i < percepts.length; i++) percepts[i] = percept(program, i);
    switch (argv[0]) {
      case "steady" -> steady(agent, percepts, n);
      case "flood" -> flood(agent, percepts, n);
      default -> throw new IllegalArgumentException(argv[0]);
    }
    System.out.flush();
    Runtime.getRuntime().halt(0);
  }

  /** The workload of bench/programs/percepts.jade: one of 4 types, a payload mod 1024. */
  static Object percept(ProgramInfo p, long i) {
    String t = TYPES[(int) (i & 3)];
    int k = (int) (i & 1023);
    return switch (t) {
      case "falling" -> p.construct(":0:0", t, List.of());
      case "qrCodeRead" -> p.construct(":0:0", t, List.of("QR" + k));
      default -> p.construct(":0:0", t, List.of(k));
    };
  }

  static void awaitIdle(JadescriptAgent a) {
    int spins = 0;
    while (!a.isIdle()) { if (++spins < 2_000) Thread.onSpinWait(); else Thread.yield(); }
  }

  static void steady(JadescriptAgent a, Object[] ps, long n) {
    long i = 0;
    for (int b = 0; b < 200; b++) {   // warm-up (JIT), not measured
      for (int k = 0; k < 1024; k++) a.notifyEvent(ps[(int) (i++ & 4095)]);
      awaitIdle(a);
    }
    long t0 = System.nanoTime(), sent = 0;
    while (sent < n) {
      int b = (int) Math.min(1024, n - sent);
      for (int k = 0; k < b; k++) a.notifyEvent(ps[(int) (i++ & 4095)]);
      sent += b;
      awaitIdle(a);
    }
    double s = (System.nanoTime() - t0) / 1e9;
    System.out.printf("COMPILED steady percepts_per_second=%.1f handled=%d seconds=%.3f%n", sent / s, sent, s);
  }

  static void flood(JadescriptAgent a, Object[] ps, long n) throws InterruptedException {
    long i = 0;
    for (int b = 0; b < 200; b++) {
      for (int k = 0; k < 1024; k++) a.notifyEvent(ps[(int) (i++ & 4095)]);
      awaitIdle(a);
    }
    long base = a.perceptsDispatched();
    long window = Math.max(1, n / 10);
    long[] marks = new long[10];
    long t0 = System.nanoTime();
    Thread sampler = new Thread(() -> {
      int k = 0;
      while (k < marks.length) {
        long done = a.perceptsDispatched() - base;
        while (k < marks.length && done >= (k + 1) * window) marks[k++] = System.nanoTime();
        Thread.onSpinWait();
      }
    }, "windows");
    sampler.setDaemon(true);
    sampler.start();
    for (long k = 0; k < n; k++) a.notifyEvent(ps[(int) (i++ & 4095)]);
    long tNotified = System.nanoTime();
    awaitIdle(a);
    long t1 = System.nanoTime();
    sampler.join(10_000);
    StringBuilder w = new StringBuilder();
    long prev = t0;
    for (int k = 0; k < marks.length; k++) {
      if (marks[k] == 0) break;
      if (k > 0) w.append(',');
      w.append(String.format("%.0f", window / ((marks[k] - prev) / 1e9)));
      prev = marks[k];
    }
    double s = (t1 - t0) / 1e9;
    System.out.printf("# flood: the host notified %d percepts in %.2f s (%.0f ns each) while the agent drained%n",
        n, (tNotified - t0) / 1e9, (tNotified - t0) / (double) n);
    System.out.printf("COMPILED flood percepts_per_second=%.1f handled=%d seconds=%.3f windows=%s%n",
        n / s, a.perceptsDispatched() - base, s, w);
  }

  /** JADE's main container in this JVM, as the harness boots it (no GUI, no
      MTP, a free port of 127.0.0.1). */
  static ContainerController boot() throws Exception {
    return jsref.runtime.Main.boot();
  }

}
