package jstest;

import java.util.LinkedHashMap;
import java.util.List;
import jsref.runtime.BehaviourInfo;
import jsref.runtime.JadescriptAgent;
import jsref.runtime.JadescriptBehaviour;
import jsref.runtime.ProgramInfo;
import jsref.values.JadescriptError;
import jsref.values.Schema;

/** Hand-written code following CONTRACT.md for conformance vector 001
    (the loop's test before the back end existed). */
public final class P001 implements ProgramInfo {
  /** A proposition percept. */
  public static final class Prop extends Schema {
    private static final long serialVersionUID = 1L;
    private final String name;
    private final int prio;
    Prop(String name, int prio) { this.name = name; this.prio = prio; }
    @Override public String schemaName() { return name; }
    @Override public String[] slotNames() { return new String[0]; }
    @Override public Object[] slotValues() { return new Object[0]; }
    @Override public Object get(String slot) { return null; }
    @Override public boolean set(String slot, Object v) { return false; }
    @Override public boolean isPercept() { return true; }
    @Override public int defaultPriority() { return prio; }
  }

  /** position(x, y). */
  public static final class Position extends Schema {
    private static final long serialVersionUID = 1L;
    /** x */ public Object x;
    /** y */ public Object y;
    Position(Object x, Object y) { this.x = x; this.y = y; }
    @Override public String schemaName() { return "position"; }
    @Override public String[] slotNames() { return new String[] { "x", "y" }; }
    @Override public Object[] slotValues() { return new Object[] { x, y }; }
    @Override public Object get(String slot) { return slot.equals("x") ? x : slot.equals("y") ? y : null; }
    @Override public boolean set(String slot, Object v) { return false; }
    @Override public boolean isPercept() { return true; }
    @Override public int defaultPriority() { return 2; }
  }

  /** agent Robot. */
  public static final class Robot extends JadescriptAgent {
    private static final long serialVersionUID = 1L;
    @Override public String typeName() { return "Robot"; }
    @Override protected void onCreate(Object[] args) {
      try { tick("p.jade:7:9"); activate("p.jade:8:17", new Handle(), new String[0], new Object[0]); }
      catch (JadescriptError e) { recordError(e); }
    }
  }

  /** cyclic behaviour Handle. */
  public static final class Handle extends JadescriptBehaviour {
    private static final long serialVersionUID = 1L;
    @Override public String typeName() { return "Handle"; }
    @Override public boolean isCyclic() { return true; }
    @Override public int perceptHandlerCount() { return 3; }
    @Override public boolean perceptHandler(int h, Object c) {
      JadescriptAgent a = agent();
      switch (h) {
        case 1: if (!(c instanceof Prop p && p.schemaName().equals("falling"))) return false;
          a.freshFuel(); a.log("falling"); return true;
        case 2: if (!(c instanceof Prop p && p.schemaName().equals("obstacle"))) return false;
          a.freshFuel(); a.log("obstacle"); return true;
        default: if (!(c instanceof Position p)) return false;
          a.freshFuel(); a.log("position " + jsref.values.Text.text(p.x)); return true;
      }
    }
  }

  @Override public String[] files() { return new String[] { "program.jade" }; }
  @Override public Class<? extends JadescriptAgent> agentClass(String type) { return type.equals("Robot") ? Robot.class : null; }
  @Override public List<BehaviourInfo> behaviours() { return List.of(new BehaviourInfo("Handle", "cyclic", false, 3, 0)); }
  @Override public LinkedHashMap<String, Integer> percepts() {
    LinkedHashMap<String, Integer> m = new LinkedHashMap<>();
    m.put("falling", 10); m.put("obstacle", 8); m.put("position", 2);
    return m;
  }
  @Override public Object construct(String at, String schema, List<Object> args) {
    switch (schema) {
      case "falling": return new Prop("falling", 10);
      case "obstacle": return new Prop("obstacle", 8);
      case "position": return new Position(toD(args.get(0)), toD(args.get(1)));
      default: throw JadescriptError.at(at, "unknown schema " + schema);
    }
  }
  private static Object toD(Object v) { return v instanceof Integer i ? (Object) (double) i : v; }
  @Override public boolean isSchema(String n) { return percepts().containsKey(n); }
  @Override public int slotCount(String n) { return n.equals("position") ? 2 : 0; }
  @Override public boolean isPercept(String n) { return isSchema(n); }
  @Override public int defaultPriority(String n) { return percepts().getOrDefault(n, 0); }
  @Override public boolean visibleTo(String agentType, String schema) { return true; }
}
