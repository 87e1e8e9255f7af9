(** The packed agent: one agent's loop, as {!Fast}, with its waiting
    percepts kept as ints instead of a queue of boxed entries.

    The reference configuration ({!Semantics.Machine.config}) keeps every
    notified percept as an entry [{p; prio; seq}] in a cell of the O2A queue,
    then in a bucket of the priority queue: in a flood of millions of
    percepts, every one of them is a few small blocks on the heap, which the
    collector promotes and marks again and again. The packed agent keeps
    them in rings of ints ({!Ring}, below):
    - the buckets, one per priority present, highest first (there are
      few): one record per waiting percept, [seq_tag; slots...] (the seq
      and the codec's tag in one int), in the order notified: first those
      of the priority queue (Transfer moved them there: how many is
      counted), then those still in O2A. A notify writes its record at the
      back of its priority's bucket at once, and Transfer moves nothing: it
      counts every bucket's records as the priority queue's (R3a). Within a
      bucket, oldest first (R3b, stable ties);
    - a percept of one integer slot of 32 bits (D8), such as [position(3)],
      or of no slot, such as [falling], is a record of one int, a {e word}
      (D39): the slot's int, the kind and the seq less the bucket's first
      share it. A seq too far from its bucket's first for a word gives the
      long record;
    - objects put into O2A (R2c) stay in the configuration's [o2a], each with
      the seq of the last percept notified before it, so that the reference's
      O2A queue can be rebuilt in its order.

    How a percept becomes ints is the {!CODEC}'s business. What the packed
    agent does itself: the host's notify and put (R2a-R2d, capacity counting
    O2A's records and the objects), Transfer (R3a: O2A's records counted in
    the priority queue, nothing moved or allocated) and Dequeue (R3b: the
    highest non-empty bucket's oldest record, decoded into the entry the
    handlers see), and the derived rule Dispatch through
    {!Fast.Make.dispatch_entry}. Every other rule (Handle, Skip,
    EndDispatch, BehaviourStep, NextIteration, Idle) reads of O2A and the
    priority queue only whether they hold a percept: it is taken by
    {!Fast.Make.step} on a view of the configuration where the O2A queue
    holds the objects and at most the first waiting percept, and the
    priority queue at most its top (one record decoded), and it changes
    neither.

    Packed mode is used only where it is simple: the [Reference] and
    [Budgeted] variants, stable ties, no flood abstraction, no ghosts
    ({!packable}). Elsewhere the agent keeps the plain configuration and
    every rule is {!Fast}'s.

    Seqs, [next_seq], [dispatched] and [last] are exactly the reference's;
    {!to_config} gives the reference's configuration (test/fastpath holds
    it equal, after every host operation and every rule, on random
    programs). A run of notifies writes no configuration: the fields they
    change ([next_seq], an idle agent's phase, [last]) are written when
    the configuration is next read. The handlers get a fresh percept equal
    to the notified one (D32). docs/semantics.md, "The packed agent". *)

(** A growable first-in first-out ring of ints, with a second ring beside it
    for boxed values: the store of the packed agent's waiting percepts
    ({!Packed}). A percept is a record of a few ints (its header and its
    slots) and, for what cannot be written as ints, boxed values in the
    side ring. Both rings are first in, first out, so a record's boxes
    follow those of the records before it.

    The ints are in {e chunks} of a fixed size (65,536 ints by default), each
    a [Bigarray] outside the OCaml heap: a ring grows by a chunk at its
    back, and nothing written is ever copied; a chunk read to its end
    leaves the ring. Chunks come from a {!pool} and go back to it, shared
    by the rings of one agent: the chunks a bucket has emptied are taken by
    the next bucket to grow, so that the agent's percepts are in memory
    about once (D39). The boxed values are in chunks too,
    ordinary arrays of a 64th of that length (1,024 by default), made when
    needed and left to the collector once read to their end. A ring that
    has drained gives its chunks back ({!shrink}), and a pool keeps at most
    8 of them, so that a flood's memory does not stay with the agent once
    it is idle.

    Nothing is allocated per element except when a ring takes a chunk that
    its pool does not have, or a chunk of boxes. *)
