(* Facts about the operators of Loop.v that several proofs use: the
   percepts of the queues, the priority queue's candidates and removal,
   what a behaviour step takes from the message queue. *)

From Coq Require Import List Bool Arith Lia Permutation.
Import ListNotations.
From Jsref Require Import Loop.

Section Facts.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation entry := (entry P).
Implicit Types (q : list entry) (e f : entry).

(* The percept entries of a message queue, in order. *)
Fixpoint msg_percepts (q : list (msg_item P M)) : list entry :=
  match q with
  | [] => []
  | M_percept e :: r => e :: msg_percepts r
  | M_message _ _ :: r => msg_percepts r
  end.

Lemma o2a_percepts_app : forall (l1 l2 : list (o2a_item P Ob)),
  o2a_percepts (l1 ++ l2) = o2a_percepts l1 ++ o2a_percepts l2.
Proof. induction l1 as [|[e|o] l IH]; intros; simpl; try rewrite IH; auto. Qed.

Lemma o2a_percepts_objects : forall (l : list (o2a_item P Ob)), o2a_percepts (o2a_objects l) = [].
Proof. induction l as [|[e|o] l IH]; simpl; auto. Qed.

Lemma o2a_objects_app : forall (l1 l2 : list (o2a_item P Ob)),
  o2a_objects (l1 ++ l2) = o2a_objects l1 ++ o2a_objects l2.
Proof. intros; unfold o2a_objects; apply filter_app. Qed.

Lemma o2a_objects_length : forall (l : list (o2a_item P Ob)), length (o2a_objects l) <= length l.
Proof.
  induction l as [|[e|o] l IH]; simpl; [lia|lia|]. unfold o2a_objects in *; simpl; lia.
Qed.

Lemma o2a_percepts_length : forall (l : list (o2a_item P Ob)), length (o2a_percepts l) <= length l.
Proof. induction l as [|[e|o] l IH]; simpl; lia. Qed.

Lemma msg_percepts_app : forall (l1 l2 : list (msg_item P M)),
  msg_percepts (l1 ++ l2) = msg_percepts l1 ++ msg_percepts l2.
Proof. induction l1 as [|[m s|e] l IH]; intros; simpl; try rewrite IH; auto. Qed.

Lemma msg_percepts_map : forall (l : list entry), msg_percepts (map (@M_percept P M) l) = l.
Proof. induction l; simpl; congruence. Qed.

Lemma msg_percepts_perm : forall (q q' : list (msg_item P M)),
  Permutation q q' -> Permutation (msg_percepts q) (msg_percepts q').
Proof.
  intros q q' H; induction H as [|[m s|e] l l' H IH|[m s|e] [m' s'|e'] l|l l' l'' H1 IH1 H2 IH2];
    simpl; auto; try constructor; auto; try apply perm_swap; eauto using Permutation_trans.
Qed.

(* Without the flood abstraction, Enqueue appends. *)
Lemma pq_add_noflood : forall q e, p_flood p = false -> pq_add peqb p q e = q ++ [e].
Proof. intros q e H; unfold pq_add; rewrite H; reflexivity. Qed.

Lemma fold_pq_add_noflood : forall l q, p_flood p = false ->
  fold_left (pq_add peqb p) l q = q ++ l.
Proof.
  induction l as [|e l IH]; intros q H; simpl; [rewrite app_nil_r; auto|].
  rewrite IH, pq_add_noflood, <- app_assoc; auto.
Qed.

Lemma fold_pq_add_length : forall l q,
  length (fold_left (pq_add peqb p) l q) <= length q + length l.
Proof.
  induction l as [|e l IH]; intros q; simpl; [lia|].
  eapply Nat.le_trans; [apply IH|]. unfold pq_add.
  destruct (p_flood p && pq_mem peqb e q); rewrite ?app_length; simpl; lia.
Qed.

Lemma fold_pq_add_incl : forall l q x,
  In x (fold_left (pq_add peqb p) l q) -> In x q \/ In x l.
