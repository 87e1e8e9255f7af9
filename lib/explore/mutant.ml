(* Mutants as altered rule tables: each takes the reference rules of
   Model.M and changes one entry, from the outside. *)

open Semantics.Machine
module M = Model.M
module Fqueue = Semantics.Fqueue
module Pqueue = Semantics.Pqueue

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

(* Dequeue: among the entries of the highest priority (the Unstable
   policy's candidates), only the LAST notified. *)
let ties_to_largest_seq p (c : M.t) =
  let cands = r.dequeue { p with tie = Unstable } c in
  let seq (l, _) = match l with Dequeue e -> e.seq | _ -> min_int in
  let m = List.fold_left (fun m x -> max m (seq x)) min_int cands in
  List.filter (fun x -> seq x = m) cands

(* Handle: the rest of the snapshot is dropped once a handler ran. *)
let first_handler_only p (c : M.t) =
  List.map (fun ((l, (c' : M.t)) as x) -> match l, c'.cur with
      | Handle _, Some d -> (l, { c' with cur = Some { d with todo = [] } })
      | _ -> x) (r.handle_or_skip p c)

(* Transfer: only the first percept of O2A moves; the rest stays in order. *)
let transfer_moves_one p (c : M.t) =
  match r.transfer p c with
  | [] -> []
  | _ ->
    match Fqueue.remove_first (function O_percept _ -> true | O_object _ -> false) c.o2a with
    | None -> r.transfer p c
    | Some (first, rest) ->
      List.map (fun (l, (c' : M.t)) -> (l, { c' with o2a = rest }))
        (r.transfer p { c with o2a = Fqueue.of_list [ first ] })

(* Transfer: the percepts are copied, O2A keeps them. *)
let o2a_not_drained p (c : M.t) =
  List.map (fun (l, (c' : M.t)) -> (l, { c' with o2a = c.o2a })) (r.transfer p c)

(* Right after a transfer, with a percept waiting and a behaviour ready, a
   behaviour step runs before the dispatch (and Dequeue waits for it). *)
let step_first (c : M.t) =
  c.phase = Dispatch_phase && c.ready <> [] && not (Pqueue.is_empty c.pq)
  && (match c.last with Transfer _ | Transfer_end -> true | _ -> false)

let step_before_dispatch_dequeue p c = if step_first c then [] else r.dequeue p c

let step_before_dispatch_step p (c : M.t) =
  if not (step_first c) then r.behaviour_step p c
  else
    List.map (fun (l, (c' : M.t)) -> (l, { c' with pq = c.pq; phase = Dispatch_phase }))
      (r.behaviour_step p { c with pq = Pqueue.empty })

(* A one-shot behaviour ends its step as a cyclic one would: the same rule
   on bodies that call every behaviour cyclic. *)
module Cyclic_bodies = struct
  include Model.Bodies
  let cyclic _ = true
end

module Mc = Semantics.Machine.Make (Cyclic_bodies)

let rules = function
  | Ties_to_largest_seq -> { r with dequeue = ties_to_largest_seq }
  | First_handler_only -> { r with handle_or_skip = first_handler_only }
  | Transfer_moves_one -> { r with transfer = transfer_moves_one }
  | O2a_not_drained -> { r with transfer = o2a_not_drained }
  | Step_before_dispatch ->
    { r with dequeue = step_before_dispatch_dequeue; behaviour_step = step_before_dispatch_step }
  | Oneshot_not_removed -> { r with behaviour_step = Mc.behaviour_step }
