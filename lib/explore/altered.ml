(* Altered rules, for any bodies: written once, used by Mutant (the
   models) and by lib/defects (the interpreter). *)

open Semantics.Machine
module Fqueue = Semantics.Fqueue
module Pqueue = Semantics.Pqueue

module Make (B : BODIES) = struct
  module M = Semantics.Machine.Make (B)

  let r = M.rules

  let ties_to_largest_seq p (c : M.t) =
    let cands = r.dequeue { p with tie = Unstable } c in
    let seq (l, _) = match l with Dequeue e -> e.seq | _ -> min_int in
    let m = List.fold_left (fun m x -> max m (seq x)) min_int cands in
    List.filter (fun x -> seq x = m) cands

  let first_handler_only p (c : M.t) =
    List.map (fun ((l, (c' : M.t)) as x) -> match l, c'.cur with
        | Handle _, Some d -> (l, { c' with cur = Some { d with todo = [] } })
        | _ -> x) (r.handle_or_skip p c)

  let transfer_moves_one p (c : M.t) =
    match r.transfer p c with
    | [] -> []
    | x ->
      match Fqueue.remove_first (function O_percept _ -> true | O_object _ -> false) c.o2a with
      | None -> x
      | Some (first, rest) ->
        List.map (fun (l, (c' : M.t)) -> (l, { c' with o2a = rest }))
          (r.transfer p { c with o2a = Fqueue.of_list [ first ] })

  (* right after a transfer, a percept waiting and a behaviour ready *)
  let step_first (c : M.t) =
    c.phase = Dispatch_phase && c.ready <> [] && not (Pqueue.is_empty c.pq)
    && (match c.last with Transfer _ | Transfer_end -> true | _ -> false)

  let step_before_dispatch_dequeue p c = if step_first c then [] else r.dequeue p c

  let step_before_dispatch_step p (c : M.t) =
    if not (step_first c) then r.behaviour_step p c
    else
      List.map (fun (l, (c' : M.t)) -> (l, { c' with pq = c.pq; phase = Dispatch_phase }))
        (r.behaviour_step p { c with pq = Pqueue.empty })
end
