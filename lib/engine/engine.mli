(** The fast engine: what runs programs, beside the reference.

    The reference (the rules of {!Semantics.Machine} and the bodies of
    {!Interp_eval.Eval}) says what a run is; the engine takes the same
    rules faster, on the same configurations. This is its whole contract
    with the reference: an engine answers {!S.step} as the reference's
    [Machine.step] answers, and {!S.dispatch} as the rules of one percept's
    dispatch taken one at a time would. One property test holds it there
    (test/fastpath/test_engine.ml: every rule, and every dispatch with its
    logs and its final configuration, on random programs and events, and
    on every state of the spec's models); nothing else of the engine is
    seen by the reference or the runtime.

    How it is faster: docs/semantics.md, "A derived rule: Dispatch and the
    fast engine". *)

(** What a handler's guard and body came to, from {!BODIES.percept_handle}. *)
type ('w, 'b) handled = ('w, 'b) Fast.handled =
  | Not_applicable of 'w   (** the guard does not hold (or failed): a Skip, in this world *)
  | Handled of 'w * 'b Semantics.Machine.effect list
      (** the guard held and the body ran: this world, these effects *)

(** Bodies as the engine takes them: the machine's, with a handler's guard
    and body in one call and a pre-test (docs/semantics.md). *)
module type BODIES = Fast.BODIES

val handle_in_two :
  ('w -> id:int -> 'b -> int -> 'p -> 'w * 'g option) ->
  ('w -> id:int -> active:int -> 'b -> int -> 'p -> 'g -> 'w * 'b Semantics.Machine.effect list) ->
  'w -> id:int -> active:int -> 'b -> int -> 'p -> ('w, 'b) handled
(** [handle_in_two percept_applicable run_percept_handler]: the guard, then
    the body when it holds: a {!BODIES.percept_handle} for any bodies. *)

(** The contract. *)
module type S = sig
  type percept
  type message
  type obj
  type beh
  type world
  type config = (percept, message, obj, beh, world) Semantics.Machine.config
  type label = (percept, message, obj) Semantics.Machine.label

  val step : Semantics.Machine.params -> config -> (label * config) list
  (** What the reference's [Machine.step] answers in this configuration. *)

  val dispatch :
    ?observe:(label -> world -> world) -> Semantics.Machine.params -> config -> config option
  (** One percept's whole dispatch in one call (the derived rule Dispatch,
      docs/semantics.md), when the configuration is in phase Handle (the
      rest of the dispatch in progress) or in phase Dispatch with Dequeue
      the one rule enabled (stable ties, no flood abstraction, not
      [Native]): the configuration the reference reaches by taking Dequeue,
      then Handle or Skip for each handler of the snapshot, then
      EndDispatch, one at a time. [observe] is told each of those rules'
      labels in order, with the world after the rule, and answers the
      world to go on with (the runtime takes the bodies' events there).
      [None] in any other configuration. *)
end

module Make (B : BODIES) : S
  with type percept = B.percept and type message = B.message and type obj = B.obj
   and type beh = B.beh and type world = B.world
(** The engine on bodies of one's own (the explorer's models, the
    simulator's OCaml mirror of the paper's agent). *)

module type INTERP = S
  with type percept = Interp_eval.Value.t and type message = Interp_eval.Eval.message
   and type obj = Interp_eval.Value.t and type beh = Interp_eval.Eval.beh
   and type world = Interp_eval.Eval.agent

val for_agent : unit -> (module INTERP)
(** The interpreter's engine for one agent: its percept handlers compiled
    to closures ({!Private.Compiled_bodies}, D38), its own memory of them.
    Make one per agent. *)

(** Not part of the contract: the engine's parts, for its own tests and
    for the bench, which measures the packed agent. *)
module Private : sig
  module Fast = Fast
  module Compiled_bodies = Compiled_bodies
  module Packed = Packed
  module Percept_codec = Percept_codec
end
