package jsref.runtime;

import java.io.BufferedReader;
import java.io.IOException;
import java.io.InputStreamReader;
import java.io.OutputStream;
import java.io.UncheckedIOException;
import java.net.Socket;
import java.nio.charset.StandardCharsets;
import java.util.ArrayDeque;
import java.util.Map;
import java.util.function.Consumer;

/** The control link between the host harness (main container's JVM) and a
    peripheral container's JVM: JSON lines over one TCP connection on
    127.0.0.1 (docs/jade.md, "Two containers").

    <p>Each side writes lines and a reader thread dispatches what comes in:
    a reply (field {@code r}) goes to whoever waits for it, in order; every
    other line is a notice handed to the side's handler at once, in the order
    received (trace events, deliveries, sync requests, commands). One
    connection keeps everything in order: the trace lines an iteration wrote
    reach the harness before the reply that ends it. */
final class Link {
  /** The requests of the harness ({@link Main}, {@link RemoteAgent}) and the
      notices between the two JVMs: the values of {@link Key#OP}. */
  static final class Op {
    private Op() {}
    static final String CREATE = "create";            // an agent here: NAME, TYPE, ARGS
    static final String IDLE = "idle";                // is it idle?
    static final String ITERATE = "iterate";          // one iteration, at most MAX rules
    static final String NOTIFY = "notify";            // PERCEPT [PRIORITY]
    static final String PUT = "put";                  // OBJECT
    static final String MESSAGE = "message";          // PERFORMATIVE, CONTENT [DURING]
    static final String RELEASE = "release";          // the held messages arrive now (D42)
    static final String QUIET = "quiet";              // running freely: is it quiet?
    static final String CREATE_MESSAGES = "create_messages";
    static final String START = "start";              // running freely: every agent exists, the loops go (D13)
    static final String FINISH = "finish";
    static final String QUIT = "quit";
    static final String DELIVERED = "delivered";      // a send of the other JVM arrived: ID
    static final String SYNCED = "synced";            // the answer to SYNC: N
  }

  /** The fields of the link's lines. */
  static final class Key {
    private Key() {}
    static final String OP = "op";
    /** A reply: the request it answers. */
    static final String REPLY = "r";
    static final String NAME = "name";
    static final String TYPE = "type";
    static final String ARGS = "args";
    static final String ERROR = "error";
    static final String ERRORS = "errors";
    static final String MAX = "max";
    static final String USED = "used";
    static final String OK = "ok";
    static final String IDLE = "idle";
    static final String PERCEPT = "percept";
    static final String PRIORITY = "priority";
    static final String OBJECT = "object";
    static final String PERFORMATIVE = "performative";
    static final String CONTENT = "content";
    /** A message held for the agent's next behaviour step (D42). */
    static final String DURING = "during";
    /** The answer to QUIET, or to RELEASE (were there any). */
    static final String QUIET = "quiet";
    /** A notice of the peripheral JVM: a trace event, for the harness to number and write. */
    static final String EVENT = "t";
    /** A notice of the peripheral JVM: a send of the harness's JVM arrived (its id). */
    static final String DELIVERED = "delivered";
    static final String ID = "id";
    /** A notice of the peripheral JVM: write every event so far, and answer SYNCED. */
    static final String SYNC = "sync";
    static final String N = "n";
  }

  private final Socket socket;
  private final OutputStream out;
  private final BufferedReader in;
  private final ArrayDeque<Map<?, ?>> replies = new ArrayDeque<>();
  private volatile boolean closed;

  Link(Socket socket) throws IOException {
    this.socket = socket;
    socket.setTcpNoDelay(true);
    this.out = socket.getOutputStream();
    this.in = new BufferedReader(new InputStreamReader(socket.getInputStream(), StandardCharsets.UTF_8));
  }

  /** Start reading: replies are queued, notices go to {@code notices}.
      @param name the reader thread's name @param notices the handler */
  void start(String name, Consumer<Map<?, ?>> notices) {
    Thread t = new Thread(() -> {
      try {
        String line;
        while ((line = in.readLine()) != null) {
          Object j;
          try { j = Json.parse(line); } catch (Json.Error e) { continue; }
          if (!(j instanceof Map<?, ?> m)) continue;
          if (m.containsKey(Key.REPLY)) synchronized (replies) { replies.add(m); replies.notifyAll(); }
          else notices.accept(m);
        }
      } catch (IOException e) {
        // the other side is gone
      } finally {
        closed = true;
        synchronized (replies) { replies.notifyAll(); }
      }
    }, name);
    t.setDaemon(true);
    t.start();
  }

  /** Send one line. @param o the object */
  void send(Json.Obj o) {
    byte[] b = (o.toString() + "\n").getBytes(StandardCharsets.UTF_8);
    synchronized (out) {
      try { out.write(b); out.flush(); } catch (IOException e) { throw new UncheckedIOException(e); }
    }
  }

  /** Send a request and wait for its reply (requests are answered in order).
      @param o the request @return the reply @throws InterruptedException if interrupted */
  Map<?, ?> call(Json.Obj o) throws InterruptedException {
    synchronized (this) {
      send(o);
      synchronized (replies) {
        while (replies.isEmpty()) {
          if (closed) throw new IllegalStateException("the peripheral container's JVM is gone");
          replies.wait();
        }
        return replies.poll();
      }
    }
  }

  void close() {
    try { socket.close(); } catch (IOException e) { /* closing anyway */ }
  }
}
