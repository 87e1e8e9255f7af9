package jsref.runtime;

import java.util.Map;
import jsref.values.Text;

/** The host's handle on an agent of a peripheral container in another JVM
    (docs/jade.md, "Two containers"): each call is a request over the
    {@link Link} to {@link Peripheral}, which makes the same call on the real
    agent there. Values cross as Jadescript literals ({@link Text#literal}),
    read back there with the program's ontologies. */
final class RemoteAgent implements HostedAgent {
  private final Link link;
  private final String name;

  RemoteAgent(Link link, String name) { this.link = link; this.name = name; }

  private Map<?, ?> call(Json.Obj o) {
    try {
      return link.call(o.put(Link.Key.NAME, name));
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new IllegalStateException("interrupted while waiting for the peripheral container");
    }
  }

  @Override public String name() { return name; }

  @Override public boolean isIdle() { return Boolean.TRUE.equals(call(new Json.Obj().put(Link.Key.OP, Link.Op.IDLE)).get(Link.Key.IDLE)); }

  @Override public boolean isQuiet() {
    return Boolean.TRUE.equals(call(new Json.Obj().put(Link.Key.OP, Link.Op.QUIET)).get(Link.Key.QUIET));
  }

  @Override public int runIteration(int maxRules) throws InterruptedException {
    Map<?, ?> r = link.call(new Json.Obj().put(Link.Key.OP, Link.Op.ITERATE).put(Link.Key.MAX, maxRules)
        .put(Link.Key.NAME, name));
    return ((Long) r.get(Link.Key.USED)).intValue();
  }

  @Override public boolean notifyEvent(Object p) {
    return Boolean.TRUE.equals(call(new Json.Obj().put(Link.Key.OP, Link.Op.NOTIFY).put(Link.Key.PERCEPT, Text.literal(p)))
        .get(Link.Key.OK));
  }

  @Override public boolean notifyEvent(Object p, int k) {
    return Boolean.TRUE.equals(call(new Json.Obj().put(Link.Key.OP, Link.Op.NOTIFY).put(Link.Key.PERCEPT, Text.literal(p))
        .put(Link.Key.PRIORITY, k)).get(Link.Key.OK));
  }

  @Override public boolean put(Object o) {
    return Boolean.TRUE.equals(call(new Json.Obj().put(Link.Key.OP, Link.Op.PUT).put(Link.Key.OBJECT, Text.literal(o)))
        .get(Link.Key.OK));
  }

  @Override public void hostMessage(String performative, Object content) {
    call(new Json.Obj().put(Link.Key.OP, Link.Op.MESSAGE).put(Link.Key.PERFORMATIVE, performative)
        .put(Link.Key.CONTENT, Text.literal(content)));
  }

  @Override public void hostMessageDuringStep(String performative, Object content) {
    call(new Json.Obj().put(Link.Key.OP, Link.Op.MESSAGE).put(Link.Key.PERFORMATIVE, performative)
        .put(Link.Key.CONTENT, Text.literal(content)).put(Link.Key.DURING, true));
  }

  @Override public boolean releaseHeld() {
    return Boolean.TRUE.equals(call(new Json.Obj().put(Link.Key.OP, Link.Op.RELEASE)).get(Link.Key.QUIET));
  }

  @Override public void deliverCreateMessages() { call(new Json.Obj().put(Link.Key.OP, Link.Op.CREATE_MESSAGES)); }

  @Override public void finishRun() { call(new Json.Obj().put(Link.Key.OP, Link.Op.FINISH)); }
}
