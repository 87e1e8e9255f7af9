(** TLA+ values, as TLC prints them and as the models write their constants.

    The explorer and TLC meet here: both sides' states are turned into these
    values and printed canonically ({!to_string}: record fields sorted by name,
    set elements sorted and unique), so that equal states print equal. *)

type t =
  | Int of int
  | Str of string
  | Bool of bool
  | Seq of t list                (** [<<a, b>>], also tuples *)
  | Set of t list                (** [{a, b}]; canonical: sorted, no repeats *)
  | Rec of (string * t) list     (** [[f |-> v, ...]]; canonical: sorted fields *)
  | Fn of (t * t) list           (** [(k :> v @@ ...)]; canonical: sorted keys *)

val set : t list -> t
val record : (string * t) list -> t
(** Canonical constructors. *)

val to_string : t -> string
(** TLA+ syntax. Canonical when the value is. *)

val compare : t -> t -> int

exception Parse_error of string

val parse : string -> t
(** Parses a value: integers, strings (TLA+ escapes), [TRUE], [FALSE],
    [<<...>>], [{...}], [[f |-> v, ...]], [(k :> v @@ ...)]. The result is
    canonical. @raise Parse_error *)

val parse_prefix : string -> int -> t * int
(** [parse_prefix s i] parses a value starting at [i], returning it and the index
    after it. @raise Parse_error *)

(** {1 Accessors} (each raises [Invalid_argument] on the wrong shape) *)

val field : string -> t -> t
val to_int : t -> int
val to_str : t -> string
val to_bool : t -> bool
val to_list : t -> t list
(** The elements of a sequence or a set. *)
