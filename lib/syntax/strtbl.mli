(** Hash tables keyed by names (strings), with a hash computed in OCaml.

    The interpreter looks names up on every access to a property or a schema;
    the generic [Hashtbl.hash] is a C call that also checks every block it
    visits, which cost more than the rest of such a lookup. This is
    [Hashtbl.Make] with a hash of constant cost, and equality that tries the
    address first (the lexer interns names). *)

include Hashtbl.S with type key = string

val hash : string -> int
(** Mixes the length and the first two, middle and last two bytes; never
    negative. *)
