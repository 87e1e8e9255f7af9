(** The printer: the canonical layout of a program ([jadescript-ref fmt]).

    Canonical layout: one tab per indentation level; one declaration, feature or
    statement per line; a blank line between declarations and around features
    that have a block; keywords in their canonical spelling ([behaviour],
    [one shot], [activate behaviour B], [uses ontology]/[uses ontologies] by
    count, the short form [on inform when ...] for message handlers with a
    performative); the fewest parentheses that keep the tree as it is.

    Printing then parsing gives back the same tree, up to regions: this is tested
    on every example and on random trees. Comments passed in are put back: a
    comment on its own line before the declaration, feature or statement that
    followed it, at that item's indentation; a comment after code on the same
    line after that line's code. *)

val program : ?comments:Lexer.comment list -> Ast.program -> string

val expr : Ast.expr -> string
val pattern : Ast.pattern -> string
val ty : Ast.ty -> string
val literal : Ast.literal -> string

val text_literal : string -> string
(** A text as a Jadescript literal, quotes and escapes included. *)
