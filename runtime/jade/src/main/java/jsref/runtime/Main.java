package jsref.runtime;

import jade.core.Profile;
import jade.core.ProfileImpl;
import jade.wrapper.ContainerController;
import java.io.FileOutputStream;
import java.io.IOException;
import java.io.OutputStream;
import java.io.PrintStream;
import java.net.ServerSocket;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.logging.Handler;
import java.util.logging.Level;
import java.util.logging.Logger;
import jsref.values.LiteralError;
import jsref.values.Literals;

/** The host harness: {@code jadescript-ref run} on JADE. It starts a JADE
    main container in this JVM (no GUI, no MTP, a free port on 127.0.0.1),
    creates the agents in order through JADE, applies the events file and
    writes the trace (docs/trace-format.md), driving the agents from its own
    thread as the paper's Android application did.

    <pre>
    java -cp RUNTIME:JADE:GENERATED jsref.runtime.Main --program jsgen.Program
         --agent NAME:TYPE[:ARGS] ... [--events F] [--trace F] [--seed N]
         [--max-steps N] [--variant V] [--fuel N] [--o2a-capacity N]
         [--budget N] [--free]
    </pre>

    <p>By default the agents run in lock step (R6): the harness grants one
    loop iteration at a time, to the agents that are not idle, round robin in
    creation order or in the seeded order of {@code Runtime.order}, and counts
    rules against {@code --max-steps}. With {@code --free} they run on their
    own JADE threads and each {@code run} line waits until all are idle.

    <p>Exit status: 0, or 1 when a run-time error was recorded (D15) or the
    input is bad (one line {@code FILE:LINE:COL: error: message}). */
public final class Main {
  private Main() {}

  /** A bad input: reported as one line, exit status 1. */
  static final class Stop extends Exception {
    private static final long serialVersionUID = 1L;
    Stop(String line) { super(line, null, false, false); }
  }

  private record Spec(String name, String type, List<Object> args) {}

  /** Runs the harness. @param argv the command line */
  public static void main(String[] argv) {
    PrintStream out = new PrintStream(new FileOutputStream(java.io.FileDescriptor.out), false, StandardCharsets.UTF_8);
    int code;
    try {
      code = run(argv, out);
    } catch (Stop s) {
      out.flush();
      System.err.println(s.getMessage());
      code = 1;
    } catch (Throwable t) {
      out.flush();
      System.err.println("jsref: error: " + t);
      code = 2;
    }
    out.flush();
    System.err.flush();
    Runtime.getRuntime().halt(code);   // JADE's threads need not be shut down
  }

  private static String need(String[] a, int i) throws Stop {
    if (i + 1 >= a.length) throw new Stop("error: option " + a[i] + " needs a value");
    return a[i + 1];
  }

  private static int intArg(String opt, String v) throws Stop {
    try { return Integer.parseInt(v); }
    catch (NumberFormatException e) { throw new Stop("error: option " + opt + ": invalid value '" + v + "', expected an integer"); }
  }

  static int run(String[] argv, PrintStream out) throws Exception {
    return run(argv, out, null, null);
  }

