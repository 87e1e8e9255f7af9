(** Running Jadescript programs: the values and evaluation rules
    ({!Value}, {!Eval}, library [interp_eval]), the runtime on the fast
    engine ({!Runtime}), and the conformance oracle ({!Oracle}). *)

module Value = Interp_eval.Value
module Eval = Interp_eval.Eval
module Runtime = Runtime
module Oracle = Oracle
