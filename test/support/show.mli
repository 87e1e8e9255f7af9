(** The interpreter's machine as text, for the tests that hold two runs of
    it equal (the fast engine, the derived rule Dispatch, the packed agent
    against the reference): two configurations are equal when their texts
    are. One printer for all of them. *)

type config =
  (Interp.Value.t, Interp.Eval.message, Interp.Value.t, Interp.Eval.beh, Interp.Eval.agent)
    Semantics.Machine.config

type label = (Interp.Value.t, Interp.Eval.message, Interp.Value.t) Semantics.Machine.label

val entry : Interp.Value.t Semantics.Machine.entry -> string
(** [percept/priority/seq]. *)

val label : label -> string
(** The TLA+ action name and the label's fields. *)

val config : config -> string
(** Every field of the configuration but [world]: O2A in order, the
    priority queue as its entries in dequeue order, the message queue's
    length, the counters, the behaviour part, the dispatch in progress, the
    ghosts' sizes and the last label. *)

val event : Interp.Eval.event -> string
(** What a body recorded. *)
