(* The inversion bound of Budget.v is exact: a run reaches it, whatever
   behaviours the agent has. And without an O2A capacity the reference loop
   has no bound at all. The run: the host notifies N percepts of priority 0,
   the agent transfers them, the host notifies one of priority 1, which waits
   in the O2A queue while the agent dispatches the N others (R3d). *)

From Coq Require Import List Bool Arith Lia.
Import ListNotations.
From Jsref Require Import Loop Run Facts Order Budget.

Section Tight.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Hypothesis Hv : p_variant p = Reference \/ p_variant p = Budgeted.
Hypothesis Hpeqb : forall x y, peqb x y = true <-> x = y.
Hypothesis Hflood : p_flood p = false.

Lemma in_step : forall (c : config) x,
  In x (transfer peqb p c) \/ In x (dequeue peqb bd p c) \/ In x (handle_or_skip bd p c)
  \/ In x (end_dispatch p c) -> In x (step peqb bd p c).
Proof. intros c x H; unfold step; rewrite !in_app_iff; tauto. Qed.

Lemma bump_keeps : forall (e : entry P) ws s k n,
  In (s, k, n) ws -> s <> eseq e -> In (s, k, if eprio e <? k then S n else n) (bump e ws).
Proof.
  intros e ws; induction ws as [|[[s0 k0] n0] ws IH]; intros s k n H Hs; simpl in *; [auto|].
  destruct H as [H|H].
  - injection H; intros; subst. apply Nat.eqb_neq in Hs. rewrite Hs. left; auto.
  - destruct (s0 =? eseq e); [|right]; auto.
Qed.

(* The dispatch in progress runs through its snapshot, then ends. *)
Lemma finish_dispatch : forall n (c : config) d,
  length (todo d) = n -> phase_of c = Handle_phase -> cur c = Some d ->
  exists c', reachable_from peqb bd p c c' /\ phase_of c' = Dispatch_phase
             /\ pq c' = pq c /\ waits c' = waits c /\ dispatched c' = dispatched c.
