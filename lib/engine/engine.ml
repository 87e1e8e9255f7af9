(* The engine's contract (engine.mli): its rules, as the reference's. *)

type ('w, 'b) handled = ('w, 'b) Fast.handled =
  | Not_applicable of 'w
  | Handled of 'w * 'b Semantics.Machine.effect list

module type BODIES = Fast.BODIES

let handle_in_two = Fast.handle_in_two

module type S = sig
  type percept
  type message
  type obj
  type beh
  type world
  type config = (percept, message, obj, beh, world) Semantics.Machine.config
  type label = (percept, message, obj) Semantics.Machine.label
  val step : Semantics.Machine.params -> config -> (label * config) list
  val dispatch :
    ?observe:(label -> world -> world) -> Semantics.Machine.params -> config -> config option
end

module Make (B : BODIES) = struct
  type percept = B.percept
  type message = B.message
  type obj = B.obj
  type beh = B.beh
  type world = B.world
  type config = (percept, message, obj, beh, world) Semantics.Machine.config
  type label = (percept, message, obj) Semantics.Machine.label
  module F = Fast.Make (B)
  let step = F.step
  let dispatch = F.dispatch
end

module type INTERP = S
  with type percept = Interp_eval.Value.t and type message = Interp_eval.Eval.message
   and type obj = Interp_eval.Value.t and type beh = Interp_eval.Eval.beh
   and type world = Interp_eval.Eval.agent

let for_agent () : (module INTERP) =
  let module B = Compiled_bodies.Make () in
  (module Make (B))

module Private = struct
  module Fast = Fast
  module Compiled_bodies = Compiled_bodies
  module Packed = Packed
  module Percept_codec = Percept_codec
end
