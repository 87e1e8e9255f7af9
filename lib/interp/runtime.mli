(** Running a checked program on a platform: the agents the host creates, the
    host's notifications, objects and messages, the agent loops interleaved as
    R6 says, and the trace of every observable step (R8,
    docs/trace-format.md). *)

module P : module type of Semantics.Platform.Make (Eval.Bodies)
(** The platform of the reference machine and bodies. *)

type t

(** What takes the agents' rules. *)
type engine =
  | Reference   (** the reference alone: [Machine.step] on {!Eval.Bodies}, one rule at a time *)
  | Fast        (** the fast engine ({!Engine.for_agent}), held equal to the reference *)

type options = {
  params : Semantics.Machine.params;
  engine : engine;
  seed : int option;          (** [None]: round-robin (R6); [Some s]: seeded *)
  interleave : int option;
      (** D45: [Some s]: the finer interleaving of R6, drawn from [s]:
          rules of different agents in any order, messages delivered after
          a delay, possibly during their receiver's behaviour step *)
  fuel : int;                 (** statements per handler or step (R7) *)
  max_steps : int;            (** agent steps in the whole run *)
  max_memory : int option;    (** D22: megabytes of heap the run may take *)
  trace : out_channel option;
  level : string;
      (** the trace's level: ["full"] (every rule's line) or ["observable"]
          (not the loop's own steps, docs/trace-format.md) *)
  on_log : string -> string -> unit;   (** agent name, text: [log e] *)
  on_error : Eval.error_kind -> Syntax.Source.region -> string -> unit;
      (** a run-time error (R7), as it is recorded: its kind, where, and
          the message; the run carries on *)
}

(** The rules one agent takes: a step (the rules enabled in a
    configuration; the first is taken) and, for the fast engine, the
    derived rule Dispatch (D29, D33). *)
type rules = {
  step : Semantics.Machine.params -> P.M.t -> (P.M.lbl * P.M.t) list;
  dispatch : (?observe:(P.M.lbl -> Eval.agent -> Eval.agent) -> Semantics.Machine.params -> P.M.t -> P.M.t option) option;
}

(** The platform operations a run takes. {!hooks_of} gives the rulings';
    a deliberately defective implementation (lib/defects, the conformance
    vectors' kill count) wraps them from the outside. *)
type hooks = {
  rules : string -> rules;
      (** the rules of the agent of that name, made once, when it is created *)
  notify_event : Semantics.Machine.params -> P.t -> int -> P.M.t -> Value.t -> default:int ->
    priority:int option -> (P.M.t, Semantics.Machine.refusal) result;
      (** notifyEvent into agent [i] (R2a, R2d) *)
  put : Semantics.Machine.params -> P.t -> int -> P.M.t -> Value.t ->
    (P.M.t, Semantics.Machine.refusal) result;
      (** putO2AObject into agent [i] (R2c, R2d) *)
  round : Random.State.t option -> P.t -> int list;   (** the order of one round (R6) *)
  create_agent : config:Eval.config -> Typing.Tenv.t -> name:string -> atype:string ->
    args:Value.t list -> Eval.agent * Eval.beh list;
      (** an agent made, its [on create] run (R5g): {!Eval.create_agent} *)
  destroy_agent : Eval.agent -> Eval.agent;   (** its [on destroy]: {!Eval.destroy_agent} *)
  failure : receiver:string -> Eval.message;   (** ams's answer to a send to [receiver]: {!failure} *)
  in_step : Semantics.Machine.params -> P.t -> sender:string -> receiver:string -> Eval.message ->
    (P.t * P.event) option;
      (** a delivery during the receiver's behaviour step (R5d revised, D42):
          {!P.deliver_in_step} *)
}

val failure : receiver:string -> Eval.message
(** R5e, D43: the [failure] [ams] sends the sender of a message to an agent
    that is not on the platform; its content is the receiver's aid. *)

val reference_rules : rules
(** [Machine.step], and no derived rule. *)

val hooks_of : engine -> hooks
(** The rulings' operations, the agents' rules taken by that engine:
    [Machine.notify_event], [Machine.put] refused when the O2A queue is
    full, [P.round]. *)

val reference_hooks : hooks
(** [hooks_of Reference]. *)

val create :
  ?hooks:hooks ->
  Typing.Tenv.t -> options -> (string * string * Value.t list) list -> t
(** Boots the agents (name, type, creation arguments) in order (R5g);
    messages sent by their [on create] are delivered once all exist (D13).
    [hooks] defaults to [hooks_of options.engine].
    @raise Eval.Link when the host's request is wrong (an unknown agent
    type, arguments that do not fit). *)

val notify : t -> agent:string -> Value.t -> default:int -> priority:int option -> (unit, string) result
(** R2: [Error] when the agent does not exist, the priority is negative
    (R2a) or the O2A queue is full (R2d); nothing is enqueued then. *)

val put : t -> agent:string -> Value.t -> (unit, string) result
(** R2c: [Error] when the agent does not exist or its O2A queue is full
    (R2d); a refused object is recorded as [refused] with its [object]. *)

val message : ?during_step:bool -> t -> agent:string -> perf:string -> Value.t -> (unit, string) result
(** A message from the host (sender ["host"]); [during_step] (D42): held
    until the agent's next behaviour step, and delivered during it
    (SendInStep, R5d), before the messages that step sent are delivered;
    if the agent takes none before its rounds end, it arrives then. *)

val run_rounds : t -> int -> unit
(** [n] rounds: in each, every agent that is not idle runs one loop iteration
    (round-robin, or a seeded order). D20: the rounds stop early when every
    agent is idle, when the step limit ([max_steps]) is reached, or after a
    round that took no step: no seeded order is drawn for a round that
    does not run. *)

val run_rules : t -> int -> unit
(** [n] single rules of the first agent, in creation order, that is not
    idle; fewer when it idles ([{"run": {"rules": n}}], docs/trace-format.md).
    The host can act between rules (R3d). *)

val run_until_idle : t -> unit
(** Until every agent is idle or the step limit is reached ([run_rounds]
    with no bound on the count). *)

val finish : t -> unit
(** Delivers every message still in flight (the finer interleaving, D45)
    and every host message held for a step that did not come (D42), then
    runs every agent's [on destroy], in creation order, and closes the
    trace (D26: what was sent before [on destroy] is delivered). *)

val steps : t -> int
val platform : t -> P.t
val env : t -> Typing.Tenv.t

val tune_gc : unit -> unit
(** The garbage-collector settings for runs: a 32 MB minor heap (runs
    allocate many short-lived values) and a space overhead of 1000 (under a
    flood the major heap is mostly waiting percepts, all live). *)