Proof.
  induction n as [|n IH]; intros c d Hn Hph Hc.
  - destruct (todo d) eqn:T; [|discriminate].
    eexists. split.
    + eapply R_next; [apply R_start|]. eapply Next_agent. apply in_step. right; right; right.
      unfold end_dispatch. rewrite Hph, Hc, T. left; reflexivity.
    + simpl; auto.
  - destruct (todo d) as [|[id h] rest] eqn:T; [discriminate|].
    set (d' b := {| de := de d; todo := rest; applied := b |}).
    assert (exists l c1, In (l, c1) (handle_or_skip bd p c) /\ phase_of c1 = Handle_phase
                         /\ (exists b, cur c1 = Some (d' b)) /\ pq c1 = pq c
                         /\ waits c1 = waits c /\ dispatched c1 = dispatched c)
      as [l [c1 [Hin [Hph1 [[b Hc1] [Hq [Hw Hd]]]]]]].
    { unfold handle_or_skip. rewrite Hph, Hc, T.
      destruct (find_instance id (active c)) as [bh|];
        [destruct (percept_accepts bd bh h (ep (de d)))|];
        do 2 eexists; (split; [left; reflexivity|]); simpl; repeat split; eauto. }
    assert (Hlen : length (todo (d' b)) = n) by (simpl in Hn; simpl; lia).
    destruct (IH c1 (d' b) Hlen Hph1 Hc1) as [c' [Hr [H1 [H2 [H3 H4]]]]].
    exists c'. split; [|repeat split; congruence].
    clear H1 H2 H3 H4. induction Hr as [|c2 c3 Hr IH' Hn'].
    + eapply R_next; [apply R_start|]. eapply Next_agent; apply in_step; eauto.
    + eapply R_next; eauto.
Qed.

Lemma reachable_trans : forall (c0 c1 c2 : config),
  reachable_from peqb bd p c0 c1 -> reachable_from peqb bd p c1 c2 ->
  reachable_from peqb bd p c0 c2.
Proof. intros c0 c1 c2 H1 H2; induction H2; auto; eapply R_next; eauto. Qed.

Variable N : nat.
Hypothesis HN_budget : p_variant p = Budgeted -> N <= p_budget p.

(* The dispatches of the N low percepts, one after the other. *)
Lemma dispatch_lows : forall r (c0 c : config),
  reachable_from peqb bd p c0 c -> phase_of c = Dispatch_phase ->
  length (pq c) = r -> dispatched c + r = N ->
  (forall e, In e (pq c) -> eprio e = 0 /\ eseq e <= N) ->
  In (S N, 1, N - r) (waits c) ->
  exists c', reachable_from peqb bd p c0 c' /\ In (S N, 1, N) (waits c').
Proof.
  induction r as [|r IH]; intros c0 c Hr Hph Hl Hd Hq Hw.
  - exists c; rewrite Nat.sub_0_r in Hw; auto.
  - assert (Hne : pq c <> []) by (intros E; rewrite E in Hl; discriminate).
    destruct (candidates p (pq c)) as [|e es] eqn:C; [apply (candidates_nonempty p) in Hne; congruence|].
    assert (He : In e (pq c)) by (apply (candidates_in p (pq c)); rewrite C; left; auto).
    destruct (Hq e He) as [Hep Hes].
    set (c1 := {| o2a := o2a c; pq := remove_one peqb e (pq c); msgq := msgq c;
                  next_seq := next_seq c; msg_seq := msg_seq c; puts := puts c;
                  active := active c; ready := ready c; blocked := blocked c; pos := pos c;
                  phase_of := Handle_phase;
                  cur := Some {| de := e; todo := handlers_of bd c; applied := false |};
                  dispatched := S (dispatched c); done_ := done_ c; waits := bump_waits p c e;
                  last := L_dequeue e |} : config).
    assert (H1 : In (L_dequeue e, c1) (dequeue peqb bd p c)).
    { unfold dequeue, budget_spent, is_native. rewrite Hph.
      destruct Hv as [V|V]; rewrite V; simpl.
      - destruct (pq c) as [|x q]; [congruence|]. simpl. rewrite C. left; reflexivity.
      - assert (Hb : (p_budget p <=? dispatched c) = false) by (apply Nat.leb_gt; specialize (HN_budget V); lia).
        rewrite Hb. destruct (pq c) as [|x q]; [congruence|]. simpl. rewrite C. left; reflexivity. }
    destruct (finish_dispatch (length (handlers_of bd c)) c1
                {| de := e; todo := handlers_of bd c; applied := false |})
      as [c2 [Hr2 [Hph2 [Hq2 [Hw2 Hd2]]]]]; auto.
    apply (IH c0 c2).
    + eapply reachable_trans; [|apply Hr2]. eapply R_next; [apply Hr|].
      eapply Next_agent. apply in_step. eauto.
    + auto.
    + rewrite Hq2; simpl. pose proof (remove_one_length peqb Hpeqb e (pq c) He). lia.
    + rewrite Hd2; simpl. lia.
    + intros f Hf. rewrite Hq2 in Hf; simpl in Hf. apply remove_one_incl in Hf. auto.
    + rewrite Hw2; simpl. unfold bump_waits; rewrite Hflood.
      replace (N - r) with (if eprio e <? 1 then S (N - S r) else N - S r)
        by (rewrite Hep; simpl; lia).
      apply bump_keeps; auto. lia.
Qed.

Variable x : P.
Variable behs : list B.
Hypothesis HN_capacity : forall k, p_capacity p = Some k -> N <= k /\ 1 <= k.

Definition low (i : nat) : config := Nat.iter i (fun c => notify p c x 0) (init behs).

Lemma low_facts : forall i, i <= N ->
  reachable_from peqb bd p (init behs) (low i) /\ phase_of (low i) = Transfer_phase
  /\ pq (low i) = [] /\ next_seq (low i) = i /\ length (o2a (low i)) = i
  /\ (forall it, In it (o2a (low i)) -> exists e, it = O_percept e /\ eprio e = 0 /\ eseq e <= i).
Proof.
  induction i as [|i IH]; intros Hi.
  - simpl. repeat split; auto; [apply R_start|intros it []].
  - destruct IH as [Hr [Hph [Hq [Hs [Hl Ho]]]]]; [lia|].
    change (low (S i)) with (notify p (low i) x 0).
    split.
    { eapply R_next; [apply Hr|]. apply Next_host. apply H_notify.
      unfold o2a_has_room. rewrite (not_native p Hv).
      destruct (p_capacity p) as [k|] eqn:K; auto. apply Nat.ltb_lt.
      destruct (HN_capacity k eq_refl). lia. }
    unfold notify, notify_effect; rewrite Hflood; simpl.
    repeat split.
    + unfold wake_idle; rewrite Hph; auto.
    + auto.
    + auto.
    + rewrite app_length; simpl; lia.
    + intros it Hit. apply in_app_or in Hit as [Hit|[Hit|[]]].
      * destruct (Ho it Hit) as [e [He1 [He2 He3]]]. exists e; repeat split; auto.
      * subst it. eexists; repeat split; simpl; lia.
Qed.

Lemma all_percepts : forall (l : list (o2a_item P Ob)) (Q : entry P -> Prop),
  (forall it, In it l -> exists e, it = O_percept e /\ Q e) ->
  o2a_objects l = [] /\ length (o2a_percepts l) = length l
  /\ (forall e, In e (o2a_percepts l) -> Q e).
Proof.
  induction l as [|it l IH]; intros Q H; simpl; [repeat split; auto; intros e []|].
  destruct (H it (or_introl eq_refl)) as [e [-> He]].
  destruct (IH Q) as [H1 [H2 H3]]; [intros; apply H; right; auto|].
  unfold o2a_objects in *; simpl. repeat split; auto.
  intros f [<-|Hf]; auto.
Qed.

Lemma reach_inversion : exists c : config, reachable_from peqb bd p (init behs) c /\ In (S N, 1, N) (waits c).
Proof.
  destruct (low_facts N (le_n N)) as [Hr [Hph [Hq [Hs [Hl Ho]]]]].
  destruct (all_percepts _ (fun e => eprio e = 0 /\ eseq e <= N) Ho) as [Hobj [Hlen Hall]].
  (* Transfer *)
  set (ct := {| o2a := o2a_objects (o2a (low N));
                pq := fold_left (pq_add peqb p) (o2a_percepts (o2a (low N))) (pq (low N));
                msgq := msgq (low N); next_seq := next_seq (low N); msg_seq := msg_seq (low N);
                puts := puts (low N); active := active (low N); ready := ready (low N);
                blocked := blocked (low N); pos := pos (low N); phase_of := Dispatch_phase;
                cur := cur (low N); dispatched := 0; done_ := done_ (low N);
                waits := waits (low N);
                last := L_transfer (length (o2a_percepts (o2a (low N)))) |} : config).
  assert (Ht : In (L_transfer (length (o2a_percepts (o2a (low N)))), ct) (transfer peqb p (low N))).
  { unfold transfer. rewrite (not_printed p Hv), (not_native p Hv), Hph. left; reflexivity. }
  (* the high-priority percept arrives after the Transfer *)
  set (ch := notify p ct x 1).
  assert (Hrh : reachable_from peqb bd p (init behs) ch).
  { eapply R_next; [eapply R_next; [apply Hr|]|].
    - eapply Next_agent. apply in_step. left; eauto.
    - apply Next_host. apply H_notify. unfold o2a_has_room. rewrite (not_native p Hv).
      destruct (p_capacity p) as [k|] eqn:K; auto. apply Nat.ltb_lt.
      destruct (HN_capacity k eq_refl). simpl. rewrite Hobj. simpl. lia. }
  apply (dispatch_lows N (init behs) ch Hrh).
  - unfold ch, notify, notify_effect; simpl; auto.
  - unfold ch, notify, notify_effect; simpl.
    rewrite fold_pq_add_noflood, Hq by auto. simpl. congruence.
  - unfold ch, notify, notify_effect; simpl. lia.
  - intros e He. unfold ch, notify, notify_effect in He; simpl in He.
    rewrite fold_pq_add_noflood, Hq in He by auto. apply Hall; auto.
  - unfold ch, notify, notify_effect, add_wait; rewrite Hflood; simpl.
    rewrite Hs, Nat.sub_diag. apply in_or_app; right; left; reflexivity.
Qed.

End Tight.

(* THEOREM inversion_bound_reached. The bound of inversion_within_bound is
   exact: whatever the agent's behaviours and handlers, with an O2A queue
   that holds at least one entry, a reachable configuration has a percept
   of priority 1 that has waited behind exactly that many dispatches of
   percepts of priority 0. *)
Theorem inversion_bound_reached :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (behs : list B) (x : P) (n : nat),
  (p_variant p = Reference \/ p_variant p = Budgeted) ->
  p_flood p = false ->
  (forall x y, peqb x y = true <-> x = y) ->
  p_capacity p <> Some 0 ->
  dispatch_bound p = Some n ->
  exists c : config P M Ob B,
    reachable_from peqb bd p (init behs) c /\ In (S n, 1, n) (waits c).
Proof.
  intros P M Ob B peqb bd p behs x n Hv Hf Hp Hc Hb.
  refine (reach_inversion peqb bd p Hv Hp Hf n _ x behs _); unfold dispatch_bound in Hb.
  - intros V; rewrite V in Hb. destruct (p_capacity p); injection Hb; intros; lia.
  - intros k Hk. destruct k as [|k]; [congruence|]. split; [|lia].
    destruct Hv as [V|V]; rewrite V, Hk in Hb; injection Hb; intros; lia.
Qed.

(* THEOREM reference_inversion_unbounded. Without an O2A capacity (the
   default, R2d) the reference loop has no inversion bound: for every n a
   reachable configuration has a percept that has waited behind n
   dispatches of lower-priority percepts. *)
Theorem reference_inversion_unbounded :
  forall {P M Ob B : Type} (peqb : P -> P -> bool) (bd : bodies P M B) (p : params)
         (behs : list B) (x : P) (n : nat),
  p_variant p = Reference -> p_capacity p = None -> p_flood p = false ->
  (forall x y, peqb x y = true <-> x = y) ->
  exists c : config P M Ob B,
    reachable_from peqb bd p (init behs) c /\ In (S n, 1, n) (waits c).
Proof.
  intros P M Ob B peqb bd p behs x n Hv Hc Hf Hp.
  refine (reach_inversion peqb bd p (or_introl Hv) Hp Hf n _ x behs _).
  - intros V; congruence.
  - intros k Hk; congruence.
Qed.
