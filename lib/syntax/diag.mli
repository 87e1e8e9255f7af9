(** Diagnostics: the errors every stage of jadescript-ref reports.

    Following the WebAssembly reference interpreter, errors are distinct kinds that
    all carry a source region:
    - [Syntax]: the lexer or the parser rejected the text;
    - [Type]: the type checker rejected a well-formed program;
    - [Runtime]: a program went wrong while running (R7: recorded, the agent goes on);
    - [Crash]: a broken invariant of jadescript-ref itself (a bug, never the
      user's fault), still reported as one located line, never as a backtrace.

    Every command prints a diagnostic as one line [FILE:LINE:COL: error: message]. *)

type kind = Syntax | Type | Runtime | Crash

type severity = Error | Warning

type t = { kind : kind; severity : severity; at : Source.region; message : string }

exception Failed of t
(** Raised by a stage that stops at its first error (the lexer and the parser). *)

val error : kind -> Source.region -> string -> 'a
(** [error k at msg] raises [Failed]. *)

val errorf : kind -> Source.region -> ('a, unit, string, 'b) format4 -> 'a

val make : ?severity:severity -> kind -> Source.region -> string -> t

val to_string : t -> string
(** [FILE:LINE:COL: error: message] (or [warning:]); the message is flattened to
    one line. A crash reads [internal error: ...]. *)

val compare : t -> t -> int
(** By file, line, column, then message: the order diagnostics are printed in. *)
