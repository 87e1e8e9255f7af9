package jsref.runtime;

import jade.core.AID;
import jade.lang.acl.ACLMessage;
import jade.lang.acl.MessageTemplate;
import java.util.ArrayList;
import java.util.Collections;
import java.util.IdentityHashMap;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;
import jsref.values.Nothing;
import jsref.values.Text;

/** Messages between agents on JADE (R5b, R5e, docs/jade.md): a body's
    sends, held until its rule is over and then sent as ACL messages with
    JADE's {@code send} (in lock step, each delivery awaited); their arrival
    in JADE's message queue of the receiver (its per-receiver seq and the
    {@code deliver} line), the AMS's FAILURE answer to a send to an unknown
    agent ({@code undeliverable}); the host's messages; a handler's pattern
    as JADE's {@link MessageTemplate}, so that JADE's {@code receive} takes the
    first match in arrival order; and, in {@code native}, the percepts moved
    into the message queue. Contents are shared by reference within the JVM
    (a table by message id); the ACL content is the literal, for people
    reading sniffer output, and crosses JVMs (two containers) serialized. */
final class Messaging {
  /** Ids of the runtime's own messages. */
  private static final AtomicLong MESSAGE_IDS = new AtomicLong();
  /** Two containers (docs/jade.md): called with the id of a message that
      arrived here from a sender in another JVM, whose delivery that JVM awaits. */
  private static volatile java.util.function.LongConsumer remoteArrival;
  /** Message contents by message id (shared by reference, as the interpreter does). */
  private static final Map<Long, Object> CONTENTS = new ConcurrentHashMap<>();
  /** Percepts moved to the message queue (native), by message id. */
  private static final Map<Long, PerceptEntry> PERCEPTS = new ConcurrentHashMap<>();
  /** Sends not yet delivered nor refused, by message id. */
  private static final Map<Long, Outgoing> PENDING = new ConcurrentHashMap<>();

  // the runtime's own parameters of an ACL message
  private static final String P_ID = "jsref-id";
  private static final String P_PERF = "jsref-performative";
  private static final String P_FROM = "jsref-from";
  private static final String P_PERCEPT = "jsref-percept";
  private static final String P_SERIAL = "jsref-serialized";
  /** The sender of the host's messages (R5e). */
  private static final String HOST = "host";

  private final JadescriptAgent agent;
  /** The last seq given to a message that arrived (under the message queue's lock). */
  private int msgSeq;
  /** The messages in JADE's queue, as the runtime knows them. */
  final Map<ACLMessage, Arrived> arrivals = Collections.synchronizedMap(new IdentityHashMap<>());
  /** The sends of the running body, and those of {@code on create} (D13). */
  private final ArrayList<Outgoing> outbox = new ArrayList<>();
  private final ArrayList<Outgoing> createOutbox = new ArrayList<>();
  private boolean createDelivered;

  Messaging(JadescriptAgent agent) { this.agent = agent; }

  /** A message that arrived in JADE's queue: a Jadescript message with its
      seq, or a percept moved there (native). */
  record Arrived(Message msg, int seq, PerceptEntry percept) {}

  /** A send waiting for its delivery. */
  static final class Outgoing {
    final long id;
    final String sender;
    final String receiver;
    final Message message;
    final CountDownLatch done = new CountDownLatch(1);
    volatile Object barrier;
    Outgoing(long id, String sender, String receiver, Message message) {
      this.id = id; this.sender = sender; this.receiver = receiver; this.message = message;
    }
  }

  // ------------------------------------------------------------ sending

  /** A body's {@code send}: one message per receiver, sent when the rule is
      over (R5e), or, from {@code on create}, when every agent exists (D13).
      @param performative as written @param content the content
      @param receivers the receivers' names @param fromCreate sent by {@code on create} */
  void post(String performative, Object content, List<String> receivers, boolean fromCreate) {
    String me = agent.getLocalName();
    for (String r : receivers)
      (fromCreate ? createOutbox : outbox).add(
          new Outgoing(MESSAGE_IDS.incrementAndGet(), me, r, new Message(performative, content, me)));
  }

  /** Send what the rule's body sent. */
  void deliverSent() { deliver(outbox); }

  /** Forget what the body sent (the run is over). */
  void dropSent() { outbox.clear(); }

  /** Send what {@code on create} sent (D13), once. */
  void deliverCreateMessages() {
    createDelivered = true;
    deliver(createOutbox);
  }

  /** Running freely: the first iteration sends what {@code on create} sent,
      once every agent of the run exists (D13).
      @throws InterruptedException if interrupted while waiting */
  void deliverCreateMessagesWhenAllExist() throws InterruptedException {
    if (createDelivered) return;
    createDelivered = true;
    agent.cfg.awaitAllCreated();
    deliver(createOutbox);
  }

