(* The bounds of the budgeted loop, and of the reference loop under a
   bounded O2A queue: how many percepts one iteration dispatches, how many
   dispatches a behaviour waits, how many lower-priority dispatches a
   percept waits behind (the ghost [waits]). TLA+ counterparts:
   DispatchesWithinBudget and BoundedInversion (spec/results.md). *)

From Coq Require Import List Bool Arith Lia.
Import ListNotations.
From Jsref Require Import Loop Run Facts Order.

(* The exact bound on the dispatches of one iteration, hence on the
   lower-priority dispatches a percept waits behind: Budget, or the O2A
   capacity if it is smaller, in the budgeted loop; the O2A capacity in the
   reference loop; none otherwise. *)
Definition dispatch_bound (p : params) : option nat :=
  match p_variant p with
  | Budgeted =>
    Some (match p_capacity p with Some k => Nat.min (p_budget p) k | None => p_budget p end)
  | Reference => p_capacity p
  | _ => None
  end.

(* n is within the bound b (None: no bound). *)
Definition within (n : nat) (b : option nat) : Prop :=
  match b with Some k => n <= k | None => True end.

(* The labels that end an iteration: a behaviour step, or NextIteration and
   Idle, which are taken only when no behaviour is ready. *)
Definition is_iteration_end {P M Ob : Type} (l : label P M Ob) : bool :=
  match l with L_behaviour_step _ _ | L_next_iteration | L_idle => true | _ => false end.

Definition is_dequeue {P M Ob : Type} (l : label P M Ob) : bool :=
  match l with L_dequeue _ => true | _ => false end.

(* Facts about the phase, from the enabling conditions. *)
Ltac phase_from E :=
  match type of E with
  | context [phase_eqb (phase_of ?c) ?ph] =>
    let H := fresh "Hph" in
    assert (H : phase_of c = ph)
      by (destruct (phase_of c); simpl in E; auto; rewrite ?andb_false_r, ?andb_false_l in E;
          discriminate)
  end.

Section Dispatches.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Hypothesis Hv : p_variant p = Reference \/ p_variant p = Budgeted.
Hypothesis Hpeqb : forall x y, peqb x y = true <-> x = y.

Lemma not_native : is_native p = false.
Proof. unfold is_native; destruct Hv as [H|H]; rewrite H; auto. Qed.

Lemma not_printed : is_printed p = false.
Proof. unfold is_printed; destruct Hv as [H|H]; rewrite H; auto. Qed.

Definition in_iteration (c : config) : Prop :=
  phase_of c = Dispatch_phase \/ phase_of c = Handle_phase.

(* The O2A capacity limits an iteration: the reference loop, or a budget
   at least the capacity. *)
Definition capacity_limits (k : nat) : Prop := p_variant p = Reference \/ k <= p_budget p.

Definition dinv (c : config) : Prop :=
  (forall k, p_capacity p = Some k -> length (o2a c) <= k)
  /\ (p_variant p = Budgeted -> dispatched c <= p_budget p)
  /\ (forall k, p_capacity p = Some k -> capacity_limits k ->
        (~ in_iteration c -> pq c = [] /\ dispatched c <= k)
        /\ (in_iteration c -> dispatched c + length (pq c) <= k)).

Lemma dinv_init : forall behs, dinv (init behs).
Proof.
  intros behs; repeat split; simpl; intros; try lia.
Qed.

Lemma room_length : forall (c : config) k,
  o2a_has_room p c = true -> p_capacity p = Some k -> S (length (o2a c)) <= k.
Proof.
  intros c k H Hk; unfold o2a_has_room in H; rewrite Hk, not_native in H.
  apply Nat.ltb_lt in H; lia.
Qed.

Lemma wake_in_iteration : forall c : config,
  in_iteration c <-> (wake_idle c = Dispatch_phase \/ wake_idle c = Handle_phase).
Proof. intros c; unfold in_iteration, wake_idle; destruct (phase_of c); intuition discriminate. Qed.

