(** Persistent first-in first-out queues (a front list and a reversed back
    list): the O2A queue and the message queue of an agent. Every operation is
    amortised O(1) except those that say otherwise. *)

type 'a t

val empty : 'a t
val is_empty : 'a t -> bool
val length : 'a t -> int
(** O(1). *)

val push : 'a -> 'a t -> 'a t
(** Add at the back. *)

val peek : 'a t -> 'a option
(** The front element. *)

val pop : 'a t -> ('a * 'a t) option

val first : 'a t -> 'a
(** The front element, as {!peek} gives it, without an option.
    @raise Invalid_argument on an empty queue. *)

val drop : 'a t -> 'a t
(** The queue without its front element (the empty queue stays empty): the
    queue of {!pop} without the pair, for the engine's dequeue, which
    allocates nothing else per percept. *)

val to_list : 'a t -> 'a list
(** Front first. O(n). *)

val of_list : 'a list -> 'a t

val of_list_length : 'a list -> int -> 'a t
(** [of_list_length l n]: [of_list l], [l] being [n] elements long (not
    counted again). *)

val append : 'a list -> 'a t -> 'a t
(** [append l q] adds the elements of [l] at the back, the head of [l] first.
    O(length of [l]). *)

val partition : ('a -> bool) -> 'a t -> 'a list * 'a t
(** [partition f q] is the elements satisfying [f], front first, and the queue
    of the others in their order. O(n). *)

val remove_first : ('a -> bool) -> 'a t -> ('a * 'a t) option
(** The first element satisfying the predicate, and the queue without it.
    O(position). *)

val exists : ('a -> bool) -> 'a t -> bool
val fold : ('acc -> 'a -> 'acc) -> 'acc -> 'a t -> 'acc
(** Front to back. *)

val fold_newest : ('acc -> 'a -> 'acc) -> 'acc -> 'a t -> 'acc
(** Back to front: the newest element first. Allocates nothing for the
    elements pushed since the last {!pop}. *)