Proof.
  induction l as [|e l IH]; intros q x H; simpl in *; [auto|].
  apply IH in H as [H|H]; [|auto].
  unfold pq_add in H. destruct (p_flood p && pq_mem peqb e q); [auto|].
  apply in_app_or in H as [H|[H|[]]]; auto.
Qed.

(* entry_eqb decides the equality of entries when peqb decides that of percepts. *)
Lemma entry_eqb_spec : (forall x y, peqb x y = true <-> x = y) ->
  forall a b : entry, entry_eqb peqb a b = true <-> a = b.
Proof.
  intros Hp [x k s] [y k' s']; unfold entry_eqb; simpl.
  rewrite !andb_true_iff, Hp, !Nat.eqb_eq; split.
  - intros [[-> ->] ->]; auto.
  - intros H; injection H; auto.
Qed.

Lemma entry_eqb_seq : forall a b : entry, entry_eqb peqb a b = true -> eseq a = eseq b.
Proof.
  intros a b H; unfold entry_eqb in H; rewrite !andb_true_iff in H.
  destruct H as [_ H]; apply Nat.eqb_eq; auto.
Qed.

Lemma remove_one_perm : (forall x y, peqb x y = true <-> x = y) ->
  forall e q, In e q -> Permutation q (e :: remove_one peqb e q).
Proof.
  intros Hp e q; induction q as [|x q IH]; intros H; simpl in *; [destruct H|].
  destruct (entry_eqb peqb x e) eqn:E.
  - apply (entry_eqb_spec Hp) in E; subst; auto.
  - destruct H as [->|H].
    + assert (entry_eqb peqb e e = true) by (apply (entry_eqb_spec Hp); auto). congruence.
    + eapply Permutation_trans; [apply perm_skip, IH, H|apply perm_swap].
Qed.

Lemma remove_one_incl : forall e q x, In x (remove_one peqb e q) -> In x q.
Proof.
  intros e q; induction q as [|y q IH]; intros x H; simpl in *; auto.
  destruct (entry_eqb peqb y e); [auto|]. destruct H as [->|H]; auto.
Qed.

(* An entry with another seq than e stays when e is removed. *)
Lemma remove_one_keeps : forall e q x, In x q -> eseq x <> eseq e -> In x (remove_one peqb e q).
Proof.
  intros e q; induction q as [|y q IH]; intros x H Hs; simpl in *; auto.
  destruct (entry_eqb peqb y e) eqn:E.
  - destruct H as [->|H]; auto. apply entry_eqb_seq in E; congruence.
  - destruct H as [->|H]; simpl; auto.
Qed.

Lemma remove_one_length : (forall x y, peqb x y = true <-> x = y) ->
  forall e q, In e q -> S (length (remove_one peqb e q)) = length q.
Proof.
  intros Hp e q H. apply (remove_one_perm Hp) in H. apply Permutation_length in H.
  simpl in H; auto.
Qed.