  /** One run, as {@link #main} makes it; the batch server ({@link Batch})
      gives each program its own class loader and class path.
      @param argv the command line @param out where the program's log goes
      @param loader the program's classes (null: this class's loader)
      @param programPath the program's classes as a class path entry, for a
             peripheral container's JVM (null: this JVM's class path has them)
      @return the exit status @throws Exception on bad input ({@link Stop}) or JADE's failure */
  static int run(String[] argv, PrintStream out, ClassLoader loader, String programPath) throws Exception {
    String programClass = null;
    List<String> agentSpecs = new ArrayList<>();
    String events = null, tracePath = null, variantName = "reference", level = "full";
    Integer seed = null, capacity = null;
    int maxSteps = 1_000_000, fuel = 100_000, budget = 1;
    boolean free = false, split = false;
    java.util.Set<String> peripheral = new java.util.LinkedHashSet<>();
    java.util.Set<String> seen = new java.util.HashSet<>();
    for (int i = 0; i < argv.length; i++) {
      String a = argv[i];
      String v = null;
      int eq = a.indexOf('=');
      if (a.startsWith("--") && eq > 0) { v = a.substring(eq + 1); a = a.substring(0, eq); }
      boolean takes = !a.equals("--free") && !a.equals("--split");
      if (takes && v == null) { v = need(argv, i); i++; }
      if (!a.equals("--agent") && !seen.add(a)) throw new Stop("error: option '" + a + "' cannot be repeated");
      switch (a) {
        case "--program" -> programClass = v;
        case "--agent" -> agentSpecs.add(v);
        case "--events" -> events = v;
        case "--trace" -> tracePath = v;
        case "--seed" -> seed = intArg(a, v);
        case "--max-steps" -> maxSteps = intArg(a, v);
        case "--variant" -> variantName = v;
        case "--fuel" -> fuel = intArg(a, v);
        case "--o2a-capacity" -> capacity = intArg(a, v);
        case "--budget" -> budget = intArg(a, v);
        case "--free" -> free = true;
        case "--split" -> split = true;
        case "--peripheral" -> peripheral.add(v);
        case "--level" -> level = v;
        default -> throw new Stop("error: unknown option " + a);
      }
    }
    if (programClass == null) throw new Stop("error: no program: give --program CLASS");
    ProgramInfo program;
    try {
      program = (ProgramInfo) Class.forName(programClass, true, loader != null ? loader : Main.class.getClassLoader())
          .getDeclaredConstructor().newInstance();
    } catch (ReflectiveOperationException | ClassCastException | LinkageError e) {
      throw new Stop("error: cannot load the program " + programClass + ": " + e);
    }
    List<Spec> specs = new ArrayList<>();
    for (String s : agentSpecs) specs.add(agentSpec(program, s));
    if (specs.isEmpty()) throw new Stop("error: no agent: give at least one --agent NAME:TYPE");
    java.util.Set<String> names = new java.util.HashSet<>();
    for (Spec s : specs) {
      // JADE: agent names are unique in a platform
      if (!names.add(s.name()))
        throw new Stop("--agent " + s.name() + ":" + s.type() + ": error: there is already an agent "
            + s.name() + " (JADE's agent names are unique)");
    }
    java.util.LinkedHashMap<String, String> agentTypes = new java.util.LinkedHashMap<>();
    for (Spec s : specs) agentTypes.put(s.name(), s.type());
    List<EventsFile.HostEvent> evs = events == null ? List.of() : EventsFile.read(program, agentTypes, events);
    Variant variant = Variant.of(variantName);
    if (variant == null)
      throw new Stop("error: unknown variant " + variantName + " (printed, reference, budgeted, native)");

    OutputStream traceOut = null;
    if (tracePath != null) {
      try { traceOut = new FileOutputStream(tracePath); }
      catch (IOException e) { throw new Stop(tracePath + ":1:1: error: cannot write the trace: " + e.getMessage()); }
    }
    if (!level.equals(TraceFormat.Value.FULL) && !level.equals(TraceFormat.Value.OBSERVABLE))
      throw new Stop("error: option --level: invalid value '" + level + "', expected one of 'full' or 'observable'");
    Trace trace = new Trace(traceOut);
    trace.observable(level.equals(TraceFormat.Value.OBSERVABLE));
    // Two containers (docs/jade.md): --split puts every second agent, in
    // creation order, in a peripheral container of its own JVM;
    // --peripheral NAME puts that one there. The header says so (D47).
    if (split) for (int i = 1; i < specs.size(); i += 2) peripheral.add(specs.get(i).name());
    for (String n : peripheral)
      if (!names.contains(n)) throw new Stop("--peripheral " + n + ": error: there is no agent " + n);
    Map<String, String> containers = new java.util.LinkedHashMap<>();
    for (Spec s : specs) if (peripheral.contains(s.name())) containers.put(s.name(), TraceFormat.Value.PERIPHERAL);
    trace.header(variant.traceName(), budget, capacity, seed, agentTypes, containers, program.behaviours(), program.percepts());
    RunConfig cfg = new RunConfig(program, variant, budget, capacity, fuel, trace, !free, out, System.err);
    cfg.runAgents(names);

    if (free) { cfg.holdCreateMessages(); cfg.limitFreeSteps(maxSteps); }
    ContainerController cc = boot();
    Link link = peripheral.isEmpty() ? null
        : startPeripheral(programClass, programPath, variant, budget, capacity, fuel, trace, names, free, maxSteps);
    List<HostedAgent> agents = new ArrayList<>();
    for (Spec s : specs) {
      if (link != null && peripheral.contains(s.name())) {
        List<Object> lits = new ArrayList<>();
        for (Object v : s.args()) lits.add(v instanceof RoboMe ? "@robome" : jsref.values.Text.literal(v));
        Map<?, ?> r = link.call(new Json.Obj().put(Link.Key.OP, Link.Op.CREATE).put(Link.Key.NAME, s.name())
            .put(Link.Key.TYPE, s.type()).put(Link.Key.ARGS, lits));
        if (r.get(Link.Key.ERROR) instanceof String err) { trace.flush(); throw new Stop("error: " + err); }
        agents.add(new RemoteAgent(link, s.name()));
        continue;
      }
      Object[] args = new Object[s.args().size() + 1];
      args[0] = cfg;
      for (int i = 0; i < s.args().size(); i++) args[i + 1] = s.args().get(i);
      try {
        if (loader == null) cc.createNewAgent(Names.jade(s.name()), program.agentClass(s.type()).getName(), args).start();
        else {
          // JADE loads an agent class by name with its own loader, which
          // does not see a program of the batch server: the instance instead
          jade.core.Agent a = (jade.core.Agent) program.agentClass(s.type()).getDeclaredConstructor().newInstance();
          a.setArguments(args);
          cc.acceptNewAgent(Names.jade(s.name()), a).start();
        }
      } catch (jade.wrapper.StaleProxyException e) {
        // JADE refused the name (Names.jade gives every agent a name of its
        // own, never ams or df, D48: not expected)
        trace.flush();
        throw new Stop("--agent " + s.name() + ":" + s.type() + ": error: JADE cannot create agent "
            + s.name() + " (" + e.getMessage() + ")");
      }
      JadescriptAgent ag = cfg.awaitAgent(s.name(), 60_000);
      if (ag == null) throw new Stop("error: JADE did not start agent " + s.name());
      if (ag.setupError() != null) {
        trace.flush();
        throw new Stop("error: " + ag.setupError());
      }
      agents.add(ag);
    }
    Host h = new Host(agents, seed, maxSteps, !free);
    // D13: what on create sent, once every agent exists, in creation order;
    // running freely, before any agent's loop goes
    for (HostedAgent ag : agents) ag.deliverCreateMessages();
    if (free) {
      cfg.allCreated();
      if (link != null) link.call(new Json.Obj().put(Link.Key.OP, Link.Op.START));
    }
    for (EventsFile.HostEvent e : evs) {
      if (e instanceof EventsFile.Notify n) {
        HostedAgent ag = h.agent(n.agent());
        boolean ok = n.priority() == null ? ag.notifyEvent(n.percept()) : ag.notifyEvent(n.percept(), n.priority());
        if (!ok) {
          out.flush();
          System.err.println("host: agent " + n.agent() + " refused the percept " + jsref.values.Text.literal(n.percept())
              + ": the O2A queue is full (R2d)");
        }
      } else if (e instanceof EventsFile.Put p) {
        if (!h.agent(p.agent()).put(p.value())) {
          // D24: the agent records it as refused, with the object
          out.flush();
          System.err.println("host: agent " + p.agent() + " refused the object " + jsref.values.Text.literal(p.value())
              + ": the O2A queue is full (R2d)");
        }
      } else if (e instanceof EventsFile.Msg m) {
        if (m.duringStep()) h.agent(m.agent()).hostMessageDuringStep(m.performative(), m.content());   // D42
        else h.agent(m.agent()).hostMessage(m.performative(), m.content());
      } else if (e instanceof EventsFile.Run r) {
        h.runRounds(r.rounds());
      } else if (e instanceof EventsFile.RunRules r) {
        h.runRules(r.rules());
      } else {
        h.runUntilIdle();
      }
    }
    h.runUntilIdle();
    for (HostedAgent ag : agents) ag.finishRun();   // D14
    int remoteErrors = 0;
    if (link != null) {
      Map<?, ?> r = link.call(new Json.Obj().put(Link.Key.OP, Link.Op.QUIT));
      remoteErrors = r.get(Link.Key.ERRORS) instanceof Long k ? (int) (long) k : 0;
      link.close();
    }
    trace.close();
    return cfg.errors() + remoteErrors > 0 ? 1 : 0;
  }

