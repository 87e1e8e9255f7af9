(** Running Jadescript programs: the values and evaluation rules
    ({!Value}, {!Eval}, library [interp_eval]), the runtime on the fast
    engine ({!Runtime}), its trace ({!Tracer}), the host's events file
    ({!Events}), and the conformance oracle ({!Oracle}). *)

module Value = Interp_eval.Value
module Eval = Interp_eval.Eval
module Host = Host
module Tracer = Tracer
module Events = Events
module Runtime = Runtime
module Oracle = Oracle