  /** A message from the host (sender {@code host}, R5e), posted into JADE's
      message queue of this agent. @param performative as written @param content the content */
  void hostMessage(String performative, Object content) {
    Outgoing o = new Outgoing(MESSAGE_IDS.incrementAndGet(), HOST, agent.getLocalName(),
        new Message(performative, content, HOST));
    ACLMessage acl = encode(o, new AID(HOST, AID.ISLOCALNAME));
    agent.postMessage(acl);
  }

  private ACLMessage encode(Outgoing o, AID sender) {
    Message m = o.message;
    int perf = ACLMessage.getInteger(m.performative().toUpperCase(java.util.Locale.ROOT));
    ACLMessage acl = new ACLMessage(perf < 0 ? ACLMessage.UNKNOWN : perf);
    acl.setSender(sender);
    acl.addReceiver(new AID(o.receiver, AID.ISLOCALNAME));
    acl.addUserDefinedParameter(P_ID, Long.toString(o.id));
    acl.addUserDefinedParameter(P_PERF, m.performative());
    acl.addUserDefinedParameter(P_FROM, m.sender());
    acl.setConversationId("jsref-" + o.id);
    acl.setReplyWith("jsref-" + o.id);
    acl.setContent(Text.literal(m.content()));
    CONTENTS.put(o.id, m.content() == null ? Nothing.NOTHING : m.content());
    return acl;
  }

  /** Send each message through JADE, in order; in lock step, wait for each
      to arrive (or for the AMS to refuse it) before the next (R5e, R6). */
  private void deliver(List<Outgoing> out) {
    if (out.isEmpty()) return;
    RunConfig cfg = agent.cfg;
    List<Outgoing> l = new ArrayList<>(out);
    out.clear();
    for (Outgoing o : l) {
      boolean platformAgent = !cfg.isRunAgent(o.receiver)
          && ("ams".equalsIgnoreCase(o.receiver) || "df".equalsIgnoreCase(o.receiver));
      if (!platformAgent) PENDING.put(o.id, o);
      ACLMessage acl = encode(o, agent.getAID());
      if (!cfg.hasAgent(o.receiver) && o.message.content() instanceof java.io.Serializable ser) {
        // to another JVM (two containers): the content travels serialized
        try {
          acl.setContentObject(ser);
          acl.addUserDefinedParameter(P_SERIAL, "1");
        } catch (java.io.IOException e) {
          // not serializable after all: the receiver reads the literal
        }
      }
      cfg.trace.sync();   // two containers: every event before the send is written first
      agent.send(acl);
      if (platformAgent) {
        // JADE's own AMS or DF: delivered, but not to a Jadescript agent (no
        // deliver event); the reference has no such agents (undeliverable)
        CONTENTS.remove(o.id);
        continue;
      }
      if (cfg.lockStep) {
        try {
          if (!o.done.await(20, TimeUnit.SECONDS))
            System.err.println("jsref: no delivery of a message to " + o.receiver + " after 20 s");
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
          return;
        }
        Object barrier = o.barrier;
        if (barrier != null) synchronized (barrier) { /* JADE's postMessage is over */ }
      }
    }
  }

  // ------------------------------------------------------------ arriving

  /** A message is about to join JADE's queue of this agent (JADE's thread of
      the sender, holding the queue's monitor): a message of the run gets its
      seq and its {@code deliver} line; the AMS's FAILURE answer to a send of
      the runtime is its {@code undeliverable} line and is kept out.
      @param m the message @return false to keep it out of the queue */
  boolean arriving(ACLMessage m) {
    RunConfig cfg = agent.cfg;
    if (m.getPerformative() == ACLMessage.FAILURE && m.getSender() != null
        && "ams".equalsIgnoreCase(m.getSender().getLocalName())) {
      Long id = idOf(m.getInReplyTo());
      if (id == null) id = idOf(m.getConversationId());
      Outgoing o = id == null ? null : PENDING.remove(id);
      if (o != null) {
        CONTENTS.remove(o.id);
        cfg.trace.undeliverable(o.sender, o.receiver, o.message.performative(), o.message.content());
        o.barrier = agent.hooks.queue;
        o.done.countDown();
        return false;
      }
      return true;
    }
    String pid = m.getUserDefinedParameter(P_PERCEPT);
    if (pid != null) {
      PerceptEntry e = PERCEPTS.remove(Long.parseLong(pid));
      if (e == null) return false;
      arrivals.put(m, new Arrived(null, 0, e));
      return true;
    }
    String sid = m.getUserDefinedParameter(P_ID);
    if (sid == null) return true;   // not a Jadescript message: JADE keeps it; no handler takes it
    long id = Long.parseLong(sid);
    Object content = CONTENTS.remove(id);
    if (content == null) content = remoteContent(m);
    Message msg = new Message(m.getUserDefinedParameter(P_PERF), content, m.getUserDefinedParameter(P_FROM));
    int seq = ++msgSeq;
    arrivals.put(m, new Arrived(msg, seq, null));
    cfg.trace.deliver(agent.getLocalName(), msg, seq);
    return true;
  }

