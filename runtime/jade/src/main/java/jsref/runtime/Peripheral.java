package jsref.runtime;

import jade.core.Profile;
import jade.wrapper.ContainerController;
import java.io.FileOutputStream;
import java.io.PrintStream;
import java.net.InetAddress;
import java.net.Socket;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.LinkedBlockingQueue;
import jsref.values.LiteralError;
import jsref.values.Literals;

/** The peripheral container's JVM of a split run (docs/jade.md, "Two
    containers"): it joins the platform of the harness's main container over
    127.0.0.1 as a JADE peripheral container, connects back to the harness's
    control port, and creates and drives the agents the harness places here,
    on the harness's requests ({@link RemoteAgent}). Its trace events go to the
    harness, which writes the one trace of the run; messages between its agents
    and those of the main container travel through JADE's IMTP.

    <pre>
    java -cp ... jsref.runtime.Peripheral --control PORT --main-port PORT
         --program CLASS --variant V --budget N --fuel N [--o2a-capacity N]
         --run-agents A,B,... --free 0|1 --max-steps N
    </pre>

    Started by {@link Main}; not meant to be started by hand. */
public final class Peripheral {
  private Peripheral() {}

  /** Message ids of this JVM start here, apart from the main JVM's. */
  static final long MESSAGE_ID_BASE = 1L << 40;

  /** Runs the peripheral side. @param argv the command line */
  public static void main(String[] argv) {
    int code = 0;
    try {
      run(argv);
    } catch (Throwable t) {
      System.err.println("jsref: peripheral container: error: " + t);
      code = 2;
    }
    System.out.flush();
    System.err.flush();
    Runtime.getRuntime().halt(code);
  }