Lemma dinv_host : forall c c', dinv c -> host_step p c c' -> dinv c'.
Proof.
  intros c c' [D1 [D2 D3]] H.
  destruct H as [x k Hr|x k Hr|o Hr|m]; unfold dinv;
    unfold notify, notify_with, notify_effect, put, send; simpl; (split; [|split]); auto;
    try (intros K HK; pose proof (room_length c K Hr HK); rewrite app_length; simpl; lia);
    try (intros K HK; apply D1; auto; fail);
    intros K HK HL; destruct (D3 K HK HL) as [D3a D3b];
    (split; intros Hi; [apply D3a|apply D3b]); revert Hi;
    unfold in_iteration, wake_idle; simpl; destruct (phase_of c); intuition discriminate.
Qed.

(* The end of an iteration (BehaviourStep, NextIteration, Idle) leaves the
   priority queue empty when the capacity limits the iteration. *)
Lemma iteration_end_empties : forall c : config,
  dinv c -> phase_of c = Dispatch_phase -> dispatch_over p c = true ->
  forall k, p_capacity p = Some k -> capacity_limits k -> pq c = [] /\ dispatched c <= k.
Proof.
  intros c [_ [_ D3]] Hph Hov k Hk HL. destruct (D3 k Hk HL) as [_ D3b].
  assert (Hit : in_iteration c) by (left; auto). specialize (D3b Hit).
  unfold dispatch_over, budget_spent in Hov.
  destruct (pq c) as [|e q]; [simpl in *; split; auto; lia|].
  simpl in *. destruct (p_variant p) eqn:V; try discriminate.
  apply Nat.leb_le in Hov. destruct HL as [HL|HL]; [congruence|]. lia.
Qed.

