(** How the interpreter's percepts ({!Interp_eval.Value.t}) are packed into
    ints for the packed agent ({!Packed}).

    A percept that is a schema value whose slots all hold an [integer], a
    [boolean] or a [text] (at most 3 texts; e.g. [position(3)], [falling],
    [qrCodeRead("A7")]) is written as one int per integer or boolean slot,
    and each text as a box: the slot's [Text] value itself, which nothing
    can change. Its tag stands for its schema name, its slot names and how
    each slot is written, interned per agent (kind 1 for the first such
    kind seen, 2 for the next, ... at most 1,023 kinds of at most 255 int
    slots; after that, boxed whole). Reading it back builds a fresh schema
    value, equal to the one notified (same schema name string, same slot
    names, [Int], [Bool] and [Text] as they were). Any other percept (a
    float or a double, a nested value, a list, a map, a host object...) has
    the kind 0 and travels boxed whole, as it is, in the side ring.

    A fresh value cannot be told from the notified one: the host of
    [jadescript-ref] builds a new value per notify and keeps none, and
    nothing in the agent has the notified value before Dequeue gives the
    decoded one to the handlers (all handlers of one dispatch get the same
    value, as in the reference; a handler that sets [k of content] changes
    that value only). A host that changed a value after notifying it, or
    notified one value twice and then looked at it, could tell: the packed
    agent is not for such a host (D32). *)

include Packed.CODEC with type percept = Interp_eval.Value.t

val kinds : t -> int
(** Kinds of packed percepts interned so far. *)