  // ---------------------------------------------------------------- two containers

  /** The port of this JVM's main container (a peripheral joins it there). */
  private static int mainPort;
  /** The main container {@link #boot} started last (the batch server kills it after each run). */
  static volatile ContainerController lastContainer;

  /** Start the peripheral container's JVM (jsref.runtime.Peripheral, the
      same class path) and take its connection: its trace events are
      numbered and written here, in the order they come, and deliveries and
      syncs between the two JVMs go over it (docs/jade.md, "Two containers"). */
  private static Link startPeripheral(String programClass, String programPath, Variant variant, int budget, Integer capacity,
                                      int fuel, Trace trace, java.util.Collection<String> runAgents,
                                      boolean free, int maxSteps) throws Exception {
    ServerSocket server = new ServerSocket(0, 1, java.net.InetAddress.getLoopbackAddress());
    List<String> cmd = new ArrayList<>(List.of(
        Path.of(System.getProperty("java.home"), "bin", "java").toString(),
        "-cp", (programPath == null ? "" : programPath + java.io.File.pathSeparator) + System.getProperty("java.class.path"),
        "jsref.runtime.Peripheral",
        "--control", Integer.toString(server.getLocalPort()), "--main-port", Integer.toString(mainPort),
        "--program", programClass, "--variant", variant.traceName(),
        "--budget", Integer.toString(budget), "--fuel", Integer.toString(fuel),
        "--run-agents", String.join(",", runAgents), "--free", free ? "1" : "0",
        "--max-steps", Integer.toString(maxSteps)));
    if (capacity != null) { cmd.add("--o2a-capacity"); cmd.add(Integer.toString(capacity)); }
    Process proc = new ProcessBuilder(cmd).inheritIO().start();
    server.setSoTimeout(60_000);
    java.net.Socket s;
    try {
      s = server.accept();
    } catch (java.net.SocketTimeoutException e) {
      proc.destroyForcibly();
      throw new Stop("error: the peripheral container's JVM did not connect within 60 s");
    } finally {
      server.close();
    }
    Link link = new Link(s);
    Messaging.onRemoteArrival(id -> link.send(new Json.Obj().put(Link.Key.OP, Link.Op.DELIVERED).put(Link.Key.ID, id)));
    link.start("jsref-main-link", m -> {
      if (m.get(Link.Key.EVENT) instanceof Map<?, ?> ev) {
        Json.Obj o = new Json.Obj();
        for (Map.Entry<?, ?> e : ev.entrySet()) o.put((String) e.getKey(), e.getValue());
        trace.event(o);
      } else if (m.get(Link.Key.DELIVERED) instanceof Long id) {
        Messaging.remoteDelivered(id);
      } else if (m.get(Link.Key.SYNC) instanceof Long n) {
        trace.flush();
        link.send(new Json.Obj().put(Link.Key.OP, Link.Op.SYNCED).put(Link.Key.N, n));
      }
    });
    return link;
  }

