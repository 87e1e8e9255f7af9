(** The fast path of the agent loop: the same rules as
    {!Semantics.Machine}, taken faster. Programs run on it ([jadescript-ref
    run], the corridor simulator, the bench); the reference machine stays
    plain and is what it is tested against, rule for rule.

    What is faster here, and what stands for it in the reference:
    - Transfer in one pass over O2A — the reference partitions O2A, then
      folds [Pqueue.insert] over the percepts;
    - Dequeue under stable ties as one pop, with the snapshot of the
      registered handlers remembered for the last [active] list seen
      (physically) — the reference asks for the candidates and rebuilds
      HandlersOf every time;
    - the derived rule {!Make.dispatch}: Dequeue, every Handle or Skip and
      EndDispatch in one call, on local variables, with the bodies' pre-test
      {!BODIES.percept_may_apply} deciding Skips without evaluating guards,
      asked once per kind of percept ({!BODIES.percept_kind}) and snapshot
      of the handlers when no one observes the labels.

    docs/semantics.md, "A derived rule: Dispatch" and "The fast engine". *)

(** What a handler's guard and body came to, from {!BODIES.percept_handle}. *)
type ('w, 'b) handled =
  | Not_applicable of 'w
      (** the guard does not hold (or failed): a Skip, in this world *)
  | Handled of 'w * 'b Semantics.Machine.effect list
      (** the guard held and the body ran: this world, these effects *)

val handle_in_two :
  ('w -> id:int -> 'b -> int -> 'p -> 'w * 'g option) ->
  ('w -> id:int -> active:int -> 'b -> int -> 'p -> 'g -> 'w * 'b Semantics.Machine.effect list) ->
  'w -> id:int -> active:int -> 'b -> int -> 'p -> ('w, 'b) handled
(** [handle_in_two percept_applicable run_percept_handler]: the guard, then
    the body when it holds: a {!BODIES.percept_handle} for any bodies. *)

module type BODIES = sig
  include Semantics.Machine.BODIES

  val percept_handle : world -> id:int -> active:int -> beh -> int -> percept -> (world, beh) handled
  (** [percept_applicable] and, when it holds, [run_percept_handler] at
      once, as the Handle rule takes them (R3b): what the two give in turn
      ({!handle_in_two}). Bodies that keep the guard's bindings for the
      body may do it in one go. *)

  val percept_may_apply : world -> beh -> int -> percept -> bool
  (** A pre-test: [false] only when [percept_applicable] would surely answer
      [false] for handler [h] of the behaviour and this percept, leaving the
      world as it is and recording nothing. [fun _ _ _ _ -> true] is always
      correct. *)

  val percept_kind : percept -> int
  (** A key for the pre-test: two percepts of the same kind [k >= 0] get
      the same answer from [percept_may_apply] for every behaviour and
      handler of one agent, whatever its world. {!Make.dispatch} then asks
      the pre-test once per kind and snapshot of the handlers, and tries
      only the handlers it leaves. [-1]: no key (every handler is tried);
      [fun _ -> -1] is always correct. Kinds are small: they index an
      array. *)
end

module Make (B : BODIES) : sig
  module M : module type of Semantics.Machine.Make (B)
  (** The reference machine on the same bodies. *)

  val transfer : Semantics.Machine.params -> M.t -> M.lbl * M.t
  (** Transfer in one pass, in a configuration where the reference's
      [M.transfer] is enabled and the variant is not [Native] (there the
      reference's own rule is taken). *)

  val transfer_into : M.t -> B.percept Semantics.Pqueue.t -> int -> M.lbl * M.t
  (** {!transfer} in a configuration whose O2A queue is empty, as if it
      held [n] percepts (no object), given as the priority queue [pq] they
      make with the configuration's own: the same label and configuration,
      without building that O2A queue. Variant [Reference] or [Budgeted],
      no flood abstraction, phase Transfer. *)

  val dispatch_lists : Semantics.Machine.params -> M.t -> B.percept Semantics.Machine.entry list list -> M.t * int
  (** {!dispatch_run} where the percepts wait elsewhere, as lists: each
      entry in turn, the lists in order (highest priority first, each in
      seq order), to the end; the priority queue of the result is the
      configuration's own. From phase Dispatch, unobserved, no ghosts,
      variant [Reference]. *)

  val step : Semantics.Machine.params -> M.t -> (M.lbl * M.t) list
  (** What [M.step] answers, faster: the batch Transfer, Dequeue as one pop
      with a remembered snapshot, every other rule the reference's. *)

  val dispatch : ?observe:(M.lbl -> B.world -> B.world) -> Semantics.Machine.params -> M.t -> M.t option
  (** One percept's whole dispatch in one call, when the configuration is in
      phase Handle (the rest of the dispatch in progress) or in phase
      Dispatch with Dequeue the one rule enabled (stable ties, no flood
      abstraction, not [Native]): Dequeue, then Handle or Skip for each
      handler of the snapshot, then EndDispatch. The result is the
      configuration that [M.step] reaches by applying those rules one at a
      time (each is then the only rule enabled), without building the
      configurations in between; [observe] sees their labels in order,
      each with the world after its rule, and answers the world to go on
      with (an observer may take the bodies' events there).
      [None] in any other configuration. *)

  val dispatch_run : Semantics.Machine.params -> M.t -> (M.t * int) option
  (** {!dispatch}, unobserved, again and again while it is enabled, from
      phase Dispatch (stable ties, no flood abstraction, no ghosts, not
      [Native]): the configuration that many calls of [dispatch] reach, and
      how many percepts left. The configurations between two percepts are
      not built while no body has effects. [None] where [dispatch] would
      not start from phase Dispatch, or where there is nothing to dispatch. *)

  val dispatch_from : Semantics.Machine.params -> M.t -> int -> (unit -> B.percept Semantics.Machine.entry) ->
    M.t * int
  (** {!dispatch_run} where the percepts wait elsewhere: [dispatch_from p c
      count pop] dispatches [count] percepts, each given by [pop ()] already
      taken from the top of its priority queue (as {!dispatch_entry});
      [count] is as many as Dequeue allows in a row (the percepts waiting,
      the budget left: the caller knows, a dispatch never adds to the
      queue). From phase Dispatch, unobserved, no ghosts; the priority queue
      of the result is the configuration's own. *)

  val dequeue_entry : Semantics.Machine.params -> M.t -> B.percept Semantics.Machine.entry ->
    pq:B.percept Semantics.Pqueue.t -> M.lbl * M.t
  (** Dequeue (R3b) of an entry the caller has already taken from the top of
      its priority queue, [pq] being that queue without it: in phase
      Dispatch, stable ties, no flood abstraction, not [Native], with the
      entry the one candidate. What [M.dequeue] answers there. The packed
      agent ({!Packed}) keeps its percepts apart and gives them here. *)

  val dispatch_entry : ?observe:(M.lbl -> B.world -> B.world) -> Semantics.Machine.params -> M.t ->
    B.percept Semantics.Machine.entry -> pq:B.percept Semantics.Pqueue.t -> M.t
  (** {!dispatch} from phase Dispatch, the entry already taken from the top
      of the priority queue as in {!dequeue_entry}. *)
end
