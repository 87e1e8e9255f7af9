package jsref.runtime;

import java.io.BufferedReader;
import java.io.File;
import java.io.FileOutputStream;
import java.io.InputStreamReader;
import java.io.OutputStreamWriter;
import java.io.PrintStream;
import java.io.Writer;
import java.net.InetAddress;
import java.net.ServerSocket;
import java.net.Socket;
import java.net.URL;
import java.net.URLClassLoader;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Base64;
import java.util.List;
import java.util.stream.Stream;
import javax.tools.JavaCompiler;
import javax.tools.ToolProvider;

/** The batch server: many runs of {@link Main}, one after another, in one
    warm JVM (scripts/jade-serve; docs/jade.md, "Many programs in one JVM").
    Starting a JVM, JADE and javac costs seconds a program; here each run
    still boots its own fresh JADE main container (a new platform on a new
    port), creates its agents through JADE and runs them on JADE's threads,
    and the container is killed when the run ends, before the next boots; only the JVM, the JIT's
    work and the Java compiler are shared. Each program's classes are loaded
    by a class loader of their own (every program's classes are in package
    {@code jsgen}), and compiled in this JVM by the JDK's compiler when not
    cached.

    <p>{@code scripts/jade-run}, when {@code JSREF_JADE_SERVER} names the
    port, sends its run here instead of starting a JVM: one connection a
    run, a request of lines (each field base64, UTF-8)
    <pre>
    cwd DIR          the directory the run's relative paths are from
    out FILE         where the program's log goes (its stdout)
    err FILE         where its errors go (its stderr)
    classes DIR      the program's compiled classes
    javac SRC        (optional) compile SRC's .java files into DIR first
    arg A            Main's arguments, in order (repeated)
    run
    </pre>
    answered by one line {@code exit N} (N as {@link Main#main}'s status; 2
    when javac fails), or {@code retry} when the harness failed inside (an
    exception out of {@code Main.run}, which in this JVM may be JADE's worn
    state rather than the program): the client then makes the run in a JVM
    of its own. Runs are served one at a time; after {@code --runs} of them
    (default 40), or a {@code retry}, the server deletes its port file and
    stops, and scripts/jade-serve starts a fresh one. A run that has not
    ended after {@code --limit} seconds halts the server with status 3 (its
    JADE threads cannot be stopped): the client then sees the connection
    close, and later runs fall back to a JVM of their own.

    <p>Runs with two containers are not served ({@code scripts/jade-run}
    keeps them in JVMs of their own): JADE's IMTP keeps one command
    dispatcher a JVM, and once a platform has run and shut down in this JVM,
    a later platform manager is not its object 0, which a peripheral
    container asks for when it joins ("No skeleton for object-id 0"), even
    with no other platform left.

    <pre>java -cp RUNTIME:JADE jsref.runtime.Batch --port-file F [--limit S] [--runs N]</pre> */
public final class Batch {
  private Batch() {}

  /** Serves runs (see above). @param argv {@code --port-file F [--limit S] [--runs N]}
      @throws Exception if the server's socket fails */
  public static void main(String[] argv) throws Exception {
    String portFile = null;
    long limit = 120;
    int runs = 40;
    for (int i = 0; i + 1 < argv.length; i += 2) {
      switch (argv[i]) {
        case "--port-file" -> portFile = argv[i + 1];
        case "--limit" -> limit = Long.parseLong(argv[i + 1]);
        case "--runs" -> runs = Integer.parseInt(argv[i + 1]);
        default -> { System.err.println("jsref batch: error: unknown option " + argv[i]); System.exit(1); }
      }
    }
    Main.quietLogging();
    ServerSocket server = new ServerSocket(0, 8, InetAddress.getLoopbackAddress());
    if (portFile != null) {
      Path tmp = Path.of(portFile + ".tmp");
      Files.writeString(tmp, Integer.toString(server.getLocalPort()));
      Files.move(tmp, Path.of(portFile), java.nio.file.StandardCopyOption.ATOMIC_MOVE);
    } else System.out.println(server.getLocalPort());
    final long limitMs = limit * 1000;
    PrintStream serverErr = System.err;
    for (int served = 0; ; ) {
      try (Socket s = server.accept()) {
        s.setSoTimeout(30_000);
        BufferedReader in = new BufferedReader(new InputStreamReader(s.getInputStream(), StandardCharsets.UTF_8));
        Writer w = new OutputStreamWriter(s.getOutputStream(), StandardCharsets.UTF_8);
        int code;
        try {
          code = serve(in, limitMs, serverErr);
        } catch (Exception e) {
          serverErr.println("jsref batch: error: " + e);
          code = 2;
        }
        System.setErr(serverErr);
        // JADE is not made for many platforms one after another in a JVM
        // (its Runtime restarts the same timer thread object when a platform
        // boots after the last ended, which now and then fails, and each
        // platform leaves threads behind): after --runs runs, or when the
        // harness failed inside (it may be JADE's state, not the program), this server
        // stops and scripts/jade-serve starts another; a failed run is
        // made again by scripts/jade-run in a JVM of its own ("retry")
        boolean last = ++served >= runs || code == RETRY;
        if (last && portFile != null) Files.deleteIfExists(Path.of(portFile));
        w.write(code == RETRY ? "retry\n" : "exit " + code + "\n");
        w.flush();
        if (last) {
          s.close();
          server.close();
          System.out.flush();
          System.err.flush();
          Runtime.getRuntime().halt(0);
        }
      }
    }
  }

