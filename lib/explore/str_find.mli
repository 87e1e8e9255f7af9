(** Substring search. *)

val find : string -> string -> int
(** [find s sub] is the index of the first occurrence of [sub] in [s].
    @raise Not_found *)
