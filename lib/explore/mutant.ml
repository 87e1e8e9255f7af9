(* Mutants as altered rule tables: each takes the reference rules of
   Model.M and changes one entry, from the outside. *)

open Semantics.Machine
module M = Model.M

type t =
  | Ties_to_largest_seq
  | First_handler_only
  | Transfer_moves_one
  | Step_before_dispatch
  | Oneshot_not_removed
  | O2a_not_drained

let all = [
  "ties-largest-seq", Ties_to_largest_seq;
  "first-handler-only", First_handler_only;
  "transfer-moves-one", Transfer_moves_one;
  "step-before-dispatch", Step_before_dispatch;
  "oneshot-not-removed", Oneshot_not_removed;
  "o2a-not-drained", O2a_not_drained;
]

let r = M.rules

(* Ties to the last notified, the first handler only, one percept moved,
   a behaviour step before the dispatch: the altered rules shared with the
   bug catalogue (Altered). *)
module A = Altered.Make (Model.Bodies)

(* Transfer: the percepts are copied, O2A keeps them. *)
let o2a_not_drained p (c : M.t) =
  List.map (fun (l, (c' : M.t)) -> (l, { c' with o2a = c.o2a })) (r.transfer p c)

(* A one-shot behaviour ends its step as a cyclic one would: the same rule
   on bodies that call every behaviour cyclic. *)
module Cyclic_bodies = struct
  include Model.Bodies
  let cyclic _ = true
end

module Mc = Semantics.Machine.Make (Cyclic_bodies)

let rules = function
  | Ties_to_largest_seq -> { r with dequeue = A.ties_to_largest_seq }
  | First_handler_only -> { r with handle_or_skip = A.first_handler_only }
  | Transfer_moves_one -> { r with transfer = A.transfer_moves_one }
  | O2a_not_drained -> { r with transfer = o2a_not_drained }
  | Step_before_dispatch ->
    { r with dequeue = A.step_before_dispatch_dequeue; behaviour_step = A.step_before_dispatch_step }
  | Oneshot_not_removed -> { r with behaviour_step = Mc.behaviour_step }
