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

val string_literal : string -> string
(** A string as a TLA+ string literal, quoted: the one writer of TLA+
    strings ({!to_string}, and through it every module and constant the
    project generates). A quote, a backslash, line feed, tab, carriage
    return and form feed are written as a backslash followed by the quote,
    the backslash, n, t, r or f, the escapes TLC reads; TLC's lexer has no
    other escape. Every other ASCII byte but the backtick is written as it
    is, and TLC 2.18 reads it as itself (control characters and NUL
    included). TLC cannot read the rest, and there is no escape for them:
    a backtick opens a region that runs to the next single quote, even
    across strings, so that the module means something else; UTF-8 it reads
    as Unicode but refuses many characters (U+0100, U+4E2D, U+2028, any
    beyond the BMP); a byte that is not UTF-8 it reads as U+FFFD.
    @raise Invalid_argument on a backtick or a byte beyond ASCII (the
    strings the project writes are generated names and Jadescript names,
    which are ASCII without backticks). Tested against TLC (test/semantics,
    TLA+ strings: TLC reads them back). *)

val compare : t -> t -> int

exception Parse_error of string

val max_depth : int
(** 1,000: {!parse} refuses values nested deeper (a model's constants nest
    a few deep), so that neither it nor the code that walks its values
    runs out of stack. *)

val parse : string -> t
(** Parses a value: integers, strings (the escapes of {!string_literal}; another
    escape is an error), [TRUE], [FALSE],
    [<<...>>], [{...}], [[f |-> v, ...]], [(k :> v @@ ...)], nested at most
    {!max_depth} deep; a long sequence or set is read in a loop. The result is
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
