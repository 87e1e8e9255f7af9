package jsref.runtime;

import java.util.LinkedHashMap;
import java.util.List;

/** What the runtime and the host need to know of a compiled program; the back
    end generates one implementation per program, {@code jsgen.Program}. */
public interface ProgramInfo {
  /** The source files, as given to the compiler (error positions name them). */
  String[] files();

  /** The generated class of an agent type, or null when there is none. */
  Class<? extends JadescriptAgent> agentClass(String type);

  /** Every behaviour type, in the type environment's order (the trace header). */
  List<BehaviourInfo> behaviours();

  /** Every percept type with its default priority (R1a), in declaration order. */
  LinkedHashMap<String, Integer> percepts();

  /** A schema value built by the host (Eval.construct: arity, slot types,
      integers widened to float/double slots, R1c); errors as the interpreter's. */
  Object construct(String at, String schema, List<Object> args);

  boolean isSchema(String name);

  int slotCount(String name);

  boolean isPercept(String name);

  int defaultPriority(String name);

  /** Is the schema in an ontology that the agent type uses (directly or not)? */
  boolean visibleTo(String agentType, String schema);
}