(* The priority queue's candidates. *)
Lemma max_prio_ge_acc : forall (q : list entry) m, m <= fold_left (fun m e => Nat.max m (eprio e)) q m.
Proof.
  induction q as [|e q IH]; intros m; simpl; [lia|].
  eapply Nat.le_trans; [|apply IH]; lia.
Qed.

Lemma max_prio_ge : forall q e, In e q -> eprio e <= max_prio q.
Proof.
  unfold max_prio; generalize 0.
  intros m q; revert m; induction q as [|x q IH]; intros m e H; simpl in *; [destruct H|].
  destruct H as [->|H]; [|apply IH; auto].
  eapply Nat.le_trans; [|apply max_prio_ge_acc]; lia.
Qed.

Lemma min_seq_acc_le : forall (q : list entry) m, fold_left (fun m x => Nat.min m (eseq x)) q m <= m.
Proof.
  induction q as [|e q IH]; intros m; simpl; [lia|].
  eapply Nat.le_trans; [apply IH|]; lia.
Qed.

Lemma min_seq_le : forall q e, In e q -> min_seq q <= eseq e.
Proof.
  intros [|x q] e H; [destruct H|]. unfold min_seq.
  revert x e H; induction q as [|y q IH]; intros x e H; simpl in *.
  - destruct H as [->|[]]; lia.
  - destruct H as [->|[->|H]].
    + eapply Nat.le_trans; [apply min_seq_acc_le|]; lia.
    + eapply Nat.le_trans; [apply min_seq_acc_le|]; lia.
    + specialize (IH (Build_entry (ep x) (Nat.min (eseq x) (eseq y)) (Nat.min (eseq x) (eseq y))) e).
      simpl in IH. apply IH; auto.
Qed.

Lemma candidates_in : forall q e, In e (candidates p q) -> In e q.
Proof.
  intros q e H; unfold candidates, top in H.
  destruct (p_tie p); repeat (apply filter_In in H; destruct H as [H _]); auto.
Qed.

Lemma candidates_max : forall q e f, In e (candidates p q) -> In f q -> eprio f <= eprio e.
Proof.
  intros q e f H Hf; unfold candidates, top in H.
  assert (In e (filter (fun e => Nat.eqb (eprio e) (max_prio q)) q)) as H'
    by (destruct (p_tie p); auto; apply filter_In in H; tauto).
  apply filter_In in H' as [_ H']. apply Nat.eqb_eq in H'. rewrite H'. apply max_prio_ge; auto.
Qed.

Lemma candidates_stable : p_tie p = Stable -> forall q e f,
  In e (candidates p q) -> In f q -> eprio f = eprio e -> eseq e <= eseq f.
Proof.
  intros Ht q e f H Hf Hk; unfold candidates in H; rewrite Ht in H.
  apply filter_In in H as [Htop Hs]. apply Nat.eqb_eq in Hs. rewrite Hs.
  apply min_seq_le. unfold top in *. apply filter_In in Htop as [_ Htop].
  apply filter_In; split; auto. apply Nat.eqb_eq in Htop. apply Nat.eqb_eq; congruence.
Qed.

Lemma fold_max_cases : forall (q : list entry) m,
  fold_left (fun m e => Nat.max m (eprio e)) q m = m
  \/ exists e, In e q /\ eprio e = fold_left (fun m e => Nat.max m (eprio e)) q m.
Proof.
  induction q as [|x q IH]; intros m; simpl; [auto|].
  destruct (IH (Nat.max m (eprio x))) as [H|[e [H1 H2]]].
  - rewrite H. destruct (Nat.max_spec m (eprio x)) as [[_ ->]|[_ ->]]; eauto.
  - eauto.
Qed.

Lemma fold_min_cases : forall (q : list entry) m,
  fold_left (fun m x => Nat.min m (eseq x)) q m = m
  \/ exists e, In e q /\ eseq e = fold_left (fun m x => Nat.min m (eseq x)) q m.
Proof.
  induction q as [|x q IH]; intros m; simpl; [auto|].
  destruct (IH (Nat.min m (eseq x))) as [H|[e [H1 H2]]].
  - rewrite H. destruct (Nat.min_spec m (eseq x)) as [[_ ->]|[_ ->]]; eauto.
  - eauto.
Qed.

Lemma max_prio_in : forall q, q <> [] -> exists e, In e q /\ eprio e = max_prio q.
Proof.
  intros [|x q] Hq; [congruence|].
  assert (E : max_prio (x :: q)
              = fold_left (fun m e => Nat.max m (eprio e)) q (Nat.max 0 (eprio x))) by reflexivity.
  rewrite E.
  destruct (fold_max_cases q (Nat.max 0 (eprio x))) as [H|[e [H1 H2]]].
  - exists x; split; [left; auto|]. rewrite H; lia.
  - exists e; split; [right|]; auto.
Qed.

Lemma min_seq_in : forall q, q <> [] -> exists e, In e q /\ eseq e = min_seq q.
Proof.
  intros [|x q] Hq; [congruence|]. unfold min_seq.
  destruct (fold_min_cases q (eseq x)) as [H|[e [H1 H2]]].
  - exists x; split; [left|]; auto.
  - exists e; split; [right|]; auto.
Qed.

