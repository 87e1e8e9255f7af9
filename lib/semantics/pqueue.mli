(** The priority queue of percepts: a persistent bucket queue of entries
    ([percept], effective priority, seq), as [PerceptPriority.tla] specifies.

    Entries leave by priority, highest first, then by seq, smallest first
    (R3b: among equal priorities the first notified is the first handled).
    There is one first-in first-out bucket per priority present. With [k]
    distinct priorities in the queue, [insert] is O(log k) when the entry's seq
    is the largest of its priority (always so in the agent loop, whose seqs
    grow with every notify), O(bucket) otherwise; [pop] is O(log k)
    amortised. The cost per entry does not depend on how many entries wait.
    The state of the queue is the set of its entries: {!to_sorted_list} gives
    that set in one canonical order, so two queues with the same entries built
    in different orders project onto the same TLA+ value. *)

type 'p entry = { p : 'p; prio : int; seq : int }

type 'p t

val empty : 'p t
val is_empty : 'p t -> bool
val size : 'p t -> int

val insert : 'p entry -> 'p t -> 'p t

val insert_newest_first : (('p entry -> unit) -> unit) -> 'p t -> 'p t
(** [insert_newest_first feed q] inserts every entry that [feed] passes to its
    argument, which must come in decreasing seq order (the transfer walks O2A
    from its newest percept). Equal to inserting them one by one in
    increasing seq order; when each priority's entries come after those
    already in [q] (always so in the agent loop) each priority's entries go into
    its bucket in one piece, O(n + r log k) for [n] entries that change
    priority [r] times, without building a queue per entry. *)

val top : 'p t -> 'p entry option
(** The entry DequeueMax takes under the Stable policy: highest priority, then
    smallest seq. *)

val pop : 'p t -> ('p entry * 'p t) option

val first : 'p t -> 'p entry
(** The entry {!top} gives, without an option.
    @raise Invalid_argument on an empty queue. *)

val drop_first : 'p t -> 'p t
(** The queue {!pop} gives, without the pair: the engine's dequeue (one
    record per pop). The empty queue stays empty. *)

val candidates : stable:bool -> 'p t -> 'p entry list
(** The entries a dequeue may take ([Candidates] of PerceptPriority.tla): with
    [stable], those with the highest priority and, among them, the smallest seq
    (one entry unless seqs repeat, as in the flood abstraction); otherwise every
    entry with the highest priority (java.util.PriorityQueue's freedom). *)

val remove : 'p entry -> 'p t -> 'p t
(** The queue without one occurrence of that entry (structurally equal). *)

val mem : 'p entry -> 'p t -> bool
(** O(size of the entry's bucket). *)

val of_runs : (int * 'p entry list * int * int) list -> 'p t
(** [of_runs [(prio, entries, n, last); ...]]: the queue of those entries,
    each [entries] of priority [prio], [n] of them, in seq order, the last
    of seq [last], the priorities distinct: the same queue as inserting
    them one by one. *)

val runs : 'p t -> 'p entry list list
(** The entries, one list per priority, highest priority first, each in
    seq order: the order in which popping them all under stable ties
    (R3b) gives them. *)

val to_sorted_list : 'p t -> 'p entry list
(** Every entry, in dequeue order (priority descending, seq ascending, then by
    [compare] on the percept). O(n log n). *)

val iter : ('p entry -> unit) -> 'p t -> unit
(** In no particular order. *)
