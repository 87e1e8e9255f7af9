package jsref.runtime;

import jade.core.AID;
import jade.core.Agent;
import jade.core.behaviours.CyclicBehaviour;
import jade.lang.acl.ACLMessage;
import jade.wrapper.ContainerController;
import java.util.ArrayList;
import java.util.Iterator;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.Semaphore;
import java.util.concurrent.TimeUnit;

/** Pins, on plain JADE 4.3 agents (no Jadescript runtime), what the platform
    answers, for R5e and R6 (docs/jade.md, "What the platform answers"):

    <ol>
    <li><b>A message to an agent that is not on the platform.</b> The AMS
    sends the sender a {@code FAILURE}: sender {@code ams}, the reply of the
    message ({@code ACLMessage.createReply}: the same conversation id,
    in-reply-to its reply-with, its ontology and protocol, none of its
    user-defined parameters), language {@code fipa-sl}, content
    {@code ( (action SENDER-AID (ACLMessage) ) (MTS-error RECEIVER-AID (internal-error "Agent not found: ...")) )}
    (JADE's {@code MessagingService}: {@code notifyFailureToSender}, then
    {@code handleNotifyFailure}).
    JADE's delivery threads find the receiver missing after {@code send}
    has returned (the default, asynchronous delivery); with
    {@link ACLMessage#SYNCH_DELIVERY} the sender's own thread finds it
    inside {@code send}; either way the FAILURE then travels as any
    message, through the delivery threads, to the sender's queue.</li>
    <li><b>{@code ams} and {@code df} and a message they cannot read.</b>
    Every behaviour of JADE 4.3's {@code ams} and {@code df} takes only
    messages whose ontology is one of theirs ({@code FIPA-Agent-Management},
    {@code JADE-Agent-Management}, ...), and, but for subscriptions, only
    REQUESTs. A message without their ontology, of any of the 22
    performatives, is never taken: no answer ever comes, and the message
    stays in their queue. Only a REQUEST in their ontology whose content
    they cannot parse is answered, with a {@code NOT_UNDERSTOOD}.</li>
    <li><b>Two senders, one receiver.</b> Within one JVM every message goes
    through JADE's one {@code MessageManager}: a box per receiver, served by
    one delivery thread at a time, first in first out. So the messages to
    one receiver arrive in the order of the {@code send} calls that made
    them, whichever agent sent them: here two senders alternate 500 times,
    each send made after the other's returned, and the receiver gets all
    1,000 in that order.</li>
    </ol>

    <pre>java -cp target/classes:target/test-classes:target/lib/jade-4.3.jar jsref.runtime.JadePlatformAnswers</pre>
    Prints what it saw and "N passed, M failed"; exit 0 when every fact
    above holds (a change of JADE's behaviour fails it). */
public final class JadePlatformAnswers {
  private JadePlatformAnswers() {}

  private static int passed;
  private static int failed;

  private static void check(String what, boolean ok) {
    if (ok) passed++; else { failed++; System.out.println("FAIL: " + what); }
  }

  /** Every message an agent of the test received, with when. */
  record Got(ACLMessage m, long nanos) {}

  static final Map<String, List<Got>> INBOX = new ConcurrentHashMap<>();
  static final Map<String, Agent> AGENTS = new ConcurrentHashMap<>();
  static final CountDownLatch READY = new CountDownLatch(4);

  /** A plain JADE agent that takes every message and records it. */
  public static final class Recorder extends Agent {
    private static final long serialVersionUID = 1L;
    @Override protected void setup() {
      INBOX.put(getLocalName(), java.util.Collections.synchronizedList(new ArrayList<>()));
      addBehaviour(new CyclicBehaviour(this) {
        private static final long serialVersionUID = 1L;
        @Override public void action() {
          ACLMessage m = myAgent.receive();
          if (m == null) { block(); return; }
          INBOX.get(myAgent.getLocalName()).add(new Got(m, System.nanoTime()));
        }
      });
      AGENTS.put(getLocalName(), this);
      READY.countDown();
    }
  }

  /** A message as the Jadescript runtime sends one: no language, no
      ontology, the content a Jadescript literal, a conversation id and a
      reply-with of its own. */
  static ACLMessage jadescriptLike(Agent from, String to, int performative, String tag) {
    ACLMessage m = new ACLMessage(performative);
    m.setSender(from.getAID());
    m.addReceiver(new AID(to, AID.ISLOCALNAME));
    m.setConversationId("conv-" + tag);
    m.setReplyWith("rw-" + tag);
    m.addUserDefinedParameter("jsref-id", tag);
    m.setContent("greeting(\"hi\")");
    return m;
  }