Lemma candidates_nonempty : forall q, q <> [] -> candidates p q <> [].
Proof.
  intros q Hq. destruct (max_prio_in q Hq) as [e [He Hk]].
  assert (Ht : In e (top q)) by (unfold top; apply filter_In; split; auto; apply Nat.eqb_eq; auto).
  assert (Hnt : top q <> []) by (intros H; rewrite H in Ht; destruct Ht).
  unfold candidates. destruct (p_tie p); [|auto].
  destruct (min_seq_in (top q) Hnt) as [f [Hf Hs]].
  intros H. assert (In f (filter (fun e => Nat.eqb (eseq e) (min_seq (top q))) (top q))) as G
    by (apply filter_In; split; auto; apply Nat.eqb_eq; auto).
  rewrite H in G; destruct G.
Qed.

(* What a behaviour step takes from the message queue. *)
Lemma take_percept_perm : forall b h (q : list (msg_item P M)) e (q' : list (msg_item P M)),
  take_percept bd b h q = Some (e, q') -> Permutation q (M_percept e :: q').
Proof.
  intros b h q; induction q as [|x q IH]; intros e q' H; simpl in H; [discriminate|].
  destruct x as [m s|e0].
  - destruct (take_percept bd b h q) as [[e1 r]|] eqn:T; [|discriminate].
    injection H; intros; subst. eapply Permutation_trans; [apply perm_skip, IH; eauto|].
    apply perm_swap.
  - destruct (percept_accepts bd b h (ep e0)).
    + injection H; intros; subst; auto.
    + destruct (take_percept bd b h q) as [[e1 r]|] eqn:T; [|discriminate].
      injection H; intros; subst. eapply Permutation_trans; [apply perm_skip, IH; eauto|].
      apply perm_swap.
Qed.

Lemma take_message_perm : forall b h (q : list (msg_item P M)) m s (q' : list (msg_item P M)),
  take_message bd b h q = Some (m, s, q') -> Permutation q (M_message m s :: q').
Proof.
  intros b h q; induction q as [|x q IH]; intros m s q' H; simpl in H; [discriminate|].
  destruct x as [m0 s0|e0].
  - destruct (message_accepts bd b h m0).
    + injection H; intros; subst; auto.
    + destruct (take_message bd b h q) as [[[m1 s1] r]|] eqn:T; [|discriminate].
      injection H; intros; subst. eapply Permutation_trans; [apply perm_skip, IH; eauto|].
      apply perm_swap.
  - destruct (take_message bd b h q) as [[[m1 s1] r]|] eqn:T; [|discriminate].
    injection H; intros; subst. eapply Permutation_trans; [apply perm_skip, IH; eauto|].
    apply perm_swap.
Qed.

Lemma first_match_perm : forall b (q : list (msg_item P M)) hs effs x (q' : list (msg_item P M)),
  first_match bd b q hs = Some (effs, x, q') -> Permutation q (x :: q').
Proof.
  intros b q hs; induction hs as [|[h|h] hs IH]; intros effs x q' H; simpl in H; [discriminate| |].
  - destruct (take_percept bd b h q) as [[e r]|] eqn:T.
    + injection H; intros; subst. eapply take_percept_perm; eauto.
    + eauto.
  - destruct (take_message bd b h q) as [[[m s] r]|] eqn:T.
    + injection H; intros; subst. eapply take_message_perm; eauto.
    + eauto.
Qed.

(* Outside native, a behaviour step takes only messages. *)
Lemma first_match_message : forall b (q : list (msg_item P M)) effs x (q' : list (msg_item P M)),
  is_native p = false ->
  first_match bd b q (step_handlers bd p b) = Some (effs, x, q') -> exists m s, x = M_message m s.
Proof.
  intros b q effs x q' Hn. unfold step_handlers; rewrite Hn; simpl.
  generalize (seq 1 (message_handlers bd b)) as hs.
  induction hs as [|h hs IH]; simpl; intros H; [discriminate|].
  destruct (take_message bd b h q) as [[[m s] r]|] eqn:T.
  - injection H; intros; subst; eauto.
  - auto.
Qed.

End Facts.
