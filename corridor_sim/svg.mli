(** The pictures of a run, as standalone SVG 1.1 documents.

    - {!map}: the corridor seen from above (x to the right, y up), drop-offs
      (red), extra walls, the cubes with the QR text of each face written
      outside it, the trajectory (blue, green dot at the start, black at the
      end), the agent's worldMap entries (orange dots) with, for each mapped
      cube, the mean of its entries (orange diamond) joined to the true cube
      by a dashed line, collisions (red crosses) and falls (red rings).
    - {!timeline}: percept handling. Top: the first seconds of the run, one
      row for the agent's work (transfers, dispatches, behaviour steps) and
      one row per priority where each percept is a segment from its
      notification (hollow dot) to its dispatch (filled dot); red segments
      never reached their dispatch. Bottom: the latency of every percept
      over the whole run (log scale, one colour per priority; at most one
      point per priority and time bin, the worst), with never-dispatched
      percepts as red lower bounds. *)

val map : Sim.result -> Metrics.t -> string
val timeline : ?window:float -> Sim.result -> Metrics.t -> string
(** [window]: the seconds shown in the top panel (default: the first 10 s,
    or the whole run if shorter). *)

val escape : string -> string
(** XML escaping of text. *)
