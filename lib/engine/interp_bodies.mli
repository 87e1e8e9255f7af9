(** The interpreter's bodies for the fast engine: {!Interp_eval.Eval.Bodies},
    with percept guards taken faster and a pre-test for {!Fast.Make.dispatch}.

    - A guard of the shape [content matches S(x1, ..., xn)] (optionally
      followed by [and rest]), S a schema with n slots and each xi a variable
      or [_], is {e resolved} once per handler: on a percept of schema S
      itself the slots are bound by position, which is what the general rules
      do on that shape; any other percept takes the general rules.
    - The {e pre-test}: a guard whose leftmost conjunct is [content matches S]
      or [content matches S(...)] is false, with no effect and no possible
      error, on a percept whose type neither is S nor extends S. The answer
      per percept type is remembered (a memo by the type name's address, the
      lexer interning names). [percept_applicable] itself answers [false] at
      once there, leaving the world as it is.
    - A percept's {e kind} ({!Fast.BODIES.percept_kind}) is a number for its
      schema's name, the same in every agent: the pre-test's answer depends
      on the name only.

    Everything else is [Eval.Bodies]'. Tested against [Eval.Bodies] (which
    has no memo and no resolved guard) on random programs, rule for rule. *)

include Fast.BODIES
  with type percept = Interp_eval.Value.t
   and type message = Interp_eval.Eval.message
   and type obj = Interp_eval.Value.t
   and type beh = Interp_eval.Eval.beh
   and type world = Interp_eval.Eval.agent