  /** The run failed inside the harness: made again in a JVM of its own. */
  private static final int RETRY = -1;

  private static String decode(String field) {
    return new String(Base64.getDecoder().decode(field), StandardCharsets.UTF_8);
  }

  /** One request: read it, compile if asked, run, clean up. */
  private static int serve(BufferedReader in, long limitMs, PrintStream serverErr) throws Exception {
    String cwd = null, outFile = null, errFile = null, classes = null, javac = null;
    List<String> args = new ArrayList<>();
    for (String line; (line = in.readLine()) != null && !line.equals("run"); ) {
      int sp = line.indexOf(' ');
      String key = sp < 0 ? line : line.substring(0, sp), val = sp < 0 ? "" : decode(line.substring(sp + 1));
      switch (key) {
        case "cwd" -> cwd = val;
        case "out" -> outFile = val;
        case "err" -> errFile = val;
        case "classes" -> classes = val;
        case "javac" -> javac = val;
        case "arg" -> args.add(val);
        default -> throw new IllegalArgumentException("unknown request line " + key);
      }
    }
    if (cwd == null || outFile == null || errFile == null || classes == null)
      throw new IllegalArgumentException("incomplete request");
    try (PrintStream out = new PrintStream(new FileOutputStream(outFile), false, StandardCharsets.UTF_8);
         PrintStream err = new PrintStream(new FileOutputStream(errFile), true, StandardCharsets.UTF_8)) {
      long tc = System.nanoTime();
      boolean compiled = javac == null || compile(Path.of(javac), Path.of(classes), err);
      if (javac != null) serverErr.printf("jsref batch: javac %.0f ms%n", (System.nanoTime() - tc) / 1e6);
      if (!compiled) {
        err.println("jade-run: error: javac failed on the generated sources");
        return 2;
      }
      // the run's relative paths (events, trace) are the client's
      String[] argv = args.toArray(new String[0]);
      for (int i = 0; i < argv.length; i++) {
        String a = argv[i];
        if ((a.equals("--events") || a.equals("--trace")) && i + 1 < argv.length) {
          argv[i + 1] = resolve(cwd, argv[i + 1]);
          i++;
        } else if (a.startsWith("--events=") || a.startsWith("--trace=")) {
          int eq = a.indexOf('=');
          argv[i] = a.substring(0, eq + 1) + resolve(cwd, a.substring(eq + 1));
        }
      }
      System.setErr(err);
      Main.lastContainer = null;
      Messaging.forgetRuns();
      Thread watchdog = new Thread(() -> {
        try {
          Thread.sleep(limitMs);
          serverErr.println("jsref batch: a run took more than " + limitMs / 1000 + " s: the server stops");
          err.println("jsref batch: error: the run took more than " + limitMs / 1000 + " s");
          err.flush();
          Runtime.getRuntime().halt(3);
        } catch (InterruptedException e) { /* the run ended */ }
      }, "jsref-batch-watchdog");
      watchdog.setDaemon(true);
      watchdog.start();
      int code;
      try (URLClassLoader loader = new URLClassLoader(new URL[] { new File(classes).toURI().toURL() },
                                                      Batch.class.getClassLoader())) {
        long t0 = System.nanoTime();
        try {
          code = Main.run(argv, out, loader, classes);
        } catch (Main.Stop st) {
          out.flush();
          err.println(st.getMessage());
          code = 1;
        } catch (Throwable t) {
          out.flush();
          t.printStackTrace(serverErr);
          code = RETRY;
        } finally {
          out.flush();
          long t1 = System.nanoTime();
          shutDown();
          serverErr.printf("jsref batch: run %.0f ms, %d threads%n", (t1 - t0) / 1e6, Thread.activeCount());
        }
      } finally {
        watchdog.interrupt();
      }
      return code;
    }
  }