  private static void run(String[] argv) throws Exception {
    Map<String, String> o = new HashMap<>();
    for (int i = 0; i + 1 < argv.length; i += 2) o.put(argv[i], argv[i + 1]);
    ProgramInfo program = (ProgramInfo) Class.forName(o.get("--program")).getDeclaredConstructor().newInstance();
    Variant variant = Variant.of(o.get("--variant"));
    Integer capacity = o.containsKey("--o2a-capacity") ? Integer.valueOf(o.get("--o2a-capacity")) : null;
    PrintStream out = new PrintStream(new FileOutputStream(java.io.FileDescriptor.out), true, StandardCharsets.UTF_8);

    Socket s = new Socket(InetAddress.getLoopbackAddress(), Integer.parseInt(o.get("--control")));
    Link link = new Link(s);
    Object syncLock = new Object();
    long[] synced = { 0 };
    long[] asked = { 0 };
    LinkedBlockingQueue<Map<?, ?>> requests = new LinkedBlockingQueue<>();
    link.start("jsref-peripheral-link", m -> {
      Object op = m.get(Link.Key.OP);
      if (Link.Op.SYNCED.equals(op)) {
        synchronized (syncLock) { synced[0] = (Long) m.get(Link.Key.N); syncLock.notifyAll(); }
      } else if (Link.Op.DELIVERED.equals(op)) {
        Messaging.remoteDelivered((Long) m.get(Link.Key.ID));
      } else requests.add(m);
    });

    // The trace goes to the harness; before a message leaves this JVM, the
    // harness has written every event before it (R8: the trace's order).
    Trace trace = Trace.forwardingTo(ev -> link.send(new Json.Obj().put(Link.Key.EVENT, ev)));
    trace.onSync(() -> {
      synchronized (syncLock) {
        long n = ++asked[0];
        link.send(new Json.Obj().put(Link.Key.SYNC, n));
        while (synced[0] < n) {
          try { syncLock.wait(); } catch (InterruptedException e) { Thread.currentThread().interrupt(); return; }
        }
      }
    });
    Messaging.messageIdBase(MESSAGE_ID_BASE);
    Messaging.onRemoteArrival(id -> link.send(new Json.Obj().put(Link.Key.DELIVERED, id)));
    boolean free = "1".equals(o.get("--free"));
    RunConfig cfg = new RunConfig(program, variant, Integer.parseInt(o.get("--budget")), capacity,
        Integer.parseInt(o.get("--fuel")), trace, !free, out, System.err);
    cfg.runAgents(List.of(o.get("--run-agents").split(",", -1)));
    if (free) { cfg.holdCreateMessages(); cfg.limitFreeSteps(Long.parseLong(o.get("--max-steps"))); }

    ContainerController cc = boot(Integer.parseInt(o.get("--main-port")));
    Map<String, JadescriptAgent> agents = new HashMap<>();
    for (;;) {
      Map<?, ?> r = requests.take();
      String op = (String) r.get(Link.Key.OP);
      String name = (String) r.get(Link.Key.NAME);
      JadescriptAgent a = name == null ? null : agents.get(name);
      Json.Obj reply = new Json.Obj().put(Link.Key.REPLY, op);
      switch (op) {
        case Link.Op.CREATE -> {
          List<Object> args = new ArrayList<>();
          args.add(cfg);
          String error = null;
          for (Object lit : (List<?>) r.get(Link.Key.ARGS)) {
            if ("@robome".equals(lit)) { args.add(new RoboMe()); continue; }
            try { args.add(Literals.parse((String) lit, program, "--agent")); }
            catch (LiteralError e) { error = e.message(); }
          }
          if (error == null) {
            cc.createNewAgent(Names.jade(name), program.agentClass((String) r.get(Link.Key.TYPE)).getName(), args.toArray()).start();
            JadescriptAgent ag = cfg.awaitAgent(name, 60_000);
            if (ag == null) error = "JADE did not start agent " + name;
            else if (ag.setupError() != null) error = ag.setupError();
            else agents.put(name, ag);
          }
          trace.flush();
          reply.put(Link.Key.ERROR, error);
        }
        case Link.Op.IDLE -> reply.put(Link.Key.IDLE, a.isIdle());
        case Link.Op.ITERATE -> reply.put(Link.Key.USED, a.runIteration(((Long) r.get(Link.Key.MAX)).intValue()));
        case Link.Op.NOTIFY -> {
          Object p = literal(r.get(Link.Key.PERCEPT), program);
          Object k = r.get(Link.Key.PRIORITY);
          reply.put(Link.Key.OK, k == null ? a.notifyEvent(p) : a.notifyEvent(p, ((Long) k).intValue()));
        }
        case Link.Op.PUT -> reply.put(Link.Key.OK, a.put(literal(r.get(Link.Key.OBJECT), program)));
        case Link.Op.MESSAGE -> {
          String perf = (String) r.get(Link.Key.PERFORMATIVE);
          Object content = literal(r.get(Link.Key.CONTENT), program);
          if (Boolean.TRUE.equals(r.get(Link.Key.DURING))) a.hostMessageDuringStep(perf, content);
          else a.hostMessage(perf, content);
        }
        case Link.Op.RELEASE -> reply.put(Link.Key.QUIET, a.releaseHeld());
        case Link.Op.QUIET -> reply.put(Link.Key.QUIET, a.isQuiet());
        case Link.Op.CREATE_MESSAGES -> a.deliverCreateMessages();
        case Link.Op.START -> cfg.allCreated();
        case Link.Op.FINISH -> a.finishRun();
        case Link.Op.QUIT -> {
          trace.flush();
          out.flush();
          link.send(reply.put(Link.Key.ERRORS, cfg.errors()));
          link.close();
          return;
        }
        default -> reply.put(Link.Key.ERROR, "unknown request " + op);
      }
      trace.flush();
      link.send(reply);
    }
  }

  private static Object literal(Object lit, ProgramInfo program) {
    try { return Literals.parse((String) lit, program, "--peripheral"); }
    catch (LiteralError e) { throw new IllegalArgumentException(e.message()); }
  }

  /** A peripheral container joining the main container at 127.0.0.1:mainPort. */
  private static ContainerController boot(int mainPort) throws Exception {
    Profile p = Main.loopbackProfile("jsref-jade-peripheral");
    p.setParameter(Profile.MAIN, "false");
    p.setParameter(Profile.MAIN_HOST, "127.0.0.1");
    p.setParameter(Profile.MAIN_PORT, Integer.toString(mainPort));
    p.setParameter(Profile.CONTAINER_NAME, "Peripheral-1");
    jade.core.Runtime rt = jade.core.Runtime.instance();
    rt.setCloseVM(false);
    ContainerController cc = rt.createAgentContainer(p);
    if (cc == null) throw new IllegalStateException("JADE's peripheral container did not join the platform");
    return cc;
  }
}