  static List<Got> waitFor(String agent, java.util.function.Predicate<ACLMessage> p, int n, long millis)
      throws InterruptedException {
    long end = System.currentTimeMillis() + millis;
    while (true) {
      List<Got> l = new ArrayList<>();
      synchronized (INBOX.get(agent)) { for (Got g : INBOX.get(agent)) if (p.test(g.m())) l.add(g); }
      if (l.size() >= n || System.currentTimeMillis() > end) return l;
      Thread.sleep(5);
    }
  }

  static String describe(ACLMessage m) {
    StringBuilder b = new StringBuilder();
    b.append("performative=").append(ACLMessage.getPerformative(m.getPerformative()))
        .append(" sender=").append(m.getSender() == null ? null : m.getSender().getLocalName())
        .append(" receivers=");
    for (Iterator<?> it = m.getAllReceiver(); it.hasNext(); ) b.append(((AID) it.next()).getLocalName()).append(' ');
    b.append("language=").append(m.getLanguage()).append(" ontology=").append(m.getOntology())
        .append(" protocol=").append(m.getProtocol())
        .append(" conversation-id=").append(m.getConversationId()).append(" in-reply-to=").append(m.getInReplyTo())
        .append(" user-parameters=").append(m.getAllUserDefinedParameters())
        .append("\n    content=").append(m.getContent());
    return b.toString();
  }

