(** Evaluation of Jadescript code, and the bodies it gives the machine.

    An agent's state ({!agent}) holds its properties, the host objects it was
    given, and what its code produced during the current step: trace events
    (log, invoke, send, activate, deactivate, error), effects on the behaviours
    (for the machine, R5g/R5h) and messages to send (for the platform, R5e).
    {!Bodies} runs handlers and action blocks on it; {!create_agent} runs an
    agent's property initialisers and [on create].

    Run-time errors (R7) stop the handler, action block or [on create] that
    raised them; they are recorded as an [Error] event with their source
    location, and what the code did before the error stays done. A step budget
    ([fuel], statements and loop iterations per handler or step) turns an endless
    loop into such an error. *)

type message = {
  perf : string;       (** the performative *)
  content : Value.t;
  sender : string;     (** an agent's name, or ["host"] *)
}

type cell = { mutable v : Value.t; ty : Typing.Types.t }
(** A property of an agent or a behaviour: its value, and its declared type,
    to which every assignment converts (an integer to float or double). *)

(** What the fast engine keeps with a behaviour instance (its resolved
    guards): a slot the evaluation rules never read. *)
type engine_slot = ..
type engine_slot += Nothing_kept

type beh = private {
  uid : int;
  btype : Typing.Tenv.behaviour;
  bprops : cell Syntax.Strtbl.t;          (** its properties *)
  mutable bcache : (string * cell option) list;
      (** properties its code found by name, by the name's address *)
  phandlers : Typing.Tenv.handler array;  (** percept handlers, in order *)
  mhandlers : Typing.Tenv.handler array;  (** message handlers, in order *)
  action : Syntax.Ast.block option;
  mutable kept : engine_slot;             (** the fast engine's, never read here *)
}
(** A behaviour instance: its type, its properties, its handlers. *)

(** {1 Run-time errors}

    One exception per kind, as the WebAssembly reference interpreter has
    them. A body that raises one stops; the error is recorded as an [Error]
    event (R7) and the run carries on. The trace's [error] line is the same
    for all three kinds (its [message] is the exception's); the kind decides
    how a report words it ({!wording}). A broken invariant of the
    implementation is {!Semantics.Fault.Crash}, never recorded. *)

exception Trap of Syntax.Source.region * string
(** R7: the program did what the language does not allow (a division by
    zero, an index out of bounds, a missing map key, a value of the wrong
    type). *)

exception Exhaustion of Syntax.Source.region * string
(** A resource ran out: the step budget of one handler or step ([--fuel]),
    or the depth of nested calls of functions and procedures
    ({!max_call_depth}: deep recursion never becomes an OCaml stack
    overflow). *)

exception Link of Syntax.Source.region * string
(** Something the host gave does not fit: a host object without the native
    method invoked, a native method given arguments it does not take, an
    agent type that does not exist or creation arguments that do not fit its
    parameters. *)

type error_kind = Trap_error | Exhaustion_error | Link_error

val wording : error_kind -> string -> string
(** A report of an error of this kind: a trap's message as it is,
    ["exhaustion: "] or ["link error: "] before the others'. *)

val max_call_depth : int

(** 200 nested calls: what a browser's JavaScript stack holds (the playground
    must report what [run] reports), with room to spare. *)

val max_text : int
val max_map_size : int
(** D21: a text holds at most 1,000,000 bytes and a map at most 1,000,000
    entries. Building a bigger one ([s + t], [m[k] = v] with a new key), or
    a [log], [send] or [invoke] of a value whose text or literal would be
    longer than [max_text], is an exhaustion error at that expression or
    assignment (R7); the length is counted without building the text. *)

val set_max_memory : int option -> unit
(** D22: [set_max_memory (Some mb)]: a run takes at most [mb] megabytes of
    heap. The evaluator compares the heap with it every 1,024 statements
    and before building a text of more than 64 KB; over it (after a
    compaction), the statement is an exhaustion error (R7): ["out of
    memory: the run takes more than MB MB (--max-memory)"]. [None] (the
    default of the library): no bound. Where the error falls depends on the
    garbage collector: it is a safety net, not part of the conformance
    contract (D21 is). *)

val max_behaviours : int
(** D19: 10,000 active behaviour instances per agent. An [activate] when
    the agent has that many is an exhaustion error at the [activate]
    (R7): the body stops, the instance is not made. The bound keeps the
    rules' own work in each step (the ready list, the handler snapshot)
    bounded. *)

type event =
  | Log of string
  | Invoke of { meth : string; cls : string; args : Value.t list; result : Value.t }
  | Sent of { perf : string; content : Value.t; receivers : string list }
  | Activated of string          (** the behaviour type *)
  | Deactivated of int           (** the instance id *)
  | Error of error_kind * Syntax.Source.region * string
  | Ran of { handler : int; effects : beh Semantics.Machine.effect list }
      (** a handler ([h], from 1) or an action block ([0]) of a behaviour
          ended, with these effects on the behaviours (R5g, R5h); not a
          trace line, but what the trace says of the rule that ran it *)

type frame
(** What a running body sees: its agent, behaviour, locals, content or
    message, and step budget. *)

val beh_type : beh -> string

val keep : beh -> engine_slot -> unit
(** Fills the instance's slot for the fast engine. *)

type agent = {
  env : Typing.Tenv.t;
  name : string;
  atype : Typing.Tenv.agent;
  props : cell Syntax.Strtbl.t;   (** the agent's properties, by name *)
  mutable acache : (string * cell option) list;
      (** properties the agent's own code found by name, remembered by the
          name's address (names are interned by the lexer) *)
  mutable outbox : (string * message) list;     (** newest first *)
  mutable events : event list;                  (** newest first *)
  mutable effects : beh Semantics.Machine.effect list;  (** newest first *)
  mutable fuel_limit : int;
  mutable pending : (int * int * frame) option;
      (** the frame of the last applicable percept guard (instance, handler):
          its body runs in it, with the guard's bindings *)
  mutable record_ran : bool;
      (** record a [Ran] event after each handler and action block (what
          the trace says of a rule's effects); [true] unless set otherwise
          by a caller that writes no trace (the bench) *)
  mutable live : int;
      (** D19: the agent's active behaviour instances when the current rule
          started ({!set_live}), plus the activations its bodies made since,
          minus their [deactivate this]: what [activate] checks against
          {!max_behaviours} *)
}

val property : agent -> string -> Value.t option
(** The current value of an agent property. *)

val take_events : agent -> event list
(** The events since the last call, oldest first. *)

val set_live : agent -> int -> unit
(** [set_live a n]: the agent has [n] active instances now. Whoever runs
    the machine calls it after each rule that changed them (the runtime,
    the playground), so that {!max_behaviours} counts what is active, not
    every activation ever made. *)

val create_agent :
  Typing.Tenv.t -> name:string -> atype:string -> args:Value.t list -> fuel:int ->
  agent * beh list
(** Creates the agent: its properties in declaration order (inherited first),
    then its [on create] with [args] (R5g). Returns the behaviours that
    [on create] activated, in activation order. An error in [on create] is an
    [Error] event, as in a handler.
    @raise Link when the agent type does not exist or the arguments do not
    fit the parameters (the host's mistake, reported to the host). *)

val destroy_agent : agent -> unit
(** Runs [on destroy], if any. *)

val percept_value : Typing.Tenv.t -> agent_type:string -> Syntax.Ast.expr -> Value.t * int
(** A percept written in Jadescript by the host (an events file, the command
    line): it must construct a percept type visible to the agent, with
    arguments of the slots' types (integers widen, R1c). Returns the value and
    its type's default priority (R1a).
    @raise Trap otherwise. *)

val literal_value : Typing.Tenv.t -> Syntax.Ast.expr -> Value.t
(** A literal value given by the host (an agent's creation arguments, a [put]):
    numbers, texts, booleans, lists, maps, [aid("r")] and schema
    constructions. @raise Trap *)

(** {1 For the fast engine}

    What [lib/engine/interp_bodies.ml] needs to evaluate a percept guard the
    way the general rules do, faster. *)

val percept_handler : beh -> int -> Typing.Tenv.handler
(** Percept handler [h] (from 1) of the instance, in declaration order. *)

val percept_handler_count : beh -> int

val guard_frame : agent -> id:int -> beh -> Value.t -> frame
(** The frame a percept guard of the instance is evaluated in, for this
    percept (a fresh step budget). *)

val record_error : agent -> exn -> bool
(** Records a run-time error (a trap, an exhaustion or a link error) as an
    [Error] event of the agent: [true]; any other exception: [false]. *)

val bind_local : frame -> string -> Value.t -> unit
(** Binds a pattern variable, as a pattern does. *)

val condition_part : frame -> whole:Syntax.Ast.expr -> Syntax.Ast.expr -> bool
(** The value of [part], a conjunct of the [when] condition [whole], which
    must be a boolean. @raise Trap *)

(** {2 What the compiled percept handlers reuse}

    [lib/engine/compiled_bodies.ml] compiles percept handlers to closures;
    every rule it needs is one of these, exactly as the evaluator above uses
    it. A frame made by {!guard_frame} gives the rules that read a frame
    (names, [of], patterns, the step budget) the agent and the behaviour. *)

val err : Syntax.Source.region -> ('a, unit, string, 'b) format4 -> 'a
(** Raises a {!Trap} with the formatted message. *)

val lookup : frame -> Syntax.Source.region -> string -> Value.t
(** The value of a name: a local of the frame, else a property (the
    behaviour's, then the agent's), else a schema without slots, else the
    trap ["unknown name"]. *)

val set_cell : cell -> Value.t -> unit
(** Assigns a property, converted to its declared type. *)

val coerce : Typing.Types.t -> Value.t -> Value.t

val coerce_param : Typing.Types.t -> Value.t -> Value.t option
(** The value as a slot or parameter of that type takes it (R1c: an
    integer widens to float or double), or [None] when it does not fit:
    what {!construct} checks of each slot. *)

val literal : Syntax.Ast.literal -> Value.t

val pattern : frame -> (string * Value.t) list ref -> Syntax.Ast.pattern -> Value.t -> bool
(** Does the value match the pattern? Its variables' bindings are added to
    the list, newest first. *)

val of_ : frame -> Syntax.Source.region -> string -> Value.t -> Value.t
(** [p of v]. *)

val slot : Syntax.Source.region -> Value.schema_v -> string -> Value.t ref

val construct : Typing.Tenv.t -> Syntax.Source.region -> string -> Value.t list -> Value.t
(** A schema value built by its constructor (R1c conversions of its slots). *)

val arith : Syntax.Source.region -> Syntax.Ast.binop -> Value.t -> Value.t -> Value.t
(** [+ - * / %] on numbers (D8: integers are 32-bit). *)

val compare_values : Syntax.Source.region -> Syntax.Ast.binop -> Value.t -> Value.t -> Value.t
(** [< > <= >=]. *)

val equal_values : Syntax.Source.region -> Value.t -> Value.t -> bool
(** [=] (D37: an exhaustion error past {!Value.max_visits} values). *)

val map_set_bounded : Syntax.Source.region -> Value.map_v -> Value.t -> Value.t -> unit
(** [m[k] = v] within D21's and D37's bounds. *)

val too_large_to_compare : Syntax.Source.region -> 'a
val too_big : Syntax.Source.region -> string -> 'a

val bounded_text : quote:bool -> Syntax.Source.region -> Value.t -> Value.t
(** The value, when its text (or literal) is at most {!max_text} bytes long;
    an exhaustion error otherwise. *)

val check_memory : Syntax.Source.region -> unit
(** D22's comparison of the heap with [--max-memory]. *)

val tick : frame -> Syntax.Source.region -> unit
(** One statement or loop iteration of the frame's step budget. *)

val reset_fuel : frame -> unit
(** A fresh step budget for the frame, as a handler body gets. *)

val agent_frame : frame -> frame
(** The frame an agent's own function or procedure runs in when called
    from this frame's code: no behaviour, no content, fresh locals, the
    same step budget (shared, as a call's). *)

val receivers_of : Syntax.Source.region -> Value.t -> string list
(** The receivers a value of a [send] names: an aid, or a list of aids;
    the error otherwise, at the region given. *)

val post_send : agent -> string -> Value.t -> string list -> unit
(** [post_send a perf content receivers]: the message in each receiver's
    outbox entry of [a], and the [Sent] event, as a [send] does once its
    content and receivers are evaluated. *)

val invoke_values : agent -> Syntax.Source.region -> Syntax.Ast.invoke -> Value.t -> Value.t list -> Value.t
(** [invoke] at a region (the statement's or the expression's), once its
    target and its arguments are evaluated, in that order: each
    argument's literal within {!max_text}, then the host's method, its
    [Invoke] event and its result. *)

val activate_at : frame -> depth:int -> Syntax.Source.region -> string -> (string * Value.t) list -> unit
(** [activate behaviour B with x = v, ...] at a region, its arguments
    evaluated, from code [depth] calls deep (what bounds the calls of the
    behaviour's [on create], {!max_call_depth}): the frame gives the agent
    and the step budget. *)

val recover : agent -> exn -> unit
(** What ends a body: [return], [break] and [continue] nothing, a run-time
    error recorded, any other exception raised again. *)

val take_ran : agent -> int -> beh Semantics.Machine.effect list
(** The effects of the body that just ran ([handler], 0 for an action
    block), recorded in a [Ran] event when the agent records them. *)

(** {1 The bodies}

    The reference: every percept guard is evaluated by the general rules,
    with no memo and no pre-test. *)

module Bodies : Semantics.Machine.BODIES
  with type percept = Value.t and type message = message and type obj = Value.t
   and type beh = beh and type world = agent
