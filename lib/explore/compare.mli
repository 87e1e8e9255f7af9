(** Are two state graphs the same? The explorer's graph and TLC's, both mapped
    to canonical TLA+ states, compared as sets of states, of initial states and
    of labelled transitions (from-state, action, to-state). *)

type side = Explorer_only | Tlc_only

type difference =
  | Initial of side * Tla.t
  | State of side * Tla.t
  | Transition of side * Tla.t * string * Tla.t

type report = {
  ocaml_view : string -> string option;
      (** the explorer's configuration (OCaml notation) of a canonical TLA+ state *)
  explorer_states : int;
  tlc_states : int;
  explorer_transitions : int;
  tlc_transitions : int;
  differences : difference list;        (** all of them, shortest path first *)
  witness : (string * Tla.t) list;      (** a shortest path to the first difference,
                                            in the graph that has it *)
}

val graphs : Explorer.graph -> Dot.graph -> report

val agree : report -> bool

val render : report -> string
(** A summary; on a difference, the first one and the path to it, each step
    in both notations: the TLA+ variables it changed, and the OCaml
    configuration (or a note that the machine does not reach that state). *)
