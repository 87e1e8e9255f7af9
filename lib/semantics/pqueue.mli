(** The priority queue of percepts: a persistent pairing heap of entries
    ([percept], effective priority, seq), as [PerceptPriority.tla] specifies.

    The heap is ordered by priority, highest first, then by seq, smallest first
    (R3b: among equal priorities the first notified is the first handled).
    [insert] is O(1), [pop] O(log n) amortised. The state of the queue is the set
    of its entries: {!to_sorted_list} gives that set in one canonical order, so
    two heaps with the same entries but different shapes project onto the same
    TLA+ value. *)

type 'p entry = { p : 'p; prio : int; seq : int }

type 'p t

val empty : 'p t
val is_empty : 'p t -> bool
val size : 'p t -> int

val insert : 'p entry -> 'p t -> 'p t

val top : 'p t -> 'p entry option
(** The entry DequeueMax takes under the Stable policy: highest priority, then
    smallest seq. *)

val pop : 'p t -> ('p entry * 'p t) option

val candidates : stable:bool -> 'p t -> 'p entry list
(** The entries a dequeue may take ([Candidates] of PerceptPriority.tla): with
    [stable], those with the highest priority and, among them, the smallest seq
    (one entry unless seqs repeat, as in the flood abstraction); otherwise every
    entry with the highest priority (java.util.PriorityQueue's freedom). *)

val remove : 'p entry -> 'p t -> 'p t
(** The queue without one occurrence of that entry (structurally equal). *)

val mem : 'p entry -> 'p t -> bool
(** O(n). *)

val to_sorted_list : 'p t -> 'p entry list
(** Every entry, in dequeue order (priority descending, seq ascending, then by
    [compare] on the percept). O(n log n). *)

val iter : ('p entry -> unit) -> 'p t -> unit
(** In no particular order. *)
