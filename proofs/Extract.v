(* The machine of Loop.v extracted to OCaml: the library proved_loop
   (proofs/dune), which test/proofs holds equal to Machine.step. *)
From Coq Require Import Arith Extraction ExtrOcamlBasic.
From Jsref Require Import Loop Budget.

(* nat is extracted to OCaml's int (63 bits): every number of a run (seqs,
   priorities, counters, ids) stays far below max_int. These realizers of
   the operations on nat that the machine uses are part of what is trusted
   (docs/proofs.md, "What is trusted"). *)
Extract Inductive nat => "int" [ "0" "Stdlib.Int.succ" ]
  "(fun fO fS n -> if n = 0 then fO () else fS (n - 1))".
Extract Inlined Constant Init.Nat.add => "(+)".
Extract Inlined Constant Init.Nat.sub => "(fun n m -> Stdlib.max 0 (n - m))".
Extract Inlined Constant Init.Nat.eqb => "(=)".
Extract Inlined Constant Init.Nat.leb => "(<=)".
Extract Inlined Constant Init.Nat.ltb => "(<)".
Extract Inlined Constant Init.Nat.max => "Stdlib.max".
Extract Inlined Constant Init.Nat.min => "Stdlib.min".
Extract Inlined Constant Init.Nat.modulo => "(fun n m -> if m = 0 then n else n mod m)".
Extract Inlined Constant PeanoNat.Nat.add => "(+)".
Extract Inlined Constant PeanoNat.Nat.sub => "(fun n m -> Stdlib.max 0 (n - m))".
Extract Inlined Constant PeanoNat.Nat.eqb => "(=)".
Extract Inlined Constant PeanoNat.Nat.leb => "(<=)".
Extract Inlined Constant PeanoNat.Nat.ltb => "(<)".
Extract Inlined Constant PeanoNat.Nat.max => "Stdlib.max".
Extract Inlined Constant PeanoNat.Nat.min => "Stdlib.min".
Extract Inlined Constant PeanoNat.Nat.modulo => "(fun n m -> if m = 0 then n else n mod m)".
Extract Inlined Constant length => "List.length".

Extraction "proved_loop.ml"
  init notify notify_with notify_event put send o2a_has_room dispatch_bound
  transfer transfer_one transfer_spin transfer_end dequeue handle_or_skip end_dispatch
  behaviour_step next_iteration idle step.
