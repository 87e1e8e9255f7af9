(** The priority queue of percepts, as [spec/PerceptPriority.tla] states it:
    a set of entries (percept, effective priority, seq).

    The entries are kept in the order R3b takes them: the highest priority
    first and, among equal priorities, the smallest seq (the first notified
    is the first handled). They are the bindings of a map whose keys are
    [(priority, seq)] in that order, so that the entry Dequeue takes under
    the stable policy is the map's first binding; every operation is
    O(log n). Two queues holding the same entries are the same value
    ({!to_sorted_list}), as two equal sets are for TLC.

    This is the reference's queue, plain on purpose; the fast engine
    (lib/engine) reads and builds it through these operations only. *)

type 'p entry = { p : 'p; prio : int; seq : int }

type 'p t

val empty : 'p t
(** [EmptyQueue]. *)

val is_empty : 'p t -> bool
val size : 'p t -> int

val insert : 'p entry -> 'p t -> 'p t
(** [Enqueue(Q, e)]. An entry equal to one already there (only the flood
    abstraction of the spec makes such entries: every seq is 0) is added
    again; the machine merges them as the spec does before inserting. *)

val top : 'p t -> 'p entry option
(** The first entry in R3b's order: what Dequeue takes under the stable
    policy. *)

val pop : 'p t -> ('p entry * 'p t) option
(** {!top} and the queue without it. *)

val candidates : stable:bool -> 'p t -> 'p entry list
(** [Candidates(Q, TiePolicy)], the entries a Dequeue may take: [stable]
    (R3b), the entries of highest priority and, among them, smallest seq
    (one entry unless seqs repeat, as in the flood abstraction); otherwise
    every entry of the highest priority (java.util.PriorityQueue's
    freedom). *)

val remove : 'p entry -> 'p t -> 'p t
(** [DequeueMax(Q, e)]: the queue without one occurrence of the entry
    (structurally equal); the queue itself when it has none. *)

val mem : 'p entry -> 'p t -> bool

val to_sorted_list : 'p t -> 'p entry list
(** Every entry in dequeue order (priority descending, seq ascending, then
    by [compare] on the percept). *)

val fold : ('a -> 'p entry -> 'a) -> 'a -> 'p t -> 'a
(** Over the entries in dequeue order. *)
