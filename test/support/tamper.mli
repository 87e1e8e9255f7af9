(** Tampered traces: ways to spoil a valid trace so that
    [jadescript-ref validate] must reject it (D25; docs/trace-format.md,
    "What validate checks"). Used by test/validate and by the fuzz campaign.

    Each kind of tampering makes the trace truly invalid, or does not apply:
    a change that could leave a valid trace (swapping two host notifications
    of different agents, dropping the last percept nobody dequeued) is never
    made. A tampering that moves, drops or adds lines renumbers the steps
    1, 2, 3..., so that the fault it plants is the only one. *)

type t = { name : string;
           apply : Random.State.t -> string list -> string list option }
(** [apply rng lines]: the lines of a valid trace (header first, as text) ->
    the lines of a tampered trace that validate must reject, or [None] when this
    kind of tampering does not apply to that trace. *)

val all : t list
(** Every kind, each with a distinct [name]: the header (version 99, a text
    version, none, an unknown variant or tie policy, an agent type that is not
    its create's, an agent twice, capacity 0, a default priority changed), the literals (a dequeue, handle,
    deliver or behaviour step carrying another percept, priority, content or
    seq than notified, dequeued or sent), the messages (a delivery before its
    send or before its receiver exists, an undeliverable message to an agent
    that exists), the agents (an event of an agent not in the header, a step
    after destroy, a create of another type), the O2A queue (refused, notify
    or put, while it has room or is unbounded), the format (a line cut short
    or with invalid UTF-8, an unknown event,
    an unknown field, [moved] as ["zero"] or [1e30], a text seq, a huge or
    negative priority, a wrong action), the steps (decreasing, swapped loop
    steps, a duplicated or dropped line where that must show). *)

val tlc_only : string list
(** The kinds only TLC can see (the order of one agent's loop steps): every
    other kind is caught by the OCaml checks ([Explore.Validate.check]),
    before TLC runs. *)
