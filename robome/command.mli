(** The commands of the RoboMe SDK that the simulation models (the
    [RoboMeCommands] set of WowWee's Android SDK, reduced to motion and head
    tilt). *)

type turn =
  | Speed of int     (** a continuous turn at speed level 1-5 *)
  | Degrees of int   (** a preset turn by 90, 180 or 360 degrees *)

type t =
  | Stop
  | Forward of int   (** speed level 1-5 *)
  | Backward of int  (** speed level 1-5 *)
  | Turn_left of turn
  | Turn_right of turn
  | Head_up
  | Head_down
  | Head_reset

val valid : t -> bool
(** Speed levels in 1-5, preset angles in {90, 180, 360}. *)

val is_motion : t -> bool
(** Everything except the head tilts. *)

val to_string : t -> string
(** ["stop"], ["forward(3)"], ["turn_left(90deg)"], ["turn_right(speed 2)"],
    ["head_up"], ... (used in traces). *)

val of_string : string -> t option
(** The inverse of {!to_string}. *)
