(* The agent loop of spec/AgentLoop.tla, rule by rule, on plain data: the
   reference. No caches, no derived rules, no test-only branches, no mutable
   state; the fast path is lib/engine/, mutants are lib/explore/mutant.ml.

   Map from the spec to this file (docs/semantics.md sections in brackets;
   docs/architecture.md has the same table with the rulings):

     Init ............... init                [Configurations]
     Notify(p) .......... notify              [Host rules]
     NotifyWith(p, k) ... notify_with         [Host rules]
     CanNotify + Notify / NotifyWith, the host's notifyEvent(p[, k]) ..
                          notify_event        [Host rules]
     Put(o) ............. put                 [Host rules]
     Send(m) ............ send                [Host rules]
     SendInStep(m) ...... send_in_step        [Host rules]
     Transfer ........... transfer            [Agent rules]
     TransferOne ........ transfer_one        [Agent rules]
     TransferSpin ....... transfer_spin       [Agent rules]
     TransferEnd ........ transfer_end        [Agent rules]
     Dequeue ............ dequeue             [Agent rules]
     Handle ............. handle              [Agent rules]  } handle_or_skip:
     Skip ............... skip                [Agent rules]  } Applicable once
     EndDispatch ........ end_dispatch        [Agent rules]
     BehaviourStep ...... behaviour_step      [Agent rules]
     NextIteration ...... next_iteration      [Agent rules]
     Idle ............... idle                [Agent rules]
     AgentStep .......... step (= step_by rules)
     Applicable(t) ...... applicable          [Agent rules]
     HandlersOf ......... handlers_of         [Agent rules]
     StepHandlers, FirstHandler, FirstEntry .. first_match [Agent rules]
     BudgetSpent, DispatchOver ............... budget_spent, dispatch_over
                                               [Variants and tie policies]
     IdleCondition ...... idle_condition      [Agent rules]
     O2AHasRoom ......... o2a_has_room        [Host rules]
     NotifyEffect ....... notify_effect       [Host rules]
     ApplyEffect(s), NewId, Deactivate, Block, RemoveReady ..
                          apply_effect(s), new_id, deactivate, block,
                          remove_ready        [Effects on behaviours]
     BumpWaits .......... bump_waits (ghost)  [Configurations] *)

type variant = Printed | Reference | Budgeted | Native
type tie_policy = Stable | Unstable

type params = {
  variant : variant;
  tie : tie_policy;
  budget : int;
  max_active : int option;
  o2a_capacity : int option;
  flood : bool;
  ghosts : bool;
}

