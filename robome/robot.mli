(** The simulated RoboMe: its pose, what it is doing, and what happens to it
    as time passes (motion, contact with walls and cubes, tipping over an
    edge and falling).

    {b Commands.} A command acts at the moment the robot has heard its tone
    ({!Sound_queue}). A motion command replaces the current motion, except
    during a preset turn (90/180/360 degrees): the robot finishes the
    manoeuvre first, and motion commands heard meanwhile wait in order and
    act when it ends; [Stop] acts at once, ends the manoeuvre and drops the
    waiting commands. Head tilts act at once. (The firmware's behaviour is
    not documented; this is an assumption.)

    {b Contact.} The body is a disc. Motion is integrated exactly
    ({!Kinematics.integrate}) over physics steps of at most [step] seconds;
    a step whose end position would overlap a wall or a cube keeps the
    position (the robot's wheels spin) and takes only the rotation. A new
    contact counts as one collision; a contact ends when the body is clear
    of every obstacle by 1 cm.

    {b Falling.} When the leading point of the body (its front when moving
    forward or turning, its back when moving backward) is over a drop-off,
    the robot is tipping: the phone's accelerometer and gyroscope notice it.
    When its centre is over a drop-off it has fallen: it stays where it is
    and ignores every later command. *)

type head = Neutral | Up | Down

type motion =
  | Halted
  | Drive of { v : float; omega : float }
  | Manoeuvre of { omega : float; until : float }

type event =
  | Collision of Kinematics.pose   (** a new contact begins *)
  | Tipping_start of Kinematics.pose
  | Tipping_end of Kinematics.pose (** the robot backed away from the edge *)
  | Fall of Kinematics.pose

type t

val create : ?step:float -> ?rng:Random.State.t -> Params.t -> World.t -> Kinematics.pose -> t
(** A halted robot at time 0 ([step], the physics step, defaults to 0.01 s).
    Motion noise ({!Params.t.speed_noise}, {!Params.t.drift}) is drawn from
    [rng] (default: a fixed seed), once per motion command. *)

val params : t -> Params.t
val world : t -> World.t
val time : t -> float
val pose : t -> Kinematics.pose
val motion : t -> motion
val head : t -> head
val tipping : t -> bool
val fallen : t -> bool
val odometer : t -> float
(** Metres travelled so far (wheel slip against an obstacle excluded). *)

val moving : t -> bool
(** Not [Halted] and not fallen. *)

val advance : t -> float -> event list
(** [advance r t] moves the robot forward to time [t] (no effect if [t] is
    not later than {!time}) and returns what happened, in order. *)

val apply : t -> Command.t -> unit
(** Act on a command at the current time (call {!advance} first).
    @raise Invalid_argument if the command is not {!Command.valid}. *)

val on_step : t -> (t -> unit) -> unit
(** Register a function called after every physics step while the robot
    moves (the simulation records the trajectory and the coverage with it). *)

val gaussian : Random.State.t -> float
(** A standard normal sample (Box-Muller). *)

val head_pitch : t -> float
(** The camera's pitch for the current head position (rad). *)
