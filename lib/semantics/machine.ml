(* The agent loop, rule by rule, as spec/AgentLoop.tla. Each rule function is
   named after its TLA+ action; docs/semantics.md states the same rules. *)

type variant = Printed | Reference | Budgeted | Native
type tie_policy = Stable | Unstable

type mutant =
  | Ties_to_largest_seq
  | First_handler_only
  | Transfer_moves_one
  | Step_before_dispatch
  | Oneshot_not_removed
  | O2a_not_drained

let mutants = [
  "ties-largest-seq", Ties_to_largest_seq;
  "first-handler-only", First_handler_only;
  "transfer-moves-one", Transfer_moves_one;
  "step-before-dispatch", Step_before_dispatch;
  "oneshot-not-removed", Oneshot_not_removed;
  "o2a-not-drained", O2a_not_drained;
]

type params = {
  variant : variant;
  tie : tie_policy;
  budget : int;
  max_active : int option;
  o2a_capacity : int option;
  flood : bool;
  ghosts : bool;
  mutant : mutant option;
}

let variant_of_string = function
  | "printed" -> Some Printed | "reference" -> Some Reference
  | "budgeted" -> Some Budgeted | "native" -> Some Native | _ -> None

let string_of_variant = function
  | Printed -> "printed" | Reference -> "reference"
  | Budgeted -> "budgeted" | Native -> "native"

type phase = Transfer_phase | Dispatch_phase | Handle_phase | Idle_phase

type 'p entry = 'p Pqueue.entry = { p : 'p; prio : int; seq : int }

type ('p, 'o) o2a_item = O_percept of 'p entry | O_object of 'o
type ('p, 'm) msg_item = M_message of { m : 'm; mseq : int } | M_percept of 'p entry
type 'b instance = { id : int; beh : 'b }
type 'p dispatch = { e : 'p entry; todo : (int * int) list; applied : bool }