let default_params = {
  variant = Reference; tie = Stable; budget = 1; max_active = None;
  o2a_capacity = None; flood = false; ghosts = false;
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

type 'b stepped =
  | Not_stepped
  | Stepped_kept
  | Stepped_blocked of { active : 'b instance list; ready : int list; blocked : int list; pos : int }

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
  stepped : 'b stepped;
  world : 'w;
}

type 'b effect = Activate of 'b | Deactivate

module type BODIES = sig
  type percept
  type message
  type obj
  type beh
  type world
  type bindings
  val cyclic : beh -> bool
  val has_action : beh -> bool
  val percept_handlers : beh -> int
  val message_handlers : beh -> int
  val percept_applicable : world -> id:int -> beh -> int -> percept -> world * bindings option
  val run_percept_handler :
    world -> id:int -> active:int -> beh -> int -> percept -> bindings -> world * beh effect list
  val run_action : world -> id:int -> active:int -> beh -> world * beh effect list
  val message_accepted : world -> id:int -> beh -> int -> message -> world * bindings option
  val run_message_handler :
    world -> id:int -> active:int -> beh -> int -> message -> bindings -> world * beh effect list
  val take_outbox : world -> world * (string * message) list
end

type refusal = Negative_priority of int | O2a_full

module Make (B : BODIES) = struct
  type t = (B.percept, B.message, B.obj, B.beh, B.world) config
  type lbl = (B.percept, B.message, B.obj) label

  (* ================================================================ *)
  (* Operators of the spec (AgentLoop.tla, "Helpers" and "Behaviour-  *)
  (* state transformers"), on plain data.                              *)
  (* ================================================================ *)

  (* BS: the behaviour part of a configuration. *)
  type bs = { active : B.beh instance list; ready : int list; blocked : int list; pos : int }

  let bs_of (c : t) = { active = c.active; ready = c.ready; blocked = c.blocked; pos = c.pos }

  (* SetBS. *)
  let with_bs (c : t) (s : bs) =
    { c with active = s.active; ready = s.ready; blocked = s.blocked; pos = s.pos }

  (* IndexOf (1-based; 0 when absent). *)
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

  (* NewId: the smallest positive id not active and not reserved. Fewer
     than [n] ids are used, so one of 1..n is free: the ids are marked in
     an array of n places, then the first unmarked is taken (one pass over
     each list, not one per candidate: D19). *)
  let new_id s reserved =
    let n = List.length s.active + List.length reserved + 1 in
    let used = Array.make (n + 1) false in
    let mark i = if i >= 1 && i <= n then used.(i) <- true in
    List.iter (fun (a : B.beh instance) -> mark a.id) s.active;
    List.iter mark reserved;
    let rec go i = if used.(i) then go (i + 1) else i in
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

  (* BOf, for an instance that may have left: [None] then. *)
  let find_instance id (active : B.beh instance list) =
    match List.find_opt (fun (a : B.beh instance) -> a.id = id) active with
    | Some a -> Some a.beh
    | None -> None

  (* BOf, for an instance that is active. *)
  let beh_of (c : t) id =
    match find_instance id c.active with
    | Some b -> b
    | None -> Fault.crash "Machine.beh_of: instance %d is not active" id

  (* The ghosts [done] and [waits]; kept only when [params.ghosts]. *)
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

  (* IsPercept, for O2A and message-queue entries. *)
  let is_o2a_percept = function O_percept _ -> true | O_object _ -> false
  let is_percept_msg = function M_percept _ -> true | M_message _ -> false

  (* PerceptInO2A. *)
  let percept_in_o2a (c : t) = Fqueue.exists is_o2a_percept c.o2a

  (* MsgqPercepts. *)
  let msgq_percepts (c : t) =
    Fqueue.fold (fun n x -> if is_percept_msg x then n + 1 else n) 0 c.msgq

  (* HandlersOf(active): the registered handlers (R4a), activation order then
     declaration order. *)
  let handlers_of (c : t) =
    List.concat_map (fun (a : B.beh instance) ->
        List.init (B.percept_handlers a.beh) (fun j -> (a.id, j + 1))) c.active

  (* TodoIds: the instances of a snapshot, reserved for NewId (D2). *)
  let todo_ids todo = List.map fst todo

  (* BudgetSpent, DispatchOver. *)
  let budget_spent p (c : t) = p.variant = Budgeted && c.dispatched >= p.budget
  let dispatch_over p (c : t) = Pqueue.is_empty c.pq || budget_spent p c

  (* IdleCondition (R3e). *)
  let idle_condition (c : t) =
    c.ready = [] && not (percept_in_o2a c) && Pqueue.is_empty c.pq

  (* Applicable(t): the instance is still active (R4b) and handler h accepts
     the percept (R3b). The bodies evaluate the pattern and [when], which may
     record an error in the world: the result carries it. *)
  let applicable (c : t) (d : B.percept dispatch) (id, h) =
    match find_instance id c.active with
    | None -> (c.world, None)
    | Some b ->
      let (world, bound) = B.percept_applicable c.world ~id b h d.e.p in
      (world, Option.map (fun bindings -> (b, bindings)) bound)

  (* ================================================================ *)
  (* Init                                                              *)
  (* ================================================================ *)

  let init _p ~world behs : t =
    let active = List.mapi (fun i b -> { id = i + 1; beh = b }) behs in
    { o2a = Fqueue.empty; pq = Pqueue.empty; msgq = Fqueue.empty;
      next_seq = 0; msg_seq = 0; puts = 0;
      active; ready = List.map (fun (a : B.beh instance) -> a.id) active;
      blocked = []; pos = 1; phase = Transfer_phase; cur = None; dispatched = 0;
      done_ = Int_set.empty; waits = []; last = Init; stepped = Not_stepped; world }

  (* ================================================================ *)
  (* Host actions                                                      *)
  (* ================================================================ *)

  (* O2AHasRoom, with O2AUsed: in Native the percepts moved on to the
     message queue count (D6). *)
  let o2a_has_room p (c : t) =
    match p.o2a_capacity with
    | None -> true
    | Some cap ->
      let used = Fqueue.length c.o2a + (if p.variant = Native then msgq_percepts c else 0) in
      used < cap

  let wake_idle (c : t) = if c.phase = Idle_phase then Transfer_phase else c.phase

  (* NotifyEffect(p, k, actName). *)
  let notify_effect p (c : t) percept prio mk_label : t =
    let seq = if p.flood then 0 else c.next_seq + 1 in
    let e = { p = percept; prio; seq } in
    { c with o2a = Fqueue.push (O_percept e) c.o2a; next_seq = seq;
             waits = add_wait p c e; phase = wake_idle c; last = mk_label e }

  (* Notify(p) (R1a, R2b). *)
  let notify p c percept prio = notify_effect p c percept prio (fun e -> Notify e)

  (* NotifyWith(p, k) (R2a). *)
  let notify_with p c percept prio = notify_effect p c percept prio (fun e -> Notify_with e)

  (* What the host's notifyEvent(p) or notifyEvent(p, k) does: refused with a
     negative k (R2a) or a full O2A queue (R2d; a refusal changes nothing),
     else Notify or NotifyWith. *)
  let notify_event p (c : t) percept ~default ~priority : (t, refusal) result =
    match priority with
    | Some k when k < 0 -> Error (Negative_priority k)
    | _ when not (o2a_has_room p c) -> Error O2a_full
    | None -> Ok (notify p c percept default)
    | Some k -> Ok (notify_with p c percept k)

  (* Put(o) (R2c): does not wake an idle agent (D3). *)
  let put _p (c : t) o : t =
    { c with o2a = Fqueue.push (O_object o) c.o2a; puts = c.puts + 1; last = Put o }

  (* Send(m) (R5e, R5d, R3e); it closes the window of the last behaviour
     step (R6: deliveries to one agent keep their order). *)
  let send _p (c : t) m : t =
    let seq = c.msg_seq + 1 in
    { c with msgq = Fqueue.push (M_message { m; mseq = seq }) c.msgq; msg_seq = seq;
             ready = c.ready @ c.blocked; blocked = []; phase = wake_idle c;
             last = Send (m, seq); stepped = Not_stepped }

  (* SendInStep(m) (R5d revised, D42): enabled in the window of the last
     behaviour step; as Send, and a behaviour that step blocked is runnable
     again at its place (the behaviour state S2 the step had before the
     block, the other blocked ones woken to the end of ready). The window
     stays open. The phase is Transfer in the window: nothing to wake. *)
  let send_in_step _p (c : t) m : t option =
    let seq = c.msg_seq + 1 in
    let msgq = Fqueue.push (M_message { m; mseq = seq }) c.msgq in
    let after c = { c with msgq; msg_seq = seq; blocked = []; last = Send (m, seq);
                           stepped = Stepped_kept } in
    match c.stepped with
    | Not_stepped -> None
    | Stepped_kept -> Some (after { c with ready = c.ready @ c.blocked })
    | Stepped_blocked s2 ->
      Some (after { c with active = s2.active; ready = s2.ready @ s2.blocked; pos = s2.pos })

  let last_action_name (c : t) =
    match c.last, c.stepped with
    | Send _, (Stepped_kept | Stepped_blocked _) -> "SendInStep"
    | l, _ -> action_name l

  (* ================================================================ *)
  (* Agent actions. Each is [params -> t -> (lbl * t) list]: the empty *)
  (* list when its enabling condition (the spec's conjuncts before the *)
  (* primed variables) does not hold; several results only where the  *)
  (* spec has an \E (Dequeue's candidates).                            *)
  (* ================================================================ *)

  type rule = params -> t -> (lbl * t) list

  (* Transfer (R3a; native: into the message queue, R5d). *)
  let transfer p (c : t) : (lbl * t) list =
    if not (p.variant <> Printed && c.phase = Transfer_phase) then [] else
    let (moving, rest) = Fqueue.partition is_o2a_percept c.o2a in
    let entries = List.filter_map (function O_percept e -> Some e | O_object _ -> None) moving in
    let n = List.length entries in
    let c' =
      if p.variant = Native then
        let msgq = List.fold_left (fun q e -> Fqueue.push (M_percept e) q) c.msgq entries in
        if n > 0 then { c with msgq; ready = c.ready @ c.blocked; blocked = [] }
        else { c with msgq }
      else
        (* pq \cup {ToPQ(moving[i])}: under Flood an equal entry merges *)
        let add q e = if p.flood && Pqueue.mem e q then q else Pqueue.insert e q in
        { c with pq = List.fold_left add c.pq entries } in
    let l = Transfer n in
    [ (l, { c' with o2a = rest; phase = Dispatch_phase; dispatched = 0; last = l;
                    stepped = Not_stepped }) ]

  (* TransferOne (printed): the head of O2A is a percept. *)
  let transfer_one p (c : t) : (lbl * t) list =
    if not (p.variant = Printed && c.phase = Transfer_phase) then [] else
    match Fqueue.pop c.o2a with
    | Some (O_percept e, rest) ->
      let pq = if p.flood && Pqueue.mem e c.pq then c.pq else Pqueue.insert e c.pq in
      let l = Transfer_one e in
      [ (l, { c with pq; o2a = rest; last = l; stepped = Not_stepped }) ]
    | Some (O_object _, _) | None -> []

  (* TransferSpin (printed): the head is an object; only last changes. *)
  let transfer_spin p (c : t) : (lbl * t) list =
    if not (p.variant = Printed && c.phase = Transfer_phase) then [] else
    match Fqueue.peek c.o2a with
    | Some (O_object o) ->
      let l = Transfer_spin o in [ (l, { c with last = l; stepped = Not_stepped }) ]
    | Some (O_percept _) | None -> []

  (* TransferEnd (printed): O2A is empty. *)
  let transfer_end p (c : t) : (lbl * t) list =
    if not (p.variant = Printed && c.phase = Transfer_phase && Fqueue.is_empty c.o2a) then [] else
    [ (Transfer_end, { c with phase = Dispatch_phase; dispatched = 0; last = Transfer_end;
                              stepped = Not_stepped }) ]

  (* Dequeue (R3b, R4a, R4b): one result per candidate. *)
  let dequeue p (c : t) : (lbl * t) list =
    if not (p.variant <> Native && c.phase = Dispatch_phase
            && not (Pqueue.is_empty c.pq) && not (budget_spent p c)) then [] else
    List.map (fun e ->
        let l = Dequeue e in
        (l, { c with pq = Pqueue.remove e c.pq; cur = Some { e; todo = handlers_of c; applied = false };
                     waits = bump_waits p c e; phase = Handle_phase;
                     dispatched = c.dispatched + 1; last = l; stepped = Not_stepped }))
      (Pqueue.candidates ~stable:(p.tie = Stable) c.pq)

  (* The number of active instances, which the bodies see (D19). *)
  let active_count (c : t) = List.length c.active

  (* Handle, once Applicable(t) held for the head [t] of the snapshot, in
     [world], with what its guard bound: its body runs, then its effects
     apply; the ids still in the snapshot are reserved (D2). *)
  let handle p (c : t) d (id, h) (b, bindings) world : lbl * t =
    let (world, effs) = B.run_percept_handler world ~id ~active:(active_count c) b h d.e.p bindings in
    let l = Handle { id; h; p = d.e.p; seq = d.e.seq } in
    let c' = { c with world; cur = Some { d with todo = List.tl d.todo; applied = true }; last = l;
                      stepped = Not_stepped } in
    (l, with_bs c' (apply_effects p (bs_of c) id effs (todo_ids d.todo)))

  (* Skip, once Applicable(t) failed for the head [t] of the snapshot. *)
  let skip (c : t) d (id, h) world : lbl * t =
    let l = Skip { id; h } in
    (l, { c with world; cur = Some { d with todo = List.tl d.todo }; last = l; stepped = Not_stepped })

  (* Handle \/ Skip: phase = "handle" /\ cur.todo # <<>>; Applicable(Head(cur.todo))
     is evaluated once and decides which of the two is enabled. *)
  let handle_or_skip p (c : t) : (lbl * t) list =
    match c.phase, c.cur with
    | Handle_phase, Some ({ todo = t :: _; _ } as d) ->
      (match applicable c d t with
       | (world, Some found) -> [ handle p c d t found world ]
       | (world, None) -> [ skip c d t world ])
    | Handle_phase, None -> Fault.crash "Machine: phase handle without a dispatch in progress"
    | _ -> []

  (* EndDispatch: the percept leaves; discarded if no handler applied (R3b). *)
  let end_dispatch p (c : t) : (lbl * t) list =
    match c.phase, c.cur with
    | Handle_phase, Some ({ todo = []; _ } as d) ->
      let l = End_dispatch { seq = d.e.seq; discarded = not d.applied } in
      [ (l, { c with done_ = add_done p c d.e.seq; cur = None; phase = Dispatch_phase; last = l;
                     stepped = Not_stepped }) ]
    | _ -> []

  (* What a behaviour step took from the message queue: a percept (native)
     or a message, with the handler that accepts it and its guard's
     bindings. *)
  type taken =
    | Took_percept of int * B.percept entry * B.bindings
    | Took_message of int * B.message * int * B.bindings

  (* FirstEntry(h): the first of the entries that handler h accepts
     ([accepts] answers what it took, with its guard's bindings), and its
     position; the world goes through every question, in order (a guard may
     record an error). *)
  let first_entry world accepts entries =
    let rec go world i = function
      | [] -> (world, None)
      | x :: rest ->
        match accepts world x with
        | (world, Some taken) -> (world, Some (i, taken))
        | (world, None) -> go world (i + 1) rest in
    go world 0 entries

  (* StepHandlers(b), FirstHandler (R5b; native: percept handlers first):
     the first handler with an entry it accepts takes the first such entry;
     the message queue without it. *)
  let first_match p (c : t) id b : B.world * (taken * (B.percept, B.message) msg_item Fqueue.t) option =
    let percept_handler h world = function
      | M_percept e ->
        (match B.percept_applicable world ~id b h e.p with
         | (w, Some bd) -> (w, Some (Took_percept (h, e, bd)))
         | (w, None) -> (w, None))
      | M_message _ -> (world, None) in
    let message_handler h world = function
      | M_message { m; mseq } ->
        (match B.message_accepted world ~id b h m with
         | (w, Some bd) -> (w, Some (Took_message (h, m, mseq, bd)))
         | (w, None) -> (w, None))
      | M_percept _ -> (world, None) in
    let handlers =
      (if p.variant = Native then List.init (B.percept_handlers b) (fun j -> percept_handler (j + 1)) else [])
      @ List.init (B.message_handlers b) (fun j -> message_handler (j + 1)) in
    match handlers with
    | [] -> (c.world, None)
    | _ when Fqueue.is_empty c.msgq -> (c.world, None)
    | _ ->
    let entries = Fqueue.to_list c.msgq in
    let rec go world = function
      | [] -> (world, None)
      | accepts :: rest ->
        match first_entry world accepts entries with
        | (world, Some (i, taken)) ->
          (world, Some (taken, Fqueue.of_list (List.filteri (fun j _ -> j <> i) entries)))
        | (world, None) -> go world rest in
    go c.world handlers

  (* BehaviourStep (R5a-R5d, R5f): one step of ready[pos]. S0..S3 as in the
     spec's LET; it opens the window of SendInStep ([stepped]). *)
  let behaviour_step p (c : t) : (lbl * t) list =
    if not (c.phase = Dispatch_phase && dispatch_over p c && c.ready <> []) then [] else
    let id = List.nth c.ready (c.pos - 1) in
    let b = beh_of c id in
    let s0 = { (bs_of c) with pos = (c.pos mod List.length c.ready) + 1 } in
    let (world, s1) =
      if B.has_action b then
        let (w, effs) = B.run_action c.world ~id ~active:(List.length s0.active) b in
        (w, apply_effects p s0 id effs [id])
      else (c.world, s0) in
    let (world, found) = first_match p { c with world } id b in
    let active = List.length s1.active in
    let (world, s2, msgq, taken) = match found with
      | None -> (world, s1, c.msgq, None)
      | Some (Took_percept (h, e, bd), msgq) ->
        let (w, effs) = B.run_percept_handler world ~id ~active b h e.p bd in
        (w, apply_effects p s1 id effs [id], msgq, Some (M_percept e))
      | Some (Took_message (h, m, mseq, bd), msgq) ->
        let (w, effs) = B.run_message_handler world ~id ~active b h m bd in
        (w, apply_effects p s1 id effs [id], msgq, Some (M_message { m; mseq })) in
    let blocks = B.cyclic b && not (B.has_action b) && taken = None && is_active_in s2 id in
    let s3 =
      if not (B.cyclic b) then deactivate s2 id
      else if blocks then block s2 id
      else s2 in
    (* the window of SendInStep (R5d revised): S2 when the step blocked *)
    let stepped =
      if blocks then Stepped_blocked { active = s2.active; ready = s2.ready; blocked = s2.blocked; pos = s2.pos }
      else Stepped_kept in
    let (done_, waits) = match taken with
      | Some (M_percept e) -> (add_done p c e.seq, bump_waits p c e)
      | _ -> (c.done_, c.waits) in
    let l = Behaviour_step { id; msg = taken } in
    [ (l, with_bs { c with world; msgq; done_; waits; phase = Transfer_phase; last = l; stepped } s3) ]

  (* NextIteration (D5): nothing to step; start the next iteration. *)
  let next_iteration p (c : t) : (lbl * t) list =
    if not (c.phase = Dispatch_phase && dispatch_over p c && c.ready = []
            && (p.variant = Printed || not (idle_condition c))) then [] else
    [ (Next_iteration, { c with phase = Transfer_phase; last = Next_iteration; stepped = Not_stepped }) ]

  (* Idle (R3e). *)
  let idle p (c : t) : (lbl * t) list =
    if not (p.variant <> Printed && c.phase = Dispatch_phase && dispatch_over p c
            && idle_condition c) then [] else
    [ (Idle, { c with phase = Idle_phase; last = Idle; stepped = Not_stepped }) ]

  (* ================================================================ *)
  (* AgentStep: the disjunction of the agent actions.                  *)
  (* ================================================================ *)

  type rules = {
    transfer : rule; transfer_one : rule; transfer_spin : rule; transfer_end : rule;
    dequeue : rule; handle_or_skip : rule; end_dispatch : rule;
    behaviour_step : rule; next_iteration : rule; idle : rule;
  }

  let rules = {
    transfer; transfer_one; transfer_spin; transfer_end;
    dequeue; handle_or_skip; end_dispatch;
    behaviour_step; next_iteration; idle;
  }

  let step_by (r : rules) p (c : t) : (lbl * t) list =
    List.concat_map (fun (rule : rule) -> rule p c)
      [ r.transfer; r.transfer_one; r.transfer_spin; r.transfer_end;
        r.dequeue; r.handle_or_skip; r.end_dispatch;
        r.behaviour_step; r.next_iteration; r.idle ]

  let step p c = step_by rules p c

  let is_idle (c : t) = c.phase = Idle_phase
end
