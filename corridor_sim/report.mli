(** The JSON report of a run (format in docs/simulation.md). Every real
    number is printed with a fixed number of decimals (3 for metres and
    fractions, 6 for seconds), so that equal runs give equal files. *)

val to_json : Sim.result -> Metrics.t -> Yojson.Safe.t
val to_string : Sim.result -> Metrics.t -> string
(** Pretty-printed, with a final newline. *)

val fixed : int -> float -> Yojson.Safe.t
(** A number printed with this many decimals ([null] for nan or infinity). *)
