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
import jsref.values.Aid;
import jsref.values.Nothing;
import jsref.values.Text;

/** Messages between agents on JADE (R5b, R5e, docs/jade.md): a body's
    sends, held until its rule is over and then sent as ACL messages with
    JADE's {@code send} (in lock step, each delivery awaited; running freely,
    at once, in the order of their lines: {@link #SENDS}); their arrival in
    JADE's message queue of the receiver (its per-receiver seq and the
    {@code deliver} line, or {@code SendInStep} during a behaviour step:
    {@link InStep}); a send to an agent that is not on the platform
    ({@code undeliverable}, and the AMS's FAILURE, which reaches the sender as
    the Jadescript message {@code failure} from {@code ams} with content
    {@code aid("RECEIVER")}, D43); a send to the platform's own {@code ams}
    and {@code df}, which JADE delivers to them (they answer nothing to a
    Jadescript message: docs/jade.md, "What the platform answers"); the
    host's messages, and those held for an agent's next behaviour step
    (D42); a handler's pattern as JADE's {@link MessageTemplate}, so that
    JADE's {@code receive} takes the first match in arrival order; and, in
    {@code native}, the percepts moved into the message queue. Contents are
    shared by reference within the JVM (a table by message id); the ACL
    content is the literal, for people reading sniffer output, and crosses
    JVMs (two containers) serialized. */
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
  /** Sends not yet delivered, nor answered by the AMS's FAILURE, by message id. */
  private static final Map<Long, Outgoing> PENDING = new ConcurrentHashMap<>();
  /** Sends to the platform's own agents, by message id: what an answer of
      theirs answers. */
  private static final Map<Long, Outgoing> TO_PLATFORM = new ConcurrentHashMap<>();
  /** Running freely, a body's send lines and JADE's {@code send} of its
      messages happen holding this, in one JVM: so the messages to one
      receiver enter JADE's delivery queue (one box per receiver, first in
      first out: docs/jade.md) in the order of their lines. */
  static final Object SENDS = new Object();

  // the runtime's own parameters of an ACL message
  private static final String P_ID = "jsref-id";
  private static final String P_PERF = "jsref-performative";
  private static final String P_FROM = "jsref-from";
  private static final String P_PERCEPT = "jsref-percept";
  private static final String P_SERIAL = "jsref-serialized";
  /** An events line's message for the agent's next behaviour step (D42). */
  private static final String P_DURING = "jsref-during-step";
  /** The sender of the host's messages (R5e). */
  static final String HOST = "host";
  /** The platform's own agents (R5e), on every JADE platform. */
  static final String AMS = "ams";
  static final String DF = "df";
  /** The performative of the AMS's answer to a message to an agent that
      is not on the platform, as a Jadescript message (D43). */
  private static final String FAILURE = "failure";

  private final JadescriptAgent agent;
  /** The last seq given to a message that arrived (under the message queue's lock). */
  private int msgSeq;
  /** How many messages and percepts have arrived (under the message queue's lock). */
  private long arrivalCount;
  /** The handlers of a behaviour step look at the arrivals numbered up to
      this: those that had arrived when JADE's scheduler picked the
      behaviour ({@link InStep}). */
  private long visible = Long.MAX_VALUE;
  /** The send whose delivery (or FAILURE) is arriving: its sender may go on. */
  private Outgoing arriving;
  /** The host's messages held for the agent's next behaviour step (D42):
      performative and content. */
  private final java.util.concurrent.ConcurrentLinkedQueue<Object[]> held = new java.util.concurrent.ConcurrentLinkedQueue<>();
  /** The messages in JADE's queue, as the runtime knows them. */
  final Map<ACLMessage, Arrived> arrivals = Collections.synchronizedMap(new IdentityHashMap<>());
  /** The sends of the running body, and those of {@code on create} (D13). */
  private final ArrayList<Outgoing> outbox = new ArrayList<>();
  private final ArrayList<Outgoing> createOutbox = new ArrayList<>();

  Messaging(JadescriptAgent agent) { this.agent = agent; }

  /** A message that arrived in JADE's queue: a Jadescript message with its
      seq, or a percept moved there (native); numbered in arrival order. */
  record Arrived(Message msg, int seq, PerceptEntry percept, long number) {}

  /** Where a message goes: an agent of the run, one of the platform's own
      agents, or nowhere (not on the platform). */
  enum To { RUN, PLATFORM, ABSENT }

  /** A send waiting for its delivery. */
  static final class Outgoing {
    final long id;
    final String sender;
    final String receiver;
    final Message message;
    final CountDownLatch done = new CountDownLatch(1);
    volatile Object barrier;
    To to;
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
    String me = agent.name();
    for (String r : receivers)
      (fromCreate ? createOutbox : outbox).add(
          new Outgoing(MESSAGE_IDS.incrementAndGet(), me, r, new Message(performative, content, me)));
  }

  /** Has the running rule's body sent something? @return true if so */
  boolean hasSent() { return !outbox.isEmpty(); }

  /** In lock step, send what the rule's body sent, each delivery awaited
      (outside the agent's monitors: the message may be for the agent itself). */
  void deliverSent() { deliver(outbox); }

  /** A message made ready for JADE's {@code send}. */
  record Prepared(Outgoing out, ACLMessage acl) {}

  /** Running freely, the first half of sending what the rule's body sent:
      each message encoded and registered, and the {@code undeliverable}
      line of one to an agent not on the platform written. The caller holds
      {@link #SENDS} and the agent's monitors, and has just written the
      rule's lines. @return the messages, for {@link #post} */
  List<Prepared> prepareSent() {
    List<Prepared> l = new ArrayList<>();
    for (Outgoing o : outbox) l.add(prepare(o));
    outbox.clear();
    return l;
  }

  /** Running freely, the second half: the messages go to JADE's
      {@code send}, in order. The caller holds {@link #SENDS} but none of
      the agent's monitors: JADE's {@code send} takes the sender's entry in
      the container's table of agents, which a delivery to the sender holds
      while it waits for the sender's message queue.
      @param l the messages, from {@link #prepareSent} */
  void post(List<Prepared> l) {
    for (Prepared p : l) post(p);
  }

  /** Forget what the body sent (the run is over). */
  void dropSent() { outbox.clear(); }

  /** Send what {@code on create} sent (D13), once: the host calls it for
      every agent in creation order once all exist (in lock step each
      delivery awaited; running freely before any agent's loop starts). */
  void deliverCreateMessages() {
    if (agent.cfg.lockStep) { deliver(createOutbox); return; }
    synchronized (SENDS) {
      List<Outgoing> l = new ArrayList<>(createOutbox);
      createOutbox.clear();
      for (Outgoing o : l) post(prepare(o));
    }
  }

  /** A message from the host (sender {@code host}, R5e), posted into JADE's
      message queue of this agent. @param performative as written @param content the content */
  void hostMessage(String performative, Object content) { hostMessage(performative, content, false); }

  private void hostMessage(String performative, Object content, boolean duringStep) {
    Outgoing o = new Outgoing(MESSAGE_IDS.incrementAndGet(), HOST, agent.name(),
        new Message(performative, content, HOST));
    ACLMessage acl = encode(o, new AID(HOST, AID.ISLOCALNAME));
    if (duringStep) acl.addUserDefinedParameter(P_DURING, "1");
    agent.postMessage(acl);
  }

  /** An events line's message for the agent's next behaviour step (D42):
      held until then. @param performative as written @param content the content */
  void holdForStep(String performative, Object content) { held.add(new Object[] { performative, content }); }

  /** @return does a message wait for the agent's next behaviour step (D42)? */
  boolean holds() { return !held.isEmpty(); }

  /** The held messages reach the agent now: during its behaviour step
      (D42; the agent's own thread), or, when it will not step again, as
      plain messages at the end of the run's rounds (the host's thread).
      @param duringStep during the step @return were there any */
  boolean postHeld(boolean duringStep) {
    boolean any = false;
    for (Object[] m; (m = held.poll()) != null; ) {
      hostMessage((String) m[0], m[1], duringStep);
      any = true;
    }
    return any;
  }

  private ACLMessage encode(Outgoing o, AID sender) {
    Message m = o.message;
    int perf = ACLMessage.getInteger(m.performative().toUpperCase(java.util.Locale.ROOT));
    ACLMessage acl = new ACLMessage(perf < 0 ? ACLMessage.UNKNOWN : perf);
    acl.setSender(sender);
    // the platform's own agents by their JADE names, any other by Names.jade
    // (D48: a name that differs from an agent's only in case is not that agent)
    acl.addReceiver(new AID(o.to == To.PLATFORM ? o.receiver : Names.jade(o.receiver), AID.ISLOCALNAME));
    acl.addUserDefinedParameter(P_ID, Long.toString(o.id));
    acl.addUserDefinedParameter(P_PERF, m.performative());
    acl.addUserDefinedParameter(P_FROM, m.sender());
    acl.setConversationId("jsref-" + o.id);
    acl.setReplyWith("jsref-" + o.id);
    acl.setContent(Text.literal(m.content()));
    CONTENTS.put(o.id, m.content() == null ? Nothing.NOTHING : m.content());
    return acl;
  }

  /** Where a message to this receiver goes (R5e). @param receiver a name @return where */
  private To to(String receiver) {
    if (agent.cfg.isRunAgent(receiver)) return To.RUN;
    if (AMS.equals(receiver) || DF.equals(receiver)) return To.PLATFORM;   // as written (D48)
    return To.ABSENT;
  }

  /** Make one message ready for JADE ({@link #post} sends it). To an agent
      that is not on the platform, the sender's {@code undeliverable} line is
      written here, before JADE's {@code send}, which goes with
      {@link ACLMessage#SYNCH_DELIVERY}: JADE finds the receiver missing
      inside {@code send} and puts the AMS's FAILURE into its delivery queue
      for the sender there, so that the FAILURE's place among the messages
      to the sender is the place of that line. */
  private Prepared prepare(Outgoing o) {
    RunConfig cfg = agent.cfg;
    o.to = to(o.receiver);
    if (o.to == To.PLATFORM) TO_PLATFORM.put(o.id, o); else PENDING.put(o.id, o);
    ACLMessage acl = encode(o, agent.getAID());
    if (o.to == To.RUN && !cfg.hasAgent(o.receiver) && o.message.content() instanceof java.io.Serializable ser) {
      // to another JVM (two containers): the content travels serialized
      try {
        acl.setContentObject(ser);
        acl.addUserDefinedParameter(P_SERIAL, "1");
      } catch (java.io.IOException e) {
        // not serializable after all: the receiver reads the literal
      }
    }
    if (o.to != To.RUN) CONTENTS.remove(o.id);
    if (o.to == To.ABSENT) {
      acl.addUserDefinedParameter(ACLMessage.SYNCH_DELIVERY, "true");
      cfg.trace.undeliverable(o.sender, o.receiver, o.message.performative(), o.message.content());
    }
    return new Prepared(o, acl);
  }

  private void post(Prepared p) {
    agent.cfg.trace.sync();   // two containers: every event before the send is written first
    agent.send(p.acl());
  }

  /** Send each message through JADE, in order; in lock step, wait for each
      to arrive (or for the AMS's FAILURE to arrive) before the next (R5e,
      R6, D44). */
  private void deliver(List<Outgoing> out) {
    if (out.isEmpty()) return;
    List<Outgoing> l = new ArrayList<>(out);
    out.clear();
    for (Outgoing o : l) {
      post(prepare(o));
      if (o.to == To.PLATFORM || !agent.cfg.lockStep) continue;
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

  // ------------------------------------------------------------ arriving

  /** A message is about to join JADE's queue of this agent (JADE's thread of
      the sender, holding the queue's monitor): a Jadescript message, the
      AMS's FAILURE for a message of this agent to an agent that is not on the
      platform (the Jadescript message {@code failure} from {@code ams}, D43),
      or an answer of {@code ams} or {@code df} to a message of this agent,
      gets its seq and its {@code deliver} line ({@link InStep}: now, or at the
      end of the behaviour step in progress); a percept moved to the message
      queue ({@code native}) its number. Any other message JADE keeps, and no
      handler takes it. @param m the message @return false to keep it out of
      the queue (never) */
  boolean arriving(ACLMessage m) {
    RunConfig cfg = agent.cfg;
    arriving = null;
    String pid = m.getUserDefinedParameter(P_PERCEPT);
    if (pid != null) {
      PerceptEntry e = PERCEPTS.remove(Long.parseLong(pid));
      if (e == null) return false;
      arrivals.put(m, new Arrived(null, 0, e, ++arrivalCount));
      return true;
    }
    Message msg;
    boolean duringStep = false;
    String sid = m.getUserDefinedParameter(P_ID);
    if (sid != null) {
      long id = Long.parseLong(sid);
      Object content = CONTENTS.remove(id);
      if (content == null) content = remoteContent(m);
      msg = new Message(m.getUserDefinedParameter(P_PERF), content, m.getUserDefinedParameter(P_FROM));
      duringStep = m.getUserDefinedParameter(P_DURING) != null;
      arriving = PENDING.get(id);
    } else {
      String from = m.getSender() == null ? null : m.getSender().getLocalName();
      Long re = idOf(m.getInReplyTo());
      if (re == null) re = idOf(m.getConversationId());
      if (from == null || re == null) return true;
      Outgoing o;
      if (AMS.equals(from) && m.getPerformative() == ACLMessage.FAILURE
          && (o = PENDING.get(re)) != null && o.to == To.ABSENT) {
        // JADE's MessagingService: the receiver is not on the platform (R5e, D43)
        msg = new Message(FAILURE, new Aid(o.receiver), AMS);
        arriving = o;
      } else if ((o = TO_PLATFORM.get(re)) != null && from.equals(o.receiver)) {
        // an answer of the platform's own agent to a message of this agent
        msg = new Message(ACLMessage.getPerformative(m.getPerformative()).toLowerCase(java.util.Locale.ROOT).replace('-', '_'),
            o.message.content(), o.receiver);
      } else {
        return true;
      }
    }
    int seq = ++msgSeq;
    Arrived a = new Arrived(msg, seq, null, ++arrivalCount);
    arrivals.put(m, a);
    switch (agent.inStep.arriving(a, duringStep)) {
      case SEND -> cfg.trace.deliver(agent.name(), msg, seq, false);
      case SEND_IN_STEP -> cfg.trace.deliver(agent.name(), msg, seq, true);
      case LATER -> { }
    }
    return true;
  }

  /** A message joined the queue: an idle agent wakes (R3e); the sender, in
      lock step, may go on. @param m the message */
  void arrived(ACLMessage m) {
    Arrived a = arrivals.get(m);
    if (a == null || a.msg() == null) return;
    agent.hooks.wakeUp();
    Outgoing o = arriving;
    arriving = null;
    if (o != null && PENDING.remove(o.id) != null) {
      o.barrier = agent.hooks.queue;
      o.done.countDown();
    } else if (o == null && remoteArrival != null && m.getUserDefinedParameter(P_ID) != null
               && !HOST.equals(m.getUserDefinedParameter(P_FROM))) {
      remoteArrival.accept(Long.parseLong(m.getUserDefinedParameter(P_ID)));
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

  /** JADE's scheduler picked a behaviour: its handlers will look at what has
      arrived until now ({@link InStep}). The caller holds the message queue's
      monitor. */
  void pickedNow() { visible = arrivalCount; }

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
      if (a == null || a.number() > messaging.visible) return false;
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

  /** Forget every message of the runs so far (the batch server, before a
      run: a message of an earlier run that never arrived would otherwise
      count as on its way in this one). */
  static void forgetRuns() {
    CONTENTS.clear();
    PERCEPTS.clear();
    PENDING.clear();
    TO_PLATFORM.clear();
    remoteArrival = null;
  }
}