  // ---------------------------------------------------------------- host

  /** The host's scheduler of agents (Runtime.iterate, run_rounds, run_until_idle). */
  private static final class Host {
    final List<HostedAgent> agents;
    final OcamlRandom rand;
    final int maxSteps;
    final boolean lockStep;
    int steps;

    Host(List<HostedAgent> agents, Integer seed, int maxSteps, boolean lockStep) {
      this.agents = agents;
      this.rand = seed == null ? null : new OcamlRandom(seed);
      this.maxSteps = maxSteps;
      this.lockStep = lockStep;
    }

    HostedAgent agent(String name) {
      for (HostedAgent a : agents) if (a.name().equals(name)) return a;
      throw new IllegalStateException(name);
    }

    int[] order() {
      if (rand != null) return rand.order(agents.size());
      int[] o = new int[agents.size()];
      for (int i = 0; i < o.length; i++) o[i] = i;
      return o;
    }

    void iterate(int i) throws InterruptedException {
      int left = maxSteps - steps;
      if (left > 0) steps += agents.get(i).runIteration(left);
    }

    boolean allIdle() {
      for (HostedAgent a : agents) if (!a.isIdle()) return false;
      return true;
    }

    /** D20: the rounds stop when every agent is idle, at the step limit, or
        after a round that took no step (no seeded order is drawn for a
        round that does not run), as Runtime.run_rounds. */
    void runRounds(long n) throws InterruptedException {
      if (!lockStep) { awaitIdle(); return; }
      for (long r = 0; r < n && steps < maxSteps && !allIdle(); r++) {
        int before = steps;
        for (int i : order()) if (!agents.get(i).isIdle()) iterate(i);
        if (steps == before) break;
      }
    }