type ('p, 'm, 'o) label =
  | Init
  | Notify of 'p entry
  | Notify_with of 'p entry
  | Put of 'o
  | Send of 'm * int
  | Transfer of int
  | Transfer_one of 'p entry
  | Transfer_spin of 'o
  | Transfer_end
  | Dequeue of 'p entry
  | Handle of { id : int; h : int; p : 'p; seq : int }
  | Skip of { id : int; h : int }
  | End_dispatch of { seq : int; discarded : bool }
  | Behaviour_step of { id : int; msg : ('p, 'm) msg_item option }
  | Next_iteration
  | Idle

let action_name = function
  | Init -> "Init" | Notify _ -> "Notify" | Notify_with _ -> "NotifyWith"
  | Put _ -> "Put" | Send _ -> "Send" | Transfer _ -> "Transfer"
  | Transfer_one _ -> "TransferOne" | Transfer_spin _ -> "TransferSpin"
  | Transfer_end -> "TransferEnd" | Dequeue _ -> "Dequeue" | Handle _ -> "Handle"
  | Skip _ -> "Skip" | End_dispatch _ -> "EndDispatch"
  | Behaviour_step _ -> "BehaviourStep" | Next_iteration -> "NextIteration"
  | Idle -> "Idle"

module Int_set = Set.Make (Int)

type ('p, 'm, 'o, 'b, 'w) config = {
  o2a : ('p, 'o) o2a_item Fqueue.t;
  pq : 'p Pqueue.t;
  msgq : ('p, 'm) msg_item Fqueue.t;
  next_seq : int;
  msg_seq : int;
  puts : int;
  active : 'b instance list;
  ready : int list;
  blocked : int list;
  pos : int;
  phase : phase;
  cur : 'p dispatch option;
  dispatched : int;
  done_ : Int_set.t;
  waits : (int * int * int) list;
  last : ('p, 'm, 'o) label;
  world : 'w;
}

type 'b effect = Activate of 'b | Deactivate

module type BODIES = sig
  type percept
  type message
  type obj
  type beh
  type world
  val cyclic : beh -> bool
  val has_action : beh -> bool
  val percept_handlers : beh -> int
  val message_handlers : beh -> int
  val percept_applicable : world -> id:int -> beh -> int -> percept -> world * bool
  val percept_may_apply : world -> beh -> int -> percept -> bool
  val run_percept_handler : world -> id:int -> beh -> int -> percept -> world * beh effect list
  val run_action : world -> id:int -> beh -> world * beh effect list
  val message_accepted : world -> id:int -> beh -> int -> message -> bool
  val run_message_handler : world -> id:int -> beh -> int -> message -> world * beh effect list
  val take_outbox : world -> world * (string * message) list
end

module Make (B : BODIES) = struct
  type t = (B.percept, B.message, B.obj, B.beh, B.world) config
  type lbl = (B.percept, B.message, B.obj) label

  (* ------------------------------------------------ behaviour states *)

  (* The behaviour part of a configuration, as the spec's record BS. *)
  type bs = { active : B.beh instance list; ready : int list; blocked : int list; pos : int }

  let bs_of (c : t) = { active = c.active; ready = c.ready; blocked = c.blocked; pos = c.pos }
  let with_bs (c : t) (s : bs) =
    { c with active = s.active; ready = s.ready; blocked = s.blocked; pos = s.pos }

  let index_of x l =
    let rec go i = function [] -> 0 | y :: r -> if y = x then i else go (i + 1) r in
    go 1 l

  (* RemoveReady: JADE's Scheduler.remove (R5f). *)
  let remove_ready s id =
    let k = index_of id s.ready in
    if k = 0 then s
    else
      let r = List.filter (( <> ) id) s.ready in
      let p1 = if k < s.pos then s.pos - 1 else s.pos in
      { s with ready = r; pos = (if p1 > List.length r then 1 else p1) }

  let is_active_in s id = List.exists (fun (a : B.beh instance) -> a.id = id) s.active

  (* Deactivate (R5h). *)
  let deactivate s id =
    if not (is_active_in s id) then s
    else
      let s1 = remove_ready s id in
      { s1 with active = List.filter (fun (a : B.beh instance) -> a.id <> id) s.active;
                blocked = List.filter (( <> ) id) s.blocked }

  (* Block (R5d). *)
  let block s id =
    let s1 = remove_ready s id in
    { s1 with blocked = s.blocked @ [id] }

  (* NewId: the smallest positive id not active and not reserved. *)
  let new_id s reserved =
    let used n = is_active_in s n || List.mem n reserved in
    let rec go n = if used n then go (n + 1) else n in
    go 1

  (* ApplyEffect / ApplyEffects (R5g, R5h). *)
  let apply_effect p s this reserved = function
    | Activate b ->
      (match p.max_active with
       | Some m when List.length s.active >= m -> s
       | _ ->
         let n = new_id s reserved in
         { s with active = s.active @ [{ id = n; beh = b }]; ready = s.ready @ [n] })
    | Deactivate -> deactivate s this

  let apply_effects p s this effs reserved =
    List.fold_left (fun s e -> apply_effect p s this reserved e) s effs

  let beh_of (c : t) id =
    match List.find_opt (fun (a : B.beh instance) -> a.id = id) c.active with
    | Some a -> a.beh
    | None -> invalid_arg "Machine.beh_of: instance not active"

  (* ------------------------------------------------------- ghosts *)

  let add_wait p (c : t) (e : B.percept entry) =
    if p.ghosts && not p.flood then c.waits @ [(e.seq, e.prio, 0)] else c.waits

  (* BumpWaits: after dispatching e, every other waiting percept of higher
     priority has waited behind one more lower-priority dispatch. *)
  let bump_waits p (c : t) (e : B.percept entry) =
    if not p.ghosts || p.flood then c.waits
    else
      List.filter_map (fun (s, k, n) ->
          if s = e.seq then None else Some (s, k, if k > e.prio then n + 1 else n)) c.waits

  let add_done p (c : t) seq =
    if p.ghosts && not p.flood then Int_set.add seq c.done_ else c.done_

  (* ------------------------------------------------------ initial *)

  let init p ~world behs : t =
    ignore p;
    let active = List.mapi (fun i b -> { id = i + 1; beh = b }) behs in
    { o2a = Fqueue.empty; pq = Pqueue.empty; msgq = Fqueue.empty;
      next_seq = 0; msg_seq = 0; puts = 0;
      active; ready = List.map (fun (a : B.beh instance) -> a.id) active;
      blocked = []; pos = 1; phase = Transfer_phase; cur = None; dispatched = 0;
      done_ = Int_set.empty; waits = []; last = Init; world }

  (* --------------------------------------------------- host rules *)

  let is_percept_msg = function M_percept _ -> true | M_message _ -> false

  let msgq_percepts (c : t) =
    Fqueue.fold (fun n x -> if is_percept_msg x then n + 1 else n) 0 c.msgq

  (* O2AUsed: in Native the percepts moved on to the message queue count. *)
  let o2a_has_room p (c : t) =
    match p.o2a_capacity with
    | None -> true
    | Some cap ->
      let used = Fqueue.length c.o2a + (if p.variant = Native then msgq_percepts c else 0) in
      used < cap

  let wake_idle (c : t) = if c.phase = Idle_phase then Transfer_phase else c.phase

  let notify_effect p (c : t) percept prio mk_label : t =
    let seq = if p.flood then 0 else c.next_seq + 1 in
    let e = { p = percept; prio; seq } in
    { c with o2a = Fqueue.push (O_percept e) c.o2a; next_seq = seq;
             waits = add_wait p c e; phase = wake_idle c; last = mk_label e }

  (* Notify (R1a, R2b). *)
  let notify p c percept prio = notify_effect p c percept prio (fun e -> Notify e)

  (* NotifyWith (R2a). *)
  let notify_with p c percept prio = notify_effect p c percept prio (fun e -> Notify_with e)

  (* Put (R2c): does not wake an idle agent. *)
  let put _p (c : t) o : t =
    { c with o2a = Fqueue.push (O_object o) c.o2a; puts = c.puts + 1; last = Put o }

  (* Send (R5e, R5d, R3e). *)
  let send _p (c : t) m : t =
    let seq = c.msg_seq + 1 in
    { c with msgq = Fqueue.push (M_message { m; mseq = seq }) c.msgq; msg_seq = seq;
             ready = c.ready @ c.blocked; blocked = []; phase = wake_idle c;
             last = Send (m, seq) }

  (* --------------------------------------------- transfer rules *)

  let is_o2a_percept = function O_percept _ -> true | O_object _ -> false

  (* Transfer (R3a; native: into the message queue). One pass over O2A:
     percepts go into the priority queue, objects stay in order. *)
  let transfer_fast p (c : t) : lbl * t =
    let n = ref 0 and objects = ref [] in
    let pq =
      if p.flood then
        (* the flood abstraction: a percept already waiting is not added again *)
        Fqueue.fold (fun pq x -> match x with
            | O_percept e -> incr n; if Pqueue.mem e pq then pq else Pqueue.insert e pq
            | O_object _ -> objects := x :: !objects; pq) c.pq c.o2a
      else
        (* newest first: the objects left behind are consed back into order *)
        Pqueue.insert_newest_first (fun add ->
            Fqueue.fold_newest (fun () x -> match x with
                | O_percept e -> incr n; add e
                | O_object _ -> objects := x :: !objects) () c.o2a) c.pq in
    let objects = if p.flood then List.rev !objects else !objects in
    let l = Transfer !n in
    (l, { c with pq; o2a = (if objects = [] then Fqueue.empty else Fqueue.of_list objects);
                 phase = Dispatch_phase; dispatched = 0; last = l })

  let transfer p (c : t) : lbl * t =
    if p.variant <> Native && p.mutant = None then transfer_fast p c else
    let (moving, rest) = Fqueue.partition is_o2a_percept c.o2a in
    let (moving, rest) = match p.mutant with
      | Some Transfer_moves_one ->
        (* mutant: only the first percept moves; the rest of O2A stays in order *)
        (match Fqueue.remove_first is_o2a_percept c.o2a with
         | Some (first, rest) -> ([first], rest)
         | None -> ([], c.o2a))
      | Some O2a_not_drained -> (moving, c.o2a)   (* mutant: O2A keeps them *)
      | _ -> (moving, rest) in
    let entries = List.rev (List.rev_map (function O_percept e -> e | O_object _ -> assert false) moving) in
    let n = List.length entries in
    let c' =
      if p.variant = Native then
        let msgq = List.fold_left (fun q e -> Fqueue.push (M_percept e) q) c.msgq entries in
        if n > 0 then { c with msgq; ready = c.ready @ c.blocked; blocked = [] }
        else { c with msgq }
      else
        let add q e = if p.flood && Pqueue.mem e q then q else Pqueue.insert e q in
        { c with pq = List.fold_left add c.pq entries } in
    let l = Transfer n in
    (l, { c' with o2a = rest; phase = Dispatch_phase; dispatched = 0; last = l })

  (* TransferOne (printed). *)
  let transfer_one p (c : t) e rest : lbl * t =
    let pq = if p.flood && Pqueue.mem e c.pq then c.pq else Pqueue.insert e c.pq in
    let l = Transfer_one e in
    (l, { c with pq; o2a = rest; last = l })

  (* TransferSpin (printed): the head is an object; only last changes. *)
  let transfer_spin (c : t) o : lbl * t =
    let l = Transfer_spin o in
    (l, { c with last = l })

  (* TransferEnd (printed). *)
  let transfer_end (c : t) : lbl * t =
    (Transfer_end, { c with phase = Dispatch_phase; dispatched = 0; last = Transfer_end })

  (* ------------------------------------------------ dispatch rules *)

  let budget_spent p (c : t) = p.variant = Budgeted && c.dispatched >= p.budget
  let dispatch_over p (c : t) = Pqueue.is_empty c.pq || budget_spent p c

  (* HandlersOf: the registered handlers (R4a). The list depends only on the
     active behaviours, an immutable list: it is remembered for the last one
     seen (physically), which most dequeues share. *)
  let handlers_cache : (B.beh instance list * (int * int) list * B.beh list) option ref = ref None

  (* The snapshot, and beside it the behaviour of each entry's instance
     (which the derived rule Dispatch uses while [active] is unchanged). *)
  let handlers_and_behs (c : t) =
    match !handlers_cache with
    | Some (a, h, bs) when a == c.active -> (h, bs)
    | _ ->
      let pairs = List.concat_map (fun (a : B.beh instance) ->
          List.init (B.percept_handlers a.beh) (fun j -> ((a.id, j + 1), a.beh))) c.active in
      let h = List.map fst pairs and bs = List.map snd pairs in
      handlers_cache := Some (c.active, h, bs);
      (h, bs)

  let handlers_of (c : t) = fst (handlers_and_behs c)

  (* Dequeue (R3b, R4a, R4b). *)
  let dequeue_entry p (c : t) e pq : lbl * t =
    let l = Dequeue e in
    (l, { c with pq; cur = Some { e; todo = handlers_of c; applied = false };
                 waits = bump_waits p c e; phase = Handle_phase;
                 dispatched = c.dispatched + 1; last = l })

  let dequeue p (c : t) : (lbl * t) list =
    match p.tie, p.flood, p.mutant, Pqueue.pop c.pq with
    | Stable, false, None, Some (e, pq) ->
      (* Seqs are unique: the top is the one candidate (R3b); one pop. *)
      [ dequeue_entry p c e pq ]
    | _ ->
    let cands = Pqueue.candidates ~stable:(p.tie = Stable) c.pq in
    let cands = match p.mutant with
      | Some Ties_to_largest_seq ->
        (* mutant: among the highest priority, the LAST notified *)
        let top = Pqueue.candidates ~stable:false c.pq in
        let m = List.fold_left (fun m e -> max m e.seq) min_int top in
        List.filter (fun e -> e.seq = m) top
      | _ -> cands in
    List.map (fun e -> dequeue_entry p c e (Pqueue.remove e c.pq)) cands

  let rec find_instance id = function
    | [] -> None
    | (a : B.beh instance) :: rest -> if a.id = id then Some a.beh else find_instance id rest

  (* Handle: run the next handler of the snapshot. The ids still to try are
     reserved: an instance activated now does not take one (D2). *)
  let handle p (c : t) d (id, h) b rest world : lbl * t =
    let (world, effs) = B.run_percept_handler world ~id b h d.e.p in
    let l = Handle { id; h; p = d.e.p; seq = d.e.seq } in
    let rest = match p.mutant with Some First_handler_only -> [] | _ -> rest in  (* mutant *)
    let c' = { c with world; cur = Some { d with todo = rest; applied = true }; last = l } in
    match effs with
    | [] -> (l, c')
    | _ -> (l, with_bs c' (apply_effects p (bs_of c) id effs (List.map fst d.todo)))

  (* Skip: the next handler does not apply. *)
  let skip (c : t) d (id, h) rest world : lbl * t =
    let l = Skip { id; h } in
    (l, { c with world; cur = Some { d with todo = rest }; last = l })

  (* EndDispatch: the percept leaves; discarded if no handler applied (R3b). *)
  let end_dispatch p (c : t) d : lbl * t =
    let l = End_dispatch { seq = d.e.seq; discarded = not d.applied } in
    (l, { c with done_ = add_done p c d.e.seq; cur = None; phase = Dispatch_phase; last = l })

  (* --------------------------------------------- behaviour rules *)

  (* StepHandlers / FirstHandler / FirstEntry (R5b; native: percept handlers
     first). Returns the handler and the entry it takes, if any. *)
  let first_match p (c : t) id b =
    let world = ref c.world in
    let percept_ok h x = match x with
      | M_percept e ->
        let (w, ok) = B.percept_applicable !world ~id b h e.p in
        world := w; ok
      | M_message _ -> false in
    let message_ok h x = match x with
      | M_message { m; _ } -> B.message_accepted !world ~id b h m
      | M_percept _ -> false in
    let handlers =
      (if p.variant = Native then
         List.init (B.percept_handlers b) (fun j -> (`Percept, j + 1))
       else [])
      @ List.init (B.message_handlers b) (fun j -> (`Message, j + 1)) in
    let rec go = function
      | [] -> None
      | (kind, h) :: rest ->
        let ok = match kind with `Percept -> percept_ok h | `Message -> message_ok h in
        (match Fqueue.remove_first ok c.msgq with
         | Some (x, msgq) -> Some (kind, h, x, msgq)
         | None -> go rest) in
    let r = go handlers in
    (!world, r)

  (* BehaviourStep (R5a-R5d, R5f): one step of ready[pos]. *)
  let behaviour_step p (c : t) : lbl * t =
    let n = List.length c.ready in
    let id = List.nth c.ready (c.pos - 1) in
    let b = beh_of c id in
    let s0 = { (bs_of c) with pos = (c.pos mod n) + 1 } in
    let (world, s1) =
      if B.has_action b then
        let (w, effs) = B.run_action c.world ~id b in
        (w, apply_effects p s0 id effs [id])
      else (c.world, s0) in
    let (world, found) = first_match p { c with world } id b in
    let (world, s2, msgq, taken) = match found with
      | None -> (world, s1, c.msgq, None)
      | Some (kind, h, x, msgq) ->
        let (w, effs) = match kind, x with
          | `Percept, M_percept e -> B.run_percept_handler world ~id b h e.p
          | `Message, M_message { m; _ } -> B.run_message_handler world ~id b h m
          | _ -> assert false in
        (w, apply_effects p s1 id effs [id], msgq, Some x) in
    let s3 =
      if not (B.cyclic b) && (match p.mutant with Some Oneshot_not_removed -> false | _ -> true)
      then deactivate s2 id
      else if not (B.has_action b) && taken = None && is_active_in s2 id then block s2 id
      else s2 in
    let (done_, waits) = match taken with
      | Some (M_percept e) -> (add_done p c e.seq, bump_waits p c e)
      | _ -> (c.done_, c.waits) in
    let l = Behaviour_step { id; msg = taken } in
    (l, with_bs { c with world; msgq; done_; waits; phase = Transfer_phase; last = l } s3)

  let idle_condition (c : t) =
    c.ready = [] && not (Fqueue.exists is_o2a_percept c.o2a) && Pqueue.is_empty c.pq

  (* NextIteration: nothing to step; start the next iteration. *)
  let next_iteration (c : t) : lbl * t =
    (Next_iteration, { c with phase = Transfer_phase; last = Next_iteration })

  (* Idle (R3e). *)
  let idle (c : t) : lbl * t = (Idle, { c with phase = Idle_phase; last = Idle })

  (* ---------------------------------------------------------- step *)

  let step p (c : t) : (lbl * t) list =
    match c.phase, c.cur with
    | Transfer_phase, _ when p.variant = Printed ->
      (match Fqueue.pop c.o2a with
       | None -> [transfer_end c]
       | Some (O_percept e, rest) -> [transfer_one p c e rest]
       | Some (O_object o, _) -> [transfer_spin c o])
    | Transfer_phase, _ -> [transfer p c]
    | Dispatch_phase, _ when (match p.mutant with Some Step_before_dispatch -> true | _ -> false)
                             && c.ready <> []
                             && not (Pqueue.is_empty c.pq)
                             && (match c.last with Transfer _ | Transfer_end -> true | _ -> false) ->
      (* mutant: right after the transfer, a behaviour step runs before the dispatch *)
      let (l, c') = behaviour_step p c in
      [ (l, { c' with phase = Dispatch_phase }) ]
    | Dispatch_phase, _ when p.variant <> Native && not (dispatch_over p c) -> dequeue p c
    | Dispatch_phase, _ when c.ready <> [] -> [behaviour_step p c]
    | Dispatch_phase, _ when p.variant <> Printed && idle_condition c -> [idle c]
    | Dispatch_phase, _ -> [next_iteration c]
    | Handle_phase, Some d ->
      (match d.todo with
       | [] -> [end_dispatch p c d]
       | ((id, h) as t) :: rest ->
         (* Applicable: the instance is still active (R4b) and the handler
            applies; then Handle, else Skip. *)
         match find_instance id c.active with
         | None -> [skip c d t rest c.world]
         | Some b ->
           let (world, ok) = B.percept_applicable c.world ~id b h d.e.p in
           if ok then [handle p c d t b rest world] else [skip c d t rest world])
    | Handle_phase, None -> invalid_arg "Machine.step: phase Handle without a dispatch"
    | Idle_phase, _ -> []

  let is_idle (c : t) = c.phase = Idle_phase

  (* ------------------------------------------------ derived rule *)

  (* Dispatch: [step] taken from a Dequeue (when it is the one rule enabled)
     or from the Handle phase, through the Handle arm until the snapshot is
     empty, then EndDispatch; on local variables instead of a configuration
     per rule. Each branch below is the branch of [step], [dequeue_entry],
     [handle], [skip] or [end_dispatch] whose name it carries; what they
     would have written in the configuration (world, todo, applied, the
     behaviour part) is kept here and written once, at the end. *)
  (* The Handle arm over the snapshot [todo] of the dispatch of [e], from
     configuration [c] (whose behaviour part is [bs] once a handler had
     effects). No closure is allocated: this runs once per percept. *)
  let rec dispatch_handlers observe p (c : t) e world applied bs todo behs =
    match todo with
    | [] -> (world, applied, bs)
    | (id, h) :: rest ->
      (* [behs]: beside [todo], the behaviour of each entry's instance in
         [c.active], when the snapshot was just taken from it ([] otherwise);
         while no body had effects, the instance is found there *)
      let found = match bs, behs with
        | None, b :: _ -> Some b
        | Some s, _ -> find_instance id s.active
        | None, [] -> find_instance id c.active in
      let behs = match behs with _ :: brest -> brest | [] -> [] in
      (* the pre-test: where it says no, percept_applicable would answer
         false, changing nothing *)
      let found = match found with
        | Some b when B.percept_may_apply world b h e.p -> found
        | _ -> None in
      match found with
      | None ->                                                              (* skip *)
        (match observe with Some f -> f (Skip { id; h }) | None -> ());
        dispatch_handlers observe p c e world applied bs rest behs
      | Some b ->
        let (world, ok) = B.percept_applicable world ~id b h e.p in
        if not ok then begin                                                 (* skip *)
          (match observe with Some f -> f (Skip { id; h }) | None -> ());
          dispatch_handlers observe p c e world applied bs rest behs
        end else begin                                                       (* handle *)
          let (world, effs) = B.run_percept_handler world ~id b h e.p in
          let bs = match effs with
            | [] -> bs
            | _ ->
              let s = match bs with Some s -> s | None -> bs_of c in
              Some (apply_effects p s id effs (List.map fst todo)) in
          (match observe with Some f -> f (Handle { id; h; p = e.p; seq = e.seq }) | None -> ());
          dispatch_handlers observe p c e world true bs
            (match p.mutant with Some First_handler_only -> [] | _ -> rest) behs  (* mutant *)
        end

  (* The configuration after the handlers and EndDispatch; [pq], [waits]
     and [dispatched] are [c]'s, or what Dequeue made of them. *)
  let dispatch_end observe p (c : t) e ~pq ~waits ~dispatched (world, applied, bs) =
    let l = End_dispatch { seq = e.seq; discarded = not applied } in        (* end_dispatch *)
    (match observe with Some f -> f l | None -> ());
    let c' = { c with pq; waits; dispatched; world; done_ = add_done p c e.seq; cur = None;
                      phase = Dispatch_phase; last = l } in
    match bs with Some s -> with_bs c' s | None -> c'

  let dispatch ?observe p (c : t) : t option =
    match c.phase, c.cur with
    | Handle_phase, Some d ->
      Some (dispatch_end observe p c d.e ~pq:c.pq ~waits:c.waits ~dispatched:c.dispatched
              (dispatch_handlers observe p c d.e c.world d.applied None d.todo []))
    | Dispatch_phase, _ when p.mutant = None && p.variant <> Native && p.tie = Stable && not p.flood
                             && not (dispatch_over p c) ->
      (match Pqueue.pop c.pq with                                            (* dequeue_entry *)
       | Some (e, pq) ->
         (match observe with Some f -> f (Dequeue e) | None -> ());
         let (todo, behs) = handlers_and_behs c in
         Some (dispatch_end observe p c e ~pq ~waits:(bump_waits p c e) ~dispatched:(c.dispatched + 1)
                 (dispatch_handlers observe p c e c.world false None todo behs))
       | None -> None)
    | _ -> None
end
