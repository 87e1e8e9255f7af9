(** The interpreter's bodies with percept handlers compiled (D38).

    Each percept handler (its [when] guard and its body) is compiled once,
    per behaviour type and agent type, to OCaml closures, and those run
    instead of walking the tree:
    - a pattern variable or a local is a numbered slot of a small array
      (a local that has no value yet falls back to what {!Interp_eval.Eval.lookup}
      answers: the property, the schema without slots, or the error);
    - a property the code names is its cell, found once per behaviour
      instance (the behaviour's, then the agent's);
    - a literal is its value; the choice between statements and between
      expressions is made at compile time.
    Every rule that computes a value, raises an error or counts the step
    budget is {!Interp_eval.Eval}'s own (arithmetic, comparisons, patterns,
    map updates within D21/D37, [tick] with D22's memory check), in the
    order Eval applies them, so that the world afterwards, the events (logs,
    errors with their kind, region and message, [Ran] with its effects) and
    the point where the budget runs out are those of {!Interp_eval.Eval.Bodies}.

    A call of the behaviour's or the agent's own function or procedure
    ([do p with ...], [f(...)]) runs the callee compiled too: each callee is
    compiled once per handler (memoised, so recursion finds it), its
    parameters and locals in slots of its own while it runs (the caller's
    are put back however it ends), with Eval.run_routine's order: the
    arguments, a tick at the call, the depth against
    {!Interp_eval.Eval.max_call_depth}, the arguments against the
    parameters, then the body; an agent's routine sees the agent's
    properties only, as Eval's frame without behaviour does. [invoke],
    [activate] and [send] are compiled with Eval's rules
    ({!Interp_eval.Eval.invoke_values}, {!Interp_eval.Eval.activate_at}).

    What it does not compile — a call or an [invoke] in a [when] guard (the
    guard's step budget is not renewed by the entry points), [message] —
    makes that handler, whole, run on {!Interp_bodies} (its resolved guard
    and pre-test). Message handlers and action blocks are {!Interp_bodies}'
    too.

    The guard's bindings wait for the body as in the reference (R3b), and
    only while no other guard, compiled or not, has been evaluated since: a
    count of the guards evaluated tells (D38), not the agent's [pending]
    frame, which a compiled guard leaves empty; otherwise the body starts
    in fresh locals, as the reference's would. Percept kinds are
    {!Interp_bodies}' (a number per schema name). *)

include Fast.BODIES
  with type percept = Interp_eval.Value.t
   and type message = Interp_eval.Eval.message
   and type obj = Interp_eval.Value.t
   and type beh = Interp_eval.Eval.beh
   and type world = Interp_eval.Eval.agent

val compiled_handlers : world -> id:int -> beh -> int
(** How many of the instance's percept handlers run compiled (the others
    fall back): for tests and the bench. *)