    /** {@code {"run": {"rules": n}}} (D23, docs/trace-format.md): n single
        rules, each by the first agent in creation order that is not idle; an
        agent stopped in the middle of an iteration goes on from there at its
        next grant. Running freely there are no single rules: it waits as
        {@code run} does. */
    void runRules(long n) throws InterruptedException {
      if (!lockStep) { awaitIdle(); return; }
      for (long k = 0; k < n && steps < maxSteps; k++) {
        HostedAgent first = null;
        for (HostedAgent a : agents) if (!a.isIdle()) { first = a; break; }
        if (first == null) return;
        int used = first.runIteration(1);
        steps += used;
        if (used == 0) return;
      }
    }

    /** Rounds until every agent is idle (or {@code --max-steps}); then the
        messages held for a behaviour step that did not come arrive, agents in
        the order of their names (D42), and the rounds go on. */
    void runUntilIdle() throws InterruptedException {
      while (true) {
        if (!lockStep) awaitIdle(); else runRounds(Long.MAX_VALUE);
        if (lockStep && steps >= maxSteps) return;
        List<HostedAgent> byName = new ArrayList<>(agents);
        byName.sort(java.util.Comparator.comparing(HostedAgent::name));
        boolean any = false;
        for (HostedAgent a : byName) any |= a.releaseHeld();
        if (!any) return;
      }
    }

    /** Free running: wait until every agent is asleep with nothing ready
        and no message on its way, twice in a row 1 ms apart (at most a minute). */
    void awaitIdle() throws InterruptedException {
      long end = System.currentTimeMillis() + 60_000;
      int quiet = 0;
      while (quiet < 2 && System.currentTimeMillis() < end) {
        boolean q = true;
        for (HostedAgent a : agents) q &= a.isQuiet();
        quiet = q ? quiet + 1 : 0;
        if (quiet < 2) Thread.sleep(1);
      }
    }
  }

  // ---------------------------------------------------------------- JADE

  public static void quietLogging() {
    Logger root = Logger.getLogger("");
    root.setLevel(Level.SEVERE);
    for (Handler hd : root.getHandlers()) hd.setLevel(Level.SEVERE);
  }

