(* Runs of the machine of Loop.v: the host's actions and the agent's rules
   as one step relation (the spec's Next = HostStep \/ AgentStep), the
   configurations reachable from Init, finite runs, and the lemmas every
   proof uses: which rule produced a step, and what each rule leaves
   unchanged. *)

From Coq Require Import List Bool Arith Lia.
Import ListNotations.
From Jsref Require Import Loop.

Section Run.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).
Notation label := (label P M Ob).

(* HostStep: the host notifies (any percept, any priority; refused when
   the O2A queue is full, R2d), puts an object (refused when full), or
   sends a message. Nothing bounds how often. *)
Inductive host_step (c : config) : config -> Prop :=
| H_notify : forall x k, o2a_has_room p c = true -> host_step c (notify p c x k)
| H_notify_with : forall x k, o2a_has_room p c = true -> host_step c (notify_with p c x k)
| H_put : forall o, o2a_has_room p c = true -> host_step c (put c o)
| H_send : forall m, host_step c (send c m).

(* Next: a host step or any agent step that the extracted [step] returns. *)
Inductive next (c c' : config) : Prop :=
| Next_host : host_step c c' -> next c c'
| Next_agent : forall l, In (l, c') (step peqb bd p c) -> next c c'.

(* The configurations reachable from c0. *)
Inductive reachable_from (c0 : config) : config -> Prop :=
| R_start : reachable_from c0 c0
| R_next : forall c c', reachable_from c0 c -> next c c' -> reachable_from c0 c'.

(* Reachable from Init, whatever behaviours the agent's on create activated. *)
Definition reachable (c : config) : Prop := exists behs, reachable_from (init behs) c.

(* A finite run from c: the configurations after each step, in order. *)
Inductive run : config -> list config -> Prop :=
| Run_nil : forall c, run c []
| Run_cons : forall c c' cs, next c c' -> run c' cs -> run c (c' :: cs).

(* R holds of every step (c1, c2) of the run from c through cs. *)
Fixpoint every_step (R : config -> config -> Prop) (c : config) (cs : list config) : Prop :=
  match cs with
  | [] => True
  | c' :: rest => R c c' /\ every_step R c' rest
  end.

End Run.

Arguments host_step {P M Ob B}.
Arguments next {P M Ob B}.
Arguments reachable_from {P M Ob B}.
Arguments reachable {P M Ob B}.
Arguments run {P M Ob B}.
Arguments every_step {P M Ob B}.

(* ------------------------------------------------------------------ *)
(* Lemmas about single steps                                            *)
(* ------------------------------------------------------------------ *)

(* Turn a hypothesis In x (rule ...) into the cases of the rule. *)
Ltac in_cases H :=
  repeat match type of H with
  | In _ [] => destruct H
  | In _ (_ :: _) => destruct H as [H|H]
  | In _ (if ?b then _ else _) => let E := fresh "E" in destruct b eqn:E
  | In _ (match ?x with _ => _ end) => let E := fresh "E" in destruct x eqn:E
  | In _ (map _ _) => let e := fresh "e" in let Hin := fresh "Hin" in
                      apply in_map_iff in H; destruct H as [e [H Hin]]
  | (_, _) = (_, _) => injection H; clear H; intros; subst
  | False => destruct H
  end.

Section Lemmas.

Context {P M Ob B : Type}.
Variable peqb : P -> P -> bool.
Variable bd : bodies P M B.
Variable p : params.

Notation config := (config P M Ob B).

Lemma in_step_cases : forall (c : config) l c',
  In (l, c') (step peqb bd p c) ->
  In (l, c') (transfer peqb p c) \/ In (l, c') (transfer_one peqb p c)
  \/ In (l, c') (transfer_spin p c) \/ In (l, c') (transfer_end p c)
  \/ In (l, c') (dequeue peqb bd p c) \/ In (l, c') (handle_or_skip bd p c)
  \/ In (l, c') (end_dispatch p c) \/ In (l, c') (behaviour_step bd p c)
  \/ In (l, c') (next_iteration p c) \/ In (l, c') (idle p c).
Proof.
  intros c l c' H; unfold step in H;
  repeat (apply in_app_or in H; destruct H as [H|H]; [tauto|]); tauto.
Qed.

(* The rule that produced an agent step, by its label. *)
Definition rule_of (l : label P M Ob) : config -> list (label P M Ob * config) :=
  match l with
  | L_transfer _ => transfer peqb p
  | L_transfer_one _ => transfer_one peqb p
  | L_transfer_spin _ => transfer_spin p
  | L_transfer_end => transfer_end p
  | L_dequeue _ => dequeue peqb bd p
  | L_handle _ _ _ _ | L_skip _ _ => handle_or_skip bd p
  | L_end_dispatch _ _ => end_dispatch p
  | L_behaviour_step _ _ => behaviour_step bd p
  | L_next_iteration => next_iteration p
  | L_idle => idle p
  | _ => fun _ => []
  end.

(* Every agent rule records itself in [last], and its label names it. *)
Lemma step_rule : forall (c : config) l c',
  In (l, c') (step peqb bd p c) -> In (l, c') (rule_of l c) /\ last c' = l.
Proof.
  intros c l c' H; apply in_step_cases in H;
  repeat destruct H as [H|H]; pose proof H as H0;
  unfold transfer, transfer_one, transfer_spin, transfer_end, dequeue, handle_or_skip,
    end_dispatch, behaviour_step, next_iteration, idle, set_last in H;
  in_cases H; (split; [exact H0|reflexivity]).
Qed.

Lemma step_last : forall (c : config) l c', In (l, c') (step peqb bd p c) -> last c' = l.
Proof. intros c l c' H; apply (step_rule c l c' H). Qed.

Lemma run_app : forall (c : config) cs c' cs',
  run peqb bd p c (cs ++ c' :: cs') ->
  run peqb bd p c (cs ++ [c']) /\ run peqb bd p c' cs'.
Proof.
  intros c cs; revert c; induction cs as [|x cs IH]; intros c c' cs' H; simpl in *.
  - inversion H; subst; split; [constructor; auto; constructor | auto].
  - inversion H; subst. apply IH in H4 as [H4 H5]. split; [constructor; auto | auto].
Qed.

Lemma run_reachable : forall c0 (c : config) cs,
  reachable_from peqb bd p c0 c -> run peqb bd p c cs ->
  forall c', In c' cs -> reachable_from peqb bd p c0 c'.
Proof.
  intros c0 c cs Hr Hrun; induction Hrun; intros c'' Hin; simpl in Hin.
  - destruct Hin.
  - destruct Hin as [<-|Hin].
    + econstructor; eauto.
    + apply IHHrun; auto. econstructor; eauto.
Qed.

End Lemmas.
