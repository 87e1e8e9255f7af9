(** Well-formed UTF-8 (RFC 3629). Jadescript texts are UTF-8 (docs/syntax.md):
    the lexer rejects another byte in a text literal, located; the trace
    reader rejects a trace line that is not UTF-8 (JSON text is UTF-8, RFC
    8259). *)

val first_invalid : string -> int option
(** The offset of the first byte of the string that does not begin a
    well-formed UTF-8 character (overlong forms, surrogates, code points above
    U+10FFFF and cut-short sequences are not well formed), if any. *)

val repair : string -> string
(** The string with each byte that does not begin a well-formed character
    (as {!first_invalid} finds them) replaced by U+FFFD, as the JADE back
    end decodes a text; the string itself when it is well formed. For a
    file name that is not UTF-8, which a trace writes in an [error]'s
    position. *)
