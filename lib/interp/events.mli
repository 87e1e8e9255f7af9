(** The host's events file of [jadescript-ref run --events] (JSON lines,
    docs/trace-format.md): what the host does, in order. The file is read
    one line at a time, twice: {!check} reads every line and reports every
    bad one before anything runs; {!iter} reads it again and hands each
    event over as it is read. Memory does not grow with the file. *)

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

val check :
  Typing.Tenv.t -> agents:(string * string) list -> string ->
  report:(line:int -> col:int -> string -> unit) -> int
(** Reads every line of the file and reports each problem; returns how many
    there were. @raise Sys_error when the file cannot be read. *)

val iter :
  Typing.Tenv.t -> agents:(string * string) list -> string ->
  report:(line:int -> col:int -> string -> unit) -> (t -> unit) -> bool
(** Hands each event of the file over in order, as it is read. A line that
    is bad now (the file changed since {!check}) is reported and ends the
    reading: [false]. *)

val fold_lines :
  string -> ('a -> int -> string -> [ `Continue of 'a | `Stop of 'a ]) -> 'a -> 'a
(** Every line of the file in order, with its number from 1, as
    [input_line] reads them (split at each newline, the last line with or
    without its own; a carriage return is kept), until the function says
    [`Stop]. Only the line being read is kept in memory.
    @raise Sys_error when the file cannot be read. *)

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
(** The full path: the line through Yojson, the percept through the
    program's grammar ([Syntax.Parse.expr]) and [Eval.percept_value]. *)

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
  | Message_text of { agent : string; perf : string option; content : string }
      (** [{"agent": A, "message": C, "performative": F}]; [None]: [inform] *)
  | Run_rounds of int                                          (** [{"run": K}] *)
  | Run_until_idle                                             (** [{"run": "idle"}] *)
  | Run_single_rules of int                                    (** [{"run": {"rules": K}}] (D23) *)

val source_to_line : source -> string
(** One line of an events file, without its newline. *)
