package jsref.runtime;

import jade.core.Agent;
import jade.core.behaviours.Behaviour;
import jade.lang.acl.ACLMessage;
import jade.wrapper.ContainerController;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;

/** Pins a difference between JADE 4.3 and the rulings (R5d with R5e), on
    plain JADE behaviours: a message that arrives while a behaviour's step
    runs, in a step that ends with {@code block()}. JADE's
    {@code Agent$ActiveLifeCycle.execute} sees the behaviour's restart counter
    changed (the arrival's {@code restartAll}) and leaves it runnable, at its
    place in the ready list; the rulings block it and then wake it, which puts
    it at the end of the ready list. With ready = [X, A, B] and A receiving a
    message during its first step and blocking, JADE steps X A B X A B; the
    rulings give X A B A X B.
    <pre>java -cp target/classes:target/test-classes:target/lib/jade-4.3.jar jsref.runtime.JadeRestartDuringStep</pre>
    Prints JADE's order and the ruling's, and exits 0 when they differ as
    described (the difference is JADE's behaviour, pinned). */
public final class JadeRestartDuringStep {
  private JadeRestartDuringStep() {}

  static final List<String> STEPS = java.util.Collections.synchronizedList(new ArrayList<>());
  static final CountDownLatch DONE = new CountDownLatch(1);

  /** A behaviour that records its steps; A posts a message to its own agent
      and blocks in its first step. */
  static final class Recorder extends Behaviour {
    private static final long serialVersionUID = 1L;
    private final String name;
    private int steps;
    Recorder(String name) { this.name = name; }
    @Override public void action() {
      STEPS.add(name);
      if (STEPS.size() >= 6) { DONE.countDown(); block(); return; }
      if (name.equals("A") && steps++ == 0) {
        ACLMessage m = new ACLMessage(ACLMessage.INFORM);
        m.setSender(myAgent.getAID());
        myAgent.postMessage(m);   // arrives during this step
        block();                  // the step took nothing: it blocks (R5d)
      } else if (name.equals("A")) {
        myAgent.receive();
      }
    }
    @Override public boolean done() { return false; }
  }

  /** The demo agent: X, A, B in that order. */
  public static final class Demo extends Agent {
    private static final long serialVersionUID = 1L;
    @Override protected void setup() {
      addBehaviour(new Recorder("X"));
      addBehaviour(new Recorder("A"));
      addBehaviour(new Recorder("B"));
    }
  }

  /** Runs the demo. @param args ignored @throws Exception if JADE fails */
  public static void main(String[] args) throws Exception {
    ContainerController cc = Main.boot();
    cc.createNewAgent("demo", Demo.class.getName(), new Object[0]).start();
    boolean ok = DONE.await(30, TimeUnit.SECONDS);
    String jade;
    synchronized (STEPS) { jade = String.join(" ", STEPS.subList(0, Math.min(6, STEPS.size()))); }
    String ruling = "X A B A X B";
    System.out.println("JADE 4.3: " + jade);
    System.out.println("rulings:  " + ruling);
    boolean pinned = ok && jade.equals("X A B X A B");
    System.out.println(pinned ? "JADE keeps the behaviour at its place (difference pinned)"
                              : "unexpected: JADE's order changed");
    System.out.flush();
    Runtime.getRuntime().halt(pinned ? 0 : 1);
  }
}
