(** Scenario files: the world, the robot, the sensors and the agent of one
    simulated experiment, read from JSON. The format is documented field by
    field in docs/simulation.md. Units: metres, seconds, hertz and degrees
    (angles in files are in degrees; inside the simulation they are
    radians). Unknown fields are rejected, so that a misspelt field is not
    silently ignored. *)

type sensors = {
  position_rate : float;     (** Hz: UWB [position] percepts *)
  uwb_sigma : float;         (** m: standard deviation of the UWB noise per axis *)
  proximity_rate : float;    (** Hz: proximity sensor and edge detector samples *)
  obstacle_band : float;     (** m: bands at or below this give [obstacle] *)
  obstacle_repeat : float;   (** s: an alert repeats this often while it lasts *)
  edge_detector : bool;      (** is the robot's edge detector in use? *)
  camera_rate : float;       (** Hz: camera frames searched for QR codes *)
  qr_repeat : float;         (** s: the same text is not notified again sooner *)
  imu_rate : float;          (** Hz: accelerometer/gyroscope samples *)
  falling_repeat : float;    (** s: [falling] repeats this often while tipping *)
  overrides : (string * int) list;
      (** percept name -> priority passed to [notify] (R2a); absent: default *)
}

type flood = {
  percept : string;          (** ["position"], ["obstacle"], ["qrCodeRead"] or ["falling"] *)
  text : string;             (** the QR text of a [qrCodeRead] flood *)
  rate : float;              (** Hz *)
  start_time : float;        (** s *)
  end_time : float;          (** s *)
  priority : int option;     (** override, if any *)
}

type random_cubes = {
  count : int;
  size : float;              (** m *)
  min_gap : float;           (** m between two cubes, and from the walls *)
  keep_clear : float;        (** m: no cube this close to the start position *)
}

type t = {
  name : string;
  description : string;
  seed : int;
  duration : float;          (** s of simulated time *)
  length : float;            (** m *)
  width : float;             (** m *)
  walls : Robome.World.segment list;
  cubes : Robome.World.cube list;
  random_cubes : random_cubes option;
  dropoffs : Robome.World.rect list;
  start : Robome.Kinematics.pose;
  params : Robome.Params.t;
  mapping : Robome.Host.mapping;
  sensors : sensors;
  flood : flood option;
  loop : Agent.loop;
  cost : Agent.cost;
  physics_step : float;      (** s *)
  trajectory_step : float;   (** s between two recorded trajectory points *)
}

exception Error of string

val of_json : Yojson.Safe.t -> t
(** @raise Error naming the offending field. *)

val load : string -> t
(** Read a scenario file. @raise Error (also for unreadable JSON). *)

val world : t -> seed:int -> Robome.World.t
(** The world of a run: the fixed cubes and, if the scenario asks for them,
    cubes placed at random from the seed (their faces read [R<i>-E],
    [R<i>-N], [R<i>-W], [R<i>-S]). *)

val with_position_rate : t -> float -> t
(** The same scenario with another [position_rate] (the benchmark's 50 Hz). *)
