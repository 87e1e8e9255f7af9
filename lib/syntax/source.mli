(** Source positions and regions.

    A region is a half-open span of a source file. Lines and columns are 1-based;
    a column counts bytes, so a tab is one column. Every AST node carries the region
    it was parsed from, so every later stage can report errors at a location. *)

type pos = { file : string; line : int; column : int }

type region = { left : pos; right : pos }

type 'a phrase = { at : region; it : 'a }
(** A node with its region, as in the WebAssembly reference interpreter. *)

val no_pos : pos
val no_region : region
(** For nodes made by tools rather than parsed (generated programs, tests). *)

val ( @@ ) : 'a -> region -> 'a phrase
(** [x @@ r] is [x] located at [r]. *)

val of_lexing : Lexing.position -> pos
val region_of_lexing : Lexing.position -> Lexing.position -> region

val span : region -> region -> region
(** [span a b] runs from the start of [a] to the end of [b]. *)

val string_of_pos : pos -> string
(** [FILE:LINE:COL]. *)

val string_of_region : region -> string
(** The start of the region, as [FILE:LINE:COL]. *)
