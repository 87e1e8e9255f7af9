(** Run-time values of Jadescript.

    - [integer] is Java's 32-bit [int]: arithmetic wraps around on overflow, as
      Java's does (docs/semantics.md, "Values"); division truncates towards zero;
    - [float] is IEEE binary32: every operation's result is rounded to binary32;
    - [double] is IEEE binary64;
    - lists and maps are mutable and shared by reference, like Java's; maps keep
      insertion order and compare keys structurally (a percept or a concept can
      be a key: [worldMap[currentPosition] = qrCode], R1c);
    - schema values (concepts, predicates, propositions, actions, percepts) are
      records of slots, compared structurally;
    - [any] values are host objects with named methods (OCaml closures). *)

module Int_table : sig
  type 'a t
  val create : int -> 'a t
  val find_default : 'a t -> int -> 'a -> 'a
  (** The binding of the key, else the default given. *)

  val replace : 'a t -> int -> 'a -> unit
end
(** Hash tables keyed by the structural hash of a value (an int): chained
    buckets in an array of a power of two places, found without a call
    through a functor (what a map look-up does first). *)

type t =
  | Bool of bool
  | Int of int               (** always within -2^31 .. 2^31-1 *)
  | Float of float           (** always a binary32 value *)
  | Double of float
  | Text of string
  | Aid of string            (** an agent identifier: the agent's name *)
  | List of list_v
  | Map of map_v
  | Schema of schema_v
  | Native of native         (** an [any] value *)
  | Agent_ref of string      (** [agent]: the agent, by name *)
  | Behaviour_ref of int     (** [this] in a behaviour: its instance (by a
                                 unique number, not the machine's id) *)
  | Unit                     (** no value: a procedure's or a method's result *)

and list_v = { mutable items : t array; mutable len : int }

and map_v = {
  table : (t * t ref) list Int_table.t;        (** structural hash -> bindings *)
  mutable order : (t * t ref) list;            (** the bindings, newest first *)
  mutable size : int;
}
(** A hash map keyed by structural equality, remembering insertion order. *)

and schema_v = { sname : string; slots : (string * t ref) array }

and native = {
  nid : int;
  cls : string;                              (** shown in messages and traces *)
  methods : (string * (t list -> t)) list;   (** by name *)
}

val int32 : int -> t
(** Wraps an OCaml integer to Java's [int] range. *)

val float32 : float -> float
(** Rounds to the nearest binary32. *)

exception Too_large
(** D37: a comparison or a hash would visit more than {!max_visits} values. *)

val max_visits : int
(** 10,000,000. Every value a comparison ({!compare}, {!equal}) or a hash
    ({!hash}) reaches counts one, each time it is reached (a part shared
    twice counts twice); each call has a budget of its own. A look-up in a
    map ({!map_find}, {!map_set}) is one hash of the key and one comparison
    with each stored key of the same hash. Past the bound the call raises
    {!Too_large}: the evaluator makes it an exhaustion error at the
    operator (docs/semantics.md, D37). *)

val compare : t -> t -> int
(** Structural, with integers, floats and doubles compared by value.
    @raise Too_large past {!max_visits} (D37). *)

val equal : t -> t -> bool

val hash : t -> int
(** Consistent with {!equal}: equal values hash equal (1 and 1.0 included). *)

val list_of : t list -> t
val list_items : list_v -> t list
val map_empty : unit -> t
val map_find : map_v -> t -> t option
val map_set : map_v -> t -> t -> unit
val map_bindings : map_v -> (t * t) list
(** In insertion order. *)

val to_text : t -> string
(** As [log] and text concatenation show it: [3], [2.5], [A7] (text without
    quotes), [position(1.0, 2.0)], [[1, 2]], [{a: 1}], [aid(r)]. *)

val to_literal : t -> string
(** As a Jadescript literal (texts quoted): used in traces. *)

val printed_within : quote:bool -> int -> t -> bool
(** [printed_within ~quote n v]: [to_literal v] ([quote]) or [to_text v]
    is at most [n] bytes long (D21). It stops counting past [n]: its cost
    is bounded by [n], whatever the value shares. *)

val type_name : t -> string
(** For error messages: [integer], [text], [position], ... *)
