(* The flaws of Algorithm 1 as printed (the "printed" variant), for every
   size: TLC finds them as lassos in MCPrintedObject and MCFloodPrinted
   (NoLoss, BehaviourProgress, MessageProgress violated; docs/spec.md,
   counterexamples 1 and 2). *)

From Coq Require Import List Bool Arith Lia.
Import ListNotations.
From Jsref Require Import Loop Run Facts Order Budget.

Definition is_notification {P M Ob : Type} (l : label P M Ob) : bool :=
  match l with L_notify _ | L_notify_with _ => true | _ => false end.

Definition is_behaviour_step {P M Ob : Type} (l : label P M Ob) : bool :=
  match l with L_behaviour_step _ _ => true | _ => false end.

Section Printed.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Hypothesis Hv : p_variant p = Printed.

Lemma printed : is_printed p = true.
Proof. unfold is_printed; rewrite Hv; auto. Qed.

(* With an object at the head of the O2A queue in the transfer phase,
   TransferSpin is the one rule the agent can take. *)
Lemma step_spins : forall (c : config) o rest,
  phase_of c = Transfer_phase -> o2a c = O_object o :: rest ->
  step peqb bd p c = [(L_transfer_spin o, set_last c (L_transfer_spin o))].
Proof.
  intros c o rest Hph Ho.
  unfold step, transfer, transfer_one, transfer_spin, transfer_end, dequeue, handle_or_skip,
    end_dispatch, behaviour_step, next_iteration, idle, is_native.
  rewrite printed, Hph, Ho, Hv. simpl. rewrite ?andb_false_r. reflexivity.
Qed.

Definition spinning (o : Ob) (q : list (entry P)) (c : config) : Prop :=
  phase_of c = Transfer_phase /\ (exists rest, o2a c = O_object o :: rest) /\ pq c = q.

Lemma spinning_next : forall o q c c', spinning o q c -> next peqb bd p c c' -> spinning o q c'.
Proof.
  intros o q c c' [Hph [[rest Ho] Hq]] H. destruct H as [H|l H].
  - destruct H; unfold spinning, notify, notify_with, notify_effect, put, send, wake_idle; simpl;
      rewrite Hph, ?Ho; repeat split; eauto; simpl; eexists; reflexivity.
  - rewrite (step_spins c o rest Hph Ho) in H. destruct H as [H|[]].
    injection H; intros; subst. unfold spinning, set_last; simpl; repeat split; eauto.
Qed.

Lemma spinning_run : forall o q c cs,
  spinning o q c -> run peqb bd p c cs -> forall c', In c' (c :: cs) -> spinning o q c'.
Proof.
  intros o q c cs S0 Hr; induction Hr as [c1|c1 c2 cs Hn Hr IH]; intros c' Hin.
  - destruct Hin as [<-|[]]; auto.
  - destruct Hin as [<-|Hin]; auto. apply IH; auto. eapply spinning_next; eauto.
Qed.

(* A host that notifies a percept whenever the O2A queue is empty in the
   transfer phase keeps the printed loop in its transfer loop. *)
Lemma flood_next : forall c c' : config,
  phase_of c = Transfer_phase -> next peqb bd p c c' ->
  (o2a c = [] -> is_notification (last c') = true) ->
  phase_of c' = Transfer_phase /\ is_behaviour_step (last c') = false
  /\ is_dequeue (last c') = false.
Proof.
  intros c c' Hph H Hs. destruct H as [H|l H].
  - destruct H; unfold notify, notify_with, notify_effect, put, send, wake_idle; simpl;
      rewrite Hph; auto.
  - pose proof (step_last peqb bd p c l c' H) as Hl.
    apply in_step_cases in H. repeat destruct H as [H|H];
      unfold transfer, transfer_one, transfer_spin, transfer_end, dequeue, handle_or_skip,
        end_dispatch, behaviour_step, next_iteration, idle, set_last in H;
      rewrite ?printed, ?Hph in H; simpl in H; in_cases H; simpl; auto;
      try (match goal with E : _ = true |- _ =>
             rewrite ?andb_false_r, ?andb_false_l in E; discriminate E end).
    (* TransferEnd: the O2A queue was empty, so the host notified instead *)
    destruct (o2a c) eqn:Ho;
      [specialize (Hs eq_refl); simpl in Hs; discriminate
      |simpl in *; rewrite ?andb_false_r in *; discriminate].
Qed.

(* One round of the flood: the host notifies, the agent moves it. *)
Definition round (x : P) (k : nat) (c : config) : config :=
  match transfer_one peqb p (notify p c x k) with (_, c') :: _ => c' | [] => c end.

Lemma round_facts : forall x k (c : config),
  phase_of c = Transfer_phase -> o2a c = [] ->
  In (L_transfer_one {| ep := x; eprio := k; eseq := if p_flood p then 0 else S (next_seq c) |},
      round x k c) (step peqb bd p (notify p c x k))
  /\ phase_of (round x k c) = Transfer_phase /\ o2a (round x k c) = []
  /\ ready (round x k c) = ready c.
Proof.
  intros x k c Hph Ho.
  unfold round, notify, notify_effect, transfer_one, wake_idle; rewrite printed, Ho, Hph; simpl.
  repeat split; auto.
  unfold step; apply in_or_app; right; apply in_or_app; left.
  unfold transfer_one; rewrite printed; simpl. left; reflexivity.
Qed.

End Printed.

(* THEOREM printed_spins_forever. In the printed loop, once a non-percept
   object is at the head of the O2A queue in the transfer phase, whatever
   the host does next: the agent stays in its transfer loop with that
   object at the head, the priority queue never changes, and the one rule
   it can take is TransferSpin, which changes nothing: it busy-waits
   forever, handles no percept and runs no behaviour. *)
Theorem printed_spins_forever :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B) (o : Ob) (rest : list (o2a_item P Ob)) (cs : list (config P M Ob B)),
  p_variant p = Printed ->
  phase_of c = Transfer_phase -> o2a c = O_object o :: rest ->
  run peqb bd p c cs ->
  forall c', In c' (c :: cs) ->
  phase_of c' = Transfer_phase /\ (exists rest', o2a c' = O_object o :: rest')
  /\ pq c' = pq c
  /\ step peqb bd p c' = [(L_transfer_spin o, set_last c' (L_transfer_spin o))].
