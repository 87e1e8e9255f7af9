(** The host's events file of [jadescript-ref run --events] (JSON lines,
    docs/trace-format.md): what the host does, in order. The file is read
    once, from its start to its end, whatever it is (a file, a pipe, a
    FIFO, [/dev/stdin]): {!read} checks every line as it is read and keeps
    the good ones' text in memory (about the size of those lines); if every
    line is good, {!iter} hands their events over, one at a time, as the
    run applies them. Nothing runs before every line was checked. The
    limits: a line of at most {!max_line} bytes, a file of at most
    {!max_bytes}. *)

type t =
  | Notify of { agent : string; percept : Value.t; default : int; priority : int option }
      (** notifyEvent (R2): the percept, its type's default priority (R1a),
          and the override (R2a) *)
  | Put of { agent : string; obj : Value.t }          (** putO2AObject (R2c) *)
  | Message of { agent : string; perf : string; content : Value.t; during_step : bool }
      (** from ["host"] (R5e); [during_step]: ["during": "step"], it arrives
          during the agent's next behaviour step (D42, R5d) *)
  | Run of int                                         (** that many rounds (R6) *)
  | Run_rules of int
      (** that many single rules of the first agent that is not idle, so
          that the host can act between rules (R3d) *)
  | Run_idle                                           (** until every agent is idle *)

val max_line : int
(** 16 MB (16,777,216 bytes): a longer line is an error at it, and is never
    held in memory. *)

val max_bytes : int
(** 1 GiB (1,073,741,824 bytes): a longer file is an error, and is not read
    past that (an endless pipe ends there). *)

type file
(** An events file read and checked: the text of its event lines. *)

val read :
  Typing.Tenv.t -> agents:(string * string) list -> string ->
  report:(line:int -> col:int -> string -> unit) -> (file, int) result
(** Reads the file once and checks every line as it is read, reporting
    each problem; [Error n] when there were [n] (then nothing is kept).
    @raise Sys_error when the file cannot be opened or read. *)

val length : file -> int
(** How many event lines it holds (blank and [#] lines are not kept). *)

val iter : file -> (t -> unit) -> unit
(** Hands each event over in order, as it is read from the text kept (the
    same event {!parse_line} read when it was checked); the text of each
    block of lines is dropped once its events were handed over, so [iter]
    goes once over a file. *)

val fold_lines :
  string -> ('a -> int -> string option -> [ `Continue of 'a | `Stop of 'a ]) -> 'a -> 'a
(** Every line of the file in order, with its number from 1, as
    [input_line] reads them (split at each newline, the last line with or
    without its own; a carriage return is kept), [None] for a line longer
    than {!max_line} (not held in memory), until the function says
    [`Stop]. Only the line being read is kept in memory, and each byte is
    looked at once.
    @raise Sys_error when the file cannot be read, or is longer than
    {!max_bytes}. *)

(** {1 Reading one line}

    Most lines of a long events file are a notify of a percept literal
    ([{"agent":"a","notify":"position(1, 2)"}]); they are read by a quick
    path beside the full one (D30). *)

val parse_line :
  Typing.Tenv.t -> agents:(string * string) list -> file:string -> string ->
  (t option, (int * string) list) result
(** One line: [Ok None] for a blank or [#] line, [Ok (Some e)] for an
    event, [Error] with each problem's column and message. The quick path
    first, then, for any line it does not take, {!parse_line_full}: the
    answer is the same. *)

val parse_line_full :
  Typing.Tenv.t -> agents:(string * string) list -> file:string -> string ->
  (t option, (int * string) list) result
(** The full path: the line through the JSON reader ([Json_read]: strict,
    bounded), each field checked (an action's own fields only, docs/trace-format.md),
    the percept through the program's grammar ([Syntax.Parse.expr]) and [Eval.percept_value]. *)

val quick_notify : Typing.Tenv.t -> agents:(string * string) list -> string -> t option
(** The quick path alone: [Some] event only for a line of the two fields
    ["agent"] and ["notify"] (printable ASCII, no JSON escapes but a quote's
    and a backslash's) whose percept is built of the program's schema names,
    calls, and integer, decimal, text (no escapes) and boolean literals, and
    is a good percept for that agent; then {!parse_line_full} answers the
    same event. [None] for any other line. *)

val to_line : t -> string
(** The line of an event (without its newline), which {!parse_line} reads
    back as the same event (a notify's [default] is the percept type's, so
    it is not written): for generated events files (the bench). *)

(** {1 Writing from text} *)

(** A host action as it is written in an events file: percepts, objects and
    contents as Jadescript text (what generators of test inputs produce; the
    fuzz campaign, fuzz/, writes its events files with {!source_to_line}). *)
type source =
  | Notify_text of { agent : string; percept : string; priority : int option }
      (** [{"agent": A, "notify": P}], with ["priority"] when overridden (R2a) *)
  | Put_text of { agent : string; obj : string }              (** [{"agent": A, "put": O}] *)
  | Message_text of { agent : string; perf : string option; content : string; during_step : bool }
      (** [{"agent": A, "message": C, "performative": F}]; [None]: [inform];
          [during_step]: with ["during": "step"] (D42, R5d) *)
  | Run_rounds of int                                          (** [{"run": K}] *)
  | Run_until_idle                                             (** [{"run": "idle"}] *)
  | Run_single_rules of int                                    (** [{"run": {"rules": K}}] (D23) *)

val source_to_line : source -> string
(** One line of an events file, without its newline. *)
