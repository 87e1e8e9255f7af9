(** The simulation's agenda: a binary min-heap of events ordered by time,
    ties broken by insertion order (first scheduled, first run), so that the
    order of events never depends on anything but the schedule. *)

type 'a t

val create : unit -> 'a t
val is_empty : 'a t -> bool
val size : 'a t -> int
val add : 'a t -> float -> 'a -> unit
(** Schedule an event at a time. *)

val pop : 'a t -> (float * 'a) option
(** The earliest event (the first scheduled among equal times). *)

val peek_time : 'a t -> float option
(** The time of the earliest event, if any. *)

val next_time : 'a t -> float
(** The time of the earliest event; [infinity] if there is none (nothing
    allocated: the simulation's loop asks this before every event). *)

val take : 'a t -> 'a
(** Remove the earliest event and return it (its time is {!next_time}
    just before).
    @raise Invalid_argument if the queue is empty. *)
