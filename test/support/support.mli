(** Helpers shared by the test suites. *)

val qcheck : ?count:int -> ?long_factor:int -> string -> 'a QCheck.arbitrary ->
  ('a -> bool) -> unit Alcotest.test_case
(** [qcheck name arb prop]: a QCheck property as an alcotest case (there is no
    qcheck-alcotest package here). The seed is [QCHECK_SEED] when set, else 42,
    and is printed on failure; [JSREF_LONG=1] multiplies the count by
    [long_factor] (default 10), as [make conformance] does;
    [JSREF_QCHECK_COUNT=N] makes it N (the fuzz campaign's engine target). *)

val seed : int

val root : string
(** The repository root, found from the test's working directory. *)

val read_file : string -> string

val run_command : string -> int * string * string
(** [run_command cmd] runs [cmd] with [/bin/sh -c] and returns its exit status,
    standard output and standard error. *)

val exe : string
(** The jadescript-ref executable built by dune. *)

val bench_workload : ?types:string list -> ?handlers:(string * string) list -> unit -> string
(** The bench's workload ([bench/programs/percepts.jade]: four percept
    types, three behaviours, four handlers) with a [log] in each handler,
    as one source text; [types] (ontology lines, such as ["predicate
    level(x as double) extends percept"]) and [handlers] (pattern and
    one-line body, added to the behaviour [Others]) are added to it. *)

val with_file : string -> string -> (string -> 'a) -> 'a
(** [with_file name text f]: [f] of the path of a file [name] holding
    [text], in a fresh temporary directory of its own (two test processes
    at once never share it), removed afterwards. *)

val tricky_text : string QCheck.arbitrary
(** Valid UTF-8 texts for the escaping functions' round trips: any ASCII
    byte (control characters, NUL and DEL included), quotes, backslashes,
    and characters of 2, 3 and 4 bytes (U+2028, U+FEFF, U+FFFD among them). *)

val write_lines : string -> string list -> unit
(** Writes the lines to the file, each ended by a newline. *)

val lines_of : string -> string list
(** The file's lines that are not blank. *)

val with_lines : string list -> (string -> 'a) -> 'a
(** [with_lines lines k]: [k] on a temporary file holding [lines], removed after. *)
