(** The counterexamples of docs/spec.md ("The counterexamples that matter"),
    replayed on the OCaml machine: for each TLC model, a Jadescript program
    with the model's percepts, priorities, handlers and O2A capacity, the
    model's loop variant and tie policy, and TLC's steps as host actions and
    agent rules, each labelled with its TLA+ action and a sentence on what
    goes wrong. The last state is checked against the state TLC printed
    ({!check}), or, for a model where every property holds and TLC prints
    none (MCBudgeted), against the state the same steps reach there. *)

type action =
  | Host of Session.host_action
  | Rule                    (** the one enabled rule (the first under unstable ties) *)
  | Dequeue_seq of int      (** under unstable ties: the Dequeue of this seq *)

type step = {
  action : action;
  tla : string;             (** the TLA+ action, as TLC's trace labels it *)
  say : string;             (** what happens, and what goes wrong *)
}

type t = {
  id : string;              (** the model: ["MCPrintedObject"], ... *)
  title : string;
  finding : string;         (** the property violated, and the lesson *)
  command : string;         (** the one command line that has TLC find it ([make spec ...]) *)
  setup : Session.setup;
  steps : step list;
  final : string;
      (** the last state, in the spec's terms: TLC's counterexample's when
          [violated]; otherwise the state these steps reach in the model,
          where TLC prints no state *)
  violated : bool;
      (** whether TLC finds a property of the model violated (it then prints
          the counterexample replayed); [false] for MCBudgeted, where every
          property holds *)
}

val all : t list
(** MCPrintedObject, MCFloodPrinted, MCInversion, MCBudgeted (the same
    events, with the budget that bounds the wait), MCTiesUnstable, MCNative,
    MCFloodNative. *)

val find : string -> t option

val apply : Session.t -> step -> (unit, string) result
(** Does one step in the session (which must have been created from the
    replay's setup). *)

val check : t -> Session.t -> (unit, string) result
(** After every step: is the session's agent in the state TLC printed
    ({!t.final}; for MCBudgeted, the state these steps reach)? [Error] says
    which part differs. *)

val run : t -> (Session.t, string) result
(** Creates the session and applies every step. *)

val to_json : unit -> Yojson.Safe.t
(** Every replay, for the page: id, title, finding, command, final, violated, the setup
    (files, agents, variant, tie, budget, o2a_capacity) and the steps (tla,
    say, and what is done). *)
