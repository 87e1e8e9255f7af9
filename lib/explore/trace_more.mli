(** Checks of a trace that {!Trace_check} does not make, run by
    [validate] after it (docs/trace-format.md, "What validate checks"):

    - a body's [activate] and [deactivate] events against the [effects] its
      step declares ([handle]: [effects]; [behaviour_step]: [action_effects]
      and the handler's [effects], in either order): the same effects, in the
      same order, none dropped, none added, none repeated;
    - every percept literal of a [notify] or a refused notify parses as a
      value as the interpreter writes it (a percept type's name, alone or
      with its slots' values in parentheses: numbers, texts, [true],
      [false], lists, maps, schema values, [aid(...)]), nested at most
      1,000 deep, and every literal of one percept type has the same number
      of slots.

    - a step's messages leave when it ends (R5e, R6 revised): once a
      message a step sent is delivered, a body line of that step is an
      error at it.

    Only the trace is known here, not the program: a percept type's number of
    slots is the one its first literal has. *)

val check : Trace.header -> (int * Trace.line) list -> (unit, int * string) result
(** [Error (line, message)] at the first line found wrong. *)

val literal_arity : string -> (string * int, string) result
(** The percept type and number of slots of a percept literal ([obstacle]:
    0; [position(0.0, 1.0)]: 2), or why it does not parse. *)
