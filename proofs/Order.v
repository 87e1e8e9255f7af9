(* Transfer (R3a) and the order of dispatches (R3b). TLA+ counterparts:
   O2AOrderPreserved (Transfer), PriorityOrder and FifoAmongEquals
   (Dequeue), checked by TLC on the models of spec/models. *)

From Coq Require Import List Bool Arith Lia.
Import ListNotations.
From Jsref Require Import Loop Run Facts.

(* The labels of a transfer step: the iteration boundary. *)
Definition is_transfer_label {P M Ob : Type} (l : label P M Ob) : bool :=
  match l with L_transfer _ | L_transfer_one _ | L_transfer_end => true | _ => false end.

(* Finish the cases of in_cases whose label is not the one looked for. *)
Ltac wrong_label :=
  match goal with
  | H : L_transfer _ = _ |- _ => discriminate H
  | H : L_dequeue _ = _ |- _ => discriminate H
  | H : _ = L_transfer _ |- _ => discriminate H
  | H : _ = L_dequeue _ |- _ => discriminate H
  end.

Section Transfer.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Lemma transfer_step : forall (c c' : config) n,
  In (L_transfer n, c') (step peqb bd p c) -> In (L_transfer n, c') (transfer peqb p c).
Proof. intros c c' n H. apply (step_rule peqb bd p) in H. exact (proj1 H). Qed.

End Transfer.

(* THEOREM transfer_moves_every_percept (R3a). A Transfer of the reference
   or budgeted loop moves every percept of the O2A queue into the priority
   queue and nothing else: the O2A queue keeps exactly its objects, in
   their order, the priority queue gains exactly the O2A percepts, and the
   step's label counts them. *)
Theorem transfer_moves_every_percept :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c c' : config P M Ob B) (n : nat),
  p_flood p = false -> p_variant p <> Native ->
  In (L_transfer n, c') (step peqb bd p c) ->
  o2a c' = o2a_objects (o2a c)
  /\ pq c' = pq c ++ o2a_percepts (o2a c)
  /\ n = length (o2a_percepts (o2a c)).
Proof.
  intros P M Ob B peqb bd p c c' n Hf Hv H. apply transfer_step in H.
  unfold transfer in H; in_cases H;
    try (unfold is_native in *; destruct (p_variant p); congruence).
  simpl. rewrite fold_pq_add_noflood; auto.
Qed.

(* THEOREM transfer_native. In the native variant a Transfer appends every
   O2A percept, in order, to the message queue, and the O2A queue keeps
   exactly its objects, in their order. *)
Theorem transfer_native :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c c' : config P M Ob B) (n : nat),
  p_variant p = Native ->
  In (L_transfer n, c') (step peqb bd p c) ->
  o2a c' = o2a_objects (o2a c)
  /\ msgq c' = msgq c ++ map M_percept (o2a_percepts (o2a c))
  /\ pq c' = pq c.
Proof.
  intros P M Ob B peqb bd p c c' n Hv H. apply transfer_step in H.
  unfold transfer in H; in_cases H; simpl; auto.
  unfold is_native in *; rewrite Hv in *; discriminate.
Qed.

(* THEOREM transfer_always_taken. In the transfer phase of the reference
   and budgeted loops, Transfer is the one rule the agent can take: it
   never spins and never waits (unlike the printed loop, see Printed.v). *)
Theorem transfer_always_taken :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B),
  (p_variant p = Reference \/ p_variant p = Budgeted) ->
  phase_of c = Transfer_phase ->
  exists c', step peqb bd p c = [(L_transfer (length (o2a_percepts (o2a c))), c')].
Proof.
  intros P M Ob B peqb bd p c Hv Hph.
  unfold step, transfer, transfer_one, transfer_spin, transfer_end, dequeue, handle_or_skip,
    end_dispatch, behaviour_step, next_iteration, idle, is_printed, is_native.
  rewrite Hph. destruct Hv as [Hv|Hv]; rewrite Hv; simpl; eexists; reflexivity.
Qed.

Lemma last_cons : forall {A : Type} (x d : A) l, List.last (x :: l) d = List.last l x.
Proof.
  intros A x d l; revert x d; induction l as [|y l IH]; intros x d; [reflexivity|].
  change (List.last (y :: l) d = List.last (y :: l) x). rewrite (IH y d), (IH y x); reflexivity.
Qed.

Section Dequeue.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Lemma dequeue_step : forall (c c' : config) e,
  In (L_dequeue e, c') (step peqb bd p c) ->
  In e (candidates p (pq c)) /\ pq c' = remove_one peqb e (pq c).
Proof.
  intros c c' e H. apply (step_rule peqb bd p) in H as [H _]. simpl in H.
  unfold dequeue in H; in_cases H; auto.
Qed.

(* Steps that are not transfers take nothing into the priority queue. *)
Lemma pq_shrinks : forall (c c' : config) x,
  next peqb bd p c c' -> is_transfer_label (last c') = false -> In x (pq c') -> In x (pq c).
Proof.
  intros c c' x H Hl Hx. destruct H as [H|l H].
  - destruct H; auto.
  - pose proof (step_last peqb bd p c l c' H) as Hlast.
    apply in_step_cases in H. repeat destruct H as [H|H];
    unfold transfer, transfer_one, transfer_spin, transfer_end, dequeue, handle_or_skip,
      end_dispatch, behaviour_step, next_iteration, idle, set_last in H;
    in_cases H; simpl in *; subst; simpl in *; try discriminate; auto.
    eapply remove_one_incl; eauto.
Qed.

End Dequeue.

(* THEOREM dequeue_takes_highest (R3b). Every Dequeue takes an entry of
   the priority queue whose priority is maximal; under the Stable tie
   policy, among the entries of that priority, one with the smallest seq. *)
Theorem dequeue_takes_highest :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c c' : config P M Ob B) (e : entry P),
  In (L_dequeue e, c') (step peqb bd p c) ->
  In e (pq c)
  /\ (forall f, In f (pq c) -> eprio f <= eprio e)
  /\ (p_tie p = Stable -> forall f, In f (pq c) -> eprio f = eprio e -> eseq e <= eseq f).
Proof.
  intros P M Ob B peqb bd p c c' e H. apply dequeue_step in H as [H _].
  split; [eapply candidates_in; eauto|split].
  - intros f Hf; eapply candidates_max; eauto.
  - intros Ht f Hf Hk; eapply candidates_stable; eauto.
Qed.

(* THEOREM dequeues_do_not_increase (R3b). Within one iteration the
   dequeued priorities do not increase: after a Dequeue of e1, along any
   run (host steps included) with no transfer step, a later Dequeue takes
   an entry of priority at most that of e1. *)
Theorem dequeues_do_not_increase :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c0 c1 c2 : config P M Ob B) (cs : list (config P M Ob B)) (e1 e2 : entry P),
  In (L_dequeue e1, c1) (step peqb bd p c0) ->
  run peqb bd p c1 cs ->
  (forall c, In c cs -> is_transfer_label (last c) = false) ->
  In (L_dequeue e2, c2) (step peqb bd p (List.last cs c1)) ->
  eprio e2 <= eprio e1.
Proof.
  intros P M Ob B peqb bd p c0 c1 c2 cs e1 e2 H1 Hrun Hnt H2.
  assert (Hc1 : forall f, In f (pq c1) -> eprio f <= eprio e1).
  { apply dequeue_step in H1 as [Hc Hq]. intros f Hf. rewrite Hq in Hf.
    apply remove_one_incl in Hf. eapply candidates_max; eauto. }
  assert (Hall : forall f, In f (pq (List.last cs c1)) -> eprio f <= eprio e1).
  { clear H1 H2. revert Hc1 Hnt. induction Hrun as [c|c c' cs Hn Hr IH]; intros Hc Hnt; auto.
    rewrite last_cons. apply IH; [|intros x Hx; apply Hnt; right; auto].
    intros f Hf. apply Hc. eapply pq_shrinks; eauto. apply Hnt; left; auto. }
  apply dequeue_step in H2 as [H2 _]. apply Hall. eapply candidates_in; eauto.
Qed.
