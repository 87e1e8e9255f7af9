(** The interface between the simulated world and the agent that controls
    the robot.

    The simulation does not know how the agent is implemented: it talks to
    any module of type {!AGENT}. The OCaml reference controller
    ({!Reference_controller}) is one; an interpreter running
    [examples/paper/robome_completed.jade] is meant to be another, plugged in
    without changing the simulation.

    {b Time.} The agent runs in simulated time. The simulation asks it for
    one unit of work at a time ({!AGENT.step}: a transfer, the dispatch of
    one percept to its handlers, a behaviour step, or the loop's own
    bookkeeping) and charges that work's cost ({!cost}) before asking for the
    next one, so notifications from the sensors interleave with the agent's
    loop exactly as the host actions interleave with the agent's steps in
    [spec/AgentLoop.tla]. *)

type percept =
  | Falling                     (** [falling], priority 10 *)
  | Obstacle                    (** [obstacle], priority 8 *)
  | Qr_code_read of string      (** [qrCodeRead(qrCode)], priority 4 *)
  | Position of float * float   (** [position(x, y)], priority 2; metres *)
(** The percepts of the [RoboMeApplication] ontology (paper, Figure 5). *)

val default_priority : percept -> int
(** The ontology's default priorities: 10, 8, 4, 2 (R1a). *)

val percept_name : percept -> string
(** ["falling"], ["obstacle"], ["qrCodeRead"], ["position"]. *)

val percept_to_string : percept -> string
(** [falling], [qrCodeRead("A1")], [position(1.250, 0.500)] (fixed
    precision: traces compare byte for byte). *)

type host = Robome.Host.t
(** The host object the agent receives in [on create] (paper: [as any]). *)

(** One unit of agent work, as reported by {!AGENT.step}. *)
type work =
  | Transfer of { moved : int; o2a_calls : int }
      (** percepts moved from the O2A queue to the priority queue (R3a), with
          the number of O2A accesses it took (1 for the reference loop's
          atomic transfer, 1 per percept in the printed loop) *)
  | Dispatch of { percept : percept; priority : int; seq : int; handlers_run : int }
      (** one percept removed from the priority queue and offered to every
          registered handler (R3b); [seq] is the one {!AGENT.notify}
          returned; [handlers_run] = 0 means it was discarded *)
  | Behaviour_step  (** one behaviour step (R3c, R5) *)
  | Loop of { o2a_calls : int }
      (** the loop's bookkeeping: the end of a printed transfer loop, the
          start of a new iteration, going idle *)

(** How much simulated time a unit of work costs (seconds). *)
type cost = {
  o2a_call : float;            (** one synchronised access to the O2A queue *)
  transfer_per_percept : float;(** moving one percept into the priority queue *)
  dispatch : float;            (** dequeue and pattern-match one percept *)
  handler : float;             (** run one handler body *)
  invoke : float;              (** one [invoke] of a host method *)
  behaviour_step : float;      (** one behaviour step *)
  iteration : float;           (** the loop's bookkeeping per {!Loop} *)
}

val work_of_step :
  take:(unit -> ('p, 'm, 'o) Semantics.Machine.label option) -> percept:('p -> percept) ->
  ('p, 'm, 'o) Semantics.Machine.label -> work
(** The unit of work that begins with this step of the machine: a [Dequeue]
    takes the following steps ([take]) up to its [EndDispatch], counting the
    handlers that ran; [percept] turns the machine's percepts into the
    simulation's. Shared by every agent built on {!Semantics.Machine}. *)

val default_cost : cost
(** 0.2 ms per O2A access, 0.01 ms per percept moved, 0.05 ms per dispatch,
    0.1 ms per handler body, 0.05 ms per invoke, 0.1 ms per behaviour step,
    0.01 ms of bookkeeping: a plausible order of magnitude for JADE on an
    Android phone of the paper's time; these are assumptions. *)

val cost_of : cost -> work -> invokes:int -> float
(** The cost of a unit of work during which the agent invoked [invokes]
    host methods. *)

(** How the agent's loop is run: the variants of [spec/AgentLoop.tla]. *)
type loop = {
  variant : Semantics.Machine.variant;  (** [Reference] (R3), [Printed], [Budgeted] *)
  budget : int;                         (** dispatches per iteration, [Budgeted] only *)
  o2a_capacity : int option;            (** R2d; [None]: unbounded *)
}

val default_loop : loop
(** The reference loop, budget 4, unbounded O2A queue. *)

(** An agent controlling the robot. *)
module type AGENT = sig
  type t

  val name : string
  (** A short name for reports (["reference"], ...). *)

  val create : loop -> host -> t
  (** Create the agent and run its [on create] with the host object (R5g);
      the host methods it invokes act at simulated time 0. *)

  val notify : t -> percept -> priority:int option -> (int, string) result
  (** The host notifies a percept (R2): [priority = None] gives the
      percept's default priority, [Some k] overrides it. [Ok seq] is the
      percept's arrival number (R2b), reported back by the {!work.Dispatch}
      that handles it; [Error] when the notification is refused (a negative
      priority, a full O2A queue: R2a, R2d). Never blocks, never runs the
      agent. *)

  val step : t -> work option
  (** Run one unit of work of the agent's loop; the handlers it runs may
      invoke host methods. [None] when the agent is idle (R3e): nothing is
      run, and the agent wakes on the next notification. *)

  val world_map : t -> (float * float * string) list
  (** The agent's [worldMap]: for each mapped position (x, y), the QR text
      stored there, in the order the keys were first stored. *)
end

val dispatch_work :
  dispatch:((('p, 'm, 'o) Semantics.Machine.label -> unit) -> bool) ->
  record:(('p, 'm, 'o) Semantics.Machine.label -> unit) -> percept:('p -> percept) -> work option
(** A whole dispatch as one piece of work, what {!work_of_step} makes of its
    rules taken one at a time (Dequeue, Handle or Skip per handler,
    EndDispatch), in one call of the engine's derived rule (D29):
    [dispatch observe] runs [Engine.Fast.dispatch ~observe] and says whether
    it applied; every label is [record]ed in order. [None] when it did not
    apply (the caller then takes one rule). *)
