(** Mutable tables keyed by names (strings).

    The interpreter looks a name up on every access to a property and the
    type environment on every schema name in a pattern. [Stdlib.Hashtbl]'s
    generic hash is a C call that also inspects every block it visits, and a
    [Hashtbl.Make] table is reached through closures; this small open-addressing
    table (linear probing, at most half full) hashes in OCaml and compares keys
    by address first (the lexer interns names, so equal names are usually one
    string). *)

type 'a t

val create : int -> 'a t
(** An empty table sized for about that many names. *)

val length : 'a t -> int
val find_opt : 'a t -> string -> 'a option
val find : 'a t -> string -> 'a
(** @raise Not_found *)

val mem : 'a t -> string -> bool
val replace : 'a t -> string -> 'a -> unit
(** Binds the name, replacing any earlier binding. *)

val iter : (string -> 'a -> unit) -> 'a t -> unit
(** In no particular order. *)

val hash : string -> int
(** Mixes the length and the first two, middle and last two bytes; never
    negative, the same cost for every name. *)
