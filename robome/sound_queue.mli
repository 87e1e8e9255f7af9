(** The sound channel from the phone to the robot.

    The SDK plays each command as a tone on the headset output; tones are
    queued and played one after another, with a gap between two tones (the
    Android SDK's default gap is 100 ms). The robot acts on a command when it
    has heard its whole tone. A command enqueued at time [t] therefore takes
    effect at [max t free + duration], where [free] is when the channel
    becomes free (the end of the previous tone plus the gap). *)

type t

val create : duration:float -> gap:float -> t
(** An empty, free channel (seconds). *)

val enqueue : t -> now:float -> Command.t -> unit
(** Queue a command issued at [now]. Commands must be enqueued in
    non-decreasing order of [now]. *)

val next_effect : t -> float option
(** When the command at the head of the queue will take effect, if any. *)

val pop : t -> (Command.t * float * float) option
(** Play the head command: the command, when it was issued and when it takes
    effect ({!next_effect}); the channel is then busy until that time plus the
    gap. *)

val length : t -> int
(** Commands waiting. *)
