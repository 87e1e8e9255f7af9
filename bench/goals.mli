(** The bench's goals and the figures one run measured for them, so that
    [make bench] prints every figure with its goal (bench/README.md). *)

val record : ?met:bool -> string -> string -> unit
(** [record ~met goal figure]: the goal as words ("steady: at least 3x
    JADE's direct O2A in every round"), this run's figure, and whether the
    figure meets it ([None]: a figure printed for reference, no goal). *)

val print : unit -> unit
(** The table of every goal recorded so far, in order, with a count of
    those met and not met. *)
