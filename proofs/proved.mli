(** The agent loop proved in Coq ([proofs/Loop.v]), extracted to OCaml by
    [proofs/Extract.v] at build time: the same rules as
    {!Semantics.Machine} (the twin of [spec/AgentLoop.tla]), on the spec's
    abstraction of handlers ({!Proved_loop.bodies}: acceptance and
    activate/deactivate effects, no world). The theorems of docs/proofs.md
    are about exactly these functions; test/proofs holds {!Proved_loop.step}
    and the host rules equal to [Machine.step] and the machine's host rules
    on every state of every model of spec/models and on random runs beyond
    them.

    Numbers are OCaml ints (the proofs' natural numbers, docs/proofs.md,
    "What is trusted"); lists are plain lists; the priority queue is a list
    whose order means nothing (a multiset of entries, as the spec's set). *)

module Loop = Proved_loop
(** Every definition of [proofs/Loop.v]: the types ([config], [label],
    [params], [bodies], ...), the host rules ([init], [notify],
    [notify_with], [notify_event], [put], [send], [o2a_has_room]), the agent
    rules ([transfer], ..., [idle]) and [step], their disjunction (AgentStep).
    Each function takes the percepts' equality and the bodies first, as the
    Coq section that defines it does. *)
