module Value = Interp_eval.Value
module Eval = Interp_eval.Eval
module Runtime = Runtime
module Oracle = Oracle
