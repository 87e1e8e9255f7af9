(** Evaluation of Jadescript code, and the bodies it gives the machine: the
    reference.

    An agent ({!agent}) is a value: its properties, the limits of the run
    ({!config}), the supply of behaviour instance numbers, and what its code
    did that nobody has taken yet (trace events, messages to send). A body
    (a handler, an action block, [on create]) takes the agent and answers
    the agent after it, with its effects on the behaviours (R5g, R5h) for
    the machine; {!Bodies} is that, for {!Semantics.Machine}. What changes
    in place is only the program's own data: its properties, and the lists,
    maps and schema values they reach, which Jadescript shares by reference
    as Java does (docs/semantics.md, "Values").

    Run-time errors (R7) stop the handler, action block or [on create] that
    raised them; they are recorded as an [Error] event with their source
    location, and what the code did before the error stays done. A step
    budget ([config.fuel], statements and loop iterations per handler or
    step) turns an endless loop into such an error.

    The fast engine's twin of the percept handlers is
    [lib/engine/compiled_bodies.ml]: it calls the rules of the section "For
    the fast engine" for every value it computes. *)

type message = {
  perf : string;       (** the performative *)
  content : Value.t;
  sender : string;     (** an agent's name, ["host"] or a platform agent ([ams]) *)
}

type cell = { mutable v : Value.t; ty : Typing.Types.t }
(** A property of an agent or a behaviour: its value, and its declared type,
    to which every assignment converts (an integer to float or double). *)

type beh = {
  uid : int;                              (** its number ([this], D40) *)
  btype : Typing.Tenv.behaviour;
  bprops : cell Syntax.Strtbl.t;          (** its properties *)
  phandlers : Typing.Tenv.handler array;  (** percept handlers, in order *)
  mhandlers : Typing.Tenv.handler array;  (** message handlers, in order *)
  action : Syntax.Ast.block option;
}
(** A behaviour instance: its type, its properties, its handlers. *)

val beh_type : beh -> string

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
(** A resource ran out: the step budget of one handler or step, the depth
    of nested calls, the active behaviours, the size of a value, the
    memory. *)

exception Link of Syntax.Source.region * string
(** Something the host gave does not fit: a host object without the native
    method invoked, a native method given arguments it does not take, an
    agent type that does not exist or creation arguments that do not fit its
    parameters. *)

type error_kind = Trap_error | Exhaustion_error | Link_error

val wording : error_kind -> string -> string
(** A report of an error of this kind: a trap's message as it is,
    ["exhaustion: "] or ["link error: "] before the others'. *)

(** {1 The limits of a run} *)

type config = {
  fuel : int;
      (** statements one handler or step may execute (R7; [run --fuel]) *)
  max_call_depth : int;
      (** D18: nested calls of functions and procedures; the next is an
          exhaustion error (never an OCaml stack overflow) *)
  max_behaviours : int;
      (** D19: active behaviour instances per agent; an [activate] past it
          is an exhaustion error at the [activate], the instance not made *)
  max_memory : int option;
      (** D22: megabytes of heap the run may take ([None]: no bound). The
          heap is compared with it every 1,024 statements and before a text
          of more than 64 KB is built; over it (after a compaction), the
          statement is an exhaustion error. Where it falls depends on the
          garbage collector: a safety net, not part of the conformance
          contract (D21 is). *)
  record_effects : bool;
      (** record a [Ran] event after each handler and action block (what
          the trace says of a rule's effects); off when no trace is
          written *)
}

val default_config : config
(** Fuel 100,000; 200 nested calls (what a browser's JavaScript stack holds,
    so that the playground reports what [run] reports); 10,000 active
    behaviours; no memory bound; effects recorded. *)

val max_text : int
val max_map_size : int
(** D21: a text holds at most 1,000,000 bytes and a map at most 1,000,000
    entries. Building a bigger one ([s + t], [m[k] = v] with a new key), or
    a [log], [send] or [invoke] of a value whose text or literal would be
    longer than [max_text], is an exhaustion error at that expression or
    assignment (R7). These bounds are part of the conformance contract, the
    same in every run. *)

(** {1 Agents} *)

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

type agent = {
  env : Typing.Tenv.t;
  name : string;
  atype : Typing.Tenv.agent;
  props : cell Syntax.Strtbl.t;   (** the agent's properties, by name *)
  config : config;
  next_uid : int;                 (** the number of its next behaviour instance (D40) *)
  events : event list;            (** not yet taken, newest first *)
  outbox : (string * message) list;   (** not yet taken, newest first *)
}

val property : agent -> string -> Value.t option
(** The current value of an agent property. *)

val take_events : agent -> agent * event list
(** The agent without its events, and the events, oldest first. *)

val create_agent :
  ?config:config -> Typing.Tenv.t -> name:string -> atype:string -> args:Value.t list -> agent * beh list
(** Creates the agent: its properties in declaration order (inherited first),
    then its [on create] with [args] (R5g). Returns the agent and the
    behaviours that [on create] activated, in activation order. An error in
    [on create] is an [Error] event, as in a handler.
    @raise Link when the agent type does not exist or the arguments do not
    fit the parameters (the host's mistake, reported to the host). *)

val destroy_agent : agent -> agent
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

(** {1 The bodies} *)

module Bodies : Semantics.Machine.BODIES
  with type percept = Value.t and type message = message and type obj = Value.t
   and type beh = beh and type world = agent and type bindings = (string * Value.t) list
(** The reference bodies: a guard evaluated by the rules of this module in
    fresh locals, its bindings (its pattern variables, oldest first) handed
    to the body (R3b). D41: a guard that reaches an [activate] or a
    [deactivate] (through a call) fails there with an error. *)

(** {1 For the fast engine}

    [lib/engine/compiled_bodies.ml] compiles percept handlers to closures;
    every rule it needs is one of these, exactly as the evaluator uses it. *)

type run = {
  mutable fuel : int;                                   (** statements left (R7) *)
  mutable events : event list;                          (** newest first *)
  mutable outbox : (string * message) list;             (** newest first *)
  mutable effects : beh Semantics.Machine.effect list;  (** newest first *)
  mutable next_uid : int;                               (** the next instance number (D40) *)
  mutable live : int;
      (** D19: active instances as the body started, plus its activations,
          minus its [deactivate this] *)
}
(** A body's run: its step budget left and what it did so far, which the
    agent gets when the body ends ({!finish_run}). Made afresh for each
    body, and shared by the calls it makes and the behaviours it
    activates. *)

type frame
(** What a running body sees: its agent, its run, its behaviour, locals,
    content or message. *)

val new_run : agent -> active:int -> run
(** A fresh run for a body of the agent: the step budget of the agent's
    config, nothing done yet, [active] instances active (D19). *)

val reset_run : run -> agent -> active:int -> unit
(** The same run made fresh again, for a body of [agent] (the engine runs
    its bodies in a run of its own, reset each time). *)

val refuel : run -> agent -> unit
(** A fresh step budget for the run (a body after its guard). *)

val quiet : run -> agent -> bool
(** The run recorded nothing: no event, no message, no effect on the
    behaviours, no new instance: the agent after it is the agent
    itself. *)

val body_frame : agent -> run -> id:int -> beh -> frame
(** The frame a handler of instance [id] runs in, in that run (its content
    and locals are the engine's own). *)

val finish_run : agent -> run -> agent
(** The agent after the run: its events and messages added, its instance
    numbers advanced; the agent itself when the run recorded none. *)

val finish : agent -> run -> handler:int -> agent * beh Semantics.Machine.effect list
(** The end of handler [handler] (0: an action block) that ran in the run,
    on the agent as it was when the body started: its [Ran] event when the
    config records effects, the agent after it ({!finish_run}), and its
    effects on the behaviours, in order. *)

val run_effects : run -> beh Semantics.Machine.effect list
(** The run's effects on the behaviours so far, in order. *)

val record_error : frame -> exn -> bool
(** Records a run-time error (a trap, an exhaustion or a link error) in the
    frame's run: [true]; any other exception: [false]. *)

val recover : frame -> exn -> unit
(** What ends a body: [return], [break] and [continue] nothing, a run-time
    error recorded, any other exception raised again. *)

val err : Syntax.Source.region -> ('a, unit, string, 'b) format4 -> 'a
(** Raises a {!Trap} with the formatted message. *)

val lookup : frame -> Syntax.Source.region -> string -> Value.t
(** The value of a name: a local of the frame, else a property (the
    behaviour's, then the agent's), else a schema without slots, else the
    trap ["unknown name"]. *)

val prop_cell : frame -> string -> cell option
(** The property a name denotes: the running behaviour's, else the agent's. *)

val set_cell : cell -> Value.t -> unit
(** Assigns a property, converted to its declared type. *)

val coerce : Typing.Types.t -> Value.t -> Value.t

val coerce_param : Typing.Types.t -> Value.t -> Value.t option
(** The value as a slot or parameter of that type takes it (R1c: an
    integer widens to float or double), or [None] when it does not fit. *)

val literal : Syntax.Ast.literal -> Value.t

val pattern : Typing.Tenv.t -> (string * Value.t) list ref -> Syntax.Ast.pattern -> Value.t -> bool
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

val check_memory : agent -> Syntax.Source.region -> unit
(** D22's comparison of the heap with the agent's [max_memory]. *)

val tick : frame -> Syntax.Source.region -> unit
(** One statement or loop iteration of the run's step budget. *)

val agent_frame : frame -> frame
(** The frame an agent's own function or procedure runs in when called
    from this frame's code: no behaviour, no content, fresh locals, the
    same run (a call shares its caller's step budget). *)

val receivers_of : Syntax.Source.region -> Value.t -> string list
(** The receivers a value of a [send] names: an aid, or a list of aids;
    the error otherwise, at the region given. *)

val post_send : frame -> string -> Value.t -> string list -> unit
(** [post_send f perf content receivers]: the message for each receiver,
    and the [Sent] event, as a [send] does once its content and receivers
    are evaluated. *)

val invoke_values : frame -> Syntax.Source.region -> Syntax.Ast.invoke -> Value.t -> Value.t list -> Value.t
(** [invoke] at a region (the statement's or the expression's), once its
    target and its arguments are evaluated, in that order: each
    argument's literal within {!max_text}, then the host's method, its
    [Invoke] event and its result. *)

val activate_at : frame -> depth:int -> Syntax.Source.region -> string -> (string * Value.t) list -> unit
(** [activate behaviour B with x = v, ...] at a region, its arguments
    evaluated, from code [depth] calls deep (what bounds the calls of the
    behaviour's [on create], D18). *)

val deactivate_at : frame -> Syntax.Source.region -> unit
(** [deactivate this] (R5h, D16). *)

val log_value : frame -> Syntax.Source.region -> Value.t -> unit
(** [log e], once [e] is evaluated (at its own region). *)

(** {1 The rules over their primitives}

    What the evaluator does with numbers, texts and schema types is one
    small module, {!PRIMITIVES}; the rules of this file are a functor over
    it, applied once to {!Primitives}, the reference's: every value above is
    of that application. The bug catalogue (lib/defects) applies {!Make} to
    primitives with one function changed (integer division, widening,
    equality, the text of a real...), and runs the machine on the bodies
    that come out; the reference knows nothing of them. *)

module type PRIMITIVES = sig
  val arith : Syntax.Source.region -> Syntax.Ast.binop -> Value.t -> Value.t -> Value.t
  (** [+ - * / %] on numbers (D8: integers are 32-bit) *)

  val compare_values : Syntax.Source.region -> Syntax.Ast.binop -> Value.t -> Value.t -> Value.t
  (** [< > <= >=] *)

  val equal_values : Syntax.Source.region -> Value.t -> Value.t -> bool
  (** [=] and [!=] *)

  val coerce_param : Typing.Types.t -> Value.t -> Value.t option
  (** a value as a slot, parameter or property of a type takes it (R1c:
      integers widen) *)

  val text : Value.t -> string
  (** the text of a value: what [log] writes and [+] appends to a text *)

  val subschema : Typing.Tenv.t -> string -> string -> bool
  (** [subschema env s t]: a value of schema [s] is one of [t] (R1a), for
      patterns and [matches] *)
end

module Primitives : PRIMITIVES
(** The reference's: {!arith}, {!compare_values}, {!equal_values},
    {!coerce_param}, {!Value.to_text}, {!Typing.Tenv.subschema}. *)

(** What an application of {!Make} gives: the bodies, and the agent's own
    code. *)
module type S = sig
  val create_agent :
    ?config:config -> Typing.Tenv.t -> name:string -> atype:string -> args:Value.t list -> agent * beh list
  val destroy_agent : agent -> agent
  module Bodies : Semantics.Machine.BODIES
    with type percept = Value.t and type message = message and type obj = Value.t
     and type beh = beh and type world = agent and type bindings = (string * Value.t) list
end

module Make (_ : PRIMITIVES) : S
(** The rules of evaluation over the primitives [P]. *)
