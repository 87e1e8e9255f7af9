(* The agent loop of one Jadescript agent, as a Coq function: the rules of
   spec/AgentLoop.tla and lib/semantics/machine.ml, written once more.

   This file is the machine that the proofs are about AND the machine that
   is extracted to OCaml (Extract.v): the test test/proofs holds the
   extracted [step] equal to [Machine.step] on every state of every model
   of spec/models. Each definition below carries the name of the TLA+
   operator and of the OCaml function it mirrors; docs/proofs.md says what
   is abstracted.

   What handlers and action blocks do is abstracted as the spec abstracts
   it (record [bodies]): a handler accepts some percepts (or messages) and
   has a list of effects, activate a behaviour or [deactivate this], which
   may depend on the value it handles (the spec's byValue). *)

From Coq Require Import List Bool Arith.
Import ListNotations.

(* ------------------------------------------------------------------ *)
(* Parameters (Machine.params)                                          *)
(* ------------------------------------------------------------------ *)

Inductive variant := Printed | Reference | Budgeted | Native.
Inductive tie_policy := Stable | Unstable.

(* The constants of the spec that are not bodies: Variant, TiePolicy,
   Budget, MaxActive (None: no bound), O2ACapacity (None: unbounded, R2d),
   Flood. The model bounds MaxNotify, MaxPut, MaxSend are not here: the
   host may notify, put and send without end. *)
Record params := {
  p_variant : variant;
  p_tie : tie_policy;
  p_budget : nat;
  p_max_active : option nat;
  p_capacity : option nat;
  p_flood : bool;
}.

Inductive phase := Transfer_phase | Dispatch_phase | Handle_phase | Idle_phase.

Definition phase_eqb (a b : phase) : bool :=
  match a, b with
  | Transfer_phase, Transfer_phase | Dispatch_phase, Dispatch_phase
  | Handle_phase, Handle_phase | Idle_phase, Idle_phase => true
  | _, _ => false
  end.

(* ------------------------------------------------------------------ *)
(* Configurations (Machine.config), over any type of percepts P,        *)
(* messages M, objects Ob and behaviours B.                             *)
(* ------------------------------------------------------------------ *)

(* A notified percept: the percept, its effective priority (R2a), its seq
   (R2b). *)
Record entry (P : Type) := { ep : P; eprio : nat; eseq : nat }.

Inductive o2a_item (P Ob : Type) :=
| O_percept (e : entry P)
| O_object (o : Ob).

Inductive msg_item (P M : Type) :=
| M_message (m : M) (mseq : nat)
| M_percept (e : entry P).

Record instance (B : Type) := { iid : nat; ibeh : B }.

(* The dispatch in progress: the percept, the registered handlers not yet
   tried (instance id, handler index from 1), whether one ran. *)
Record dispatch (P : Type) := { de : entry P; todo : list (nat * nat); applied : bool }.

Inductive effect (B : Type) := Activate (b : B) | Deactivate.

Inductive label (P M Ob : Type) :=
| L_init
| L_notify (e : entry P)
| L_notify_with (e : entry P)
| L_put (o : Ob)
| L_send (m : M) (s : nat)
| L_transfer (moved : nat)
| L_transfer_one (e : entry P)
| L_transfer_spin (o : Ob)
| L_transfer_end
| L_dequeue (e : entry P)
| L_handle (id h : nat) (x : P) (s : nat)
| L_skip (id h : nat)
| L_end_dispatch (s : nat) (discarded : bool)
| L_behaviour_step (id : nat) (msg : option (msg_item P M))
| L_next_iteration
| L_idle.

Record config (P M Ob B : Type) := {
  o2a : list (o2a_item P Ob);
  pq : list (entry P);            (* a multiset: its order means nothing *)
  msgq : list (msg_item P M);
  next_seq : nat;
  msg_seq : nat;
  puts : nat;
  active : list (instance B);
  ready : list nat;
  blocked : list nat;
  pos : nat;
  phase_of : phase;
  cur : option (dispatch P);
  dispatched : nat;
  done_ : list nat;               (* ghost: seqs that left, one per exit *)
  waits : list (nat * nat * nat); (* ghost: (seq, priority, inversions) *)
  last : label P M Ob;
}.

(* The bodies, as the spec abstracts them (the constants Kind, HasAction,
   ActionEffects, PerceptHandlers, MessageHandlers; Machine.BODIES on
   abstract tables). Handler indices count from 1. *)
Record bodies (P M B : Type) := {
  cyclic : B -> bool;
  has_action : B -> bool;
  action_effects : B -> list (effect B);
  percept_handlers : B -> nat;
  percept_accepts : B -> nat -> P -> bool;
  percept_effects : B -> nat -> P -> list (effect B);
  message_handlers : B -> nat;
  message_accepts : B -> nat -> M -> bool;
  message_effects : B -> nat -> M -> list (effect B);
}.

(* What the host passes as a priority to notifyEvent(p, k): a Java int,
   negative ([Negative m] stands for -m) or a natural number (R2a). *)
Inductive host_int := Negative (m : nat) | Natural (k : nat).

Inductive refusal := Negative_priority (k : host_int) | O2a_full.

Inductive result (A : Type) := Ok (a : A) | Error (r : refusal).

Arguments ep {P}. Arguments eprio {P}. Arguments eseq {P}.
Arguments Build_entry {P}.
Arguments O_percept {P Ob}. Arguments O_object {P Ob}.
Arguments M_message {P M}. Arguments M_percept {P M}.
Arguments iid {B}. Arguments ibeh {B}. Arguments Build_instance {B}.
Arguments de {P}. Arguments todo {P}. Arguments applied {P}. Arguments Build_dispatch {P}.
Arguments Activate {B}. Arguments Deactivate {B}.
Arguments L_init {P M Ob}. Arguments L_notify {P M Ob}. Arguments L_notify_with {P M Ob}.
Arguments L_put {P M Ob}. Arguments L_send {P M Ob}. Arguments L_transfer {P M Ob}.
Arguments L_transfer_one {P M Ob}. Arguments L_transfer_spin {P M Ob}.
Arguments L_transfer_end {P M Ob}. Arguments L_dequeue {P M Ob}. Arguments L_handle {P M Ob}.
Arguments L_skip {P M Ob}. Arguments L_end_dispatch {P M Ob}.
Arguments L_behaviour_step {P M Ob}. Arguments L_next_iteration {P M Ob}.
Arguments L_idle {P M Ob}.
Arguments o2a {P M Ob B}. Arguments pq {P M Ob B}. Arguments msgq {P M Ob B}.
Arguments next_seq {P M Ob B}. Arguments msg_seq {P M Ob B}. Arguments puts {P M Ob B}.
Arguments active {P M Ob B}. Arguments ready {P M Ob B}. Arguments blocked {P M Ob B}.
Arguments pos {P M Ob B}. Arguments phase_of {P M Ob B}. Arguments cur {P M Ob B}.
Arguments dispatched {P M Ob B}. Arguments done_ {P M Ob B}. Arguments waits {P M Ob B}.
Arguments last {P M Ob B}. Arguments Build_config {P M Ob B}.
Arguments cyclic {P M B}. Arguments has_action {P M B}. Arguments action_effects {P M B}.
Arguments percept_handlers {P M B}. Arguments percept_accepts {P M B}.
Arguments percept_effects {P M B}. Arguments message_handlers {P M B}.
Arguments message_accepts {P M B}. Arguments message_effects {P M B}.
Arguments Ok {A}. Arguments Error {A}.

(* The behaviour part of a configuration (the spec's BS). *)
Record bstate (B : Type) := { bs_active : list (instance B); bs_ready : list nat;
                              bs_blocked : list nat; bs_pos : nat }.
Arguments bs_active {B}. Arguments bs_ready {B}. Arguments bs_blocked {B}.
Arguments bs_pos {B}. Arguments Build_bstate {B}.

Definition is_nil {A : Type} (l : list A) : bool :=
  match l with [] => true | _ => false end.

Section Machine.

Context {P M Ob B : Type}.
(* Equality of percepts: the flood abstraction merges equal entries, and a
   dequeue removes the entry it took. *)
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).
Notation entry := (entry P).
Notation label := (label P M Ob).
Notation bstate := (bstate B).

(* ---------------------------------------------------------------- *)
(* Operators of the spec                                             *)
(* ---------------------------------------------------------------- *)

Definition entry_eqb (a b : entry) : bool :=
  peqb (ep a) (ep b) && Nat.eqb (eprio a) (eprio b) && Nat.eqb (eseq a) (eseq b).

Definition bs_of (c : config) : bstate :=
  {| bs_active := active c; bs_ready := ready c; bs_blocked := blocked c; bs_pos := pos c |}.

(* SetBS *)
Definition with_bs (c : config) (s : bstate) : config :=
  {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
     msg_seq := msg_seq c; puts := puts c; active := bs_active s; ready := bs_ready s;
     blocked := bs_blocked s; pos := bs_pos s; phase_of := phase_of c; cur := cur c;
     dispatched := dispatched c; done_ := done_ c; waits := waits c; last := last c |}.

(* IndexOf (1-based, 0 when absent) *)
Fixpoint index_from (x i : nat) (l : list nat) : nat :=
  match l with
  | [] => 0
  | y :: r => if Nat.eqb y x then i else index_from x (S i) r
  end.
Definition index_of (x : nat) (l : list nat) : nat := index_from x 1 l.

Definition without (id : nat) (l : list nat) : list nat :=
  filter (fun y => negb (Nat.eqb y id)) l.

(* RemoveReady: JADE's Scheduler.remove (R5f) *)
Definition remove_ready (s : bstate) (id : nat) : bstate :=
  let k := index_of id (bs_ready s) in
  if Nat.eqb k 0 then s
  else
    let r := without id (bs_ready s) in
    let p1 := if Nat.ltb k (bs_pos s) then bs_pos s - 1 else bs_pos s in
    {| bs_active := bs_active s; bs_ready := r; bs_blocked := bs_blocked s;
       bs_pos := if Nat.ltb (length r) p1 then 1 else p1 |}.

Definition is_active_in (act : list (instance B)) (id : nat) : bool :=
  existsb (fun a => Nat.eqb (iid a) id) act.

(* Deactivate (R5h) *)
Definition deactivate (s : bstate) (id : nat) : bstate :=
  if negb (is_active_in (bs_active s) id) then s
  else
    let s1 := remove_ready s id in
    {| bs_active := filter (fun a => negb (Nat.eqb (iid a) id)) (bs_active s);
       bs_ready := bs_ready s1; bs_blocked := without id (bs_blocked s);
       bs_pos := bs_pos s1 |}.

(* Block (R5d) *)
Definition block (s : bstate) (id : nat) : bstate :=
  let s1 := remove_ready s id in
  {| bs_active := bs_active s1; bs_ready := bs_ready s1;
     bs_blocked := bs_blocked s ++ [id]; bs_pos := bs_pos s1 |}.

(* NewId (D2): the smallest positive id neither active nor reserved *)
Fixpoint first_free (used : list nat) (fuel n : nat) : nat :=
  match fuel with
  | 0 => n
  | S f => if existsb (Nat.eqb n) used then first_free used f (S n) else n
  end.
Definition new_id (s : bstate) (reserved : list nat) : nat :=
  let used := map iid (bs_active s) ++ reserved in
  first_free used (S (length used)) 1.

(* ApplyEffect, ApplyEffects (R5g, R5h) *)
Definition apply_effect (this : nat) (reserved : list nat) (s : bstate) (eff : effect B) : bstate :=
  match eff with
  | Activate b =>
    let act :=
      let n := new_id s reserved in
      {| bs_active := bs_active s ++ [{| iid := n; ibeh := b |}];
         bs_ready := bs_ready s ++ [n]; bs_blocked := bs_blocked s; bs_pos := bs_pos s |} in
    match p_max_active p with
    | Some m => if Nat.leb m (length (bs_active s)) then s else act
    | None => act
    end
  | Deactivate => deactivate s this
  end.

Definition apply_effects (s : bstate) (this : nat) (effs : list (effect B)) (reserved : list nat)
  : bstate :=
  fold_left (apply_effect this reserved) effs s.

(* BOf, for an instance that may have left *)
Definition find_instance (id : nat) (act : list (instance B)) : option B :=
  match find (fun a => Nat.eqb (iid a) id) act with
  | Some a => Some (ibeh a)
  | None => None
  end.

(* The ghosts. AddWait: a notified percept starts waiting with no
   inversion. BumpWaits: after the dispatch of e, every other waiting
   percept of a higher priority has waited one more lower-priority
   dispatch, and e stops waiting. *)
Definition add_wait (c : config) (e : entry) : list (nat * nat * nat) :=
  if p_flood p then waits c else waits c ++ [(eseq e, eprio e, 0)].

Fixpoint bump (e : entry) (ws : list (nat * nat * nat)) : list (nat * nat * nat) :=
  match ws with
  | [] => []
  | (s, k, n) :: r =>
    if Nat.eqb s (eseq e) then bump e r
    else (s, k, if Nat.ltb (eprio e) k then S n else n) :: bump e r
  end.

Definition bump_waits (c : config) (e : entry) : list (nat * nat * nat) :=
  if p_flood p then waits c else bump e (waits c).

Definition add_done (c : config) (s : nat) : list nat :=
  if p_flood p then done_ c else s :: done_ c.

Definition is_o2a_percept (x : o2a_item P Ob) : bool :=
  match x with O_percept _ => true | O_object _ => false end.

Definition is_percept_msg (x : msg_item P M) : bool :=
  match x with M_percept _ => true | M_message _ _ => false end.

(* The percept entries of an O2A queue, in order. *)
Fixpoint o2a_percepts (l : list (o2a_item P Ob)) : list entry :=
  match l with
  | [] => []
  | O_percept e :: r => e :: o2a_percepts r
  | O_object _ :: r => o2a_percepts r
  end.

(* The rest of an O2A queue: its objects, in order. *)
Definition o2a_objects (l : list (o2a_item P Ob)) : list (o2a_item P Ob) :=
  filter (fun x => negb (is_o2a_percept x)) l.

(* PerceptInO2A *)
Definition percept_in_o2a (c : config) : bool := existsb is_o2a_percept (o2a c).

(* MsgqPercepts *)
Definition msgq_percepts (c : config) : nat := length (filter is_percept_msg (msgq c)).

(* HandlersOf(active): activation order, then declaration order (R4a) *)
Definition handlers_of (c : config) : list (nat * nat) :=
  flat_map (fun a => map (fun j => (iid a, j)) (seq 1 (percept_handlers bd (ibeh a))))
           (active c).

(* BudgetSpent, DispatchOver *)
Definition budget_spent (c : config) : bool :=
  match p_variant p with
  | Budgeted => Nat.leb (p_budget p) (dispatched c)
  | _ => false
  end.
Definition dispatch_over (c : config) : bool := is_nil (pq c) || budget_spent c.

(* IdleCondition (R3e) *)
Definition idle_condition (c : config) : bool :=
  is_nil (ready c) && negb (percept_in_o2a c) && is_nil (pq c).

Definition is_native : bool := match p_variant p with Native => true | _ => false end.
Definition is_printed : bool := match p_variant p with Printed => true | _ => false end.

(* O2AHasRoom, with O2AUsed: in native the percepts moved on to the
   message queue count (D6) *)
Definition o2a_has_room (c : config) : bool :=
  match p_capacity p with
  | None => true
  | Some cap => Nat.ltb (length (o2a c) + (if is_native then msgq_percepts c else 0)) cap
  end.

Definition wake_idle (c : config) : phase :=
  match phase_of c with Idle_phase => Transfer_phase | ph => ph end.

(* The priority queue (PerceptPriority.tla): a multiset of entries. *)
Definition pq_mem (e : entry) (q : list entry) : bool := existsb (entry_eqb e) q.

(* Enqueue: under the flood abstraction an equal entry merges. *)
Definition pq_add (q : list entry) (e : entry) : list entry :=
  if p_flood p && pq_mem e q then q else q ++ [e].

(* DequeueMax: the queue without (one occurrence of) e. *)
Fixpoint remove_one (e : entry) (q : list entry) : list entry :=
  match q with
  | [] => []
  | x :: r => if entry_eqb x e then r else x :: remove_one e r
  end.

(* MaxPrio, MinSeq, Candidates (R3b) *)
Definition max_prio (q : list entry) : nat := fold_left (fun m e => Nat.max m (eprio e)) q 0.
Definition min_seq (q : list entry) : nat :=
  match q with
  | [] => 0
  | e :: r => fold_left (fun m x => Nat.min m (eseq x)) r (eseq e)
  end.
Definition top (q : list entry) : list entry :=
  filter (fun e => Nat.eqb (eprio e) (max_prio q)) q.
Definition candidates (q : list entry) : list entry :=
  match p_tie p with
  | Unstable => top q
  | Stable => filter (fun e => Nat.eqb (eseq e) (min_seq (top q))) (top q)
  end.

(* ---------------------------------------------------------------- *)
(* Init                                                              *)
(* ---------------------------------------------------------------- *)

Fixpoint number_from (i : nat) (bs : list B) : list (instance B) :=
  match bs with
  | [] => []
  | b :: r => {| iid := i; ibeh := b |} :: number_from (S i) r
  end.

(* The agent after its on create activated behs (R5g): instances 1..n,
   all ready, phase transfer. *)
Definition init (behs : list B) : config :=
  {| o2a := []; pq := []; msgq := []; next_seq := 0; msg_seq := 0; puts := 0;
     active := number_from 1 behs; ready := seq 1 (length behs); blocked := []; pos := 1;
     phase_of := Transfer_phase; cur := None; dispatched := 0; done_ := []; waits := [];
     last := L_init |}.

(* ---------------------------------------------------------------- *)
(* Host rules                                                        *)
(* ---------------------------------------------------------------- *)

(* NotifyEffect(p, k, actName) *)
Definition notify_effect (c : config) (x : P) (k : nat) (mk : entry -> label) : config :=
  let s := if p_flood p then 0 else S (next_seq c) in
  let e := {| ep := x; eprio := k; eseq := s |} in
  {| o2a := o2a c ++ [O_percept e]; pq := pq c; msgq := msgq c; next_seq := s;
     msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
     blocked := blocked c; pos := pos c; phase_of := wake_idle c; cur := cur c;
     dispatched := dispatched c; done_ := done_ c; waits := add_wait c e; last := mk e |}.

(* Notify(p) (R1a, R2b): k is the percept type's default priority. *)
Definition notify (c : config) (x : P) (k : nat) : config := notify_effect c x k L_notify.

(* NotifyWith(p, k) (R2a) *)
Definition notify_with (c : config) (x : P) (k : nat) : config :=
  notify_effect c x k L_notify_with.

(* The host's notifyEvent(p) (priority None) or notifyEvent(p, k): a
   negative k (R2a) or a full O2A queue (R2d) is refused. *)
Definition notify_event (c : config) (x : P) (default : nat) (priority : option host_int)
  : result config :=
  match priority with
  | Some (Negative m) => Error (Negative_priority (Negative m))
  | _ =>
    if negb (o2a_has_room c) then Error O2a_full
    else match priority with
         | Some (Natural k) => Ok (notify_with c x k)
         | _ => Ok (notify c x default)
         end
  end.

(* Put(o) (R2c): does not wake an idle agent (D3) *)
Definition put (c : config) (o : Ob) : config :=
  {| o2a := o2a c ++ [O_object o]; pq := pq c; msgq := msgq c; next_seq := next_seq c;
     msg_seq := msg_seq c; puts := S (puts c); active := active c; ready := ready c;
     blocked := blocked c; pos := pos c; phase_of := phase_of c; cur := cur c;
     dispatched := dispatched c; done_ := done_ c; waits := waits c; last := L_put o |}.

(* Send(m) (R5e, R5d, R3e) *)
Definition send (c : config) (m : M) : config :=
  let s := S (msg_seq c) in
  {| o2a := o2a c; pq := pq c; msgq := msgq c ++ [M_message m s]; next_seq := next_seq c;
     msg_seq := s; puts := puts c; active := active c; ready := ready c ++ blocked c;
     blocked := []; pos := pos c; phase_of := wake_idle c; cur := cur c;
     dispatched := dispatched c; done_ := done_ c; waits := waits c; last := L_send m s |}.

(* ---------------------------------------------------------------- *)
(* Agent rules: each is the empty list when its action is disabled.   *)
(* ---------------------------------------------------------------- *)

Definition set_last (c : config) (l : label) : config :=
  {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
     msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
     blocked := blocked c; pos := pos c; phase_of := phase_of c; cur := cur c;
     dispatched := dispatched c; done_ := done_ c; waits := waits c; last := l |}.

(* Transfer (R3a; native: into the message queue, R5d) *)
Definition transfer (c : config) : list (label * config) :=
  if negb is_printed && phase_eqb (phase_of c) Transfer_phase then
    let moving := o2a_percepts (o2a c) in
    let n := length moving in
    let l := L_transfer n in
    let go q' m' r' b' :=
      {| o2a := o2a_objects (o2a c); pq := q'; msgq := m'; next_seq := next_seq c;
         msg_seq := msg_seq c; puts := puts c; active := active c; ready := r';
         blocked := b'; pos := pos c; phase_of := Dispatch_phase; cur := cur c;
         dispatched := 0; done_ := done_ c; waits := waits c; last := l |} in
    if is_native then
      let m' := msgq c ++ map M_percept moving in
      if Nat.ltb 0 n then [(l, go (pq c) m' (ready c ++ blocked c) [])]
      else [(l, go (pq c) m' (ready c) (blocked c))]
    else [(l, go (fold_left pq_add moving (pq c)) (msgq c) (ready c) (blocked c))]
  else [].

(* TransferOne (printed): the head of O2A is a percept *)
Definition transfer_one (c : config) : list (label * config) :=
  if is_printed && phase_eqb (phase_of c) Transfer_phase then
    match o2a c with
    | O_percept e :: rest =>
      let l := L_transfer_one e in
      [(l, {| o2a := rest; pq := pq_add (pq c) e; msgq := msgq c; next_seq := next_seq c;
              msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
              blocked := blocked c; pos := pos c; phase_of := phase_of c; cur := cur c;
              dispatched := dispatched c; done_ := done_ c; waits := waits c; last := l |})]
    | _ => []
    end
  else [].

(* TransferSpin (printed): the head is an object; only last changes *)
Definition transfer_spin (c : config) : list (label * config) :=
  if is_printed && phase_eqb (phase_of c) Transfer_phase then
    match o2a c with
    | O_object o :: _ => [(L_transfer_spin o, set_last c (L_transfer_spin o))]
    | _ => []
    end
  else [].

(* TransferEnd (printed): O2A is empty *)
Definition transfer_end (c : config) : list (label * config) :=
  if is_printed && phase_eqb (phase_of c) Transfer_phase && is_nil (o2a c) then
    [(L_transfer_end,
      {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
         msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
         blocked := blocked c; pos := pos c; phase_of := Dispatch_phase; cur := cur c;
         dispatched := 0; done_ := done_ c; waits := waits c; last := L_transfer_end |})]
  else [].

(* Dequeue (R3b, R4a, R4b): one result per candidate *)
Definition dequeue (c : config) : list (label * config) :=
  if negb is_native && phase_eqb (phase_of c) Dispatch_phase && negb (is_nil (pq c))
     && negb (budget_spent c) then
    map (fun e =>
           (L_dequeue e,
            {| o2a := o2a c; pq := remove_one e (pq c); msgq := msgq c;
               next_seq := next_seq c; msg_seq := msg_seq c; puts := puts c;
               active := active c; ready := ready c; blocked := blocked c; pos := pos c;
               phase_of := Handle_phase;
               cur := Some {| de := e; todo := handlers_of c; applied := false |};
               dispatched := S (dispatched c); done_ := done_ c; waits := bump_waits c e;
               last := L_dequeue e |}))
        (candidates (pq c))
  else [].

(* Handle \/ Skip: Applicable(Head(cur.todo)) decides which (R3b, R4b);
   Handle applies the handler's effects with the snapshot's ids reserved
   (D2). *)
Definition handle_or_skip (c : config) : list (label * config) :=
  match phase_of c, cur c with
  | Handle_phase, Some d =>
    match todo d with
    | [] => []
    | (id, h) :: rest =>
      let x := ep (de d) in
      let skip :=
        let l := L_skip id h in
        (l, {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
               msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
               blocked := blocked c; pos := pos c; phase_of := phase_of c;
               cur := Some {| de := de d; todo := rest; applied := applied d |};
               dispatched := dispatched c; done_ := done_ c; waits := waits c; last := l |}) in
      match find_instance id (active c) with
      | Some b =>
        if percept_accepts bd b h x then
          let l := L_handle id h x (eseq (de d)) in
          let s := apply_effects (bs_of c) id (percept_effects bd b h x) (map fst (todo d)) in
          [(l, {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
                  msg_seq := msg_seq c; puts := puts c; active := bs_active s;
                  ready := bs_ready s; blocked := bs_blocked s; pos := bs_pos s;
                  phase_of := phase_of c;
                  cur := Some {| de := de d; todo := rest; applied := true |};
                  dispatched := dispatched c; done_ := done_ c; waits := waits c;
                  last := l |})]
        else [skip]
      | None => [skip]
      end
    end
  | _, _ => []
  end.

(* EndDispatch: the percept leaves; discarded if no handler applied (R3b) *)
Definition end_dispatch (c : config) : list (label * config) :=
  match phase_of c, cur c with
  | Handle_phase, Some d =>
    match todo d with
    | [] =>
      let l := L_end_dispatch (eseq (de d)) (negb (applied d)) in
      [(l, {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
              msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
              blocked := blocked c; pos := pos c; phase_of := Dispatch_phase; cur := None;
              dispatched := dispatched c; done_ := add_done c (eseq (de d));
              waits := waits c; last := l |})]
    | _ => []
    end
  | _, _ => []
  end.

(* StepHandlers, FirstHandler, FirstEntry (R5b; native: percept handlers
   first): the first handler with a matching entry takes the first such
   entry. *)
Fixpoint take_percept (b : B) (h : nat) (q : list (msg_item P M))
  : option (entry * list (msg_item P M)) :=
  match q with
  | [] => None
  | x :: r =>
    match x with
    | M_percept e =>
      if percept_accepts bd b h (ep e) then Some (e, r)
      else match take_percept b h r with Some (e', r') => Some (e', x :: r') | None => None end
    | M_message _ _ =>
      match take_percept b h r with Some (e', r') => Some (e', x :: r') | None => None end
    end
  end.

Fixpoint take_message (b : B) (h : nat) (q : list (msg_item P M))
  : option (M * nat * list (msg_item P M)) :=
  match q with
  | [] => None
  | x :: r =>
    match x with
    | M_message m s =>
      if message_accepts bd b h m then Some (m, s, r)
      else match take_message b h r with Some (y, r') => Some (y, x :: r') | None => None end
    | M_percept _ =>
      match take_message b h r with Some (y, r') => Some (y, x :: r') | None => None end
    end
  end.

(* The handlers a behaviour step tries: inl h a percept handler, inr h a
   message handler. *)
Definition step_handlers (b : B) : list (nat + nat) :=
  (if is_native then map inl (seq 1 (percept_handlers bd b)) else [])
  ++ map inr (seq 1 (message_handlers bd b)).

(* What a behaviour step took: the handler, the item, the message queue
   without it. *)
Fixpoint first_match (b : B) (q : list (msg_item P M)) (hs : list (nat + nat))
  : option (list (effect B) * msg_item P M * list (msg_item P M)) :=
  match hs with
  | [] => None
  | inl h :: rest =>
    match take_percept b h q with
    | Some (e, q') => Some (percept_effects bd b h (ep e), M_percept e, q')
    | None => first_match b q rest
    end
  | inr h :: rest =>
    match take_message b h q with
    | Some (m, s, q') => Some (message_effects bd b h m, M_message m s, q')
    | None => first_match b q rest
    end
  end.

(* BehaviourStep (R5a-R5d, R5f): one step of ready[pos]; S0..S3 as in the
   spec's LET. *)
Definition behaviour_step (c : config) : list (label * config) :=
  if phase_eqb (phase_of c) Dispatch_phase && dispatch_over c && negb (is_nil (ready c)) then
    let id := nth (pos c - 1) (ready c) 0 in
    match find_instance id (active c) with
    | None => []
    | Some b =>
      let s0 := {| bs_active := active c; bs_ready := ready c; bs_blocked := blocked c;
                   bs_pos := S (Nat.modulo (pos c) (length (ready c))) |} in
      let s1 := if has_action bd b then apply_effects s0 id (action_effects bd b) [id] else s0 in
      let found := first_match b (msgq c) (step_handlers b) in
      let s2 := match found with
                | Some (effs, _, _) => apply_effects s1 id effs [id]
                | None => s1
                end in
      let q' := match found with Some (_, _, q') => q' | None => msgq c end in
      let taken := match found with Some (_, x, _) => Some x | None => None end in
      let s3 := if negb (cyclic bd b) then deactivate s2 id
                else if negb (has_action bd b)
                        && negb (match taken with Some _ => true | None => false end)
                        && is_active_in (bs_active s2) id
                     then block s2 id else s2 in
      let dn := match taken with Some (M_percept e) => add_done c (eseq e) | _ => done_ c end in
      let ws := match taken with Some (M_percept e) => bump_waits c e | _ => waits c end in
      let l := L_behaviour_step id taken in
      [(l, {| o2a := o2a c; pq := pq c; msgq := q'; next_seq := next_seq c;
              msg_seq := msg_seq c; puts := puts c; active := bs_active s3;
              ready := bs_ready s3; blocked := bs_blocked s3; pos := bs_pos s3;
              phase_of := Transfer_phase; cur := cur c; dispatched := dispatched c;
              done_ := dn; waits := ws; last := l |})]
    end
  else [].

(* NextIteration (D5): nothing to step, start the next iteration *)
Definition next_iteration (c : config) : list (label * config) :=
  if phase_eqb (phase_of c) Dispatch_phase && dispatch_over c && is_nil (ready c)
     && (is_printed || negb (idle_condition c)) then
    [(L_next_iteration,
      {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
         msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
         blocked := blocked c; pos := pos c; phase_of := Transfer_phase; cur := cur c;
         dispatched := dispatched c; done_ := done_ c; waits := waits c;
         last := L_next_iteration |})]
  else [].

(* Idle (R3e) *)
Definition idle (c : config) : list (label * config) :=
  if negb is_printed && phase_eqb (phase_of c) Dispatch_phase && dispatch_over c
     && idle_condition c then
    [(L_idle,
      {| o2a := o2a c; pq := pq c; msgq := msgq c; next_seq := next_seq c;
         msg_seq := msg_seq c; puts := puts c; active := active c; ready := ready c;
         blocked := blocked c; pos := pos c; phase_of := Idle_phase; cur := cur c;
         dispatched := dispatched c; done_ := done_ c; waits := waits c; last := L_idle |})]
  else [].

(* AgentStep: every enabled agent rule, in the spec's order of the
   disjuncts (Machine.step). *)
Definition step (c : config) : list (label * config) :=
  transfer c ++ transfer_one c ++ transfer_spin c ++ transfer_end c
  ++ dequeue c ++ handle_or_skip c ++ end_dispatch c
  ++ behaviour_step c ++ next_iteration c ++ idle c.

End Machine.
