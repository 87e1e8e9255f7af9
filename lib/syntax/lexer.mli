(** The raw lexer: characters to tokens, before layout.

    It knows nothing of blocks: at each line break it measures the indentation of
    the next line that holds code (blank lines and comment-only lines are skipped)
    and returns it as a {!Newline}; {!Layout} turns those into the parser's
    [NEWLINE], [INDENT] and [DEDENT] tokens. Comments ([# ...] to the end of the
    line) are not tokens: they are collected in {!state.comments} for the printer. *)

type comment = { region : Source.region; text : string (** including the [#] *) }

type state = { mutable comments : comment list  (** newest first *) }

type raw =
  | Tok of Parser.token
  | Newline of string
      (** a line break; the string is the leading white space of the next line
          that holds code *)
  | End

val create : unit -> state

val line_start : state -> Lexing.lexbuf -> raw
(** Lex at the start of a line: skip blank and comment-only lines and return the
    [Newline] of the next code line (or [End]). Call it first, at the start of a
    file. *)

val token : state -> Lexing.lexbuf -> raw
(** The next raw token. The returned token's region is
    [Lexing.lexeme_start_p]/[lexeme_end_p]; for a [Newline] both are where the
    next code line's first token starts.
    @raise Diag.Failed on an unexpected character, an unterminated text literal,
    a bad escape or an integer literal too large. *)

val keyword_of_string : string -> Parser.token option
(** The keyword spelled by an identifier, if any ([behavior] is [BEHAVIOUR]). *)

val describe : Parser.token -> string
(** How a token is named in error messages: ['do'], [an identifier],
    [the end of the line], ... *)
