(** Breadth-first enumeration of the reachable configurations of a model
    ([jadescript-ref explore MODEL]), with the host's actions bounded as the
    model says and every agent rule of {!Semantics.Machine}.

    States are identified by a compact canonical key (the O2A and message
    queues in order, the priority queue as a sorted set, every other variable),
    so two configurations are the same state exactly when they project onto the
    same TLA+ state. *)

type graph = {
  model : Model.t;
  states : Model.M.t array;          (** by state number, in discovery order *)
  initial : int list;
  edges : (int * string * int) array; (** (from, TLA+ action name, to) *)
  deadlocks : int list;              (** states with no successor *)
  seconds : float;
}

val successors : ?rules:Model.M.rules -> Model.t -> Model.M.t -> (Model.M.lbl * Model.M.t) list
(** Host rules (within the model's bounds) then agent rules: those of
    [rules] (the reference {!Semantics.Machine.Make.rules} by default; a
    mutant's table, {!Mutant.rules}, in the conformance checks). *)

val key : Model.M.t -> string
(** The canonical key of a configuration. *)

val show : Model.t -> Model.M.t -> string
(** A configuration in OCaml notation, one line: the phase, the queues, the
    behaviours and the last rule, as the machine's record holds them (the
    priority queue shown in dequeue order). *)

val default_max_states : int
(** 1,000,000: about 650 MB of states, keys and transitions. *)

val explore : ?max_states:int -> ?rules:Model.M.rules -> Model.t -> graph
(** @raise Failure (an exhaustion error) when more than [max_states] (default
    {!default_max_states}) states are found, before memory runs out. *)

val shortest_path : graph -> int -> (string * int) list
(** The labelled path from an initial state to the state, as (action, state)
    steps; the first element is ("Init", initial state). *)
