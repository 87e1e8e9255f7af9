module Value = Interp_eval.Value
module Eval = Interp_eval.Eval
module Host = Host
module Tracer = Tracer
module Events = Events
module Runtime = Runtime
module Oracle = Oracle