  /** A message joined the queue: an idle agent wakes (R3e); the sender, in
      lock step, may go on. @param m the message */
  void arrived(ACLMessage m) {
    if (m.getUserDefinedParameter(P_PERCEPT) != null) return;
    String sid = m.getUserDefinedParameter(P_ID);
    if (sid == null) return;
    agent.hooks.wakeUp();
    Outgoing o = PENDING.remove(Long.parseLong(sid));
    if (o != null) {
      o.barrier = agent.hooks.queue;
      o.done.countDown();
    } else if (remoteArrival != null && !HOST.equals(m.getUserDefinedParameter(P_FROM))) {
      remoteArrival.accept(Long.parseLong(sid));
    }
  }

  /** The content of a message from another JVM: the serialized value, else
      the literal read back with the program's ontologies. */
  private Object remoteContent(ACLMessage m) {
    if ("1".equals(m.getUserDefinedParameter(P_SERIAL))) {
      try {
        Object v = m.getContentObject();
        if (v != null) return v;
      } catch (jade.lang.acl.UnreadableException e) {
        // fall back to the literal
      }
    }
    String lit = m.getContent();
    try {
      // (the label names the literal in a parse error, which is not shown)
      return jsref.values.Literals.parse(lit, agent.cfg.program, "a message from another JVM");
    } catch (jsref.values.LiteralError e) {
      return lit;
    }
  }

  private static Long idOf(String s) {
    if (s == null || !s.startsWith("jsref-")) return null;
    try { return Long.parseLong(s.substring(6)); } catch (NumberFormatException e) { return null; }
  }

  // ------------------------------------------------------------ taking (R5b)

  /** Percepts moved to the message queue ({@code native} Transfer), each a
      message to the agent itself, posted through JADE's {@code postMessage}
      (which restarts the blocked behaviours). The caller holds the queue's
      monitor. @param e the percept */
  void postPercept(PerceptEntry e) {
    long id = MESSAGE_IDS.incrementAndGet();
    PERCEPTS.put(id, e);
    ACLMessage m = new ACLMessage(ACLMessage.INFORM);
    m.setSender(agent.getAID());
    m.addReceiver(agent.getAID());
    m.addUserDefinedParameter(P_PERCEPT, Long.toString(id));
    m.setContent(Text.literal(e.percept()));
    agent.postMessage(m);
  }

  /** JADE's {@code receive} with handler h of b as the template: the first
      message (or, for a percept handler, percept) in arrival order that the
      handler takes, removed from JADE's queue; null when none.
      @param b the instance @param h the handler @param percept a percept handler ({@code native})
      @return what it took */
  Arrived take(JadescriptBehaviour b, int h, boolean percept) {
    ACLMessage m = agent.receive(new MessageTemplate(new HandlerMatch(this, b, h, percept)));
    return m == null ? null : arrivals.remove(m);
  }

  /** A handler as a JADE message template. A percept handler (native): the
      percept messages in arrival order; the first whose handler applies is
      taken, and its body has run. A message handler: its performative,
      pattern and {@code when} (R5b). One class for both, as they differ only
      in what they look at. */
  private static final class HandlerMatch implements MessageTemplate.MatchExpression {
    private static final long serialVersionUID = 1L;
    private final transient Messaging messaging;
    private final transient JadescriptBehaviour b;
    private final int h;
    private final boolean percept;
    HandlerMatch(Messaging messaging, JadescriptBehaviour b, int h, boolean percept) {
      this.messaging = messaging; this.b = b; this.h = h; this.percept = percept;
    }
    @Override public boolean match(ACLMessage m) {
      Arrived a = messaging.arrivals.get(m);
      if (a == null) return false;
      if (percept) {
        if (a.percept() == null) return false;
        messaging.agent.body.freshFuel();
        return b.perceptHandler(h, a.percept().percept());
      }
      if (a.msg() == null) return false;
      String perf = b.messagePerformative(h);
      if (perf != null && !perf.equals(a.msg().performative())) return false;
      messaging.agent.body.freshFuel();
      return b.messageAccepts(h, a.msg());
    }
  }

  // ------------------------------------------------------------ two containers

  /** Message ids of this JVM start after {@code base}, so that they differ
      from another JVM's (a split run's peripheral container). @param base the base */
  static void messageIdBase(long base) { MESSAGE_IDS.set(base); }

  /** What to do when a message from another JVM's sender has arrived here
      (tell that JVM, whose sender awaits the delivery). @param f the action, with the message id */
  static void onRemoteArrival(java.util.function.LongConsumer f) { remoteArrival = f; }

  /** A message sent from this JVM arrived in another JVM: its sender may go
      on (lock step, R5e). @param id the message id */
  static void remoteDelivered(long id) {
    Outgoing o = PENDING.remove(id);
    if (o != null) o.done.countDown();
  }

  /** @return is no message of the run on its way, from any agent of this JVM? */
  static boolean noneOnItsWay() { return PENDING.isEmpty(); }
}