  /** A JADE container profile on 127.0.0.1 only: no GUI, no MTP, IMTP on a
      free port accepting local connections only, JADE's files in a fresh
      temporary folder. Shared by the main container and a peripheral one.
      @param files the temporary folder's prefix @return the profile
      @throws Exception if no port or folder can be had */
  static Profile loopbackProfile(String files) throws Exception {
    quietLogging();
    int port;
    try (ServerSocket s = new ServerSocket(0, 1, java.net.InetAddress.getLoopbackAddress())) {
      port = s.getLocalPort();
    }
    Profile p = new ProfileImpl();
    p.setParameter(Profile.GUI, "false");
    p.setParameter(Profile.NO_MTP, "true");
    p.setParameter(Profile.LOCAL_HOST, "127.0.0.1");
    p.setParameter(Profile.LOCAL_PORT, Integer.toString(port));
    p.setParameter("jade_imtp_leap_JICP_JICPServer_acceptlocalhostonly", "true");
    Path dir = Files.createTempDirectory(files);
    dir.toFile().deleteOnExit();
    p.setParameter(Profile.FILE_DIR, dir + java.io.File.separator);
    return p;
  }

  /** A JADE main container in this JVM: no GUI, no MTP, IMTP on a free
      port of 127.0.0.1 only. @return its controller @throws Exception if JADE fails */
  public static ContainerController boot() throws Exception {
    // the free port is found by opening and closing a socket, and another
    // process may take it before JADE binds it: then another port, at most 3 tries
    for (int attempt = 1; ; attempt++) {
      Profile p = loopbackProfile("jsref-jade");
      p.setParameter(Profile.MAIN, "true");
      p.setParameter(Profile.PLATFORM_ID, "jsref");
      jade.core.Runtime rt = jade.core.Runtime.instance();
      rt.setCloseVM(false);
      ContainerController cc = rt.createMainContainer(p);
      if (cc == null && attempt < 3) continue;
      lastContainer = cc;
      mainPort = Integer.parseInt(p.getParameter(Profile.LOCAL_PORT, "0"));
      if (cc == null) throw new IllegalStateException("JADE's main container did not start");
      return cc;
    }
  }

  // ---------------------------------------------------------------- input

  private static Spec agentSpec(ProgramInfo program, String spec) throws Stop {
    int i = spec.indexOf(':');
    if (i < 0) throw new Stop("--agent " + spec + ": error: expected NAME:TYPE[:ARG,...]");
    String name = spec.substring(0, i);
    String rest = spec.substring(i + 1);
    int j = rest.indexOf(':');
    String ty = j < 0 ? rest : rest.substring(0, j);
    String args = j < 0 ? "" : rest.substring(j + 1);
    if (name.isEmpty() || ty.isEmpty()) throw new Stop("--agent " + spec + ": error: expected NAME:TYPE[:ARG,...]");
    // the sender of the host's messages, and the platform's own agents (R5e),
    // in the reference's words; names are compared as written (D48: AMS is
    // not ams, and JADE holds it under another name, Names.jade)
    if (name.equals(Messaging.HOST))
      throw new Stop("--agent " + spec + ": error: the name host is reserved: it is the sender of the host's messages (R5e)");
    if (name.equals(Messaging.AMS) || name.equals(Messaging.DF))
      throw new Stop("--agent " + spec + ": error: the name " + name
          + " is the platform's own agent's (R5e): no agent of the program takes it");
    if (program.agentClass(ty) == null) throw new Stop("--agent " + spec + ": error: there is no agent type " + ty);
    List<Object> values = new ArrayList<>();
    for (String a : Literals.split(args)) {
      if (a.equals("@robome")) { values.add(new RoboMe()); continue; }
      try {
        values.add(Literals.parse(a, program, "--agent"));
      } catch (LiteralError e) {
        throw new Stop("--agent " + spec + ": error: " + e.message());
      }
    }
    return new Spec(name, ty, values);
  }


}