Lemma dinv_agent : forall c l c', dinv c -> In (l, c') (step peqb bd p c) -> dinv c'.
Proof.
  intros c l c' Hd H. pose proof Hd as [D1 [D2 D3]].
  pose proof not_native as Hn; pose proof not_printed as Hp.
  apply in_step_cases in H. repeat destruct H as [H|H].
  - (* Transfer *)
    unfold transfer in H; rewrite Hn, Hp in H; in_cases H. phase_from E.
    unfold dinv, in_iteration; simpl; split; [|split].
    + intros K Hk. specialize (D1 K Hk). pose proof (o2a_objects_length (o2a c)). lia.
    + lia.
    + intros K Hk HL. destruct (D3 K Hk HL) as [D3a _].
      unfold in_iteration in *. rewrite Hph in D3a.
      destruct D3a as [Hq _]; [intuition discriminate|].
      split; [intuition|intros _].
      rewrite Hq. pose proof (fold_pq_add_length peqb p (o2a_percepts (o2a c)) []).
      pose proof (o2a_percepts_length (o2a c)). specialize (D1 K Hk). simpl in *; lia.
  - unfold transfer_one in H; rewrite Hp in H; simpl in H; in_cases H.
  - unfold transfer_spin in H; rewrite Hp in H; simpl in H; in_cases H.
  - unfold transfer_end in H; rewrite Hp in H; simpl in H; in_cases H.
  - (* Dequeue *)
    unfold dequeue in H; in_cases H. phase_from E.
    apply andb_true_iff in E as [E Hb]. apply andb_true_iff in E as [E Hq].
    apply negb_true_iff in Hb, Hq.
    pose proof (candidates_in p _ _ Hin) as Hin'.
    pose proof (remove_one_length peqb Hpeqb e (pq c) Hin') as Hlen.
    unfold dinv, in_iteration; simpl; split; [|split]; auto.
    + intros Hb'. unfold budget_spent in Hb. rewrite Hb' in Hb. apply Nat.leb_gt in Hb. lia.
    + intros K Hk HL. destruct (D3 K Hk HL) as [_ D3b].
      assert (I : in_iteration c) by (left; auto). specialize (D3b I).
      split; [intuition|intros _; lia].
  - (* Handle, Skip *)
    unfold handle_or_skip in H; in_cases H; unfold dinv, in_iteration in *; simpl;
      rewrite E in *; auto.
  - (* EndDispatch *)
    unfold end_dispatch in H; in_cases H; unfold dinv, in_iteration in *; simpl;
      rewrite E in *; split; [|split]; auto.
    intros K Hk HL; destruct (D3 K Hk HL) as [_ D3b]; split; [intuition discriminate|auto].
  - (* BehaviourStep *)
    unfold behaviour_step in H; in_cases H. phase_from E.
    apply andb_true_iff in E as [E _]. apply andb_true_iff in E as [_ Hov].
    unfold dinv, in_iteration; simpl; split; [|split]; auto.
    intros K Hk HL; split; [|intuition discriminate].
    intros _; eapply iteration_end_empties; eauto.
  - (* NextIteration *)
    unfold next_iteration in H; in_cases H. phase_from E.
    apply andb_true_iff in E as [E _]. apply andb_true_iff in E as [E _].
    apply andb_true_iff in E as [_ Hov].
    unfold dinv, in_iteration; simpl; split; [|split]; auto.
    intros K Hk HL; split; [|intuition discriminate].
    intros _; eapply iteration_end_empties; eauto.
  - (* Idle *)
    unfold idle in H; in_cases H. phase_from E.
    apply andb_true_iff in E as [E _]. apply andb_true_iff in E as [_ Hov].
    unfold dinv, in_iteration; simpl; split; [|split]; auto.
    intros K Hk HL; split; [|intuition discriminate].
    intros _; eapply iteration_end_empties; eauto.
Qed.

Lemma dinv_reachable : forall c0 c, dinv c0 -> reachable_from peqb bd p c0 c -> dinv c.
Proof.
  intros c0 c H0 Hr; induction Hr; auto.
  destruct H as [H|l H]; [eapply dinv_host|eapply dinv_agent]; eauto.
Qed.

Lemma dinv_within : forall c, dinv c -> within (dispatched c) (dispatch_bound p).
Proof.
  intros c [D1 [D2 D3]]. unfold dispatch_bound, within.
  destruct Hv as [V|V]; rewrite V.
  - destruct (p_capacity p) as [k|] eqn:Hk; auto.
    destruct (D3 k eq_refl (or_introl V)) as [D3a D3b].
    destruct (phase_of c) eqn:Ph;
      [ destruct D3a as [_ D]; [unfold in_iteration; rewrite Ph; intuition discriminate|lia]
      | assert (I : in_iteration c) by (left; auto); specialize (D3b I); lia
      | assert (I : in_iteration c) by (right; auto); specialize (D3b I); lia
      | destruct D3a as [_ D]; [unfold in_iteration; rewrite Ph; intuition discriminate|lia]].
  - specialize (D2 V). destruct (p_capacity p) as [k|] eqn:Hk; auto.
    destruct (Nat.le_gt_cases k (p_budget p)) as [L|L]; [|lia].
    destruct (D3 k eq_refl (or_intror L)) as [D3a D3b].
    destruct (phase_of c) eqn:Ph;
      [ destruct D3a as [_ D]; [unfold in_iteration; rewrite Ph; intuition discriminate|lia]
      | assert (I : in_iteration c) by (left; auto); specialize (D3b I); lia
      | assert (I : in_iteration c) by (right; auto); specialize (D3b I); lia
      | destruct D3a as [_ D]; [unfold in_iteration; rewrite Ph; intuition discriminate|lia]].
Qed.

End Dispatches.

(* THEOREM dispatches_within_bound. In every reachable configuration of the
   budgeted loop, and of the reference loop with an O2A capacity, the
   percepts dispatched in the current (or last) iteration are at most the
   dispatch bound: min(Budget, O2A capacity) in the budgeted loop (Budget
   when the O2A queue is unbounded), the O2A capacity in the reference
   loop. *)
Theorem dispatches_within_bound :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B),
  (p_variant p = Reference \/ p_variant p = Budgeted) ->
  (forall x y, peqb x y = true <-> x = y) ->
  reachable peqb bd p c ->
  within (dispatched c) (dispatch_bound p).
Proof.
  intros P M Ob B peqb bd p c Hv Hp [behs Hr].
  apply (dinv_within p Hv). eapply dinv_reachable; eauto. apply dinv_init.
Qed.