  private static String resolve(String cwd, String p) {
    Path q = Path.of(p);
    return q.isAbsolute() ? p : Path.of(cwd).resolve(q).toString();
  }

  /** Kill the run's main container, which shuts its platform down, and
      wait for it, so that platforms of this JVM never overlap (JADE's
      {@code Runtime} is one a JVM: overlapping shutdowns stopped its shared
      timer under a platform still running, and left the AMS and DF threads
      of the old ones behind). JADE shuts no container down before it is
      3 s old ({@code AgentContainerImpl.checkCreationTime} sleeps until
      then), which was most of a run: the run has ended, every agent is
      idle or stopped and no message is on its way, so its creation time is
      set back first. */
  private static void shutDown() {
    jade.wrapper.ContainerController cc = Main.lastContainer;
    Main.lastContainer = null;
    if (cc == null) return;
    try {
      java.lang.reflect.Field impl = jade.wrapper.ContainerController.class.getDeclaredField("myImpl");
      impl.setAccessible(true);
      Object container = impl.get(cc);
      java.lang.reflect.Field created = container.getClass().getDeclaredField("creationTime");
      created.setAccessible(true);
      created.setLong(container, 0L);
    } catch (ReflectiveOperationException | RuntimeException e) {
      /* then JADE waits its 3 s */
    }
    try {
      cc.kill();
    } catch (Exception e) {
      /* already gone */
    }
  }

  private static JavaCompiler compiler;
  /** One file manager for every compilation: the class path's jars and the
      JDK's modules are opened and indexed once. */
  private static javax.tools.StandardJavaFileManager files;

  /** javac -Xlint:all -encoding UTF-8, in this JVM, into a fresh folder
      moved to {@code dest} (another run may have made it meanwhile). */
  private static boolean compile(Path src, Path dest, PrintStream err) throws Exception {
    if (Files.isDirectory(dest)) return true;
    if (compiler == null) {
      compiler = ToolProvider.getSystemJavaCompiler();
      files = compiler.getStandardFileManager(null, null, StandardCharsets.UTF_8);
    }
    List<java.io.File> sources;
    try (Stream<Path> w = Files.walk(src)) {
      sources = w.filter(p -> p.toString().endsWith(".java")).sorted().map(Path::toFile).toList();
    }
    Path work = dest.resolveSibling("." + dest.getFileName() + ".batch" + ProcessHandle.current().pid());
    Files.createDirectories(work);
    List<String> opts = new ArrayList<>(List.of("-Xlint:all", "-proc:none", "-encoding", "UTF-8", "-d", work.toString(),
        "-cp", System.getProperty("java.class.path")));
    java.io.PrintWriter ew = new java.io.PrintWriter(new OutputStreamWriter(err, StandardCharsets.UTF_8), true);
    boolean ok = compiler.getTask(ew, files, null, opts, null, files.getJavaFileObjectsFromFiles(sources)).call();
    ew.flush();
    if (!ok) { deleteTree(work); return false; }
    try {
      Files.move(work, dest, java.nio.file.StandardCopyOption.ATOMIC_MOVE);
    } catch (java.io.IOException e) {
      deleteTree(work);   // another run won
    }
    return Files.isDirectory(dest);
  }

  private static void deleteTree(Path p) throws java.io.IOException {
    if (!Files.exists(p)) return;
    try (Stream<Path> w = Files.walk(p)) {
      for (Path q : w.sorted(java.util.Comparator.reverseOrder()).toList()) Files.deleteIfExists(q);
    }
  }
}
