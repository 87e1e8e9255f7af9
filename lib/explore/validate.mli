(** Trace validation ([jadescript-ref validate TRACE]): is an interpreter run a
    behaviour of [spec/AgentLoop.tla]?

    For each agent of the trace, the run is projected onto the spec: every
    percept notified becomes its own percept value [n<seq>], every message
    [m<seq>], every object [o<k>]; the model's constants are read off the trace
    (default priorities, the overrides used, the behaviour types with their kinds
    and handlers, which percepts and messages each handler took, and the
    activate/deactivate effects each body had); and the sequence of steps becomes
    a sequence of values of the spec's variable [last] (the action and its
    parameters). A generated module asks TLC for a behaviour of the spec whose
    [last] takes exactly those values in order ([TraceInit], [TraceNext]): TLC
    accepts the trace, or deadlocks at the first step the spec cannot take.

    Limits, checked and reported rather than guessed: an action block must have
    the same effects in every step of its behaviour type; a percept handler's
    [when] must not accept a percept for one instance of a behaviour type and
    reject it for another; a message handler's [when] must not reject a
    message in one step and accept it later (this last one is not detected: the
    spec then rejects the step). *)

type verdict =
  | Accepted of { agent : string; steps : int }
  | Rejected of { agent : string; line : int; step : string; after : int }
      (** the trace line of the first step the spec does not take *)
  | Cannot of { agent : string; line : int; reason : string }

val trace : ?keep:string -> string -> verdict list
(** One verdict per agent of the trace file. [keep]: also write the generated
    modules into that folder.
    @raise Failure on a file that is not a trace (with the line), Tlc.Error *)
