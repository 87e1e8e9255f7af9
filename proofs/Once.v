(* No loss and no duplication: every notified percept is, in every
   reachable configuration, in exactly one place: the O2A queue, the
   priority queue, the dispatch in progress, the message queue (native), or
   among the percepts that left (handled or discarded), once. The TLA+
   counterpart is NoDuplication (with O2AOrderPreserved's "every percept
   that left O2A"), checked by TLC on the models of spec/models. *)

From Coq Require Import List Bool Arith Lia Permutation.
Import ListNotations.
From Jsref Require Import Loop Run Facts.

Section Once.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

(* The seq of the dispatch in progress, if any. *)
Definition cur_seqs (c : config) : list nat :=
  match cur c with Some d => [eseq (de d)] | None => [] end.

(* The seqs found in the five places, each as often as it is there. *)
Definition places (c : config) : list nat :=
  map eseq (o2a_percepts (o2a c)) ++ map eseq (pq c) ++ cur_seqs c
  ++ map eseq (msg_percepts (msgq c)) ++ done_ c.

Definition once_inv (c : config) : Prop :=
  (phase_of c <> Handle_phase -> cur c = None)
  /\ Permutation (places c) (seq 1 (next_seq c)).

Hypothesis Hflood : p_flood p = false.
Hypothesis Hpeqb : forall x y, peqb x y = true <-> x = y.

(* A permutation of lists of seqs, from another: compare the counts. *)
Ltac perm_by_counts H :=
  apply (proj2 (Permutation_count_occ Nat.eq_dec _ _)); intros s0;
  pose proof (proj1 (Permutation_count_occ Nat.eq_dec _ _) H s0) as Hc0; clear H;
  repeat progress (rewrite ?map_app, ?count_occ_app in *; simpl in *);
  repeat match goal with |- context [Nat.eq_dec ?a ?b] => destruct (Nat.eq_dec a b) end;
  repeat match goal with H : context [Nat.eq_dec ?a ?b] |- _ => destruct (Nat.eq_dec a b) end;
  lia.

Lemma once_init : forall behs, once_inv (init behs).
Proof. intros; split; [simpl; auto|apply Permutation_refl]. Qed.

Lemma perm_move : forall (A X Y : list nat),
  Permutation (A ++ X ++ Y) (X ++ A ++ Y).
Proof. intros; apply Permutation_app_swap_app. Qed.

Lemma perm_notify : forall (A X : list nat) n,
  Permutation (A ++ X) (seq 1 n) -> Permutation ((A ++ [S n]) ++ X) (seq 1 (S n)).
Proof.
  intros A X n H. rewrite seq_S, <- app_assoc. simpl.
  eapply Permutation_trans; [apply Permutation_sym, Permutation_middle|].
  eapply Permutation_trans; [|apply Permutation_cons_append]. constructor; auto.
Qed.

Lemma once_host : forall c c', once_inv c -> host_step p c c' -> once_inv c'.
Proof.
  intros c c' [Hc Hp] H.
  assert (Hw : phase_of c <> Handle_phase -> cur c = None) by auto.
  destruct H as [x k Hr|x k Hr|o Hr|m]; split;
    try (unfold notify, notify_with, notify_effect, send, wake_idle; simpl;
         intros Hph; apply Hc; destruct (phase_of c); simpl in *; congruence);
    try (unfold put; simpl; auto; fail).
  - unfold notify, notify_effect, places, cur_seqs in *; rewrite Hflood; cbn [o2a pq cur msgq done_ next_seq].
    rewrite o2a_percepts_app, map_app. apply perm_notify; auto.
  - unfold notify_with, notify_effect, places, cur_seqs in *; rewrite Hflood; cbn [o2a pq cur msgq done_ next_seq].
    rewrite o2a_percepts_app, map_app. apply perm_notify; auto.
  - unfold put, places, cur_seqs in *; cbn [o2a pq cur msgq done_ next_seq].
    rewrite o2a_percepts_app; simpl; rewrite app_nil_r; auto.
  - unfold send, places, cur_seqs in *; cbn [o2a pq cur msgq done_ next_seq].
    rewrite msg_percepts_app; simpl; rewrite app_nil_r; auto.
Qed.

Lemma once_agent : forall c l c', once_inv c -> In (l, c') (step peqb bd p c) -> once_inv c'.
Proof.
  intros c l c' [Hc Hp] H.
  assert (Hdisp : phase_of c = Dispatch_phase -> cur c = None) by (intros E; apply Hc; congruence).
  assert (Htr : phase_of c = Transfer_phase -> cur c = None) by (intros E; apply Hc; congruence).
  apply in_step_cases in H. repeat destruct H as [H|H].
  - (* Transfer *)
    unfold transfer in H; in_cases H;
      (assert (Ht : phase_of c = Transfer_phase)
         by (destruct (phase_of c); simpl in *; auto; rewrite andb_false_r in *; discriminate));
      (split; [simpl; intros _; auto|]); unfold places, cur_seqs in *; simpl;
      rewrite o2a_percepts_objects; simpl.
    + rewrite msg_percepts_app, msg_percepts_map. perm_by_counts Hp.
    + rewrite msg_percepts_app, msg_percepts_map. perm_by_counts Hp.
    + rewrite fold_pq_add_noflood by auto. perm_by_counts Hp.
  - (* TransferOne *)
    unfold transfer_one in H; in_cases H.
    split; [simpl; intros; apply Hc; auto|].
    unfold places, cur_seqs in *; simpl. rewrite E0 in Hp; simpl in Hp.
    rewrite pq_add_noflood by auto. perm_by_counts Hp.
  - (* TransferSpin *)
    unfold transfer_spin, set_last in H; in_cases H. split; auto.
    unfold places, cur_seqs in *; rewrite E0 in Hp; auto.
  - (* TransferEnd *)
    unfold transfer_end in H; in_cases H.
    assert (Ht : phase_of c = Transfer_phase)
      by (destruct (phase_of c); simpl in *; auto; rewrite ?andb_false_r in *; discriminate).
    split; [simpl; auto|auto].
  - (* Dequeue *)
    unfold dequeue in H; in_cases H.
    assert (Hd : phase_of c = Dispatch_phase)
      by (destruct (phase_of c); simpl in *; auto; rewrite ?andb_false_r in *; discriminate).
    split; [simpl; congruence|].
    unfold places, cur_seqs in *; simpl. rewrite (Hdisp Hd) in Hp.
    apply candidates_in in Hin. apply (remove_one_perm peqb Hpeqb) in Hin.
    apply (Permutation_map eseq) in Hin.
    eapply Permutation_trans; [|apply Hp].
    apply Permutation_app_head. perm_by_counts Hin.
  - (* Handle, Skip *)
    unfold handle_or_skip in H; in_cases H; split; simpl; try congruence;
      unfold places, cur_seqs in *; simpl; rewrite E0 in Hp; auto.
  - (* EndDispatch *)
    unfold end_dispatch in H; in_cases H. unfold add_done; rewrite Hflood.
    split; [simpl; auto|].
    unfold places, cur_seqs in *; simpl; rewrite E0 in Hp. perm_by_counts Hp.
  - (* BehaviourStep *)
    unfold behaviour_step in H; in_cases H.
    assert (Hd : phase_of c = Dispatch_phase)
      by (destruct (phase_of c); simpl in *; auto; rewrite ?andb_false_r in *; discriminate).
    split; [simpl; auto|].
    unfold places, cur_seqs in *; simpl.
    destruct (first_match bd b (msgq c) (step_handlers bd p b)) as [[[effs x] q']|] eqn:F;
      simpl; auto.
    apply first_match_perm in F. apply msg_percepts_perm in F.
    apply (Permutation_map eseq) in F.
    destruct x as [m s|e]; simpl in *.
    + eapply Permutation_trans; [|apply Hp].
      apply Permutation_app_head, Permutation_app_head, Permutation_app_head.
      apply Permutation_app_tail, Permutation_sym, F.
    + unfold add_done; rewrite Hflood.
      eapply Permutation_trans; [|apply Hp].
      apply Permutation_app_head, Permutation_app_head, Permutation_app_head.
      perm_by_counts F.
  - (* NextIteration *)
    unfold next_iteration in H; in_cases H.
    split; [simpl; intros; apply Hdisp|auto].
    destruct (phase_of c); simpl in *; auto; rewrite ?andb_false_r in *; discriminate.
  - (* Idle *)
    unfold idle in H; in_cases H.
    split; [simpl; intros; apply Hdisp|auto].
    destruct (phase_of c); simpl in *; auto; rewrite ?andb_false_r in *; discriminate.
Qed.

Lemma once_reachable : forall c0 c, once_inv c0 -> reachable_from peqb bd p c0 c -> once_inv c.
Proof.
  intros c0 c H0 Hr; induction Hr; auto.
  destruct H as [H|l H]; [eapply once_host|eapply once_agent]; eauto.
Qed.

End Once.

Ltac bool_to_prop :=
  repeat match goal with
         | H : (_ <=? _) = true |- _ => apply Nat.leb_le in H
         | H : (_ <=? _) = false |- _ => apply Nat.leb_gt in H
         | H : (_ <? _) = true |- _ => apply Nat.ltb_lt in H
         | H : (_ <? _) = false |- _ => apply Nat.ltb_ge in H
         end.

Lemma count_occ_seq : forall n a s,
  count_occ Nat.eq_dec (seq a n) s = (if (a <=? s) && (s <? a + n) then 1 else 0).
Proof.
  induction n as [|n IH]; intros a s; cbn [seq count_occ]; [|rewrite IH; destruct (Nat.eq_dec a s)];
    repeat match goal with
           | |- context [?x <=? ?y] => let E := fresh "E" in destruct (x <=? y) eqn:E
           | |- context [?x <? ?y] => let E := fresh "E" in destruct (x <? y) eqn:E
           end; simpl; bool_to_prop; auto; lia.
Qed.

(* THEOREM exactly_once. Without the flood abstraction, in every reachable
   configuration the seqs found in the O2A queue, the priority queue, the
   dispatch in progress, the message queue and among the percepts that left
   are 1..next_seq, each exactly once: no notified percept is lost, none is
   duplicated, and nothing else is there. *)
Theorem exactly_once :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B),
  p_flood p = false ->
  (forall x y, peqb x y = true <-> x = y) ->
  reachable peqb bd p c ->
  forall s, count_occ Nat.eq_dec (places c) s
            = (if (1 <=? s) && (s <=? next_seq c) then 1 else 0).
Proof.
  intros P M Ob B peqb bd p c Hf Hp [behs Hr] s.
  destruct (once_reachable peqb bd p Hf Hp (init behs) c (once_init _) Hr) as [_ H].
  rewrite (proj1 (Permutation_count_occ Nat.eq_dec _ _) H), count_occ_seq.
  destruct (1 <=? s); simpl; auto.
Qed.

(* THEOREM refused_notification. The host's notifyEvent is refused exactly
   when the priority is negative (R2a) or the O2A queue is full (R2d); a
   refusal yields no configuration (the agent's stays as it was, the
   percept gets no seq, so by exactly_once it is nowhere), and an accepted
   notification is a step of the host (Notify or NotifyWith). *)
Theorem refused_notification :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B) (x : P) (default : nat) (k : option host_int),
  match notify_event p c x default k with
  | Error r =>
    (exists m, k = Some (Negative m) /\ r = Negative_priority (Negative m))
    \/ (o2a_has_room p c = false /\ r = O2a_full)
  | Ok c' => next peqb bd p c c' /\ next_seq c' = (if p_flood p then 0 else S (next_seq c))
  end.
Proof.
  intros P M Ob B peqb bd p c x default k.
  unfold notify_event. destruct k as [[m|n]|].
  - left; eauto.
  - destruct (o2a_has_room p c) eqn:R; simpl.
    + split; [apply Next_host, H_notify_with; auto|reflexivity].
    + right; auto.
  - destruct (o2a_has_room p c) eqn:R; simpl.
    + split; [apply Next_host, H_notify; auto|reflexivity].
    + right; auto.
Qed.
