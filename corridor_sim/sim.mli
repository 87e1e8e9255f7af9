(** The discrete-event simulation of one run: the robot, its sensors, the
    sound channel and the agent, in simulated time.

    {b Events.} Sensor samples at their rates (UWB position, proximity and
    edge detector, camera frames, accelerometer/gyroscope, and the flood
    source if the scenario has one), deliveries of readings that reach the
    phone late (a proximity alert travels as a tone; a QR code takes time to
    decode), tones played from the sound channel, and units of agent work.
    The agenda is ordered by time, then by scheduling order; every random
    draw comes from a [Random.State.t] seeded by the run's seed (one stream
    per noise source); no hash-table iteration order is ever used. Hence
    the same scenario and seed give the same run, and the same trace byte
    for byte.

    {b The agent.} The sensors start when the agent invokes [startListening].
    A notification reaches the agent at once (R2b) and wakes it if idle. The
    agent works one unit at a time ({!Agent.AGENT.step}); a unit starting at
    [t] ends at [t + cost]; host methods it invoked put their commands on
    the sound channel at [t + cost]. Notifications arriving meanwhile wait
    in the O2A queue (R3d). A percept's latency is the time from its
    notification to the start of its dispatch.

    {b The robot} is advanced to the time of each event before the event is
    handled ({!Robome.Robot.advance}). *)

type handled = {
  seq : int;
  percept : Agent.percept;
  priority : int;
  source : string;       (** ["uwb"], ["proximity"], ["edge"], ["camera"], ["imu"], ["flood"] *)
  notified : float;      (** s *)
  dispatched : float;    (** s: start of the dispatch *)
  handlers : int;        (** handlers that ran (0: discarded) *)
}

(** The dispatched percepts in dispatch order, in columns: entry [i] of
    each array for [i < d_n] (the arrays are longer). What {!handled}
    holds, recorded without a record per dispatch; read by
    {!Metrics}. *)
type dispatch_log = private {
  mutable d_n : int;
  mutable d_seq : int array;
  mutable d_priority : int array;
  mutable d_handlers : int array;
  mutable d_notified : float array;
  mutable d_dispatched : float array;
  mutable d_kind : int array;          (** 0 falling, 1 obstacle, 2 qrCodeRead, 3 position *)
  mutable d_x : float array;           (** a position's coordinates *)
  mutable d_y : float array;
  mutable d_text : string array;       (** a QR code's text *)
  mutable d_source : string array;
}

val log_get : dispatch_log -> int -> handled
(** Entry [i] as a record. *)

type pending = { p_seq : int; p_percept : Agent.percept; p_priority : int; p_notified : float }

type busy = { b_start : float; b_end : float; b_kind : string }
(** A unit of agent work: ["transfer"], ["dispatch"], ["step"], ["loop"]. *)

type result = {
  scenario : Scenario.t;
  seed : int;
  agent_name : string;
  world : Robome.World.t;
  end_time : float;
  final_pose : Robome.Kinematics.pose;
  trajectory : (float * Robome.Kinematics.pose) list;   (** time order *)
  collisions : (float * Robome.Kinematics.pose) list;
  falls : (float * Robome.Kinematics.pose) list;
  tippings : (float * Robome.Kinematics.pose) list;      (** near falls and falls *)
  notified : (string * int) list;   (** per percept name, accepted notifications *)
  refused : int;                    (** notifications refused by the agent (R2) *)
  handled : handled list Lazy.t;    (** dispatch order; made from [dispatches] when forced *)
  dispatches : dispatch_log;        (** the same, in columns *)
  pending : pending list;           (** never dispatched by the end, by seq *)
  world_map : (float * float * string) list;
  commands : (float * float * Robome.Command.t) list;   (** issued, took effect, command *)
  busy : busy list;                 (** agent work within the timeline window *)
  busy_total : float;               (** s the agent spent working *)
  odometer : float;                 (** m *)
  coverage : float;                 (** fraction of the free floor the body swept *)
  events : int;                     (** events processed *)
  trace : string;                   (** the trace, if asked for; "" otherwise *)
}

val coverage_cell : float
(** The side of the coverage grid's cells: 0.2 m. *)

module Make (A : Agent.AGENT) : sig
  val run : ?trace:bool -> ?timeline_window:float -> ?on_create:(A.t -> unit) ->
    Scenario.t -> seed:int -> result * A.t
  (** Simulate the scenario with this seed for its duration. [trace]
      (default false) records the textual trace; agent work is kept for the
      timeline over the first [timeline_window] seconds (default 20);
      [on_create] sees the agent right after its creation. *)
end

val run : ?trace:bool -> ?timeline_window:float -> (module Agent.AGENT) -> Scenario.t -> seed:int -> result
(** {!Make.run} for an agent given as a first-class module. *)