Proof.
  intros P M Ob B peqb bd p c o rest cs Hv Hph Ho Hr.
  assert (S0 : spinning o (pq c) c) by (repeat split; eauto).
  assert (All : forall c', In c' (c :: cs) -> spinning o (pq c) c')
    by (eapply spinning_run; eauto).
  intros c' Hin. destruct (All c' Hin) as [H1 [[rest' H2] H3]].
  repeat split; eauto. eapply step_spins; eauto.
Qed.

(* THEOREM printed_flood_starves. In the printed loop, from the transfer
   phase, if the host notifies a percept whenever the O2A queue is empty
   (one percept per turn of the transfer loop), the agent never leaves its
   transfer loop: no step of the run is a Dequeue or a behaviour step. *)
Theorem printed_flood_starves :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B) (cs : list (config P M Ob B)),
  p_variant p = Printed ->
  phase_of c = Transfer_phase ->
  run peqb bd p c cs ->
  every_step (fun c1 c2 => o2a c1 = [] -> is_notification (last c2) = true) c cs ->
  forall c', In c' cs ->
  phase_of c' = Transfer_phase /\ is_dequeue (last c') = false
  /\ is_behaviour_step (last c') = false.
Proof.
  intros P M Ob B peqb bd p c cs Hv Hph Hr.
  induction Hr as [c1|c1 c2 cs Hn Hr IH]; intros Hs c' Hin; [destruct Hin|].
  destruct Hs as [Hs1 Hs].
  destruct (flood_next peqb bd p Hv c1 c2 Hph Hn Hs1) as [H1 [H2 H3]].
  destruct Hin as [<-|Hin]; auto.
Qed.

(* THEOREM printed_flood_run. Such a run exists and is fair to the agent:
   from the transfer phase with an empty O2A queue (Init, for instance),
   the host notifies a percept, the agent moves it (TransferOne), and so on
   forever. The agent takes every other step, yet it stays in its transfer
   loop: the behaviours that were ready stay ready and never run, and no
   percept is ever dispatched. *)
Theorem printed_flood_run :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B) (x : P) (k : nat),
  p_variant p = Printed ->
  phase_of c = Transfer_phase -> o2a c = [] -> p_capacity p <> Some 0 ->
  exists f : nat -> config P M Ob B,
    f 0 = c
    /\ (forall i, next peqb bd p (f i) (notify p (f i) x k)
                  /\ next peqb bd p (notify p (f i) x k) (f (S i))
                  /\ exists e, In (L_transfer_one e, f (S i)) (step peqb bd p (notify p (f i) x k)))
    /\ (forall i, phase_of (f i) = Transfer_phase /\ o2a (f i) = [] /\ ready (f i) = ready c).
Proof.
  intros P M Ob B peqb bd p c x k Hv Hph Ho Hc.
  exists (fun i => Nat.iter i (round peqb p x k) c).
  assert (Inv : forall i, phase_of (Nat.iter i (round peqb p x k) c) = Transfer_phase
                          /\ o2a (Nat.iter i (round peqb p x k) c) = []
                          /\ ready (Nat.iter i (round peqb p x k) c) = ready c).
  { induction i as [|i [H1 [H2 H3]]]; simpl; auto.
    destruct (round_facts peqb bd p Hv x k _ H1 H2) as [_ [H4 [H5 H6]]]. repeat split; congruence. }
  split; [reflexivity|split; [|exact Inv]].
  intros i. destruct (Inv i) as [H1 [H2 H3]].
  destruct (round_facts peqb bd p Hv x k _ H1 H2) as [H4 _].
  repeat split.
  - apply Next_host, H_notify. unfold o2a_has_room, is_native. rewrite H2, Hv.
    destruct (p_capacity p) as [n|]; auto. apply Nat.ltb_lt. destruct n; [congruence|]. simpl; lia.
  - eapply Next_agent; simpl; eauto.
  - eexists; simpl; eauto.
Qed.
