(** The interpreter's bodies with percept handlers compiled (D38): the
    fast engine's twin of {!Interp_eval.Eval.Bodies}.

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
    order Eval applies them, so that the agent afterwards, the events (logs,
    errors with their kind, region and message, [Ran] with its effects) and
    the point where the budget runs out are those of {!Interp_eval.Eval.Bodies}.

    A call of the behaviour's or the agent's own function or procedure
    ([do p with ...], [f(...)]) runs the callee compiled too: each callee is
    compiled once per handler (memoised, so recursion finds it), its
    parameters and locals in slots of its own while it runs (the caller's
    are put back however it ends), with Eval's order: the arguments, a tick
    at the call, the depth against the config's [max_call_depth] (D18), the
    arguments against the parameters, then the body; an agent's routine
    sees the agent's properties only, as Eval's frame without behaviour
    does. [invoke], [activate] and [send] are compiled with Eval's rules.

    What it does not compile — a call or an [invoke] in a [when] guard, the
    [message] of a message — makes that handler, whole, run on
    {!Interp_eval.Eval.Bodies}. Message handlers and action blocks are
    Eval's too.

    The guard's bindings go to the body as the reference's do (R3b):
    copied from the slots into the bindings the machine hands the body
    ({!Make.percept_applicable}, {!Make.run_percept_handler}), or kept in
    the slots when the guard and the body run in one call
    ({!Make.percept_handle}).

    The engine's state for one agent (the handlers compiled, a context per
    behaviour instance, the pre-test's answers) is the functor's: apply
    {!Make} once per agent. test/fastpath holds it equal to the reference
    on random programs. *)

type bindings
(** What a guard hands its body: a compiled guard's slots, or the
    reference's bindings for a handler that falls back. *)

module Make () : sig
  include Fast.BODIES
    with type percept = Interp_eval.Value.t
     and type message = Interp_eval.Eval.message
     and type obj = Interp_eval.Value.t
     and type beh = Interp_eval.Eval.beh
     and type world = Interp_eval.Eval.agent
     and type bindings = bindings

  val compiled_handlers : world -> id:int -> beh -> int
  (** How many of the instance's percept handlers run compiled (the others
      fall back): for tests and the bench. *)
end
