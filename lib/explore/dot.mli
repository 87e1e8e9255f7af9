(** TLC's state graph, read from [-dump dot,actionlabels FILE].

    One node per distinct state, labelled with [/\ var = value] lines (DOT
    escapes on top of TLA+ string escapes; record fields in any order); the
    initial states have [style = filled]; one edge per transition, labelled with
    the action name only. *)

type graph = {
  nodes : (string * Tla.t) list;         (** node id, state as a canonical record *)
  initial : string list;
  edges : (string * string * string) list;  (** from, action, to *)
}

val parse : string -> graph
(** @raise Tla.Parse_error or [Failure] on a malformed dump. *)

val parse_state : string -> Tla.t
(** A state written as [/\ var = value] lines (also used for TLC's
    counterexamples and simulation traces). *)
