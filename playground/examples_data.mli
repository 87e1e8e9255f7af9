(** Generated at build time by [gen/embed.ml] (see [playground/dune]): the
    example programs and the conformance vectors, so that the page fetches
    nothing. *)

val files : (string * string) list
(** Example files: the path from the repository root, and the text. *)

val vectors : (string * (string * string) list) list
(** Every folder of [conformance/], by name, with its files (name, text). *)
