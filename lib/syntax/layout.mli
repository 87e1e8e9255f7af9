(** Layout: from raw tokens to the parser's token stream.

    The rule (docs/syntax.md, "Layout"):
    - A line's indentation is its leading white space. A file indents with tabs or
      with spaces, never both: the first indented line decides, and a line whose
      indentation mixes the two, or uses the other one, is an error.
    - A line indented more than the line before opens a block ([INDENT]); a line
      indented less closes blocks ([DEDENT]) and must line up exactly with an
      enclosing block.
    - Every logical line ends with [NEWLINE]. Blank lines and comment-only lines
      do not count.
    - A line continues on the next physical line (no [NEWLINE], no block) when
      (a) a bracket [( \[ {] is open, or (b) the next line is indented more than
      the current block and either this line ends with an operator, [,], [=],
      [with], [of], [as], [to] or [matches], or the next line starts with [with],
      [uses], [extends], [and] or [or]. Figure 5 of the paper relies on (b):
      [... extends percept] / [with priority = 4].
    - Brackets must match and close before the end of the file. *)

type t

val create : Lexer.state -> Lexing.lexbuf -> t

val next : t -> Parser.token * Lexing.position * Lexing.position
(** The next token for the parser, with its start and end positions. After the
    end of the file it returns [EOF] forever.
    @raise Diag.Failed on a layout error (or a lexical one, from {!Lexer}). *)

val max_depth : int
(** Brackets and blocks nested deeper than this are rejected (an error, not a
    stack overflow). *)

val open_bracket : t -> (Parser.token * Lexing.position * Lexing.position) option
(** The innermost bracket still open, if any (to explain a syntax error that an
    unclosed bracket caused on a later line). *)
