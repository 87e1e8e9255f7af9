(** Altered rules shared by the models' mutants ({!Mutant}) and the
    interpreter's bug catalogue ([lib/defects]): each is one rule of the
    reference machine changed from the outside, for any bodies. The
    reference rules ([lib/semantics/machine.ml]) know nothing of them.

    Written once here and instantiated twice: on the abstract bodies of the
    TLA+ models and on the interpreter's bodies. *)

module Make (B : Semantics.Machine.BODIES) : sig
  module M : module type of Semantics.Machine.Make (B)

  val ties_to_largest_seq : M.rule
  (** Dequeue: among the entries of the highest priority (the [Unstable]
      policy's candidates), only the last notified (R3b: the first). *)

  val first_handler_only : M.rule
  (** Handle or Skip: the rest of the snapshot is dropped once a handler
      ran (R4b: every applicable handler runs). *)

  val transfer_moves_one : M.rule
  (** Transfer: only the first percept of O2A moves, the rest stays in
      order (R3a: all of them). *)

  val step_before_dispatch_dequeue : M.rule
  val step_before_dispatch_step : M.rule
  (** Dequeue and BehaviourStep, altered together: right after a transfer,
      with a percept waiting and a behaviour ready, a behaviour step runs
      before the dispatch, and Dequeue waits for it (R3c: the dispatch
      first). *)
end
