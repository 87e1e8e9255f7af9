(** The parser driver: text to {!Ast.program}, or one located syntax error.

    Syntax errors say what was expected: the hand-written messages of
    [parser.messages] for the common mistakes (a missing [do], a missing priority
    value, an operator with no operand, ...), and otherwise the tokens the grammar
    could have accepted at that point, computed from Menhir's incremental API. *)

type result = {
  program : Ast.program;
  comments : Lexer.comment list;  (** in source order *)
}

val string : file:string -> string -> result
(** @raise Diag.Failed with the first lexical, layout or syntax error; a NUL
    byte anywhere in the text, comments included, is one (D28), as is nesting
    deeper than {!Nesting.max_depth} (D27). *)

val file : string -> result
(** Reads and parses a file.
    @raise Diag.Failed as {!string} does, and when the file cannot be read
    (located at line 1, column 1 of that file). *)

val read_all : string -> (string, string) Stdlib.result
(** The bytes of a file, or the reason it cannot be read: the system's (no such
    file, a directory, ...), or that it holds more than {!max_source_bytes}
    (D28). Pipes and devices are read to their end, not by their reported size. *)

val max_source_bytes : int
(** 64 MB (D28). *)

val expr : file:string -> string -> Ast.expr
(** Parses one expression (a Jadescript literal on the command line, a percept in
    an events file).
    @raise Diag.Failed *)
