(** Turning a run into trace events ({!Trace}): what the runtime and the
    playground write, from the machine's labels, the configurations before
    and after each rule, and the events of the bodies, which the caller
    takes from the agent ({!Eval.take_events}) and hands over. *)

type t

val create : ?level:string -> Trace.writer -> on_body:(string -> Eval.event -> unit) -> t
(** [on_body agent e] sees every event of a body as it is written (the
    runtime prints logs and errors there). [level] ["observable"]: the
    loop's own steps are not written ({!Trace.observable}); default
    ["full"]. *)

val writer : t -> Trace.writer

val header :
  t -> Typing.Tenv.t -> Semantics.Machine.params -> seed:int option -> (string * string) list -> unit
(** The header line: the run's parameters, its agents (name, type) and the
    program's behaviours and percept types. *)

val program_summary : Typing.Tenv.t -> Trace.behaviour_info list * (string * int) list
(** The program's part of a header: every behaviour type (kind, action
    block, handler counts, inherited first) and every percept type with its
    default priority (R1a). *)

type config = (Value.t, Eval.message, Value.t, Eval.beh, Eval.agent) Semantics.Machine.config
type label = (Value.t, Eval.message, Value.t) Semantics.Machine.label

val created : t -> agent:string -> agent_type:string -> Value.t list -> Eval.beh list -> Eval.event list -> unit
(** The [create] line of an agent, then the events of its [on create]. *)

val event_of :
  percept:(?keep:bool -> Value.t -> string) -> name:(int -> string) -> config -> label -> Eval.event list ->
  Trace.event
(** The trace event of a rule: its label [l], the configuration [c] it
    reached (a Put's index), the events its bodies recorded (a handler's
    effects); [percept] writes a percept ([Value.to_literal]; [keep] for a
    dequeue), [name] names an instance's behaviour. What {!step} writes,
    and what the judge expects. *)

val body : Eval.event -> Trace.body option
(** The line of a body's event; [None] for [Ran], which is no line. *)

val host : ?in_step:bool -> t -> agent:string -> config -> unit
(** The line of a host rule (Notify, NotifyWith, Put, Send), from the
    configuration it reached; [in_step]: a message that reached the agent
    during its last behaviour step (its action SendInStep, R5d). *)

val refused : t -> agent:string -> Value.t -> unit
(** A notification refused (R2d). *)

val refused_put : t -> agent:string -> Value.t -> unit
(** An object refused by putO2AObject: the O2A queue is full (R2d). *)

val undeliverable : t -> sender:string -> receiver:string -> Eval.message -> unit

val step : t -> agent:string -> before:config -> after:config -> label -> Eval.event list -> unit
(** The line of an agent rule, then the events of the bodies it ran. *)

val inside : t -> agent:string -> start:config -> label -> Eval.event list -> unit
(** D33: the line of a rule taken inside the derived rule Dispatch
    ([Engine.S.dispatch ~observe]: Dequeue, Handle, Skip; not its last,
    EndDispatch, which the platform sees as the step), then the events of
    the body it ran; [start] is the configuration the dispatch started
    from. The lines are those {!step} writes for the same rules taken one
    at a time. *)

val destroyed : t -> agent:string -> Eval.event list -> unit
(** The [destroy] line, then the events of [on destroy]. *)