  /** Runs the checks. @param args ignored @throws Exception if JADE fails */
  public static void main(String[] args) throws Exception {
    ContainerController cc = Main.boot();
    for (String n : List.of("probe", "s1", "s2", "r"))
      cc.createNewAgent(n, Recorder.class.getName(), new Object[0]).start();
    check("the agents start", READY.await(30, TimeUnit.SECONDS));
    Agent probe = AGENTS.get("probe");

    // 1. a message to an agent that is not on the platform
    System.out.println("1. INFORM to nobody (not on the platform), from probe:");
    probe.send(jadescriptLike(probe, "nobody", ACLMessage.INFORM, "nobody"));
    int atReturn = INBOX.get("probe").size();
    List<Got> f = waitFor("probe", m -> "conv-nobody".equals(m.getConversationId()), 1, 5000);
    Thread.sleep(300);
    f = waitFor("probe", m -> "conv-nobody".equals(m.getConversationId()), 2, 0);
    for (Got g : f) System.out.println("  " + describe(g.m()));
    check("exactly one answer to a message to nobody", f.size() == 1);
    // Delivery is asynchronous: usually the answer has not arrived when send
    // returns, but a delivery thread may win the race (a loaded machine can
    // pause this thread right after send), so this is shown, not checked.
    System.out.println("  answers already there when send returned: " + atReturn + " (usually 0: asynchronous delivery)");
    if (f.size() == 1) {
      ACLMessage a = f.get(0).m();
      check("it is a FAILURE", a.getPerformative() == ACLMessage.FAILURE);
      check("from ams", a.getSender() != null && a.getSender().getLocalName().equals("ams"));
      check("to the sender", a.getAllReceiver().hasNext() && ((AID) a.getAllReceiver().next()).getLocalName().equals("probe"));
      check("in the message's conversation", "conv-nobody".equals(a.getConversationId()));
      check("in reply to its reply-with", "rw-nobody".equals(a.getInReplyTo()));
      check("language fipa-sl", "fipa-sl".equals(a.getLanguage()));
      check("the user-defined parameters are not copied", a.getUserDefinedParameter("jsref-id") == null);
      String c = a.getContent();
      check("content ( (action SENDER (ACLMessage) ) (MTS-error RECEIVER (internal-error \"Agent not found: ...\")) )",
          c != null && c.startsWith("( (action ( agent-identifier :name probe@") && c.contains("(ACLMessage) ) (MTS-error ( agent-identifier :name nobody@")
              && c.contains(" (internal-error \"Agent not found: ") && c.endsWith("\")) )"));
    }
    // the same with synchronous delivery: the FAILURE is queued inside send
    probe.send(withSynch(jadescriptLike(probe, "nobody2", ACLMessage.INFORM, "nobody2")));
    List<Got> f2 = waitFor("probe", m -> "conv-nobody2".equals(m.getConversationId()), 1, 5000);
    check("with SYNCH_DELIVERY too, one FAILURE from ams",
        f2.size() == 1 && f2.get(0).m().getPerformative() == ACLMessage.FAILURE
            && f2.get(0).m().getSender().getLocalName().equals("ams"));

    // 2. ams and df, every performative, content they cannot read
    System.out.println("2. every performative to ams and df, content greeting(\"hi\"), no language or ontology:");
    String[] perfs = ACLMessage.getAllPerformativeNames();
    for (String to : List.of("ams", "df"))
      for (int p = 0; p < perfs.length; p++) probe.send(jadescriptLike(probe, to, p, to + "-" + p));
    // and a REQUEST in their own ontology that they cannot parse
    for (String to : List.of("ams", "df")) {
      ACLMessage m = jadescriptLike(probe, to, ACLMessage.REQUEST, to + "-fipa");
      m.setLanguage("fipa-sl0");
      m.setOntology("FIPA-Agent-Management");
      probe.send(m);
    }
    Thread.sleep(3000);   // the ams's and df's answers, if any, come within this
    int answers = 0;
    for (String to : List.of("ams", "df"))
      for (int p = 0; p < perfs.length; p++) {
        String tag = to + "-" + p;
        List<Got> l = waitFor("probe", m -> ("conv-" + tag).equals(m.getConversationId()), 1, 0);
        answers += l.size();
        for (Got g : l) System.out.println("  " + perfs[p] + " to " + to + ": " + describe(g.m()));
      }
    System.out.println("  " + 2 * perfs.length + " messages (" + perfs.length + " performatives to each): "
        + answers + " answers");
    check(perfs.length + " performatives", perfs.length == 22);
    check("no answer from ams or df to a message they cannot read, of any performative", answers == 0);
    for (String to : List.of("ams", "df")) {
      List<Got> l = waitFor("probe", m -> ("conv-" + to + "-fipa").equals(m.getConversationId()), 1, 10000);
      for (Got g : l) System.out.println("  REQUEST in FIPA-Agent-Management to " + to + ": " + describe(g.m()));
      check(to + " answers a REQUEST in its ontology that it cannot parse with NOT_UNDERSTOOD",
          l.size() == 1 && l.get(0).m().getPerformative() == ACLMessage.NOT_UNDERSTOOD
              && l.get(0).m().getSender().getLocalName().equals(to));
    }

    // 3. two senders, one receiver: the order of the sends
    System.out.println("3. s1 and s2 send to r in turn, 500 rounds, each send after the other's:");
    Agent s1 = AGENTS.get("s1");
    Agent s2 = AGENTS.get("s2");
    Semaphore turn1 = new Semaphore(1);
    Semaphore turn2 = new Semaphore(0);
    int rounds = 500;
    Thread t1 = new Thread(() -> sendInTurn(s1, turn1, turn2, rounds));
    Thread t2 = new Thread(() -> sendInTurn(s2, turn2, turn1, rounds));
    t1.start(); t2.start(); t1.join(); t2.join();
    List<Got> got = waitFor("r", m -> true, 2 * rounds, 10000);
    List<String> order = new ArrayList<>();
    for (Got g : got) order.add(g.m().getSender().getLocalName() + ":" + g.m().getContent());
    List<String> want = new ArrayList<>();
    for (int i = 0; i < rounds; i++) { want.add("s1:" + i); want.add("s2:" + i); }
    int firstDiff = -1;
    for (int i = 0; i < Math.min(order.size(), want.size()); i++) if (!order.get(i).equals(want.get(i))) { firstDiff = i; break; }
    System.out.println("  r received " + order.size() + " messages; first out of order: "
        + (firstDiff < 0 ? "none" : firstDiff + " (" + order.get(firstDiff) + ")"));
    check("r receives the 1,000 messages in the order of the sends", order.equals(want));

    System.out.println(passed + " passed, " + failed + " failed");
    System.out.flush();
    Runtime.getRuntime().halt(failed == 0 ? 0 : 1);
  }

  static ACLMessage withSynch(ACLMessage m) {
    m.addUserDefinedParameter(ACLMessage.SYNCH_DELIVERY, "true");
    return m;
  }

  static void sendInTurn(Agent s, Semaphore mine, Semaphore other, int rounds) {
    try {
      for (int i = 0; i < rounds; i++) {
        mine.acquire();
        ACLMessage m = new ACLMessage(ACLMessage.INFORM);
        m.setSender(s.getAID());
        m.addReceiver(new AID("r", AID.ISLOCALNAME));
        m.setContent(Integer.toString(i));
        s.send(m);
        other.release();
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }
}
