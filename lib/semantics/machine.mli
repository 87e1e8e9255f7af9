(** The small-step semantics of one Jadescript agent's loop: the executable twin
    of [spec/AgentLoop.tla].

    A configuration ({!config}) holds exactly the variables of the spec (the O2A
    queue, the priority queue, the message queue, the active behaviours in
    activation order, JADE's ready and blocked lists and round-robin position,
    the loop phase, the dispatch in progress, the counters, the ghosts and the
    last action) plus [world], the agent's own state, which the spec abstracts
    away. Each transition is a rule named as the TLA+ action it implements and as
    the rule of docs/semantics.md; {!step} lists the enabled agent rules, the
    host functions ({!notify}, {!put}, {!send}, {!send_in_step}) are the host
    rules.

    The machine is parameterised by what handlers and behaviour steps do
    ({!BODIES}): the explorer plugs in the abstract bodies of a TLA+ model
    (acceptance tables and activate/deactivate effects), the interpreter plugs
    in real Jadescript code. A rule that runs a body takes the world from
    the configuration and puts back the world the body answers: nothing
    passes between rules or bodies but these values.

    This is the reference: plain rules, no caches, no derived rules. The fast
    path that runs programs ([lib/engine/]) is tested equal to it, rule for
    rule; the mutants of the conformance checks are altered {!Make.rules}
    tables built outside it ([lib/explore/mutant.ml]). *)

(** {1 Parameters} *)

type variant =
  | Printed    (** Algorithm 1 exactly as printed *)
  | Reference  (** the rulings, R3 *)
  | Budgeted   (** at most [budget] dispatches per iteration *)
  | Native     (** percepts through the message queue, FIFO (Jadescript 1.0) *)

type tie_policy =
  | Stable     (** R3b: equal priorities leave in seq order *)
  | Unstable   (** any entry of the highest priority (java.util.PriorityQueue) *)

type params = {
  variant : variant;
  tie : tie_policy;
  budget : int;               (** [Budget], used by [Budgeted] *)
  max_active : int option;    (** a model bound: an activation when this many
                                  instances are active is ignored; [None] in the
                                  interpreter *)
  o2a_capacity : int option;  (** R2d; [None]: unbounded *)
  flood : bool;               (** the flood abstraction of the spec: seqs are
                                  all 0, identical queue entries merge *)
  ghosts : bool;              (** maintain [done_] and [waits] (the spec's ghost
                                  variables); off in production runs *)
}

val default_params : params
(** [reference], stable ties, budget 1, no bounds, no flood abstraction, no
    ghosts: what [jadescript-ref run] uses unless told otherwise. *)

val variant_of_string : string -> variant option
val string_of_variant : variant -> string
(** ["printed"], ["reference"], ["budgeted"], ["native"]. *)

(** {1 Configurations} *)

type phase = Transfer_phase | Dispatch_phase | Handle_phase | Idle_phase
(** ["transfer"], ["dispatch"], ["handle"], ["idle"] in the spec. *)

type 'p entry = 'p Pqueue.entry = { p : 'p; prio : int; seq : int }
(** A notified percept: the percept, its effective priority (R2a), its seq (R2b). *)

type ('p, 'o) o2a_item =
  | O_percept of 'p entry
  | O_object of 'o            (** a non-percept object (R2c) *)

type ('p, 'm) msg_item =
  | M_message of { m : 'm; mseq : int }
  | M_percept of 'p entry     (** only in the [Native] variant *)

type 'b instance = { id : int; beh : 'b }
(** An active behaviour instance: its id (the smallest free one when created)
    and what the bodies know of it. *)

type 'p dispatch = {
  e : 'p entry;               (** the percept being dispatched *)
  todo : (int * int) list;    (** registered handlers not yet tried: (instance
                                  id, handler index from 1), R4a/R4b *)
  applied : bool;             (** some handler ran *)
}

