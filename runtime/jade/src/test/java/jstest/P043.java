package jstest;

import java.util.LinkedHashMap;
import java.util.List;
import jsref.runtime.BehaviourInfo;
import jsref.runtime.JadescriptAgent;
import jsref.runtime.JadescriptBehaviour;
import jsref.runtime.Message;
import jsref.runtime.ProgramInfo;
import jsref.values.JadescriptError;
import jsref.values.Schema;

/** Hand-written code following CONTRACT.md for conformance vector 043
    (messages, an unknown receiver). */
public final class P043 implements ProgramInfo {
  /** num(n). */
  public static final class Num extends Schema {
    private static final long serialVersionUID = 1L;
    /** n */ public Object n;
    Num(Object n) { this.n = n; }
    @Override public String schemaName() { return "num"; }
    @Override public String[] slotNames() { return new String[] { "n" }; }
    @Override public Object[] slotValues() { return new Object[] { n }; }
    @Override public Object get(String slot) { return slot.equals("n") ? n : null; }
    @Override public boolean set(String slot, Object v) { return false; }
  }

  /** agent Sender. */
  public static final class Sender extends JadescriptAgent {
    private static final long serialVersionUID = 1L;
    @Override public String typeName() { return "Sender"; }
    @Override protected void onCreate(Object[] args) {
      try { activate("p:1:1", new Tell(), new String[0], new Object[0]); }
      catch (JadescriptError e) { recordError(e); }
    }
  }

  /** agent Receiver. */
  public static final class Receiver extends JadescriptAgent {
    private static final long serialVersionUID = 1L;
    @Override public String typeName() { return "Receiver"; }
    @Override protected void onCreate(Object[] args) {
      try { activate("p:1:1", new Take(), new String[0], new Object[0]); }
      catch (JadescriptError e) { recordError(e); }
    }
  }

  /** one shot behaviour Tell. */
  public static final class Tell extends JadescriptBehaviour {
    private static final long serialVersionUID = 1L;
    @Override public String typeName() { return "Tell"; }
    @Override public boolean isCyclic() { return false; }
    @Override public boolean hasAction() { return true; }
    @Override protected void actionBlock() {
      agent().send("inform", new Num(7), List.of("ghost", "real"));
      agent().log("after send");
    }
  }

  /** cyclic behaviour Take. */
  public static final class Take extends JadescriptBehaviour {
    private static final long serialVersionUID = 1L;
    @Override public String typeName() { return "Take"; }
    @Override public boolean isCyclic() { return true; }
    @Override public int messageHandlerCount() { return 1; }
    @Override public String messagePerformative(int h) { return "inform"; }
    @Override public boolean messageAccepts(int h, Message m) { return m.content() instanceof Num; }
    @Override public void messageHandler(int h, Message m) { agent().log("got " + ((Num) m.content()).n); }
  }

  @Override public String[] files() { return new String[] { "program.jade" }; }
  @Override public Class<? extends JadescriptAgent> agentClass(String type) {
    return type.equals("Sender") ? Sender.class : type.equals("Receiver") ? Receiver.class : null;
  }
  @Override public List<BehaviourInfo> behaviours() {
    return List.of(new BehaviourInfo("Tell", "oneshot", true, 0, 0), new BehaviourInfo("Take", "cyclic", false, 0, 1));
  }
  @Override public LinkedHashMap<String, Integer> percepts() { return new LinkedHashMap<>(); }
  @Override public Object construct(String at, String schema, List<Object> args) { return new Num(args.get(0)); }
  @Override public boolean isSchema(String n) { return n.equals("num"); }
  @Override public int slotCount(String n) { return 1; }
  @Override public boolean isPercept(String n) { return false; }
  @Override public int defaultPriority(String n) { return 0; }
  @Override public boolean visibleTo(String agentType, String schema) { return true; }
}
