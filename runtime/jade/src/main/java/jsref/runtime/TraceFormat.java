package jsref.runtime;

/** The names of the trace format (docs/trace-format.md, version 2), written
    once: every event name, every field name of a line and of the header, the
    action names and the effect words. They are the names of the OCaml owner
    of the format, {@code lib/trace/trace.ml}; the runtime's test
    ({@code runtime/jade/test}, {@code TraceFormatCheck}) holds the two sets
    equal, and fails when one of these names is written as a string literal
    anywhere else in the runtime. {@link Trace} writes the lines. */
public final class TraceFormat {
  private TraceFormat() {}

  /** The {@code event} field's values: one per kind of line. */
  public static final class Event {
    private Event() {}
    // steps of the agent loop
    public static final String CREATE = "create";
    public static final String NOTIFY = "notify";
    public static final String PUT = "put";
    public static final String DELIVER = "deliver";
    public static final String TRANSFER = "transfer";
    public static final String TRANSFER_ONE = "transfer_one";
    public static final String TRANSFER_SPIN = "transfer_spin";
    public static final String TRANSFER_END = "transfer_end";
    public static final String DEQUEUE = "dequeue";
    public static final String HANDLE = "handle";
    public static final String SKIP = "skip";
    public static final String END_DISPATCH = "end_dispatch";
    /** An EndDispatch after which no handler had applied (R3b). */
    public static final String DISCARD = "discard";
    public static final String BEHAVIOUR_STEP = "behaviour_step";
    public static final String NEXT_ITERATION = "next_iteration";
    public static final String IDLE = "idle";
    // inside a step: what a body did
    public static final String LOG = "log";
    public static final String INVOKE = "invoke";
    public static final String SEND = "send";
    public static final String ACTIVATE = "activate";
    public static final String DEACTIVATE = "deactivate";
    public static final String ERROR = "error";
    // outside the spec
    public static final String REFUSED = "refused";
    public static final String UNDELIVERABLE = "undeliverable";
    public static final String DESTROY = "destroy";
  }

  /** The fields of a line, and of the {@code message} object of a behaviour step. */
  public static final class Field {
    private Field() {}
    public static final String STEP = "step";
    public static final String AGENT = "agent";
    public static final String EVENT = "event";
    public static final String ACTION = "action";
    public static final String TYPE = "type";
    public static final String ARGS = "args";
    public static final String BEHAVIOURS = "behaviours";
    public static final String PERCEPT = "percept";
    public static final String PRIORITY = "priority";
    public static final String SEQ = "seq";
    public static final String REASON = "reason";
    public static final String OBJECT = "object";
    public static final String INDEX = "index";
    public static final String PERFORMATIVE = "performative";
    public static final String CONTENT = "content";
    public static final String FROM = "from";
    public static final String TO = "to";
    public static final String MOVED = "moved";
    public static final String INSTANCE = "instance";
    public static final String BEHAVIOUR = "behaviour";
    public static final String HANDLER = "handler";
    public static final String EFFECTS = "effects";
    public static final String MESSAGE = "message";
    public static final String ACTION_EFFECTS = "action_effects";
    public static final String TEXT = "text";
    public static final String METHOD = "method";
    public static final String RESULT = "result";
    public static final String AT = "at";
  }

  /** The {@code action} field's values: the actions of spec/AgentLoop.tla,
      and the action of the events of {@code on destroy}. */
  public static final class Action {
    private Action() {}
    public static final String INIT = "Init";
    public static final String NOTIFY = "Notify";
    public static final String NOTIFY_WITH = "NotifyWith";
    public static final String PUT = "Put";
    public static final String SEND = "Send";
    /** R5d revised: a message that reached the agent during its last
        behaviour step, after the step's handlers looked. */
    public static final String SEND_IN_STEP = "SendInStep";
    public static final String TRANSFER = "Transfer";
    public static final String TRANSFER_ONE = "TransferOne";
    public static final String TRANSFER_SPIN = "TransferSpin";
    public static final String TRANSFER_END = "TransferEnd";
    public static final String DEQUEUE = "Dequeue";
    public static final String HANDLE = "Handle";
    public static final String SKIP = "Skip";
    public static final String END_DISPATCH = "EndDispatch";
    public static final String BEHAVIOUR_STEP = "BehaviourStep";
    public static final String NEXT_ITERATION = "NextIteration";
    public static final String IDLE = "Idle";
    /** Not a step of the spec: the events of {@code on destroy} (D14). */
    public static final String DESTROY = "destroy";
  }

  /** The header's fields (the first line), with those of its agents and
      behaviour types. */
  public static final class Header {
    private Header() {}
    public static final String TRACE = "trace";
    public static final String VERSION = "version";
    public static final String VARIANT = "variant";
    public static final String TIE_POLICY = "tie_policy";
    public static final String BUDGET = "budget";
    public static final String O2A_CAPACITY = "o2a_capacity";
    public static final String SEED = "seed";
    /** Version 2: {@code full} (every rule has its line) or {@code observable}. */
    public static final String LEVEL = "level";
    public static final String AGENTS = "agents";
    /** The agents outside the main container, each with its container's
        name; written only when there are some (D47). */
    public static final String CONTAINERS = "containers";
    public static final String PROGRAM = "program";
    public static final String PERCEPTS = "percepts";
    public static final String NAME = "name";
    public static final String KIND = "kind";
    public static final String PERCEPT_HANDLERS = "percept_handlers";
    public static final String MESSAGE_HANDLERS = "message_handlers";
    // also: Field.TYPE (an agent's), Field.BEHAVIOURS (the program's),
    // Field.ACTION (does a behaviour type have an action block)
  }

  /** Fixed values of the format. */
  public static final class Value {
    private Value() {}
    /** The header's {@code trace}. */
    public static final String FORMAT = "jadescript-ref";
    /** The container of the peripheral JVM's agents (D47). */
    public static final String PERIPHERAL = "peripheral";
    /** The header's {@code version}: the version this runtime writes. */
    public static final int VERSION = 2;
    /** The header's {@code level}: every rule has its line. */
    public static final String FULL = "full";
    /** The header's {@code level}: the loop's own steps have no line. */
    public static final String OBSERVABLE = "observable";
    /** The header's {@code tie_policy} in every run of the runtime (R3b). */
    public static final String STABLE = "stable";
    /** The {@code reason} of every {@code refused} line (R2d). */
    public static final String O2A_FULL = "the O2A queue is full (R2d)";
  }

  /** The words of an {@code effects} list: {@code "activate B"}, {@code "deactivate"}. */
  public static final class Effect {
    private Effect() {}
    public static final String ACTIVATE = "activate";
    public static final String DEACTIVATE = "deactivate";

    /** The effect of activating an instance of a behaviour type (R5g).
        @param behaviour the type @return {@code "activate B"} */
    public static String activate(String behaviour) { return ACTIVATE + " " + behaviour; }
  }
}
