(* The bug catalogue: deliberate defects of the interpreter, as a second
   implementer of Jadescript runtimes would plausibly make them. Each one is
   built from the outside, as mutants are (lib/explore/mutant.ml): an altered
   rule table of the reference machine, altered bodies given to the machine's
   functor, the evaluator's functor (Eval.Make) applied to altered
   primitives, or a platform operation wrapped around the reference's
   ({!Interp.Runtime.hooks}). The reference rules (lib/semantics/machine.ml,
   lib/interp/eval.ml) know nothing of them. *)

open Semantics.Machine
module R = Interp.Runtime
module P = R.P
module M = P.M
module Pqueue = Semantics.Pqueue
module Fqueue = Semantics.Fqueue
module B = Interp_eval.Eval.Bodies

type t = {
  name : string;
  ruling : string;
  about : string;
  can_differ : bool;
  blind : string option;
  hooks : R.hooks;
}

let r = M.rules

(* The altered rules shared with the models' mutants (lib/explore/altered.ml):
   ties to the last notified, the first handler only, one percept moved, a
   behaviour step before the dispatch. *)
module A = Explore.Altered.Make (B)
let ref_hooks = R.reference_hooks

(* Every agent's rules: this step, one rule at a time. *)
let with_step step = { ref_hooks with rules = (fun _ -> { R.step; dispatch = None }) }

(* The reference machine's step on an altered rule table. *)
let with_rules rules = with_step (M.step_by rules)

(* Every result of a rule, changed. *)
let map_results f rule p (c : M.t) = List.map (fun (l, c') -> (l, f p c l c')) (rule p c)

(* ---------------------------------------------------------- host side *)

let max_over (pl : P.t) f = Array.fold_left (fun m (a : P.agent) -> max m (f a.config)) 0 pl.agents

(* The put index counted across the agents: one counter for the platform. *)
let put_index_across_agents p pl i c v =
  ref_hooks.put p pl i { c with puts = max_over pl (fun (c : M.t) -> c.puts) } v

(* The seq counted across the agents (R2b says per agent). *)
let seq_across_agents p pl i (c : M.t) v ~default ~priority =
  ref_hooks.notify_event p pl i { c with next_seq = max_over pl (fun (c : M.t) -> c.next_seq) } v ~default ~priority

(* The capacity checked with > instead of >=: one entry too many fits. *)
let one_more p = { p with o2a_capacity = Option.map succ p.o2a_capacity }

(* Objects do not count against the capacity (R2d: percepts and objects alike). *)
let percepts_only (c : M.t) =
  { c with o2a = Fqueue.of_list (List.filter (function O_percept _ -> true | O_object _ -> false) (Fqueue.to_list c.o2a)) }

let objects_take_no_room_notify p _ _ (c : M.t) v ~default ~priority =
  match priority with
  | Some k when k < 0 -> Error (Negative_priority k)
  | _ when not (M.o2a_has_room p (percepts_only c)) -> Error O2a_full
  | None -> Ok (M.notify p c v default)
  | Some k -> Ok (M.notify_with p c v k)

let objects_take_no_room_put p _ _ (c : M.t) v =
  if M.o2a_has_room p (percepts_only c) then Ok (M.put p c v) else Error O2a_full

(* ---------------------------------------------------------- rule side *)

(* Dequeue: the lowest priority first (a comparator the wrong way round). *)
let lowest_priority_first p (c : M.t) =
  match r.dequeue p c with
  | [] -> []
  | _ ->
    let all = Pqueue.to_sorted_list c.pq in
    let low = List.fold_left (fun m (e : _ entry) -> min m e.prio) max_int all in
    let e = List.find (fun (e : _ entry) -> e.prio = low) all in
    (* the reference's rule on a queue whose only candidate is e *)
    List.map (fun (l, (c' : M.t)) -> (l, { c' with pq = Pqueue.remove e c.pq }))
      (r.dequeue p { c with pq = Pqueue.insert e Pqueue.empty })

(* EndDispatch: never a discard. *)
let discard_not_recorded p c =
  List.map (fun (l, c') -> match l with
      | End_dispatch e -> let l = End_dispatch { e with discarded = false } in (l, { c' with last = l })
      | _ -> (l, c')) (r.end_dispatch p c)

let is_percept = function O_percept _ -> true | O_object _ -> false

(* Transfer: the objects are thrown away with the percepts (R3a: they stay). *)
let objects_dropped =
  map_results (fun _ _ _ (c' : M.t) -> { c' with o2a = Fqueue.empty }) r.transfer

(* Transfer: stops at the first object (the percepts behind it stay). *)
let objects_block_transfer p (c : M.t) =
  match r.transfer p c with
  | [] -> []
  | x ->
    let rec split acc = function
      | (O_percept _ as e) :: rest -> split (e :: acc) rest
      | rest -> (List.rev acc, rest) in
    let (front, rest) = split [] (Fqueue.to_list c.o2a) in
    if rest = [] then x
    else List.map (fun (l, (c' : M.t)) -> (l, { c' with o2a = Fqueue.of_list rest }))
        (r.transfer p { c with o2a = Fqueue.of_list front })

(* Transfer: "moved" counts the objects too. *)
let transfer_counts_objects p (c : M.t) =
  let objects = Fqueue.fold (fun n x -> if is_percept x then n else n + 1) 0 c.o2a in
  List.map (fun (l, (c' : M.t)) -> match l with
      | Transfer n -> let l = Transfer (n + objects) in (l, { c' with last = l })
      | _ -> (l, c')) (r.transfer p c)

(* Printed: an object at the head of O2A is thrown away (instead of the spin). *)
let printed_drops_object p (c : M.t) =
  match r.transfer_spin p c with
  | [] -> []
  | x -> List.map (fun (l, (c' : M.t)) ->
      (l, { c' with o2a = (match Fqueue.pop c.o2a with Some (_, q) -> q | None -> c.o2a) })) x

(* Two behaviour steps per iteration (R3c: one). *)
let two_steps =
  map_results (fun _ (c : M.t) _ (c' : M.t) ->
      match c.last with
      | Behaviour_step _ -> c'
      | _ -> if c'.ready <> [] then { c' with phase = Dispatch_phase } else c') r.behaviour_step

(* Dequeue takes the late percepts of O2A into the current dispatch (R3d). *)
let late_percepts_join p (c : M.t) =
  match r.dequeue p c with
  | [] -> []
  | _ ->
    let (moving, rest) = Fqueue.partition is_percept c.o2a in
    let pq = List.fold_left (fun q -> function O_percept e -> Pqueue.insert e q | O_object _ -> q) c.pq moving in
    r.dequeue p { c with pq; o2a = rest }

(* One more NextIteration before idling (R3e). *)
let idle_late p (c : M.t) =
  match r.idle p c with
  | [] -> []
  | x -> (match c.last with
      | Next_iteration -> x
      | _ -> [ (Next_iteration, { c with phase = Transfer_phase; last = Next_iteration }) ])

(* The Reference loop dispatches one percept per iteration (R3b: all). *)
let one_dispatch_per_iteration p c =
  if p.variant = Reference then M.step { p with variant = Budgeted; budget = 1 } c else M.step p c

(* A snapshot reordered: [f] on the instances' groups of handlers. *)
let reorder_todo f =
  map_results (fun _ _ _ (c' : M.t) -> match c'.cur with
      | Some d ->
        let ids = List.sort_uniq compare (List.map fst d.todo) in
        let ids = List.filter (fun id -> List.exists (fun (a : _ instance) -> a.id = id) c'.active) ids in
        let order = List.filter (fun (a : _ instance) -> List.mem a.id ids) c'.active in
        let groups = List.map (fun (a : _ instance) -> List.filter (fun (i, _) -> i = a.id) d.todo) order in
        { c' with cur = Some { d with todo = List.concat (f groups) } }
      | None -> c') r.dequeue

(* R4b: handlers of instances activated during the dispatch join it. *)
let snapshot_grows =
  map_results (fun _ (c : M.t) l (c' : M.t) -> match l, c'.cur with
      | Handle _, Some d ->
        let fresh = List.filter (fun (a : _ instance) ->
            not (List.exists (fun (b : _ instance) -> b.id = a.id) c.active)) c'.active in
        let more = List.concat_map (fun (a : _ instance) ->
            List.init (B.percept_handlers a.beh) (fun j -> (a.id, j + 1))) fresh in
        { c' with cur = Some { d with todo = d.todo @ more } }
      | _ -> c') r.handle_or_skip

(* R5a: the position is not moved on: the head of ready runs every time. *)
let position_stuck =
  map_results (fun _ _ _ (c' : M.t) -> { c' with pos = 1 }) r.behaviour_step

(* New ready entries of a rule: the ids in c'.ready not in c.ready. *)
let fresh_ready (c : M.t) (c' : M.t) = List.filter (fun id -> not (List.mem id c.ready)) c'.ready

(* R5f: activated behaviours join the front of ready (the position stays). *)
let activated_at_front rule =
  map_results (fun _ c _ (c' : M.t) ->
      match fresh_ready c c' with
      | [] -> c'
      | fresh -> { c' with ready = fresh @ List.filter (fun id -> not (List.mem id fresh)) c'.ready }) rule

(* R5f: a removal does not correct the position: the next behaviour is skipped. *)
let removal_skips =
  map_results (fun _ (c : M.t) l (c' : M.t) -> match l with
      | Behaviour_step { id; _ } when not (List.mem id c'.ready) && c'.ready <> [] ->
        let p = (c.pos mod List.length c.ready) + 1 in
        { c' with pos = (if p > List.length c'.ready then 1 else p) }
      | _ -> c') r.behaviour_step

(* R5b: the newest message that matches is taken. *)
let newest_message_first p (c : M.t) =
  let rev q = Fqueue.of_list (List.rev (Fqueue.to_list q)) in
  List.map (fun (l, (c' : M.t)) -> (l, { c' with msgq = rev c'.msgq }))
    (r.behaviour_step p { c with msgq = rev c.msgq })

(* R5e: the messages of one step go out newest first. *)
let sends_reversed rule =
  map_results (fun _ _ _ (c' : M.t) ->
      let (a : Interp_eval.Eval.agent) = c'.world in
      { c' with world = { a with outbox = List.rev a.outbox } }) rule

(* Ids of the instances a rule activated, renamed by [pick]. *)
let renumber pick =
  let f _ (c : M.t) l (c' : M.t) =
    let old_ids = List.map (fun (a : _ instance) -> a.id) c.active in
    let reserved = match l, c.cur with
      | Handle _, Some d -> List.map fst d.todo
      | Behaviour_step { id; _ }, _ -> [ id ]
      | _ -> [] in
    let fresh = List.filter (fun (a : _ instance) -> not (List.mem a.id old_ids)) c'.active in
    if fresh = [] then c'
    else
      let (_, map) = List.fold_left (fun (taken, map) (a : _ instance) ->
          let n = pick taken reserved in (n :: taken, (a.id, n) :: map))
          (List.filter (fun id -> List.exists (fun (a : _ instance) -> a.id = id) c'.active) old_ids, []) fresh in
      let rn id = match List.assoc_opt id map with Some n -> n | None -> id in
      { c' with active = List.map (fun (a : _ instance) -> { a with id = rn a.id }) c'.active;
                ready = List.map rn c'.ready; blocked = List.map rn c'.blocked } in
  { r with handle_or_skip = map_results f r.handle_or_skip; behaviour_step = map_results f r.behaviour_step }

(* largest + 1, over the active ids and the reserved ones *)
let largest_plus_one taken reserved = 1 + List.fold_left max 0 (taken @ reserved)

(* the smallest free id, the snapshot's ids not reserved (D2) *)
let smallest_unreserved taken _ =
  let rec go n = if List.mem n taken then go (n + 1) else n in go 1

(* R5f: a behaviour woken by a message joins the front of the ready list,
   not its end. The wake happens in the platform's Send, between two rules
   of the agent; the defect remembers each agent's ready list after its
   last rule and moves the ids that appeared since to the front. *)
let ready_after : (string, int list) Hashtbl.t = Hashtbl.create 8

let woken_at_front p (c : M.t) =
  let name = c.world.Interp_eval.Eval.name in
  let c = match Hashtbl.find_opt ready_after name with
    | Some before ->
      let woken = List.filter (fun id -> not (List.mem id before)) c.ready in
      if woken = [] then c
      else { c with ready = woken @ List.filter (fun id -> not (List.mem id woken)) c.ready }
    | None -> c in
  let res = M.step p c in
  (match res with (_, (c' : M.t)) :: _ -> Hashtbl.replace ready_after name c'.ready | [] -> ());
  res

(* R4b: an instance deactivated during a dispatch still runs its handlers
   of the snapshot: the defect remembers the instances active when the
   percept was dequeued, and lends the departed one back for its handler. *)
let at_dequeue : (string, Interp_eval.Eval.beh instance list) Hashtbl.t = Hashtbl.create 8

let deactivated_dequeue p (c : M.t) =
  let res = r.dequeue p c in
  if res <> [] then Hashtbl.replace at_dequeue c.world.Interp_eval.Eval.name c.active;
  res

let deactivated_handles p (c : M.t) =
  match c.phase, c.cur with
  | Handle_phase, Some { todo = (id, _) :: _; _ } when not (List.exists (fun (a : _ instance) -> a.id = id) c.active) ->
    (match Hashtbl.find_opt at_dequeue c.world.Interp_eval.Eval.name with
     | Some was ->
       (match List.find_opt (fun (a : _ instance) -> a.id = id) was with
        | Some inst ->
          List.map (fun (l, (c' : M.t)) ->
              (l, { c' with active = List.filter (fun (a : _ instance) -> a.id <> id) c'.active;
                            ready = List.filter (( <> ) id) c'.ready;
                            blocked = List.filter (( <> ) id) c'.blocked }))
            (r.handle_or_skip p { c with active = c.active @ [ inst ] })
        | None -> r.handle_or_skip p c)
     | None -> r.handle_or_skip p c)
  | _ -> r.handle_or_skip p c

(* Bodies with one function changed, for the machine's functor. *)
module Oneshot_cyclic = struct include B let cyclic _ = true end
module Mo = Semantics.Machine.Make (Oneshot_cyclic)

module Deactivate_ignored = struct
  include B
  let run_percept_handler w ~id ~active b h p bd =
    let (w, effs) = B.run_percept_handler w ~id ~active b h p bd in
    (w, List.filter (function Deactivate -> false | Activate _ -> true) effs)
end
module Md = Semantics.Machine.Make (Deactivate_ignored)

module Effects_reversed = struct
  include B
  let run_percept_handler w ~id ~active b h p bd =
    let (w, e) = B.run_percept_handler w ~id ~active b h p bd in (w, List.rev e)
  let run_action w ~id ~active b = let (w, e) = B.run_action w ~id ~active b in (w, List.rev e)
  let run_message_handler w ~id ~active b h m bd =
    let (w, e) = B.run_message_handler w ~id ~active b h m bd in (w, List.rev e)
end
module Me = Semantics.Machine.Make (Effects_reversed)

(* [content matches S] takes only percepts of S itself, not of the percept
   types that extend S (R1a: a subtype is a percept of S too). *)
module Exact_type = struct
  include B
  let rec required (e : Syntax.Ast.expr) = match e.it with
    | Matches ({ it = Content; _ }, { it = PCons (c, _); _ }) -> Some c.it
    | Matches ({ it = Content; _ }, { it = PName x; _ }) -> Some x
    | Binop (And, l, _) -> required l
    | _ -> None
  let percept_applicable (w : Interp_eval.Eval.agent) ~id (b : Interp_eval.Eval.beh) h p =
    match b.phandlers.(h - 1).h_guard, p with
    | Some g, Interp_eval.Value.Schema s
      when (match required g with Some x -> x <> s.sname && Typing.Tenv.schema w.env x <> None | None -> false) ->
      (w, None)
    | _ -> B.percept_applicable w ~id b h p
end
module Mx = Semantics.Machine.Make (Exact_type)

(* R5b: a behaviour's message handlers are tried last declared first. *)
module Message_handlers_reversed = struct
  include B
  let flip b h = B.message_handlers b + 1 - h
  let message_accepted w ~id b h m = B.message_accepted w ~id b (flip b h) m
  let run_message_handler w ~id ~active b h m bd = B.run_message_handler w ~id ~active b (flip b h) m bd
end
module Mm = Semantics.Machine.Make (Message_handlers_reversed)

(* R4a: a behaviour's own percept handlers come before the inherited ones. *)
module Own_handlers_first = struct
  include B
  let own (b : Interp_eval.Eval.beh) =
    List.length (List.filter (fun (h : Typing.Tenv.handler) -> h.h_kind = Typing.Tenv.On_percept) b.btype.b_handlers)
  (* the machine's h-th handler is this one of the behaviour's array *)
  let map (b : Interp_eval.Eval.beh) h =
    let n = Array.length b.phandlers and o = own b in
    let inherited = n - o in
    if h <= o then inherited + h else h - o
  let percept_applicable w ~id b h p = B.percept_applicable w ~id b (map b h) p
  let run_percept_handler w ~id ~active b h p bd = B.run_percept_handler w ~id ~active b (map b h) p bd
end
module Mi = Semantics.Machine.Make (Own_handlers_first)

(* A guard evaluated twice (a pre-check, then the real one): it shows only
   when the guard fails with a run-time error, recorded twice (R7). *)
module Guard_twice = struct
  include B
  let percept_applicable w ~id b h p =
    let (w, _) = B.percept_applicable w ~id b h p in B.percept_applicable w ~id b h p
end
module Mg = Semantics.Machine.Make (Guard_twice)


(* ------------------------------------------ the evaluator's primitives *)

module E = Interp_eval.Eval
module V = Interp_eval.Value
module Ty = Typing.Types
module Ep = E.Primitives

(* The evaluator over altered primitives (Eval.Make), for every body: the
   machine's rules over its bodies, the agents' on create and on destroy. *)
let evaluator (module Pr : E.PRIMITIVES) =
  let module Ev = E.Make (Pr) in
  let module Mv = Semantics.Machine.Make (Ev.Bodies) in
  { (with_step Mv.step) with
    create_agent = (fun ~config env ~name ~atype ~args -> Ev.create_agent ~config env ~name ~atype ~args);
    destroy_agent = Ev.destroy_agent }

(* D8: integer division rounds toward negative infinity, as Python's //
   (Java's rounds toward zero), and % takes the divisor's sign. *)
module Floor_division = struct
  include Ep
  let arith at (op : Syntax.Ast.binop) a b = match op, a, b with
    | Div, V.Int x, V.Int y when y <> 0 -> V.int32 (int_of_float (Float.floor (float_of_int x /. float_of_int y)))
    | Mod, V.Int x, V.Int y when y <> 0 -> V.int32 (((x mod y) + y) mod y)
    | _ -> Ep.arith at op a b
end

(* D8: integers are 64-bit: + - * never wrap at 2^31. *)
module Wide_integers = struct
  include Ep
  let arith at (op : Syntax.Ast.binop) a b = match op, a, b with
    | Add, V.Int x, V.Int y -> V.Int (x + y)
    | Sub, V.Int x, V.Int y -> V.Int (x - y)
    | Mul, V.Int x, V.Int y -> V.Int (x * y)
    | _ -> Ep.arith at op a b
end

(* R1c: an integer given to a real slot, parameter or property stays an
   integer. *)
module No_widening = struct
  include Ep
  let coerce_param ty v = match Ty.repr ty, v with
    | (Ty.Double | Ty.Float), V.Int _ -> Some v
    | _ -> Ep.coerce_param ty v
end

(* D9: a real printed as OCaml prints it (21. where Java writes 21.0). *)
module Ocaml_reals = struct
  include Ep
  let text v = match v with V.Double f | V.Float f -> string_of_float f | _ -> Ep.text v
end

(* R8: log and + write a value's literal: a text with its quotes. *)
module Literal_text = struct
  include Ep
  let text = V.to_literal
end

(* R1c: an integer never equals a real (Java's Integer.equals(Double)). *)
module Int_real_unequal = struct
  include Ep
  let equal_values at a b = match a, b with
    | V.Int _, (V.Double _ | V.Float _) | (V.Double _ | V.Float _), V.Int _ -> false
    | _ -> Ep.equal_values at a b
end

(* R1c: schema values compared by identity (Java's default equals). *)
module Schema_identity = struct
  include Ep
  let equal_values at a b = match a, b with
    | V.Schema _, V.Schema _ -> a == b
    | _ -> Ep.equal_values at a b
end

(* R1a: a type is a subtype of itself and of its parent, not of its
   grandparent: the extends chain is not followed. *)
module Direct_parent_only = struct
  include Ep
  let subschema env a b =
    String.equal a b
    || (match Typing.Tenv.schema env a with Some s -> s.s_super = Some b | None -> false)
end

(* ------------------------------------------------ more host and rules *)

(* R2b: the priority queue numbers each transfer's percepts from 1 (the
   seq is the place in the batch, not the notification's number). *)
let seq_per_transfer p (c : M.t) =
  match r.transfer p c with
  | [] -> []
  | res ->
    let moved = List.filter_map (function O_percept e -> Some e | O_object _ -> None) (Fqueue.to_list c.o2a) in
    let renumbered = List.mapi (fun i (e : _ entry) -> { e with seq = i + 1 }) moved in
    List.map (fun (l, (c' : M.t)) ->
        (l, { c' with pq = List.fold_left (fun q e -> Pqueue.insert e q) c.pq renumbered })) res

(* R3b, R2b: equal percepts of one priority are one: the queue is a set
   (a transfer adds a percept equal to one already queued no more). *)
let duplicates_merged p (c : M.t) =
  match r.transfer p c with
  | [] -> []
  | res ->
    let moved = List.filter_map (function O_percept e -> Some e | O_object _ -> None) (Fqueue.to_list c.o2a) in
    let same (a : _ entry) (b : _ entry) = a.prio = b.prio && V.equal a.p b.p in
    let pq = List.fold_left (fun q e ->
        if List.exists (same e) (Pqueue.to_sorted_list q) then q else Pqueue.insert e q) c.pq moved in
    List.map (fun (l, (c' : M.t)) -> (l, { c' with pq })) res

(* R3b: ties go to the percept whose text comes first (a queue ordered by
   priority, then by the percept), not to the smallest seq. *)
let ties_by_text p (c : M.t) =
  match r.dequeue p c with
  | [] -> []
  | _ ->
    let all = Pqueue.to_sorted_list c.pq in
    let top = List.fold_left (fun m (e : _ entry) -> max m e.prio) min_int all in
    let ties = List.filter (fun (e : _ entry) -> e.prio = top) all in
    let key (e : _ entry) = V.to_literal e.p in
    let e = List.fold_left (fun b e -> if compare (key e) (key b) < 0 then e else b) (List.hd ties) ties in
    List.map (fun (l, (c' : M.t)) -> (l, { c' with pq = Pqueue.remove e c.pq }))
      (r.dequeue p { c with pq = Pqueue.insert e Pqueue.empty })

(* R5a: the position does not wrap: after the last ready behaviour, the
   last one runs again. *)
let position_clamps =
  map_results (fun _ (c : M.t) _ (c' : M.t) ->
      if c.ready <> [] && c.pos = List.length c.ready && c'.ready = c.ready then { c' with pos = c.pos } else c')
    r.behaviour_step

(* R5f: behaviours woken by one message join the end of ready newest
   blocked first (a stack of blocked behaviours). As woken_at_front: the
   ids that joined ready since the agent's last rule, reversed. *)
let ready_before : (string, int list) Hashtbl.t = Hashtbl.create 8

let woken_reversed p (c : M.t) =
  let name = c.world.E.name in
  let c = match Hashtbl.find_opt ready_before name with
    | Some before ->
      let (kept, woken) = List.partition (fun id -> List.mem id before) c.ready in
      if List.length woken < 2 then c else { c with ready = kept @ List.rev woken }
    | None -> c in
  let res = M.step p c in
  (match res with (_, (c' : M.t)) :: _ -> Hashtbl.replace ready_before name c'.ready | [] -> ());
  res

(* D1: a one-shot behaviour without an action block whose step took no
   message blocks (and waits for one) instead of being deactivated. *)
let oneshot_blocks p (c : M.t) =
  match r.behaviour_step p c with
  | [ (Behaviour_step { id; msg = None } as l, (c' : M.t)) ] ->
    (match M.find_instance id c.active with
     | Some b when not (B.cyclic b) && not (B.has_action b) ->
       let pos = (c.pos mod List.length c.ready) + 1 in
       let stepped = Stepped_blocked { active = c.active; ready = c.ready; blocked = c.blocked; pos } in
       [ (l, { c' with active = c.active; blocked = c'.blocked @ [ id ]; stepped }) ]
     | _ -> [ (l, c') ])
  | res -> res

(* The behaviour a step would run, when BehaviourStep is enabled. *)
let stepping p (c : M.t) =
  if c.phase = Dispatch_phase && M.dispatch_over p c && c.ready <> [] then
    let id = List.nth c.ready (c.pos - 1) in
    Option.map (fun b -> (id, b)) (M.find_instance id c.active)
  else None

(* R5b: the step takes the oldest message that some handler accepts (the
   messages in order, each tried with every handler), not the first
   message of the first handler that accepts one. *)
let oldest_message_first p (c : M.t) =
  match stepping p c with
  | None -> r.behaviour_step p c
  | Some (id, b) ->
    let entries = Fqueue.to_list c.msgq in
    let accepted = function
      | M_message { m; _ } ->
        List.exists (fun h -> snd (B.message_accepted c.world ~id b h m) <> None)
          (List.init (B.message_handlers b) (fun j -> j + 1))
      | M_percept _ -> false in
    match List.find_opt accepted entries with
    | None -> r.behaviour_step p c
    | Some x ->
      let rest = List.filter (fun y -> y != x) entries in
      List.map (fun (l, (c' : M.t)) -> match l with
          | Behaviour_step { msg = Some _; _ } ->
            (l, { c' with msgq = Fqueue.of_list (rest @ Fqueue.to_list c'.msgq) })
          | _ -> (l, { c' with msgq = Fqueue.of_list entries }))
        (r.behaviour_step p { c with msgq = Fqueue.of_list [ x ] })

(* R5b: a step takes the head message of the queue and drops it when no
   handler of the behaviour accepts it (JADE's receive() without a
   template). *)
let unmatched_dropped p (c : M.t) =
  match stepping p c with
  | Some (_, b) when B.message_handlers b > 0 ->
    List.map (fun (l, (c' : M.t)) -> match l with
        | Behaviour_step { msg = None; _ } ->
          (l, { c' with msgq = (match Fqueue.pop c'.msgq with Some (_, q) -> q | None -> c'.msgq) })
        | _ -> (l, c')) (r.behaviour_step p c)
  | _ -> r.behaviour_step p c

(* R5g: a new instance's id comes from a counter (the agent's largest id
   so far, plus one), never reused, not the smallest free. *)
let highest : (string, int) Hashtbl.t = Hashtbl.create 8
let counter = ref 0
let ids_counted =
  let rules = renumber (fun taken reserved ->
      let n = 1 + List.fold_left max !counter (taken @ reserved) in counter := n; n) in
  fun p (c : M.t) ->
    let name = c.world.E.name in
    let seen = List.fold_left (fun m (a : _ instance) -> max m a.id)
        (Option.value ~default:0 (Hashtbl.find_opt highest name)) c.active in
    counter := seen;
    let res = M.step_by rules p c in
    Hashtbl.replace highest name !counter;
    res

(* R2b, R2d: a refused percept still takes a seq number (the counter
   moves before the capacity is checked). *)
let refused : (int, int) Hashtbl.t = Hashtbl.create 8
let refused_takes_seq p pl i (c : M.t) v ~default ~priority =
  let lost = Option.value ~default:0 (Hashtbl.find_opt refused i) in
  match ref_hooks.notify_event p pl i { c with next_seq = c.next_seq + lost } v ~default ~priority with
  | Error O2a_full as e -> Hashtbl.replace refused i (lost + 1); e
  | Ok _ as ok -> Hashtbl.replace refused i 0; ok
  | e -> e

(* R7, R3b: an error in a percept handler's body ends the dispatch of that
   percept: the handlers after it are not tried. *)
let has_error (w : E.agent) = List.exists (function E.Error _ -> true | _ -> false) w.events
let error_ends_dispatch =
  map_results (fun _ _ l (c' : M.t) -> match l, c'.cur with
      | Handle _, Some d when has_error c'.world -> { c' with cur = Some { d with todo = [] } }
      | _ -> c') r.handle_or_skip

(* R7, R5g: an error in the agent's on create discards the behaviours it
   had activated before it (the creation undone, the agent kept). *)
let create_drops_behaviours ~config env ~name ~atype ~args =
  let (a, behs) = E.create_agent ~config env ~name ~atype ~args in
  if has_error a then (a, []) else (a, behs)

(* R5e: messages of one rule go out receiver by receiver (in name order),
   not in the order of the sends. *)
let by_receiver rule =
  map_results (fun _ _ _ (c' : M.t) ->
      let (a : E.agent) = c'.world in
      let oldest_first = List.rev a.outbox in
      let sorted = List.stable_sort (fun (x, _) (y, _) -> compare x y) oldest_first in
      { c' with world = { a with outbox = List.rev sorted } }) rule

let d name ruling about ?(can_differ = true) ?blind hooks = { name; ruling; about; can_differ; blind; hooks }

(* what the judge is not given (bin/judged.ml, test/judge) *)
let schedule = "R6: any order of the agents' rules is a valid run"
let receivers = "R6, R5e: messages to different receivers arrive in any order"
let host_notify = "the judge reads the host's notify from the trace: one without an override"

let all = [
  d "matches-exact-type" "R1a" "content matches S refuses percepts of the types that extend S"
    (with_rules { r with handle_or_skip = Mx.handle_or_skip });
  d "put-ignores-capacity" "R2d" "a put into a full O2A queue is accepted"
    { ref_hooks with put = (fun p _ _ c v -> Ok (M.put p c v)) };
  d "put-index-across-agents" "R2c" "the put index is counted over all agents, not per agent"
    { ref_hooks with put = put_index_across_agents };
  d "seq-across-agents" "R2b" "the seq is counted over all agents, not per agent"
    { ref_hooks with notify_event = seq_across_agents };
  d "capacity-off-by-one" "R2d" "the O2A queue takes one entry more than its capacity"
    { ref_hooks with notify_event = (fun p -> ref_hooks.notify_event (one_more p));
                     put = (fun p -> ref_hooks.put (one_more p)) };
  d "objects-take-no-room" "R2d" "objects in O2A do not count against the capacity"
    { ref_hooks with notify_event = objects_take_no_room_notify; put = objects_take_no_room_put };
  d "override-ignored" "R2a" "notifyEvent(p, k) uses the type's default priority" ~blind:host_notify
    { ref_hooks with notify_event = (fun p pl i c v ~default ~priority:_ ->
          ref_hooks.notify_event p pl i c v ~default ~priority:None) };
  d "override-zero-is-none" "R2a" "an override of 0 is taken as no override" ~blind:host_notify
    { ref_hooks with notify_event = (fun p pl i c v ~default ~priority ->
          ref_hooks.notify_event p pl i c v ~default ~priority:(if priority = Some 0 then None else priority)) };
  d "put-wakes-idle" "D3" "putting an object wakes an idle agent"
    { ref_hooks with put = (fun p pl i c v ->
          Result.map (fun (c' : M.t) -> if c.phase = Idle_phase then { c' with phase = Transfer_phase } else c')
            (ref_hooks.put p pl i c v)) };
  d "rounds-reversed" "R6" "a round runs the agents in reverse creation order" ~blind:schedule
    { ref_hooks with round = (fun rs pl -> List.rev (P.round rs pl)) };
  d "seed-ignored" "R6" "--seed is ignored: every round is in creation order" ~blind:schedule
    { ref_hooks with round = (fun _ pl -> P.round None pl) };
  d "ties-largest-seq" "R3b" "among equal priorities the newest percept goes first"
    (with_rules { r with dequeue = A.ties_to_largest_seq });
  d "lowest-priority-first" "R3b" "the lowest priority is dispatched first"
    (with_rules { r with dequeue = lowest_priority_first });
  d "first-handler-only" "R3b" "only the first applicable handler runs"
    (with_rules { r with handle_or_skip = A.first_handler_only });
  d "discard-not-recorded" "R3b" "a percept no handler took ends as end_dispatch, not discard"
    (with_rules { r with end_dispatch = discard_not_recorded });
  d "one-dispatch-per-iteration" "R3b" "one percept is dispatched per iteration, not all"
    (with_step one_dispatch_per_iteration);
  d "transfer-moves-one" "R3a" "Transfer moves only the first percept"
    (with_rules { r with transfer = A.transfer_moves_one });
  d "objects-dropped" "R3a" "Transfer throws the objects away instead of leaving them"
    (with_rules { r with transfer = objects_dropped });
  d "objects-block-transfer" "R3a" "Transfer stops at the first object"
    (with_rules { r with transfer = objects_block_transfer });
  d "transfer-counts-objects" "R3a" "Transfer's moved counts the objects that stay"
    (with_rules { r with transfer = transfer_counts_objects });
  d "printed-drops-object" "R3a" "the printed loop throws an object away instead of spinning"
    (with_rules { r with transfer_spin = printed_drops_object });
  d "step-before-dispatch" "R3c" "the behaviour step runs before the dispatch"
    (with_rules { r with dequeue = A.step_before_dispatch_dequeue; behaviour_step = A.step_before_dispatch_step });
  d "two-steps-per-iteration" "R3c" "two behaviour steps per iteration"
    (with_rules { r with behaviour_step = two_steps });
  d "late-percepts-join" "R3d" "percepts notified during a dispatch join it"
    (with_rules { r with dequeue = late_percepts_join });
  d "idle-late" "R3e" "the agent takes one more NextIteration before it idles"
    (with_rules { r with idle = idle_late });
  d "newest-behaviour-first" "R4a" "handlers of later activations come first"
    (with_rules { r with dequeue = reorder_todo List.rev });
  d "handlers-reversed" "R4a" "a behaviour's handlers in reverse declaration order"
    (with_rules { r with dequeue = reorder_todo (List.map List.rev) });
  d "snapshot-grows" "R4b" "handlers activated during a dispatch join it"
    (with_rules { r with handle_or_skip = snapshot_grows });
  d "own-handlers-first" "R4a" "a behaviour's own handlers are tried before the inherited ones"
    (with_rules { r with handle_or_skip = Mi.handle_or_skip });
  d "deactivated-still-handles" "R4b" "an instance deactivated during a dispatch still runs its handlers"
    (with_rules { r with dequeue = deactivated_dequeue; handle_or_skip = deactivated_handles });
  d "position-stuck" "R5a" "the position does not move on: the first ready behaviour always runs"
    (with_rules { r with behaviour_step = position_stuck });
  d "activated-at-front" "R5f" "an activated behaviour joins the front of the ready list"
    (with_rules { r with handle_or_skip = activated_at_front r.handle_or_skip;
                         behaviour_step = activated_at_front r.behaviour_step });
  d "woken-at-front" "R5f" "a behaviour woken by a message joins the front of the ready list"
    (with_step woken_at_front);
  d "removal-skips" "R5f" "a behaviour that leaves ready does not correct the position"
    (with_rules { r with behaviour_step = removal_skips });
  d "newest-message-first" "R5b" "a step takes the newest matching message"
    (with_rules { r with behaviour_step = newest_message_first });
  d "message-handlers-reversed" "R5b" "a behaviour's message handlers are tried last declared first"
    (with_rules { r with behaviour_step = Mm.behaviour_step });
  d "oneshot-not-removed" "R5c" "a one-shot behaviour stays after its step"
    (with_rules { r with behaviour_step = Mo.behaviour_step });
  d "deactivate-ignored-in-handler" "R5h" "deactivate this in a percept handler does nothing"
    (with_rules { r with handle_or_skip = Md.handle_or_skip });
  d "activations-reversed" "R5g" "the effects of one body apply in reverse order"
    (with_rules { r with handle_or_skip = Me.handle_or_skip; behaviour_step = Me.behaviour_step });
  d "ids-largest-plus-one" "R5g" "a new instance's id is the largest + 1, not the smallest free"
    (with_rules (renumber largest_plus_one));
  d "snapshot-ids-not-reserved" "D2" "a new instance may take an id of the pending snapshot"
    (with_rules (renumber smallest_unreserved));
  d "sends-reversed" "R5e" "the messages of one behaviour step are delivered newest first"
    (with_rules { r with behaviour_step = sends_reversed r.behaviour_step;
                         handle_or_skip = sends_reversed r.handle_or_skip });
  d "budget-off-by-one" "R3b" "the budgeted loop dispatches budget + 1 percepts"
    (with_step (fun p -> M.step { p with budget = p.budget + 1 }));
  d "waits-bookkeeping" "R8" "keeps the spec's ghost bookkeeping of waits (memory grows; nothing observable)"
    ~can_differ:false (with_step (fun p -> M.step { p with ghosts = true }));
  d "guard-evaluated-twice" "R7" "a percept guard is evaluated twice (an error in it is recorded twice)"
    (with_rules { r with handle_or_skip = Mg.handle_or_skip });
  d "int-division-floors" "D8" "integer division rounds toward negative infinity, not toward zero"
    (evaluator (module Floor_division));
  d "integers-64-bit" "D8" "integer + - * do not wrap at 32 bits"
    (evaluator (module Wide_integers));
  d "no-widening" "R1c" "an integer given to a real slot, parameter or property stays an integer"
    (evaluator (module No_widening));
  d "reals-printed-ocaml" "D9" "a real is printed as 21. rather than Java's 21.0"
    (evaluator (module Ocaml_reals));
  d "log-writes-literals" "R8" "log and + write texts with their quotes"
    (evaluator (module Literal_text));
  d "int-real-unequal" "R1c" "an integer never equals a real (1 = 1.0 is false)"
    (evaluator (module Int_real_unequal));
  d "schema-identity" "R1c" "schema values are equal only when they are the same object"
    (evaluator (module Schema_identity));
  d "subtype-one-level" "R1a" "matches and patterns follow extends one level only"
    (evaluator (module Direct_parent_only));
  d "seq-per-transfer" "R2b" "the priority queue numbers each transfer's percepts from 1"
    (with_rules { r with transfer = seq_per_transfer });
  d "duplicates-merged" "R3b" "a percept equal to one already queued, same priority, is dropped"
    (with_rules { r with transfer = duplicates_merged });
  d "ties-by-text" "R3b" "among equal priorities the percept whose text sorts first goes first"
    (with_rules { r with dequeue = ties_by_text });
  d "position-clamps" "R5a" "after the last ready behaviour the position stays there (no wrap)"
    (with_rules { r with behaviour_step = position_clamps });
  d "woken-reversed" "R5f" "behaviours woken by one message join ready newest blocked first"
    (with_step woken_reversed);
  d "oneshot-blocks" "D1" "a one-shot that took no message blocks instead of ending"
    (with_rules { r with behaviour_step = oneshot_blocks });
  d "oldest-message-first" "R5b" "a step takes the oldest message any handler accepts"
    (with_rules { r with behaviour_step = oldest_message_first });
  d "unmatched-message-dropped" "R5b" "a step drops the head message when no handler takes it"
    (with_rules { r with behaviour_step = unmatched_dropped });
  d "ids-counted" "R5g" "a new instance's id is one more than the largest ever given"
    (with_step ids_counted);
  d "create-error-drops-behaviours" "R7" "an error in on create discards the behaviours it activated"
    { ref_hooks with create_agent = create_drops_behaviours };
  d "refused-notify-takes-seq" "R2b" "a refused percept still takes a seq number"
    { ref_hooks with notify_event = refused_takes_seq };
  d "fuel-off-by-one" "R7" "--fuel N lets N + 1 statements run"
    { ref_hooks with create_agent = (fun ~config -> E.create_agent ~config:{ config with fuel = config.fuel + 1 }) };
  d "error-ends-dispatch" "R7" "an error in a percept handler skips the later handlers of that percept"
    (with_rules { r with handle_or_skip = error_ends_dispatch });
  d "on-destroy-skipped" "D14" "on destroy never runs"
    { ref_hooks with destroy_agent = Fun.id };
  d "failure-from-receiver" "D43" "the failure for an absent receiver comes from it, not from ams"
    { ref_hooks with failure = (fun ~receiver -> { (R.failure ~receiver) with sender = receiver }) };
  d "during-step-ignored" "D42" "a message during a step is delivered as after it"
    { ref_hooks with in_step = (fun _ _ ~sender:_ ~receiver:_ _ -> None) };
  d "sends-by-receiver" "R5e" "a rule's messages go out receiver by receiver, in name order" ~blind:receivers
    (with_rules { r with behaviour_step = by_receiver r.behaviour_step;
                         handle_or_skip = by_receiver r.handle_or_skip });
]

let find name = List.find_opt (fun d -> d.name = name) all
