(** The metrics of one run, computed from a {!Sim.result}. *)

type latency = {
  priority : int;
  count : int;        (** percepts of this priority dispatched *)
  mean : float;       (** s, from notification to dispatch *)
  p95 : float;        (** s *)
  max : float;        (** s *)
}

type cube_map = {
  cube : string;
  entries : int;          (** worldMap entries holding one of its texts *)
  error : float option;   (** m: distance from the mean of those positions to the true centre *)
}

type t = {
  duration : float;            (** s simulated *)
  cubes_total : int;
  cubes_mapped : int;          (** cubes with at least one of their texts in the map *)
  map_entries : int;           (** entries of the agent's worldMap *)
  map_error_mean : float option;   (** m, over the mapped cubes *)
  map_error_max : float option;    (** m *)
  cubes : cube_map list;
  collisions : int;
  falls : int;
  near_falls : int;            (** tippings that did not end in a fall *)
  distance : float;            (** m *)
  coverage : float;            (** 0-1 *)
  latency : latency list;      (** by priority, highest first *)
  latency_max : float;         (** s, over every dispatched percept *)
  notified : (string * int) list;
  refused : int;
  unhandled : int;             (** notified but never dispatched *)
  unhandled_oldest : float;    (** s: the longest such wait at the end *)
  commands : int;              (** commands the robot acted on *)
  utilisation : float;         (** fraction of the time the agent was working *)
}

val of_result : Sim.result -> t

val summary_fields : (string * (t -> float)) list
(** The numeric metrics the batch table shows, by name (a missing mapping
    error counts as [nan] and is left out of the statistics). *)

val sort_floats : float array -> unit
(** Sort in place into the order of [Array.stable_sort Float.compare] (the
    same array, element for element, nan and signed zeros included), by a
    natural merge sort that compares the floats unboxed (it merges the runs
    already in order: a run's latencies come in some forty): the latencies
    of a run are sorted with it (D35: the same floats; tested against
    [Array.stable_sort]). *)
