(** The agent that runs the paper's Jadescript program on jadescript-ref:
    [examples/robome/robome.jade] (the RoboMe agent and its HandlePercepts
    behaviour, Figures 5-7, completed), interpreted by {!Interp} on
    {!Semantics.Machine}, controlling the simulated robot through its host
    object. This is the agent of [jadescript-ref sim] and [make demo]; the
    OCaml {!Reference_controller} mirrors it for comparison. *)

val program : unit -> string
(** The program's path: [examples/robome/robome.jade], found from the current
    directory upwards. *)

val make : ?program:string -> unit -> (module Agent.AGENT)
(** The agent module for a program (default {!program}): it must declare the
    RoboMeApplication percepts and an agent [RoboMe] whose [on create] takes
    the host object [as any]. Parsed and type-checked once.
    @raise Failure with the diagnostics when the program does not check. *)

val make_logged : ?program:string -> unit -> (module Agent.AGENT) * (unit -> Reference_controller.label list)
(** The same agent, recording its machine labels (host notifications and agent
    steps) with the percepts in the simulation's terms: the second result
    returns the labels of the last agent created, in order, for
    {!Trace_check.check} (TLC validation of a simulation run). *)
