(** A platform: several agents, each a {!Machine} configuration, and the
    host's view of them (R6).

    Agents run concurrently; one loop iteration of one agent is atomic with
    respect to the others. {!iteration} runs one iteration of one agent: its
    steps from a transfer up to the next transfer (after its behaviour step or
    NextIteration) or until it idles. Messages its bodies send are delivered at
    once, at the end of the step that sent them, to the receivers' message
    queues (R5e: first in, first out per receiver); a message to an unknown
    agent is not delivered and is reported. {!round} orders the agents for one
    round: creation order, or a permutation drawn from a seed (R6); the
    runtime and the playground run the agents that are not idle in that
    order. *)

module Make (B : Machine.BODIES) : sig
  module M : module type of Machine.Make (B)

  type agent = { name : string; config : M.t }

  type t = {
    agents : agent array;      (** in creation order (R5g) *)
  }

  type event =
    | Step of string * M.lbl                   (** an agent took a rule *)
    | Delivered of { sender : string; receiver : string; message : B.message }
    | To_platform of { sender : string; receiver : string; message : B.message }
        (** a message to one of the platform's own agents ({!platform_agents}):
            theirs, never answered, since they take only messages of their
            own ontologies (R5e, D44) *)
    | Undeliverable of { sender : string; receiver : string; message : B.message }
        (** the receiver is not on the platform: the platform answers the
            sender with a failure from [ams] (R5e) *)

  val platform_agents : string list
  (** [["ams"; "df"]]: the agents every JADE platform has (R5e). No agent of
      a program takes their names. *)

  val create : (string * M.t) list -> t
  (** Agents in creation order, each already created ([on create] run). *)

  val find : t -> string -> int option

  val deliver : Machine.params -> t -> sender:string -> receiver:string -> B.message -> t * event
  (** A message from [sender] (an agent, the host or a platform agent) to
      [receiver] (R5e): into its message queue when it is an agent of the
      run ({!Delivered}); else the platform's ({!To_platform},
      {!Undeliverable}), the platform unchanged. *)

  val deliver_in_step : Machine.params -> t -> sender:string -> receiver:string -> B.message -> (t * event) option
  (** {!deliver} to an agent of the run whose last rule was a behaviour
      step, during that step (the machine's SendInStep, R5d revised);
      [None] when the receiver is not such an agent. *)

  val arrival : Machine.params -> t -> int option -> sender:string -> receiver:string -> B.message ->
    (int * M.t) option * event
  (** {!deliver} as a change: [arrival p t at ...], [at] the receiver's
      index in [t] ({!find}), gives the receiver's index and configuration
      after the message, if it is an agent of the run, and the event. For a
      run that keeps its platform in place and its agents indexed by name
      (lib/interp/runtime.ml), so that a delivery costs no copy and no
      search of the agents. *)

  val arrival_in_step : Machine.params -> t -> int option -> sender:string -> receiver:string -> B.message ->
    (int * M.t * event) option
  (** {!deliver_in_step} as a change, as {!arrival}. *)

  val iteration :
    ?max_steps:int -> ?on_event:(t -> event -> unit) ->
    ?step:(Machine.params -> M.t -> (M.lbl * M.t) list) -> ?keep:bool ->
    Machine.params -> t -> int -> t * event list
  (** One loop iteration of agent [i] ([max_steps] bounds it; default 10^6).
      Empty when the agent is idle. Under the [Unstable] tie policy the first
      candidate is taken. [on_event] sees each event as it happens, with the
      platform right after it (a step's event before the deliveries of the
      messages that step sent). [step] takes the agent's rules: [M.step]
      by default; the runtime passes the fast engine's, which answers the
      same. [~keep:false]: the events are only handed to [on_event], and
      the list answered is empty (a long iteration then holds none). *)

  val round : Random.State.t option -> t -> int list
  (** The order of one round (R6): the agents' indices in creation order
      ([None]), or a permutation drawn from the random state (Fisher-Yates
      from the last index down, docs/trace-format.md). *)

  val all_idle : t -> bool
end
