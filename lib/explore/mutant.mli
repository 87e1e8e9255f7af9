(** Deliberate semantic mutants of the agent rules, to show that the
    comparison with TLC has teeth (docs/semantics.md, "Mutants"). Each is an
    altered table of rules ({!Semantics.Machine.Make.rules}) built here, out
    of the reference rules, which know nothing of them. *)

type t =
  | Ties_to_largest_seq     (** Dequeue breaks ties towards the LAST notified *)
  | First_handler_only      (** a dispatch stops after the first handler ran *)
  | Transfer_moves_one      (** Transfer moves only the first O2A percept *)
  | Step_before_dispatch    (** a behaviour step runs before the dispatch *)
  | Oneshot_not_removed     (** a one-shot behaviour stays active *)
  | O2a_not_drained         (** Transfer copies percepts but leaves them in O2A *)

val all : (string * t) list
(** Every mutant, with its name ([ties-largest-seq], ...). *)

val rules : t -> Model.M.rules
(** The reference rules of the models' machine with the mutant's change. *)