(* ------------------------------------------------------------------ *)
(* A behaviour step at least every Budget dispatches                    *)
(* ------------------------------------------------------------------ *)

Definition count_dequeues {P M Ob B : Type} (cs : list (config P M Ob B)) : nat :=
  length (filter (fun c => is_dequeue (last c)) cs).

Section Every.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Hypothesis Hb : p_variant p = Budgeted.

(* How many more dispatches the budget allows before the iteration ends. *)
Definition remaining (c : config) : nat :=
  match phase_of c with
  | Dispatch_phase | Handle_phase => p_budget p - dispatched c
  | _ => p_budget p
  end.

Lemma remaining_step : forall c c',
  next peqb bd p c c' -> is_iteration_end (last c') = false ->
  (if is_dequeue (last c') then 1 else 0) + remaining c' <= remaining c.
Proof.
  intros c c' H He. assert (Hp : is_printed p = false) by (unfold is_printed; rewrite Hb; auto).
  assert (Hn : is_native p = false) by (unfold is_native; rewrite Hb; auto).
  destruct H as [H|l H].
  - destruct H; unfold remaining, notify, notify_with, notify_effect, put, send, wake_idle;
      simpl; destruct (phase_of c); simpl; lia.
  - pose proof (step_last peqb bd p c l c' H) as Hl. subst l.
    apply in_step_cases in H. repeat destruct H as [H|H].
    + unfold transfer in H; rewrite Hp, Hn in H; in_cases H. phase_from E.
      unfold remaining; simpl; rewrite Hph; simpl; lia.
    + unfold transfer_one in H; rewrite Hp in H; simpl in H; in_cases H.
    + unfold transfer_spin in H; rewrite Hp in H; simpl in H; in_cases H.
    + unfold transfer_end in H; rewrite Hp in H; simpl in H; in_cases H.
    + unfold dequeue in H; in_cases H. phase_from E.
      apply andb_true_iff in E as [_ Hbs]. apply negb_true_iff in Hbs.
      unfold budget_spent in Hbs; rewrite Hb in Hbs; apply Nat.leb_gt in Hbs.
      unfold remaining; rewrite <- H0; simpl; rewrite Hph; lia.
    + unfold handle_or_skip in H; in_cases H; unfold remaining; simpl; rewrite E; simpl; lia.
    + unfold end_dispatch in H; in_cases H; unfold remaining; simpl; rewrite E; simpl; lia.
    + unfold behaviour_step in H; in_cases H. rewrite <- H0 in He. discriminate.
    + unfold next_iteration in H; in_cases H. rewrite <- H0 in He. discriminate.
    + unfold idle in H; in_cases H. rewrite <- H0 in He. discriminate.
Qed.

Lemma dequeues_within_remaining : forall c cs,
  run peqb bd p c cs -> (forall c', In c' cs -> is_iteration_end (last c') = false) ->
  count_dequeues cs <= remaining c.
Proof.
  intros c cs H; induction H as [c|c c' cs Hn Hr IH]; intros He; unfold count_dequeues in *;
    simpl; [lia|].
  pose proof (remaining_step c c' Hn (He c' (or_introl eq_refl))) as S.
  assert (IH' : length (filter (fun c => is_dequeue (last c)) cs) <= remaining c')
    by (apply IH; intros x Hx; apply He; right; auto).
  destruct (is_dequeue (last c')); simpl in *; lia.
Qed.

Lemma remaining_le : forall c, remaining c <= p_budget p.
Proof. intros c; unfold remaining; destruct (phase_of c); lia. Qed.

End Every.

(* THEOREM behaviour_step_every_budget. In any run of the budgeted loop,
   from any configuration, with any host steps between: among more than
   Budget dispatches there is a step that ends an iteration, a behaviour
   step or, when no behaviour is ready (theorem
   no_behaviour_ready_at_next_iteration_or_idle), NextIteration or Idle. *)
Theorem behaviour_step_every_budget :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B) (cs : list (config P M Ob B)),
  p_variant p = Budgeted ->
  run peqb bd p c cs ->
  p_budget p < count_dequeues cs ->
  exists c', In c' cs /\ is_iteration_end (last c') = true.
Proof.
  intros P M Ob B peqb bd p c cs Hb Hr Hc.
  destruct (existsb (fun c' => is_iteration_end (last c')) cs) eqn:E.
  - apply existsb_exists in E; auto.
  - exfalso. assert (forall c', In c' cs -> is_iteration_end (last c') = false) as He.
    { intros c' Hin. destruct (is_iteration_end (last c')) eqn:X; auto.
      assert (existsb (fun c' => is_iteration_end (last c')) cs = true)
        by (apply existsb_exists; eauto). congruence. }
    pose proof (dequeues_within_remaining peqb bd p Hb c cs Hr He).
    pose proof (remaining_le p c). lia.
Qed.

(* THEOREM no_behaviour_ready_at_next_iteration_or_idle. NextIteration and
   Idle are taken only when no behaviour is ready: an iteration with a
   ready behaviour ends with a behaviour step. *)
Theorem no_behaviour_ready_at_next_iteration_or_idle :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c c' : config P M Ob B) (l : label P M Ob),
  In (l, c') (step peqb bd p c) -> (l = L_next_iteration \/ l = L_idle) -> ready c = [].
Proof.
  intros P M Ob B peqb bd p c c' l H Hl. apply in_step_cases in H.
  repeat destruct H as [H|H];
  unfold transfer, transfer_one, transfer_spin, transfer_end, dequeue, handle_or_skip,
    end_dispatch, behaviour_step, next_iteration, idle, set_last in H;
  in_cases H; destruct Hl as [Hl|Hl]; try discriminate.
  all: unfold idle_condition in *; rewrite ?andb_true_iff in *;
    destruct (ready c); [reflexivity|]; simpl in *; intuition discriminate.
Qed.

(* ------------------------------------------------------------------ *)
(* The inversion bound                                                  *)
(* ------------------------------------------------------------------ *)

Lemma bump_in : forall {P : Type} (e : entry P) ws s k n',
  In (s, k, n') (bump e ws) ->
  exists n, In (s, k, n) ws /\ s <> eseq e /\ n' = (if eprio e <? k then S n else n).
Proof.
  intros P e ws; induction ws as [|[[s0 k0] n0] ws IH]; intros s k n' H; simpl in H; [destruct H|].
  destruct (s0 =? eseq e) eqn:E.
  - destruct (IH s k n' H) as [n [H1 H2]]. exists n; split; [right|]; auto.
  - destruct H as [H|H].
    + injection H; intros; subst. exists n0. apply Nat.eqb_neq in E. split; [left|]; auto.
    + destruct (IH s k n' H) as [n [H1 H2]]. exists n; split; [right|]; auto.
Qed.

Section Inversion.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Hypothesis Hv : p_variant p = Reference \/ p_variant p = Budgeted.
Hypothesis Hpeqb : forall x y, peqb x y = true <-> x = y.
Hypothesis Hflood : p_flood p = false.

(* Every waiting percept has waited within the bound, and is in the
   priority queue, or in the O2A queue having waited no more than the
   dispatches of the current iteration. *)
Definition winv (c : config) : Prop :=
  forall s k n, In (s, k, n) (waits c) ->
  within n (dispatch_bound p)
  /\ ((exists e, In e (pq c) /\ eseq e = s /\ eprio e = k)
      \/ (exists e, In e (o2a_percepts (o2a c)) /\ eseq e = s /\ eprio e = k
                    /\ (in_iteration c -> n <= dispatched c))).

Lemma winv_init : forall behs, winv (init behs).
Proof. intros behs s k n H; destruct H. Qed.

Lemma within_le : forall n m b, n <= m -> within m b -> within n b.
Proof. intros n m [b|] H1 H2; simpl in *; lia. Qed.

Lemma winv_host : forall c c', winv c -> host_step p c c' -> winv c'.
Proof.
  intros c c' W H s k n Hin.
  destruct H as [x k0 Hr|x k0 Hr|o Hr|m];
    unfold notify, notify_with, notify_effect, put, send, add_wait in *; rewrite ?Hflood in *;
    simpl in *.
  1,2: apply in_app_or in Hin as [Hin|[Hin|[]]];
       [ destruct (W s k n Hin) as [Wb [[e [He1 He2]]|[e [He1 [He2 [He3 He4]]]]]];
         split; auto; [left; eauto|right; exists e; rewrite o2a_percepts_app;
                        repeat split; auto; [apply in_or_app; auto|];
                        intros Hi; apply He4; revert Hi; unfold in_iteration, wake_idle;
                        simpl; destruct (phase_of c); intuition discriminate]
       | injection Hin; intros; subst; split; [destruct (dispatch_bound p); simpl; lia|];
         right; eexists; rewrite o2a_percepts_app; simpl;
         split; [apply in_or_app; right; left; reflexivity|]; simpl; repeat split; lia ].
  - destruct (W s k n Hin) as [Wb [[e [He1 He2]]|[e [He1 [He2 [He3 He4]]]]]];
      split; auto; [left; eauto|right; exists e; rewrite o2a_percepts_app; simpl;
                    rewrite app_nil_r; auto].
  - destruct (W s k n Hin) as [Wb [[e [He1 He2]]|[e [He1 [He2 [He3 He4]]]]]];
      split; auto; [left; eauto|right; exists e; repeat split; auto].
    intros Hi; apply He4; revert Hi; unfold in_iteration, wake_idle;
      simpl; destruct (phase_of c); intuition discriminate.
Qed.

Lemma winv_agent : forall c l c',
  winv c -> dinv p c' -> In (l, c') (step peqb bd p c) -> winv c'.
Proof.
  intros c l c' W D' H.
  pose proof (not_native p Hv) as Hn; pose proof (not_printed p Hv) as Hp.
  apply in_step_cases in H. repeat destruct H as [H|H].
  - (* Transfer: the O2A percepts join the priority queue *)
    unfold transfer in H; rewrite Hn, Hp in H; in_cases H.
    intros s k n Hw; simpl in *.
    destruct (W s k n Hw) as [Wb [[e [He1 He2]]|[e [He1 [He2 [He3 He4]]]]]]; split; auto;
      left; exists e; rewrite fold_pq_add_noflood by auto; split; auto; apply in_or_app; auto.
  - unfold transfer_one in H; rewrite Hp in H; simpl in H; in_cases H.
  - unfold transfer_spin in H; rewrite Hp in H; simpl in H; in_cases H.
  - unfold transfer_end in H; rewrite Hp in H; simpl in H; in_cases H.
  - (* Dequeue *)
    unfold dequeue in H; in_cases H. phase_from E.
    pose proof (dinv_within p Hv _ D') as Wd; simpl in Wd.
    intros s k n' Hw; simpl in *. unfold bump_waits in Hw; rewrite Hflood in Hw.
    apply bump_in in Hw as [n [Hw [Hs Hn']]].
    destruct (W s k n Hw) as [Wb [[f [Hf1 [Hf2 Hf3]]]|[f [Hf1 [Hf2 [Hf3 Hf4]]]]]].
    + (* in the priority queue: e has at least its priority *)
      assert (Hk : k <= eprio e) by (subst k; eapply candidates_max; eauto).
      assert (Hnn : n' = n) by (rewrite Hn'; destruct (eprio e <? k) eqn:X; auto;
                                apply Nat.ltb_lt in X; lia). rewrite Hnn.
      split; auto. left; exists f; repeat split; auto.
      apply remove_one_keeps; auto. congruence.
    + (* in the O2A queue: one more dispatch of this iteration at most *)
      assert (Hi : in_iteration c) by (left; auto). specialize (Hf4 Hi).
      assert (n' <= S (dispatched c)) by (subst n'; destruct (eprio e <? k); lia).
      split; [eapply within_le; eauto|].
      right; exists f; repeat split; auto.
  - (* Handle, Skip *)
    unfold handle_or_skip in H; in_cases H; intros s k w Hw; simpl in *;
      destruct (W s k w Hw) as [Wb [[f [Hf1 [Hf2 Hf3]]]|[f [Hf1 [Hf2 [Hf3 Hf4]]]]]];
      split; auto; [left; eauto|right; exists f; unfold in_iteration in *; simpl in *;
                                 rewrite E in *; auto
                   |left; eauto|right; exists f; unfold in_iteration in *; simpl in *;
                                 rewrite E in *; auto
                   |left; eauto|right; exists f; unfold in_iteration in *; simpl in *;
                                 rewrite E in *; auto].
  - (* EndDispatch *)
    unfold end_dispatch in H; in_cases H; intros s k w Hw; simpl in *.
    destruct (W s k w Hw) as [Wb [[f [Hf1 [Hf2 Hf3]]]|[f [Hf1 [Hf2 [Hf3 Hf4]]]]]];
      split; auto; [left; eauto|right; exists f; unfold in_iteration in *; simpl in *;
                                 rewrite E in *; repeat split; auto].
  - (* BehaviourStep: outside native it takes no percept *)
    unfold behaviour_step in H; in_cases H. phase_from E.
    pose proof (dinv_within p Hv _ D') as Wd; simpl in Wd.
    intros s k w Hw; simpl in *.
    destruct (first_match bd b (msgq c) (step_handlers bd p b)) as [[[effs x] q']|] eqn:F;
      [apply first_match_message in F as [m [ms ->]]; auto|]; simpl in Hw;
      destruct (W s k w Hw) as [Wb [[f [Hf1 [Hf2 Hf3]]]|[f [Hf1 [Hf2 [Hf3 Hf4]]]]]];
      split; auto; try (left; eauto; fail); right; exists f; repeat split; auto;
      unfold in_iteration; simpl; intuition discriminate.
  - (* NextIteration *)
    unfold next_iteration in H; in_cases H. intros s k w Hw; simpl in *.
    destruct (W s k w Hw) as [Wb [[f [Hf1 [Hf2 Hf3]]]|[f [Hf1 [Hf2 [Hf3 Hf4]]]]]];
      split; auto; try (left; eauto; fail); right; exists f; repeat split; auto;
      unfold in_iteration; simpl; intuition discriminate.
  - (* Idle *)
    unfold idle in H; in_cases H. intros s k w Hw; simpl in *.
    destruct (W s k w Hw) as [Wb [[f [Hf1 [Hf2 Hf3]]]|[f [Hf1 [Hf2 [Hf3 Hf4]]]]]];
      split; auto; try (left; eauto; fail); right; exists f; repeat split; auto;
      unfold in_iteration; simpl; intuition discriminate.
Qed.

Lemma winv_reachable : forall c0 c, dinv p c0 -> winv c0 -> reachable_from peqb bd p c0 c ->
  dinv p c /\ winv c.
Proof.
  intros c0 c D0 W0 Hr; induction Hr as [|c c' Hr IH Hn]; auto.
  destruct IH as [D W]. destruct Hn as [H|l H].
  - split; [eapply dinv_host|eapply winv_host]; eauto.
  - assert (D' : dinv p c') by (eapply dinv_agent; eauto). split; auto.
    eapply winv_agent; eauto.
Qed.

End Inversion.

(* THEOREM inversion_within_bound. Without the flood abstraction, in every
   reachable configuration of the budgeted loop, and of the reference loop
   with an O2A capacity, no waiting percept has waited behind more
   dispatches of lower-priority percepts than the dispatch bound:
   min(Budget, O2A capacity) in the budgeted loop, the O2A capacity in the
   reference loop. *)
Theorem inversion_within_bound :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (c : config P M Ob B),
  (p_variant p = Reference \/ p_variant p = Budgeted) ->
  p_flood p = false ->
  (forall x y, peqb x y = true <-> x = y) ->
  reachable peqb bd p c ->
  forall s k n, In (s, k, n) (waits c) -> within n (dispatch_bound p).
Proof.
  intros P M Ob B peqb bd p c Hv Hf Hp [behs Hr] s k n Hin.
  destruct (winv_reachable peqb bd p Hv Hp Hf (init behs) c (dinv_init p behs)
                           (winv_init p behs) Hr) as [_ W].
  apply (W s k n Hin).
Qed.
