(** Generated at build time by [gen/glossary.ml] (see [playground/dune])
    from the tables of docs/rulings.md and docs/spec.md. Links are relative
    to docs/. *)

val groups : (string * string * string) list
(** The rulings' groups ([R1] ... [R5]): the number, its heading, the link. *)

val rulings : (string * string * string) list
(** Each ruling of the summary table ([R1a] ... [R8]): the number, its line,
    the link. *)

val decisions : (string * string * string) list
(** Each decision of the table of decisions ([D1] ...): the number, its
    line, the link. *)

val properties : (string * string * string) list
(** Each property of the spec's table: the name, its kind (invariant,
    liveness), its plain words. *)

val variables : (string * string) list
(** Each variable of the spec's table: the name(s), the plain words. *)
