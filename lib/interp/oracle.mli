(** The conformance oracle: test vectors any Jadescript implementation can be
    run against ([jadescript-ref conform]).

    A vector is a folder of [conformance/] holding the program ([*.jade]),
    [vector.json] ([{"about": ..., "rulings": ["R3b"], "args": [...],
    "expect": [...]}]), the host's [events.jsonl] and the [expected.jsonl]
    trace. [args] are the arguments of [run] after the files ([--agent ...],
    [--o2a-capacity 2], ...). [expect] states what the vector pins, as
    assertions over a trace, so that the expected trace is checked against the
    rulings independently of the implementation that wrote it:
    - [{"has": PATTERN}] / [{"lacks": PATTERN}]: some / no event matches;
    - [{"count": PATTERN, "is": N}];
    - [{"before": [PATTERN, PATTERN]}]: the first event matching the first
      pattern comes before the first matching the second;
    - [{"order": PATTERN, "field": F, "is": [V1, V2, ...]}]: the values of field
      F in the events matching PATTERN, in order.
    A PATTERN is a JSON object; an event matches when it has every field of the
    pattern with an equal value. *)

type vector = {
  name : string;
  dir : string;
  about : string;
  rulings : string list;
  args : string list;
  files : string list;
  expect : Yojson.Safe.t list;
}

val load : string -> vector list
(** Every vector of a folder, by name. @raise Failure *)

val read_trace : string -> Yojson.Safe.t list
(** A trace's lines, without the header. @raise Failure *)

val check_expectations : Yojson.Safe.t list -> Yojson.Safe.t list -> (unit, string) result
(** The vector's assertions on a trace. *)

type outcome =
  | Pass
  | Diverge of { index : int; expected : string; got : string }
      (** the first event (1-based, after the header) that differs *)
  | Failed of string   (** the implementation failed or wrote no trace *)

val run_vector :
  ?spawn:(timeout:float -> errs:string -> string -> int) ->
  ?timeout:float -> ?keep:string -> ?workdir:string -> impl:string -> vector -> outcome
(** Runs [impl FILES ARGS --events events.jsonl --trace TMP] in [workdir]
    (default: the vector's folder; [jadescript-ref conform] gives a fresh
    directory holding only the program files and the events, so that no
    expected trace lies beside the implementation) and judges what it did
    (docs/trace-format.md, "Conformance"). The expected trace is read before
    the implementation starts:
    - it must end within [timeout] seconds (default: 30 s plus 0.05 s per
      expected event), else it is killed and fails;
    - its exit status must be 0, or 1 exactly when its trace records a
      run-time error (D15); a signal or any other status fails;
    - its trace's first line must be a header of format ["jadescript-ref"]
      (version 2, as the expected traces are), equal to the expected header (field order aside);
    - its events must equal the expected ones, in order, [step] aside.
    The trace is read one line at a time, each line up to 1 MB, so memory
    stays bounded by the expected trace whatever the implementation writes;
    the temporary files are removed, also when [spawn] raises (conform's
    [Sys.Break] on SIGINT: the implementation is stopped, the files
    removed, the exception passed on) ([keep]: the trace is kept as
    [keep/NAME.jsonl], for [validate]). A failure shows the start of the
    first line the implementation wrote on standard error.

    [spawn ~timeout ~errs cmd] runs [sh -c cmd] under timeout(1) with
    standard error to [errs] and returns the shell's status (128 + n for
    signal n). The default uses [Sys.command], which cannot be interrupted:
    system() ignores SIGINT while it waits; [jadescript-ref conform] passes
    one built on Unix that can. *)

val first_line : string -> string
(** The first line of a file (an implementation's standard error), at most
    300 bytes; [""] when it cannot be read. *)

val describe_status : timeout:float -> int -> string
(** A shell's status in words: ["exited with status 3"], ["timed out after
    30 s (--timeout)"], ["was killed by signal 11"]. *)

val default_timeout : vector -> float
(** A vector's time limit when none is given: 30 s, plus 0.05 s per event of
    its expected trace. *)
