(* What test/proofs compares with docs/proofs.md: the statement of every
   theorem as coqc checked it and the definitions those statements use (the
   code blocks of docs/proofs.md, in this order, word for word; the
   "Arguments" lines coqc adds to a Print are left out), then the axioms
   the theorems rest on: there must be none ("Closed under the global
   context"). proofs/check.sh writes coqc's answer into audit.txt. *)

From Jsref Require Import Loop Run Facts Once Order Budget Tight Printed.

Set Printing Width 78.

(* The theorems, in the order of docs/proofs.md. *)
Check @exactly_once.
Check @refused_notification.
Check @transfer_moves_every_percept.
Check @transfer_native.
Check @transfer_always_taken.
Check @dequeue_takes_highest.
Check @dequeues_do_not_increase.
Check @dispatches_within_bound.
Check @behaviour_step_every_budget.
Check @no_behaviour_ready_at_next_iteration_or_idle.
Check @inversion_within_bound.
Check @inversion_bound_reached.
Check @reference_inversion_unbounded.
Check @printed_spins_forever.
Check @printed_flood_starves.
Check @printed_flood_run.

(* The definitions the statements use (the machine itself, Loop.v, is
   held equal to Machine.step by the tests instead). *)
Print reachable.
Print reachable_from.
Print next.
Print host_step.
Print run.
Print every_step.
Print places.
Print cur_seqs.
Print msg_percepts.
Print o2a_percepts.
Print o2a_objects.
Print is_transfer_label.
Print dispatch_bound.
Print within.
Print is_iteration_end.
Print is_dequeue.
Print count_dequeues.
Print is_notification.
Print is_behaviour_step.

(* Every theorem at once: the axioms they rest on. *)
Definition every_theorem :=
  (@exactly_once, @refused_notification, @transfer_moves_every_percept, @transfer_native,
   @transfer_always_taken, @dequeue_takes_highest, @dequeues_do_not_increase,
   @dispatches_within_bound, @behaviour_step_every_budget,
   @no_behaviour_ready_at_next_iteration_or_idle, @inversion_within_bound,
   @inversion_bound_reached, @reference_inversion_unbounded, @printed_spins_forever,
   @printed_flood_starves, @printed_flood_run).
Print Assumptions every_theorem.
