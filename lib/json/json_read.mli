(** The one reader of JSON of the project: every JSON input (an events
    file's lines, a trace's lines, [vector.json], a scenario, the trace an
    implementation writes for [conform]) is read here, into Yojson's
    values, so that one set of rules holds for all of them
    (docs/trace-format.md, "Reading JSON").

    The reader is strict (RFC 8259 and nothing more): a value is an object,
    an array, a string, a number, [true], [false] or [null], with white
    space (space, tab, line feed, carriage return) around and between its
    tokens and nothing else after it; a string holds no raw control
    character (a NUL or a line feed in a string is an error: it must be
    written [\u0000], [\n]), only well-formed UTF-8, and escapes of RFC
    8259 only, a [\u] escape of a surrogate only as the first half of a
    pair followed by its second half; a number is [-? (0 | [1-9][0-9]* )
    (. [0-9]+)? ([eE] [+-]? [0-9]+)?] (no [NaN], no [Infinity], no leading
    [+] or zero), an integer when it has neither fraction nor exponent
    ([`Int], or [`Intlit] beyond OCaml's [int]), otherwise [`Float]; an
    object names each key once.

    It is iterative (its stack is a list, never the program's) and bounded:
    arrays and objects nest at most {!max_depth} deep, so that the code that
    walks the value it returns (printing, comparing) never runs out of
    stack either. *)

val max_depth : int
(** 1,000: arrays and objects nested deeper are an error at the bracket
    that goes past it. (No input of the project nests more than five
    deep.) *)

type error = { line : int; column : int; message : string }
(** Where the text stops being JSON: line and column from 1 (the column
    counts bytes), and what is wrong, one line of printable ASCII. *)

val of_string : ?max_depth:int -> string -> (Yojson.Safe.t, error) result
(** The one value the text holds. *)

val of_file : max_bytes:int -> string -> (Yojson.Safe.t, error) result
(** The value a whole file holds; a file longer than [max_bytes] is an error
    at its line 1 and is not read past that many bytes.
    @raise Sys_error when it cannot be opened or read *)

val to_string : error -> string
(** ["LINE:COL: message"]. *)

val printable : string -> string
(** A text as one printable line: control characters and bytes beyond
    ASCII shown as [?], at most 200 bytes (with ["..."] after). For
    messages that quote what was read. *)
