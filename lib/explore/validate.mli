(** Trace validation ([jadescript-ref validate TRACE]): is an interpreter run a
    behaviour of [spec/AgentLoop.tla]?

    First, in OCaml, over the whole trace: the strict reading of the format
    ([Trace.read_located]) and the facts that the per-agent projection below
    cannot see ({!Trace_check}: agents, step numbers, literals, messages across
    agents, the O2A capacity; then {!Trace_more}: bodies against their
    steps' effects, percept literals parsed). Then TLC, agent by agent:

    For each agent of the trace, the run is projected onto the spec: every
    percept notified becomes its own percept value [n<seq>], every message
    [m<seq>], every object [o<k>]; the model's constants are read off the trace
    (default priorities, the overrides used, the behaviour types with their kinds
    and handlers, which percepts and messages each handler took, and the
    activate/deactivate effects each body had); and the sequence of steps becomes
    a sequence of values of the spec's variable [last] (the action and its
    parameters). Only these data are generated: a module holding them as
    constants ([TraceLog]) extends the checked-in trace spec
    [spec/AgentLoopTrace.tla], whose predicates (one per kind of trace line)
    ask TLC for a behaviour of the spec whose [last] takes exactly those values
    in order ([TraceInit], [TraceNext]): TLC accepts the trace, or deadlocks at
    the first step the spec cannot take.

    Limits, checked and reported rather than guessed: an action block must have
    the same effects in every step of its behaviour type; a percept handler's
    [when] must not accept a percept for one instance of a behaviour type and
    reject it for another; a message handler's [when] must not reject a
    message in one step and accept it later (this last one is not detected: the
    spec then rejects the step). *)

type verdict =
  | Accepted of { agent : string; steps : int; total : int }
      (** TLC follows the agent's first [steps] steps of its [total] in
          the trace (all of them when the trace is within the window) *)
  | Rejected of { agent : string; line : int; step : string; after : int }
      (** the trace line of the first step the spec does not take *)
  | Cannot of { agent : string; line : int; reason : string }
  | Invalid of { line : int; message : string }
      (** not a trace of version 1 or 2 (the reader of [Trace]), or a fact TLC does not see is wrong: the
          strict reading of [Trace.read_located] and the checks of
          {!Trace_check} (agents, steps, literals, messages across agents, the
          O2A capacity), made before TLC runs *)

val default_window : int
(** 300: the steps of each agent TLC follows by default (docs/trace-format.md,
    "Long traces: the window"). *)

val trace : ?keep:string -> ?window:int -> ?on_cut:(string -> int -> unit) -> string -> verdict list
(** The trace file is read and checked in OCaml; if it is [Invalid], that is
    the one verdict; otherwise one verdict per agent, from TLC. [keep]: also
    write the generated modules into that folder. [window] (default
    {!default_window}; 0 or less: no bound): TLC follows only the first
    [window] steps of each agent, from the spec's initial state, with the
    constants read off those lines; the OCaml checks above still read the
    whole trace. A last line with no
    newline that is not JSON (a run killed while it wrote it) is left out,
    the lines before it are checked, and [on_cut path line] is called with
    its number.
    @raise Tlc.Error when TLC itself fails (a one-line message) *)

val traces : ?keep:string -> ?window:int -> ?on_cut:(string -> int -> unit) -> string list -> (string * verdict list) list
(** {!trace} of several files, with one TLC run for every agent of every
    trace that passes the OCaml checks: each agent an instance of the trace
    spec (its own constants, steps and variables) in one generated module
    [TraceCheckAll], checked one after another, so that one JVM start serves
    them all; after a rejection, one more run for the agents after it. [keep]
    gets [TraceCheckAll.tla] (or, for a single agent, its [TraceCheck] module
    and cfg, named after the agent). *)

val check : string -> (unit, int * string) result
(** Only the OCaml part of {!trace}: the strict reading (a cut last line left
    out, as by {!trace}) and {!Trace_check};
    [Error (line, message)] as {!Invalid}. No TLC (fast: the fuzz campaign's
    first filter). *)