type ('p, 'm, 'o) label =
  | Init
  | Notify of 'p entry                   (** host: notifyEvent(p) *)
  | Notify_with of 'p entry              (** host: notifyEvent(p, k) *)
  | Put of 'o                            (** host: a non-percept object *)
  | Send of 'm * int                     (** host: a message and its seq *)
  | Transfer of int                      (** R3a: the number of percepts moved *)
  | Transfer_one of 'p entry             (** printed: one percept moved *)
  | Transfer_spin of 'o                  (** printed: peeking at an object *)
  | Transfer_end                         (** printed: O2A empty *)
  | Dequeue of 'p entry                  (** R3b *)
  | Handle of { id : int; h : int; p : 'p; seq : int }   (** a handler ran *)
  | Skip of { id : int; h : int }        (** a handler did not apply (R4b) *)
  | End_dispatch of { seq : int; discarded : bool }
  | Behaviour_step of { id : int; msg : ('p, 'm) msg_item option }   (** R5 *)
  | Next_iteration
  | Idle                                 (** R3e *)

val action_name : ('p, 'm, 'o) label -> string
(** The TLA+ action name: ["Notify"], ["Transfer"], ["BehaviourStep"], ... *)

module Int_set : Set.S with type elt = int

(** The window of a message that reaches the agent during its last behaviour
    step (R5d revised, D42): the spec's variable [stepped]. *)
type 'b stepped =
  | Not_stepped
      (** closed: the agent took another rule since its last behaviour step,
          or a message came after that step ({!Make.send}); the spec's
          [NoStep] *)
  | Stepped_kept
      (** open, and the step did not block its behaviour (it took a message,
          has an action block, is a one-shot or left), or a message that came
          during the step was already delivered; [[kind |-> "kept"]] *)
  | Stepped_blocked of { active : 'b instance list; ready : int list; blocked : int list; pos : int }
      (** open, and the step blocked its behaviour: the behaviour state just
          before the block (S2 of the spec's BehaviourStep), which a message
          that came during the step restores; [[kind |-> "blocked", bs |-> S2]] *)

type ('p, 'm, 'o, 'b, 'w) config = {
  o2a : ('p, 'o) o2a_item Fqueue.t;
  pq : 'p Pqueue.t;
  msgq : ('p, 'm) msg_item Fqueue.t;
  next_seq : int;             (** seq of the last percept notified *)
  msg_seq : int;              (** seq of the last message *)
  puts : int;                 (** objects put so far *)
  active : 'b instance list;  (** activation order *)
  ready : int list;           (** JADE's ready list (ids) *)
  blocked : int list;         (** blocked ids, in blocking order *)
  pos : int;                  (** 1-based index in [ready] of the next to run *)
  phase : phase;
  cur : 'p dispatch option;   (** [Some] exactly in phase [Handle] *)
  dispatched : int;           (** dequeues since the last transfer *)
  done_ : Int_set.t;          (** ghost: seqs that left the system *)
  waits : (int * int * int) list;
      (** ghost: (seq, priority, inversions) of every waiting percept, by seq *)
  last : ('p, 'm, 'o) label;
      (** the last rule; SendInStep is labelled [Send] as Send is: the two
          differ in [stepped] ({!Make.last_action_name}) *)
  stepped : 'b stepped;       (** R5d revised: set by BehaviourStep, closed by
                                  every other agent rule and by Send; Notify,
                                  NotifyWith and Put leave it *)
  world : 'w;                 (** the agent's own state (unit in the explorer) *)
}

type 'b effect =
  | Activate of 'b            (** R5g: a new instance, appended to active/ready *)
  | Deactivate                (** R5h: [deactivate this] *)

(** {1 What bodies do} *)

module type BODIES = sig
  type percept
  type message
  type obj
  type beh
  type world

  type bindings
  (** What a handler's guard bound when it held (its pattern variables),
      which its body then sees (R3b). *)

  val cyclic : beh -> bool
  val has_action : beh -> bool
  val percept_handlers : beh -> int
  (** How many [on percept] handlers the instance's behaviour declares. *)

  val message_handlers : beh -> int

  val percept_applicable : world -> id:int -> beh -> int -> percept -> world * bindings option
  (** Is handler [h] (from 1) of instance [id] applicable to the percept now
      (pattern and [when], R3b)? [Some] with the guard's bindings when it
      is. An error makes it not applicable; the world it answers may record
      the error. *)

  val run_percept_handler :
    world -> id:int -> active:int -> beh -> int -> percept -> bindings -> world * beh effect list
  (** The body of handler [h] of instance [id], in its guard's bindings;
      [active] instances are active as it starts (D19). The world after it,
      and its effects on the behaviours (R5g, R5h), in order. *)

  val run_action : world -> id:int -> active:int -> beh -> world * beh effect list
  (** The action block ([do]) of a behaviour that has one. *)

  val message_accepted : world -> id:int -> beh -> int -> message -> world * bindings option
  (** Does message handler [h] accept this message (performative, pattern,
      [when])? As {!percept_applicable}. *)

  val run_message_handler :
    world -> id:int -> active:int -> beh -> int -> message -> bindings -> world * beh effect list

  val take_outbox : world -> world * (string * message) list
  (** The messages the bodies sent since the last call, with their receivers'
      names, in order; the platform delivers them (R5e). *)
end

(** Why the host's notification was refused. *)
type refusal =
  | Negative_priority of int    (** R2a: a priority is a natural number *)
  | O2a_full                    (** R2d *)

module Make (B : BODIES) : sig
  type t = (B.percept, B.message, B.obj, B.beh, B.world) config
  type lbl = (B.percept, B.message, B.obj) label

  val init : params -> world:B.world -> B.beh list -> t
  (** The agent after its [on create] activated these behaviours (R5g):
      instances 1..n, all ready, phase [Transfer]. *)

  (** {2 Host rules} *)

  val o2a_has_room : params -> t -> bool
  (** R2d. *)

  val notify : params -> t -> B.percept -> int -> t
  (** [Notify]: append the percept with its default priority (R2b). The caller
      checks {!o2a_has_room} (a refusal changes nothing). *)

  val notify_with : params -> t -> B.percept -> int -> t
  (** [NotifyWith]: the priority overridden (R2a). *)

  val notify_event : params -> t -> B.percept -> default:int -> priority:int option -> (t, refusal) result
  (** What the host's [notifyEvent(p)] ([priority = None]: the percept type's
      [default], R1a) or [notifyEvent(p, k)] does: {!notify} or
      {!notify_with}, or a refusal that changes nothing: a negative [k]
      (R2a), a full O2A queue (R2d). *)

  val put : params -> t -> B.obj -> t
  (** [Put] (R2c). *)

  val send : params -> t -> B.message -> t
  (** [Send]: a message reaches the agent (R5e); blocked behaviours wake (R5d).
      It closes the window of the last behaviour step ([stepped]). *)

  val send_in_step : params -> t -> B.message -> t option
  (** [SendInStep]: the message reaches the agent during its last behaviour
      step, after that step's handlers looked for messages (R5d revised,
      D42). [None] when the window is closed ([stepped = Not_stepped]: the
      agent took a rule since its last behaviour step, or a message came
      after it). Otherwise as {!send}, and a behaviour that the step
      blocked is runnable again at its place in the ready list (JADE's
      restart counter); the window stays open ([Stepped_kept]), so a
      further message that came during the same step is exactly a {!send}.
      Its label is [Send (m, seq)], as Send's. The caller bounds the
      messages, as for {!send}. *)

  val last_action_name : t -> string
  (** The TLA+ name of the action that made this configuration: [action_name
      c.last], except ["SendInStep"] for a [Send] label with the window
      still open (Send closes it, SendInStep leaves it open). *)

  (** {2 Agent rules}

      Each rule is one action of the spec (each closes the window of
      {!send_in_step} but BehaviourStep, which opens it): [rule p c] is the empty list when
      the action's enabling condition does not hold in [c], else its results
      (several only for Dequeue's candidates under the [Unstable] policy or
      the flood abstraction). *)

  type rule = params -> t -> (lbl * t) list

  val transfer : rule
  (** Transfer (R3a; [native]: into the message queue). *)

  val transfer_one : rule
  (** TransferOne ([printed]). *)

  val transfer_spin : rule
  (** TransferSpin ([printed]). *)

  val transfer_end : rule
  (** TransferEnd ([printed]). *)

  val dequeue : rule
  (** Dequeue (R3b, R4a): one result per candidate. *)

  val handle_or_skip : rule
  (** Handle or Skip (R3b, R4b): Applicable of the head of the snapshot is
      evaluated once (the bodies may record an error while evaluating a
      guard), and decides which of the two actions is enabled.
      @raise Fault.Crash in phase [Handle] without a dispatch in progress. *)

  val end_dispatch : rule
  (** EndDispatch (R3b). *)

  val behaviour_step : rule
  (** BehaviourStep (R5a-R5d, R5f); it opens the window of {!send_in_step}. *)

  val next_iteration : rule
  (** NextIteration (D5). *)

  val idle : rule
  (** Idle (R3e). *)

  (** The agent rules as a table, so that a caller can build an altered
      machine (a mutant) from them without touching them. *)
  type rules = {
    transfer : rule; transfer_one : rule; transfer_spin : rule; transfer_end : rule;
    dequeue : rule; handle_or_skip : rule; end_dispatch : rule;
    behaviour_step : rule; next_iteration : rule; idle : rule;
  }

  val rules : rules
  (** The reference table. *)

  val step_by : rules -> rule
  (** AgentStep: every rule of the table enabled in this configuration, with
      its result, in the spec's order of the disjuncts. *)

  val step : rule
  (** [step_by rules]. Empty when the agent is idle. *)

  val is_idle : t -> bool

  (** {2 Operators the spec names}

      Exported for the fast engine and for altered rules; each is the TLA+
      operator of the same name. *)

  type bs = { active : B.beh instance list; ready : int list; blocked : int list; pos : int }
  (** BS: the behaviour part of a configuration. *)

  val bs_of : t -> bs
  val with_bs : t -> bs -> t
  (** SetBS. *)

  val apply_effects : params -> bs -> int -> B.beh effect list -> int list -> bs
  (** ApplyEffects(S, this, effs, reserved) (R5g, R5h, D2). *)

  val find_instance : int -> B.beh instance list -> B.beh option
  (** The behaviour of an instance, if it is active. *)

  val bump_waits : params -> t -> B.percept entry -> (int * int * int) list
  (** BumpWaits (ghost). *)

  val add_done : params -> t -> int -> Int_set.t
  (** [done \cup {seq}] (ghost). *)

  val budget_spent : params -> t -> bool
  val dispatch_over : params -> t -> bool
  (** BudgetSpent, DispatchOver. *)

  val idle_condition : t -> bool
  (** R3e: nothing ready, no percept in O2A, the priority queue empty. *)
end
