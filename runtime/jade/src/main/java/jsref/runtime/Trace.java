package jsref.runtime;

import java.io.BufferedOutputStream;
import java.io.IOException;
import java.io.OutputStream;
import java.nio.charset.StandardCharsets;

/** The trace writer (docs/trace-format.md, version 1): one JSON object per
    line, the header first, then every event with its {@code step} number
    (its position in the trace, from 1) put in front of its other fields, as
    the OCaml runtime writes them. Shared by every agent of a run; each write
    is one line, under the writer's lock. Without a file it still numbers the
    events (the step numbers are the same either way). */
public final class Trace {
  private final OutputStream out;
  private final java.util.function.Consumer<Json.Obj> sink;
  private volatile Runnable syncHook;
  private int events;

  /** A trace to a stream, or to nowhere. @param out the stream, or null */
  public Trace(OutputStream out) {
    this.out = out == null ? null : new BufferedOutputStream(out, 1 << 16);
    this.sink = null;
  }

  private Trace(java.util.function.Consumer<Json.Obj> sink) {
    this.out = null;
    this.sink = sink;
  }

  /** A trace whose events (without their step numbers) go to another
      writer: a peripheral container's, sent to the harness, which numbers
      and writes them (docs/jade.md, "Two containers").
      @param sink where each event goes @return the trace */
  public static Trace forwardingTo(java.util.function.Consumer<Json.Obj> sink) { return new Trace(sink); }

  /** What {@link #sync} does besides flushing (a forwarding trace: wait until
      the harness has written every event sent so far). @param hook the action */
  public void onSync(Runnable hook) { syncHook = hook; }

  /** Before a message leaves the agent: every event before it is written. */
  public void sync() {
    flush();
    Runnable h = syncHook;
    if (h != null) h.run();
  }

  /** Write the header line. @param header the header object */
  public synchronized void header(Json.Obj header) {
    line(header.toString());
  }

  /** Write one event: {@code step}, then the fields given.
      @param fields the event's fields, {@code agent} first */
  public synchronized void event(Json.Obj fields) {
    events++;
    if (sink != null) { sink.accept(fields); return; }
    if (out == null) return;
    Json.Obj o = new Json.Obj().put("step", events).putAll(fields);
    line(o.toString());
  }

  /** @return does this trace write its events anywhere (a file, or another
      JVM's harness)? Without, the runtime does not build them. */
  public boolean writes() { return out != null || sink != null; }

  /** @return how many events were written */
  public synchronized int events() { return events; }

  private void line(String s) {
    if (out == null) return;
    try {
      out.write(s.getBytes(StandardCharsets.UTF_8));
      out.write('\n');
    } catch (IOException e) {
      throw new java.io.UncheckedIOException(e);
    }
  }

  /** Flush what was written. */
  public synchronized void flush() {
    if (out == null) return;
    try { out.flush(); } catch (IOException e) { throw new java.io.UncheckedIOException(e); }
  }

  /** Flush and close. */
  public synchronized void close() {
    if (out == null) return;
    try { out.close(); } catch (IOException e) { throw new java.io.UncheckedIOException(e); }
  }
}