module Ring : sig
  type pool
  (** Chunks of one size, free for the rings made with the pool. *)

  val default_chunk : int
  (** 65,536 ints. *)

  val pool : ?chunk:int -> unit -> pool
  (** A pool of chunks of [chunk] ints (default {!default_chunk}; small
      ones in tests, so that rings cross chunks often).
      @raise Invalid_argument unless [chunk] is a power of two. *)

  val free_chunks : pool -> int
  (** Chunks waiting in the pool (at most 8). *)

  val pool_offheap_words : pool -> int
  (** Words of the chunks waiting in the pool. *)

  val made : pool -> int
  (** Chunks the pool has made so far (the others it gave were used
      again). *)

  type 'b t

  val create : ?pool:pool -> unit -> 'b t
  (** An empty ring, its chunks taken from [pool] (default: a pool of its
      own, of {!default_chunk}). It takes no chunk before its first int. *)

  val chunks : 'b t -> int
  (** Chunks the ring holds. *)

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

  val set : 'b t -> int -> int -> unit
  (** [set r i x]: the [i]th int from the front becomes [x] ([i < length]). *)

  val drop : 'b t -> int -> unit
  (** Remove [n] ints from the front ([n <= length]); a chunk read to its
      end goes back to the pool. *)


  val push_box : 'b t -> 'b -> unit
  val get_box : 'b t -> int -> 'b
  (** The [j]th boxed value from the front. *)

  val drop_box : 'b t -> unit
  (** Remove the front boxed value. Its chunk still holds it until the
      chunk is read to its end or the ring drains ({!shrink}): at most a
      chunk's worth of values removed is kept alive so. *)

  val shrink : 'b t -> unit
  (** When the ring is empty, give its chunks back to the pool and leave its
      chunks of boxes to the collector. Does nothing to a ring that is not
      empty. *)

  val heap_words : 'b t -> int
  val offheap_words : 'b t -> int
  (** Words the ring takes on the OCaml heap (its record, its array of
      chunks and their blocks, its chunks of boxes), and outside it (its chunks:
      [Bigarray]s, which the collector neither copies nor scans), the free
      places of its last chunk included. *)
end

(** {1 Tags}

    A percept's {e tag} says how it is written: the codec's own number for
    its kind (0 to 1,023), how many ints it takes after the record's header
    (its width, 0 to 255) and how many boxed values it has in the side ring
    (0 to 3). It is one int of 20 bits, made by {!make_tag}; the packed
    agent reads the width and the boxes from it without asking the codec. *)

val make_tag : kind:int -> width:int -> boxes:int -> int
(** @raise Invalid_argument outside the ranges above. *)

val boxed_tag : int
(** The tag of a percept that travels boxed, as it is, in the side ring
    (kind 0): the codec's for what it cannot pack, and the agent's for a
    percept notified while few wait. *)

val tag_kind : int -> int
val tag_width : int -> int
val tag_boxes : int -> int

val word_tag : int -> bool
(** Whether a word can stand for a percept of this tag (D39): width 1
    (one int slot) or 0 (no slot), no box, kind 1 to 15. *)

(** How a percept is written as ints. A percept is given a tag, then
    written as [tag_width tag] ints and [tag_boxes tag] boxed values in the
    side ring. Reading it back must give a percept equal to
    the one written (a fresh one is fine when nothing can tell them apart:
    see {!Percept_codec}). *)
module type CODEC = sig
  type percept

  type t
  (** The codec's own state (e.g. the tags it has given, per agent). *)

  val create : unit -> t

  val encode : t -> percept -> percept Ring.t -> int
  (** [encode c p r]: push the percept's ints and boxes onto [r] and
      answer its tag ({!make_tag}: [tag_width tag] ints and [tag_boxes tag]
      boxes were pushed); the kind is given once per kind of percept (e.g.
      per schema whose slots are all integers). *)

  val read : t -> int -> percept Ring.t -> pos:int -> box:int -> percept
  (** [read c tag r ~pos ~box]: the percept of this tag whose ints start at
      [pos] in [r] and whose boxes (if any) start at the [box]th boxed
      value. *)

  val encode_one : t -> percept -> int
  (** [encode_one c p]: when the percept's tag is of width 1 and no box (one
      integer or boolean slot) and its int [v] is a 32-bit integer (D8),
      [(v lsl 20) lor tag], pushing nothing; when it is of width 0 (a
      schema of no slot), [tag]; [0] otherwise. The packed
      agent writes it as a word when {!word_tag} (D39), and else asks
      {!encode}. *)

  val read_int : t -> int -> int -> percept
  (** [read_int c tag v]: the percept of a tag of width 1 and no box whose
      one int is [v]: what {!read} gives when that int is in the ring (the
      packed agent keeps such a percept in a word, D39); for a kind of no
      slot (the word's tag then says width 1 all the same), the percept of
      that kind, [v] being 0. *)
end

module Make (B : Fast.BODIES) (_ : CODEC with type percept = B.percept) : sig
  module F : module type of Fast.Make (B)
  module M = F.M

  type t
  (** A mutable agent, owned by the one loop that runs it. *)

  val packable : Semantics.Machine.params -> bool
  (** Variant [Reference] or [Budgeted], stable ties, no flood abstraction,
      no ghosts. *)

  val default_pack_above : int
  (** 4,096. *)

  val of_config : ?pack_above:int -> ?chunk:int -> ?word_x_limit:int ->
    Semantics.Machine.params -> M.t -> t
  (** The agent, its percepts packed when {!packable} (the priority
      queue's percepts into the buckets, then O2A's behind them) once at least
      [pack_above] (default {!default_pack_above}) percepts and objects
      wait in O2A and the priority queue: before that the agent is plain
      (the configuration's own queues, every rule [Fast]'s), and it is
      plain again when nothing waits. Encoding and decoding only pay where
      the collector would otherwise promote a backlog: a steady run with
      1,024 in flight packs nothing; a flood packs all but its first 4,096.
      [~pack_above:0] packs at once and stays packed. The rings' chunks
      have [chunk] ints ({!Ring.pool}). A record is a word (D39) only when
      its priority, or in a bucket its seq less the bucket's first, is
      below [word_x_limit] (default and at most 2{^26}; smaller in tests,
      so that the long form is taken).
      @raise Invalid_argument when packable and O2A's percepts are not the
      last ones notified, in order (no run of these variants reaches such
      a configuration). *)

  val to_config : t -> M.t
  (** The reference's configuration: the rings decoded into [o2a] and [pq]
      in the reference's order (objects among percepts where they were put).
      O(waiting percepts). *)

  val params : t -> Semantics.Machine.params
  val packed : t -> bool
  (** Whether the percepts are packed now: {!packable} of the params, and
      a backlog reached [pack_above] and has not drained since. *)

  val waiting : t -> int
  (** Percepts in O2A and in the priority queue. *)

  val phase : t -> Semantics.Machine.phase
  val last : t -> M.lbl
  val world : t -> B.world

  val ring_ints : t -> int
  (** Ints in the buckets (one per word, D39): for tests. *)

  val chunks_made : t -> int
  (** Chunks its rings' pool has made so far: for tests. *)

  val offheap_words : t -> int
  (** Words the rings' chunks take outside the OCaml heap (the free places
      of their last chunks and the pool's free chunks included), which [Gc]
      does not count: the bench adds them to the live words it sees. *)

  (** {2 Host rules} *)

  val o2a_has_room : t -> bool
  (** R2d: the percepts in O2A and the objects count. *)

  val notify_event : t -> B.percept -> default:int -> priority:int option ->
    (unit, Semantics.Machine.refusal) result
  (** {!Semantics.Machine.Make.notify_event}: refused (nothing changes) with
      a negative priority (R2a) or a full O2A queue (R2d). *)

  val notify : t -> B.percept -> int -> unit
  (** Notify with the type's default priority; the caller checked
      {!o2a_has_room}. *)

  val notify_with : t -> B.percept -> int -> unit
  (** NotifyWith: the priority given (a natural number, R2a). *)

  val put : t -> B.obj -> unit
  (** Put (R2c); the caller checked {!o2a_has_room}. *)

  val send : t -> B.message -> unit
  (** Send (R5e). *)

  (** {2 Agent rules} *)

  val step : t -> M.lbl option
  (** Takes the first rule {!Semantics.Machine.Make.step} lists (under
      stable ties there is one), as that rule does; [None] (nothing
      changes) when no rule is enabled. *)

  val dispatch : ?observe:(M.lbl -> B.world -> B.world) -> t -> bool
  (** The derived rule Dispatch ({!Fast.Make.dispatch}): [true] when it
      was taken, [false] (nothing changes) where {!Fast.Make.dispatch}
      answers [None]. *)

  val dispatch_run : ?max:int -> t -> int
  (** {!dispatch}, unobserved, while it is enabled from phase Dispatch, at
      most [max] times ({!Fast.Make.dispatch_run} on the plain agent,
      {!Fast.Make.dispatch_from} on the rings): how many percepts left;
      [0] (nothing changes) where it is not enabled. *)
end
