(** A growable first-in first-out ring of ints, with a second ring beside it
    for boxed values: the store of the packed agent's waiting percepts
    ({!Packed}). A percept is a record of a few ints (its header and its
    slots) and, when it cannot be written as ints, one boxed value in the
    side ring. Both rings are first in, first out, so the [j]th boxed value
    belongs to the [j]th record that has one.

    Each ring is an array whose length is a power of two, used circularly
    from [head]; it doubles when full (the elements are copied once). A
    ring that has drained can be given back its small array ({!shrink}), so
    that a flood's memory does not stay with the agent once it is idle.

    Nothing is allocated per element except when a ring grows. *)

type 'b t

val create : unit -> 'b t

val length : 'b t -> int
(** Ints in the ring. *)

val boxes : 'b t -> int
(** Boxed values in the side ring. *)

val is_empty : 'b t -> bool
(** No int and no boxed value. *)

val push : 'b t -> int -> unit
(** Add an int at the back. *)

val get : 'b t -> int -> int
(** [get r i]: the [i]th int from the front (0 is the front). Unchecked
    beyond [length]: the caller reads only what it wrote. *)

val drop : 'b t -> int -> unit
(** Remove [n] ints from the front ([n <= length]). *)

val push_box : 'b t -> 'b -> unit
val get_box : 'b t -> int -> 'b
(** The [j]th boxed value from the front. *)

val drop_box : 'b t -> unit
(** Remove the front boxed value. The ring no longer holds it (its place is
    overwritten by a value still in the ring, or by the last one pushed). *)

val shrink : 'b t -> unit
(** When the ring is empty, give back an array of more than 65,536 places
    (the ring starts again small; a smaller one is kept, so that a steady
    run does not grow its rings again after every batch). Does nothing to a ring that is not
    empty. *)

val capacity_words : 'b t -> int
(** Words the ring's two arrays take on the heap, headers included: the
    growth slack counted (the bench's live memory per waiting percept). *)
