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

(** {2 Counting with fingerprints (D31, D36)}

    The counting path ([explore --fingerprints]): the same reachable states as
    {!explore}, found depth first. The visited set holds only a 63-bit
    fingerprint of each state (8 bytes, in a table at most three quarters full, outside
    the OCaml heap), and only the configurations found and not yet expanded
    are kept; no graph. A state is marked seen when it is generated, and the
    fingerprints of one state's successors are looked up together (D36). As in TLC, two different states
    with the same fingerprint would be taken for one and the second (with what
    only it leads to) missed: the probability of that is at most
    [distinct * generated / 2^63] ({!collision_probability}), about 6e-7 for
    1.5M states and 3.7M generated, if fingerprints behave as random numbers
    (TLC makes the same assumption of its 64-bit fingerprints). Comparisons
    with TLC's state graph ([explore --against-tlc], the conformance checks)
    use {!explore}, which is exact. *)

val state_fingerprint : Model.M.t -> int
(** The 63-bit fingerprint of a configuration (never 0): computed from the
    values its canonical {!key} is made of, without building the key. It is
    made in two levels (D36): a hash of each part of the configuration that
    is a structure (the queues, the behaviour lists, the dispatch in
    progress, the ghosts), then the fingerprint of those part hashes, the
    numbers and the last action. *)

val fingerprint_after : parent:Model.M.t -> Model.M.t -> int
(** [fingerprint_after ~parent c] is [state_fingerprint c], computed the way
    the counting path does for a successor [c] of [parent] (D36): the part
    hashes of [parent] are kept for every field of [c] that is physically
    the same value as [parent]'s, and only the other parts are hashed. *)

val count_successors : Model.t -> Model.M.t -> (int * Model.M.t) list
(** The successors {!count} takes (the configurations of {!successors}, in
    another order; the agent's rules asked by phase and, where it is faster,
    by the fast engine), each with the fingerprint the counting path gives
    it without hashing it whole (D36): for an agent rule's successor, as
    {!fingerprint_after} does; for a host rule's (Notify, NotifyWith, Put,
    Send), from the parent's part hashes and what the rule changes, before
    the successor is made (the counting path makes it only when the
    fingerprint is new). *)

type count = {
  c_model : Model.t;
  distinct : int;        (** distinct states found (by fingerprint) *)
  generated : int;       (** states generated: the initial one and every transition's target *)
  final : int;           (** states with no successor *)
  depth : int;           (** the longest path of the search tree (each state under the one that
                             generated it first), in states; not TLC's breadth-first depth *)
  table_bytes : int;     (** size of the fingerprint table *)
  c_seconds : float;
}

val count : ?max_states:int -> ?rules:Model.M.rules -> Model.t -> count
(** The successors of {!count_successors}: the agent's rules of the
    reference asked by phase, or by the fast engine ([Engine.Fast], held
    equal to the reference rule for rule on every state of every model by
    the test "engine step = reference step, every model state"), or the
    rules of [rules] when given (a mutant's), all of them.
    @raise Failure (an exhaustion error) beyond [max_states] distinct states. *)

val collision_probability : count -> float
(** The bound above on the probability that a fingerprint collision hid a state. *)
