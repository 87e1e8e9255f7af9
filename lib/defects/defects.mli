(** The bug catalogue: deliberate defects of the interpreter, each a bug a
    second implementer of a Jadescript runtime could plausibly make, so that
    the conformance vectors can be judged by how many they catch (their
    "kill count": [make conformance], conformance/README.md).

    A defect is never a branch of the reference rules
    (lib/semantics/machine.ml, lib/interp/eval.ml stay as they are). Each is
    built from the outside, as the explorer's mutants are
    (lib/explore/mutant.ml): an altered rule table of the reference machine
    ([M.step_by]), the machine's functor applied to bodies with one function
    changed, the evaluator's functor ({!Interp_eval.Eval.Make}) applied to
    primitives with one changed (integer division, widening, equality, the
    text of a value, subtyping), or a platform operation (notify, put, the
    order of a round, the agent's creation and destruction, ams's failure, a
    delivery during a step) wrapped around the reference's.
    {!Interp.Runtime.create} takes the result as its [hooks]; [jadescript-ref
    run --defect NAME] runs a defective interpreter as an implementation for
    [conform --impl]. *)

type t = {
  name : string;         (** e.g. ["put-ignores-capacity"] *)
  ruling : string;       (** the ruling or decision it breaks, e.g. ["R2d"] *)
  about : string;        (** one line: what the defective implementation does *)
  can_differ : bool;
      (** whether its trace can differ from the reference's at all; [false]
          for a defect no trace can show (the vectors need not kill it) *)
  blind : string option;
      (** why the judge cannot see it, when it cannot: the defect changes
          only what the rulings leave free (the order of the agents' rules,
          of different receivers' messages, R6) or a host operation the
          judge reads from the trace itself; [defects --judge] and
          [--generated] count it as a survivor without running it *)
  hooks : Interp.Runtime.hooks;   (** how a run takes it *)
}

val all : t list
(** The catalogue, one typed table, roughly in the order of the rulings:
    percept types (R1), the host's operations (R2, D3, R6), the loop (R3),
    the handlers (R4), the behaviours and messages (R5), then the rest; then
    the later ones: the evaluator's primitives (D8, D9, R1a, R1c, R8), the
    priority queue's batches and ties, the ready list, messages, ids, errors
    (R7), on destroy (D14), failures (D43), deliveries during a step (D42)
    and the order of sends (R5e). *)

val find : string -> t option
