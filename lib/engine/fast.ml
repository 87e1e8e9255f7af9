(* The fast path beside the reference rules of lib/semantics/machine.ml.
   Every function here computes what a rule (or a run of rules) of the
   reference computes; test/semantics and test/interp hold them equal. *)

open Semantics.Machine
module Pqueue = Semantics.Pqueue
module Fqueue = Semantics.Fqueue

type ('w, 'b) handled =
  | Not_applicable of 'w
  | Handled of 'w * 'b Semantics.Machine.effect list

let handle_in_two applicable run world ~id ~active b h p =
  match applicable world ~id b h p with
  | (world, None) -> Not_applicable world
  | (world, Some bindings) -> let (world, effs) = run world ~id ~active b h p bindings in Handled (world, effs)

module type BODIES = sig
  include Semantics.Machine.BODIES
  val percept_handle : world -> id:int -> active:int -> beh -> int -> percept -> (world, beh) handled
  val percept_may_apply : world -> beh -> int -> percept -> bool
  val percept_kind : percept -> int
end

module Make (B : BODIES) = struct
  module M = Semantics.Machine.Make (B)

  (* Transfer (R3a) in one pass over O2A: percepts go into the priority
     queue, objects stay in order. *)
  let transfer p (c : M.t) : M.lbl * M.t =
    let n = ref 0 and objects = ref [] in
    let pq =
      Fqueue.fold (fun pq x -> match x with
          | O_percept e ->
            incr n;
            (* the flood abstraction: a percept already waiting is not added again *)
            if p.flood && Pqueue.mem e pq then pq else Pqueue.insert e pq
          | O_object _ -> objects := x :: !objects; pq) c.pq c.o2a in
    let objects = List.rev !objects in
    let l = Transfer !n in
    (l, { c with pq; o2a = (if objects = [] then Fqueue.empty else Fqueue.of_list objects);
                 phase = Dispatch_phase; dispatched = 0; last = l; stepped = Not_stepped })

  (* The same where O2A holds [n] percepts and no object, and [pq] is the
     priority queue they make with [c]'s: as [transfer] on the
     configuration whose O2A holds them, without building that queue. *)
  let transfer_into (c : M.t) pq n : M.lbl * M.t =
    let l = Transfer n in
    (l, { c with pq; o2a = Fqueue.empty; phase = Dispatch_phase; dispatched = 0; last = l; stepped = Not_stepped })

  (* HandlersOf, remembered for the last [active] list seen (physically):
     the list is immutable and most dequeues share it. Beside each entry,
     the behaviour of its instance, which [dispatch] uses while [active] is
     unchanged. One record, handed out as it is (no pair per dispatch). *)
  type snapshot = {
    of_active : B.beh instance list;
    todo : (int * int) list;
    behs : B.beh list;
    nactive : int;                 (* instances in [of_active] (D19) *)
    mutable plans : plan array;
      (* by percept kind ({!B.percept_kind}): the handlers the pre-test
         leaves, made when a percept of that kind is first dispatched *)
  }

  (* The handlers of the snapshot that the pre-test does not rule out for
     one kind of percept: for each, the snapshot's [todo] from it on (its
     head is the handler; the rest is what the rules would still try, which
     ApplyEffects reserves) and its instance's behaviour. The handlers left
     out would each be a Skip that changes nothing. *)
  and plan = {
    from : (int * int) list list;
    pbehs : B.beh list;
    one : one option;   (* the plan of one handler, taken apart *)
  }
  and one = { oid : int; oh : int; otodo : (int * int) list; orest : (int * int) list; ob : B.beh }

  let no_plan = { from = []; pbehs = []; one = None }

  let handlers_cache : snapshot option ref = ref None

  let handlers_and_behs (c : M.t) =
    match !handlers_cache with
    | Some k when k.of_active == c.active -> k
    | _ ->
      let pairs = List.concat_map (fun (a : B.beh instance) ->
          List.init (B.percept_handlers a.beh) (fun j -> ((a.id, j + 1), a.beh))) c.active in
      let k = { of_active = c.active; todo = List.map fst pairs; behs = List.map snd pairs;
                nactive = List.length c.active; plans = [||] } in
      handlers_cache := Some k;
      k

  (* The plan of percept [pe], of kind [kind] (>= 0), for snapshot [k]. *)
  let plan_for k world kind pe =
    if kind < Array.length k.plans && k.plans.(kind) != no_plan then k.plans.(kind)
    else begin
      let rec keep todo behs = match todo, behs with
        | ((_, h) :: rest as from), b :: brest ->
          if B.percept_may_apply world b h pe then
            let (f, bs) = keep rest brest in (from :: f, b :: bs)
          else keep rest brest
        | _ -> ([], []) in
      let (from, pbehs) = keep k.todo k.behs in
      let one = match from, pbehs with
        | [ (oid, oh) :: orest as otodo ], [ ob ] -> Some { oid; oh; otodo; orest; ob }
        | _ -> None in
      let plan = { from; pbehs; one } in
      if kind >= Array.length k.plans then begin
        let a = Array.make (max (kind + 1) (2 * Array.length k.plans)) no_plan in
        Array.blit k.plans 0 a 0 (Array.length k.plans);
        k.plans <- a
      end;
      k.plans.(kind) <- plan;
      plan
    end

  (* The ghosts, asked of the reference only when they are kept. *)
  let bump_waits p (c : M.t) e = if p.ghosts && not p.flood then M.bump_waits p c e else c.waits
  let add_done p (c : M.t) seq = if p.ghosts && not p.flood then M.add_done p c seq else c.done_

  (* Dequeue under stable ties without the flood abstraction: the top is the
     one candidate (seqs are unique); one pop. *)
  let dequeue_top p (c : M.t) e pq : M.lbl * M.t =
    let l = Dequeue e in
    (l, { c with pq; cur = Some { e; todo = (handlers_and_behs c).todo; applied = false };
                 waits = bump_waits p c e; phase = Handle_phase;
                 dispatched = c.dispatched + 1; last = l })

  let single_candidate p = p.variant <> Native && p.tie = Stable && not p.flood

  let step p (c : M.t) : (M.lbl * M.t) list =
    match c.phase with
    | Transfer_phase when p.variant = Reference || p.variant = Budgeted -> [ transfer p c ]
    | Dispatch_phase when single_candidate p && not (M.dispatch_over p c) ->
      (match Pqueue.pop c.pq with
       | None -> M.step p c
       | Some (e, pq) -> [ dequeue_top p c e pq ])
    | Dispatch_phase when M.dispatch_over p c ->
      (* the dispatch is over: of the ten rules only BehaviourStep (a
         behaviour ready), NextIteration and Idle (none ready) can be
         enabled, and at most one of them is; asked alone, in the
         reference's order, without the other seven *)
      if c.ready <> [] then M.behaviour_step p c
      else (match M.next_iteration p c with [] -> M.idle p c | l -> l)
    | Idle_phase -> []                     (* no rule is enabled in Idle *)
    | _ -> M.step p c

  (* What an observer is told of a rule taken inside a dispatch: its label
     and the world after it; it answers the world to go on with (the
     runtime takes the bodies' events from it there). *)
  let tell observe l world = match observe with Some f -> f l world | None -> world

  (* Active instances in the behaviour part: [c]'s, or [bs] once a body
     had effects. *)
  let count_active (c : M.t) = function
    | Some (s : M.bs) -> List.length s.active
    | None -> List.length c.active

  (* Dispatch: the Handle arm of the rules over the snapshot [todo] of the
     dispatch of [e], from configuration [c] (whose behaviour part is [bs]
     once a handler had effects; [n] instances active), on local
     variables; what the rules would have written in each configuration
     (world, todo, applied, the behaviour part) is written once, at the
     end. No closure or option is allocated for a handler: this runs once
     per handler per percept. *)
  let rec dispatch_handlers observe p (c : M.t) e world applied bs n todo behs =
    match todo with
    | [] -> (world, applied, bs)
    | (id, h) :: rest ->
      (* [behs]: beside [todo], the behaviour of each entry's instance in
         [c.active], when the snapshot was just taken from it ([] otherwise);
         while no body had effects, the instance is found there *)
      match bs, behs with
      | None, b :: brest -> try_handler observe p c e world applied bs n todo b brest
      | _ ->
        let brest = match behs with _ :: r -> r | [] -> [] in
        let found = match bs with
          | Some (s : M.bs) -> M.find_instance id s.active
          | None -> M.find_instance id c.active in
        match found with
        | Some b -> try_handler observe p c e world applied bs n todo b brest
        | None ->                                                            (* skip *)
          let world = tell observe (Skip { id; h }) world in
          dispatch_handlers observe p c e world applied bs n rest brest

  (* The head of [todo], a handler of an instance whose behaviour is [b]. *)
  and try_handler observe p c e world applied bs n todo b behs =
    match todo with
    | [] -> (world, applied, bs)
    | (id, h) :: rest ->
      (* the pre-test: where it says no, percept_applicable would answer
         false, changing nothing *)
      if not (B.percept_may_apply world b h e.p) then begin                 (* skip *)
        let world = tell observe (Skip { id; h }) world in
        dispatch_handlers observe p c e world applied bs n rest behs
      end else
        match B.percept_handle world ~id ~active:n b h e.p with
        | Not_applicable world ->                                            (* skip *)
          let world = tell observe (Skip { id; h }) world in
          dispatch_handlers observe p c e world applied bs n rest behs
        | Handled (world, effs) ->                                           (* handle *)
          let (bs, n) = match effs with
            | [] -> (bs, n)
            | _ ->
              let s = match bs with Some s -> s | None -> M.bs_of c in
              let s = M.apply_effects p s id effs (List.map fst todo) in
              (Some s, List.length s.active) in
          let world = tell observe (Handle { id; h; p = e.p; seq = e.seq }) world in
          dispatch_handlers observe p c e world true bs n rest behs

  (* The configuration after the handlers and EndDispatch; [pq], [waits]
     and [dispatched] are [c]'s, or what Dequeue made of them. *)
  let dispatch_end observe p (c : M.t) e ~pq ~waits ~dispatched (world, applied, bs) =
    let l = End_dispatch { seq = e.seq; discarded = not applied } in        (* end_dispatch *)
    let world = tell observe l world in
    let c' = { c with pq; waits; dispatched; world; done_ = add_done p c e.seq; cur = None;
                      phase = Dispatch_phase; last = l } in
    match bs with Some s -> M.with_bs c' s | None -> c'

  (* The handlers of a plan, unobserved: the ones left out are Skips that
     change nothing and write no label. Once a body has effects, the rest
     of the snapshot from that handler on is taken by [dispatch_handlers]
     (an instance may have left; ApplyEffects reserves the ids still to be
     tried). *)
  let rec dispatch_plan p (c : M.t) e world applied n from behs =
    match from, behs with
    | ((id, h) :: rest as todo) :: from', b :: behs' ->
      (match B.percept_handle world ~id ~active:n b h e.p with
       | Not_applicable world -> dispatch_plan p c e world applied n from' behs'
       | Handled (world, []) -> dispatch_plan p c e world true n from' behs'
       | Handled (world, effs) ->
         let s = M.apply_effects p (M.bs_of c) id effs (List.map fst todo) in
         dispatch_handlers None p c e world true (Some s) (List.length s.active) rest [])
    | _ -> (world, applied, None)

  (* A percept's handlers, unobserved: those of its kind's plan, or every
     handler of the snapshot [k] when it has no kind. *)
  let handle_unobserved p (c : M.t) k world e =
    let kind = B.percept_kind e.p in
    if kind >= 0 then
      let plan = plan_for k world kind e.p in
      dispatch_plan p c e world false k.nactive plan.from plan.pbehs
    else dispatch_handlers None p c e world false None k.nactive k.todo k.behs

  (* Dequeue of [e], already taken from the priority queue (which is now
     [pq]), then its handlers and EndDispatch. *)
  let dispatch_popped observe p (c : M.t) e pq =
    let world = tell observe (Dequeue e) c.world in
    let k = handlers_and_behs c in
    dispatch_end observe p c e ~pq ~waits:(bump_waits p c e) ~dispatched:(c.dispatched + 1)
      (match observe with
       | None -> handle_unobserved p c k world e
       | Some _ -> dispatch_handlers observe p c e world false None k.nactive k.todo k.behs)

  let dispatch ?observe p (c : M.t) : M.t option =
    match c.phase, c.cur with
    | Handle_phase, Some d ->
      Some (dispatch_end observe p c d.e ~pq:c.pq ~waits:c.waits ~dispatched:c.dispatched
              (dispatch_handlers observe p c d.e c.world d.applied None (count_active c None) d.todo []))
    | Dispatch_phase, _ when single_candidate p && not (M.dispatch_over p c) ->
      (match Pqueue.pop c.pq with
       | None -> None
       | Some (e, pq) -> Some (dispatch_popped observe p c e pq))                (* dequeue *)
    | _ -> None

  let dispatch_entry ?observe p c e ~pq = dispatch_popped observe p c e pq

  (* Runs of dispatches, unobserved (no ghosts), of entries each already
     taken from the top of the priority queue. While no body has effects,
     the behaviour part and the snapshot stay [c]'s, and what a dispatch
     changes (the world, the count) is carried in local variables; the
     configuration is built once, at the end (its priority queue [c]'s:
     the caller's to set), its last EndDispatch label from the last
     entry's seq and whether it was discarded ([lseq] = [min_int]: no
     entry, the label is [c.last]). A body with effects changes the
     behaviour part, and so the snapshot, never the queue. A percept whose
     kind's plan has one handler (the common case: one handler takes each
     type) is handled in the loop, without [handle_unobserved]'s triple. *)
  let finish_run (c : M.t) world dispatched lseq ldisc n =
    let last = if lseq = min_int then c.last else End_dispatch { seq = lseq; discarded = ldisc } in
    ({ c with world; dispatched; cur = None; phase = Dispatch_phase; last }, n)

  (* The one handler [id, h] (the head of [todo]) had effects: as
     [dispatch_plan], the rest of the snapshot from scratch; the new
     behaviour part. *)
  let after_effects p (c : M.t) e world id effs todo todo_rest =
    let s = M.apply_effects p (M.bs_of c) id effs (List.map fst todo) in
    match dispatch_handlers None p c e world true (Some s) (List.length s.active) todo_rest [] with
    | (world, _, Some s) -> (world, s)
    | (world, _, None) -> (world, s)

  (* [count] entries, each from [pop ()]. *)
  let dispatch_from p (c : M.t) count pop =
    let rec go (c : M.t) k world dispatched lseq ldisc n =
      if n = count then finish_run c world dispatched lseq ldisc n
      else
        let e = pop () in
        let kind = B.percept_kind e.p in
        let plan = if kind >= 0 then plan_for k world kind e.p else no_plan in
        match plan.one with
        | Some { oid = id; oh = h; otodo = todo; orest = todo_rest; ob = b } ->
          (match B.percept_handle world ~id ~active:k.nactive b h e.p with
           | Not_applicable world -> go c k world (dispatched + 1) e.seq true (n + 1)
           | Handled (world, []) -> go c k world (dispatched + 1) e.seq false (n + 1)
           | Handled (world, effs) ->
             let (world, s) = after_effects p c e world id effs todo todo_rest in
             let c = M.with_bs c s in go c (handlers_and_behs c) world (dispatched + 1) e.seq false (n + 1))
        | _ ->
          let (world, applied, bs) = handle_unobserved p c k world e in
          match bs with
          | None -> go c k world (dispatched + 1) e.seq (not applied) (n + 1)
          | Some s -> let c = M.with_bs c s in go c (handlers_and_behs c) world (dispatched + 1) e.seq false (n + 1) in
    go c (handlers_and_behs c) c.world c.dispatched min_int false 0

  (* The same over lists of entries, highest priority first, each in seq
     order, to the end: without a closure call per percept (5% of the
     steady run's instructions). *)
  let dispatch_lists p (c : M.t) runs =
    let rec over_runs (c : M.t) k world dispatched lseq ldisc n = function
      | [] -> finish_run c world dispatched lseq ldisc n
      | run :: runs -> over_run c k world dispatched lseq ldisc n run runs
    and over_run (c : M.t) k world dispatched lseq ldisc n run runs =
      match run with
      | [] -> over_runs c k world dispatched lseq ldisc n runs
      | e :: rest ->
        let kind = B.percept_kind e.p in
        let plan = if kind >= 0 then plan_for k world kind e.p else no_plan in
        match plan.one with
        | Some { oid = id; oh = h; otodo = todo; orest = todo_rest; ob = b } ->
          (match B.percept_handle world ~id ~active:k.nactive b h e.p with
           | Not_applicable world -> over_run c k world (dispatched + 1) e.seq true (n + 1) rest runs
           | Handled (world, []) -> over_run c k world (dispatched + 1) e.seq false (n + 1) rest runs
           | Handled (world, effs) ->
             let (world, s) = after_effects p c e world id effs todo todo_rest in
             let c = M.with_bs c s in
             over_run c (handlers_and_behs c) world (dispatched + 1) e.seq false (n + 1) rest runs)
        | _ ->
          let (world, applied, bs) = handle_unobserved p c k world e in
          match bs with
          | None -> over_run c k world (dispatched + 1) e.seq (not applied) (n + 1) rest runs
          | Some s ->
            let c = M.with_bs c s in
            over_run c (handlers_and_behs c) world (dispatched + 1) e.seq false (n + 1) rest runs in
    over_runs c (handlers_and_behs c) c.world c.dispatched min_int false 0 runs

  (* Runs of dispatches from the configuration's own priority queue, in pop
     order (R3b). In [reference] they go on until the queue is empty: its
     entries are taken in the order Pqueue.to_sorted_list lists them, and
     the queue is empty at the end. Elsewhere (budgeted, printed) by pops,
     until the queue is empty or the budget spent. *)
  let dispatch_run p (c : M.t) =
    match c.phase, c.cur with
    | Dispatch_phase, None when single_candidate p && not p.ghosts && not (M.dispatch_over p c) ->
      if p.variant = Reference then begin
        let (c', n) = dispatch_lists p c [ Pqueue.to_sorted_list c.pq ] in
        Some ({ c' with pq = Pqueue.empty }, n)
      end else begin
        (* the dispatches change the behaviours, never the queue: how
           many pops the queue and the budget allow is known now *)
        let left = if p.variant = Budgeted then p.budget - c.dispatched else max_int in
        let pq = ref c.pq in
        let pop () = match Pqueue.pop !pq with
          | Some (e, q) -> pq := q; e
          | None -> Semantics.Fault.crash "Fast.dispatch_run: the queue is shorter than its size" in
        let (c', n) = dispatch_from p c (min left (Pqueue.size c.pq)) pop in
        Some ({ c' with pq = !pq }, n)
      end
    | _ -> None

  let dequeue_entry p c e ~pq = dequeue_top p c e pq
end
