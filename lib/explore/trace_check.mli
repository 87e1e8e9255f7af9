(** The checks of a whole trace that [jadescript-ref validate] makes in OCaml,
    before and beside TLC (docs/trace-format.md, "What validate checks").

    TLC checks each agent alone against [spec/AgentLoop.tla], with every
    percept, object and message projected to a name ([n3], [o1], [m2]). What
    that projection cannot see is checked here, over all agents at once and in
    trace order:

    - the agents: every event names an agent of the header; each is created
      once, in the header's order, with the header's type; nothing happens to
      an agent before its [create] or after its [destroy] (only the events of
      its [on destroy] body);
    - the steps: numbered 1, 2, 3... in file order; an event inside a step
      names the action of its agent's last step;
    - the literals: a [notify] of a percept type of the header, with its
      default priority unless overridden, seqs 1, 2, 3... per agent (R2b); a
      [put] index 1, 2, 3... per agent; a [dequeue] (and [transfer_one], and in
      [native] a percept taken by a behaviour step) carries exactly the
      percept and priority notified with that seq, once; a [handle] the
      percept being dispatched, and no other loop step comes between a
      [dequeue] and the [end_dispatch] or [discard] of its dispatch; a
      behaviour step's message exactly the message delivered with that seq,
      once;
    - the messages across agents (R5e): a [deliver] to B from agent A needs an
      earlier [send] by A naming B, with the same performative and content,
      and deliveries to B follow the order of the sends to B; a message to an
      agent that does not exist is [undeliverable] on its sender's line, after
      that send; seqs 1, 2, 3... per receiver; a complete trace (every agent
      destroyed) leaves no sent message undelivered;
    - the O2A queue (R2d, D6): [refused] only when the queue is full under the
      header's capacity, and never with an unbounded one; no notify or put
      beyond the capacity;
    - the variant: [transfer_one], [transfer_spin], [transfer_end] only in
      [printed]; a percept taken by a behaviour step only in [native];
    - every behaviour named (created, activated, in effects) is in the header;
      agent names are distinct and none is [host]. *)

val check : Trace.header -> (int * Trace.line) list -> (unit, int * string) result
(** [check header lines], with each line's number in the file: [Ok ()], or
    the first bad line and what is wrong with it. *)
