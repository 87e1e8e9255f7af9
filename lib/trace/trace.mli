(** The trace of a run (R8, docs/trace-format.md): one typed event per line,
    and its one JSON codec. [jadescript-ref run] and the playground write
    traces with it; [validate], the conformance oracle and [conform] read
    them with it. The format is the contract between implementations: the
    JSON this module writes is, byte for byte, what
    [conformance/*/expected.jsonl] hold. *)

(** {1 Events} *)

type entry = { percept : string; priority : int; seq : int }
(** A percept entry: the percept as a Jadescript literal, its effective
    priority (R2a), its seq (R2b). *)

type message = { performative : string; content : string; from : string }
(** A message: [content] as a Jadescript literal; [from] an agent's name or
    ["host"]. *)

type effect =
  | Activated of string      (** ["activate B"]: an instance of B (R5g) *)
  | Deactivated              (** ["deactivate"] (R5h) *)

type taken =
  | Took_message of message * int   (** a message and its seq *)
  | Took_percept of entry           (** [native]: a percept *)

(** What a body did, as it happened (R8). *)
type body =
  | Log of string
  | Invoke of { meth : string; obj : string; args : string list; result : string }
      (** a native method of a host object; [obj] is its class *)
  | Send of { performative : string; content : string; receivers : string list }
  | Activate of string             (** the behaviour type *)
  | Deactivate of int              (** the instance id *)
  | Error of { at : string; message : string }
      (** a run-time error (R7): [FILE:LINE:COL] and the message *)

type event =
  | Create of { agent_type : string; args : string list; behaviours : string list }
  | Notify of { entry : entry; overridden : bool }   (** [NotifyWith] when overridden *)
  | Refused of { percept : string; reason : string } (** a notify refused (R2a, R2d) *)
  | Refused_put of { obj : string; reason : string }
      (** a put refused: the O2A queue is full (R2d); ["refused"] with ["object"] *)
  | Put of { obj : string; index : int }
  | Deliver of { message : message; seq : int; in_step : bool }
      (** a message reached the agent ([Send]); [in_step]: during its last
          behaviour step, after the step's handlers looked ([SendInStep],
          R5d) *)
  | Undeliverable of { receiver : string; performative : string; content : string }
      (** on the sender's line *)
  | Transfer of int
  | Transfer_one of entry
  | Transfer_spin of string
  | Transfer_end
  | Dequeue of entry
  | Handle of { instance : int; behaviour : string; handler : int; percept : string; seq : int;
                effects : effect list }
  | Skip of { instance : int; behaviour : string; handler : int }
  | End_dispatch of { seq : int; discarded : bool }   (** ["discard"] when discarded *)
  | Behaviour_step of { instance : int; behaviour : string; taken : taken option;
                        action_effects : effect list option;
                            (** the action block's, when the behaviour has one *)
                        handler : (int * effect list) option
                            (** the handler that took [taken], and its effects *) }
  | Next_iteration
  | Idle
  | Destroy
  | Body of { action : string; body : body }
      (** during the rule [action] (a TLA+ action name), ["Init"] for
          [on create], ["destroy"] for [on destroy] *)

type line = { step : int; agent : string; event : event }
(** [step] numbers the lines of a trace from 1, after the header. *)

val observable : event -> bool
(** Whether an event is written in an observable trace (docs/trace-format.md,
    "Observable traces"): every event but the loop's own steps (transfer,
    transfer_one, transfer_spin, transfer_end, dequeue, skip, end_dispatch,
    next_iteration, idle). A discard is written: a percept no handler took
    is what the loop promises a program to show. *)

val event_name : event -> string
(** The [event] field: ["create"], ["notify"], ..., ["log"], ["error"]. *)

val action : event -> string option
(** The [action] field: the TLA+ action ([None]: [null]). *)

(** {1 The header} *)

type behaviour_info = { name : string; kind : string; has_action : bool;
                        percept_handlers : int; message_handlers : int }

type header = {
  variant : string;
  tie_policy : string;            (** ["stable"] or ["unstable"] *)
  budget : int;
  o2a_capacity : int option;
  seed : int option;
  level : string;
      (** ["full"]: every rule has its line; ["observable"]: the loop's own
          steps have none (docs/trace-format.md, "Observable traces");
          a version 1 header has no level: ["full"] *)
  agents : (string * string) list;          (** name, type *)
  containers : (string * string) list;
      (** the agents that run outside the main container, with their
          container's name ([containers] in JSON, written only when not
          empty): messages sent from different containers to one receiver
          are not ordered by R5e (D47); version 2 only *)
  behaviours : behaviour_info list;
  percepts : (string * int) list;           (** percept type, default priority *)
}

val without_containers : Yojson.Safe.t -> Yojson.Safe.t
(** A header's JSON without its [containers] field: where an implementation
    ran its agents, which a vector does not fix (D47). *)

val main_container : string
(** ["main"]: the container of an agent the header's [containers] does not
    name (D47). *)

(** {1 JSON} *)

val line_to_json : line -> Yojson.Safe.t
val line_to_buffer : Buffer.t -> line -> unit
(** Appends the line's JSON, byte for byte what
    [Yojson.Safe.to_string (line_to_json l)] is, without building the JSON
    tree ({!write} uses it). *)

val line_of_json : Yojson.Safe.t -> (line, string) result
val header_to_json : header -> Yojson.Safe.t
val header_of_json : Yojson.Safe.t -> (header, string) result
val is_header : Yojson.Safe.t -> bool
(** Is this JSON value a trace header (its [trace] field)? *)

val version : int
(** The version of the format this module writes: 2 (it reads 1 and 2; a
    header of version 1 has no [level] and is read as ["full"]). *)

val header_version : Yojson.Safe.t -> Yojson.Safe.t option
(** [Some v] when the value is a jadescript-ref header ([trace] is
    ["jadescript-ref"]): its [version] field ([`Null] if it has none). *)

val is_error : Yojson.Safe.t -> bool
(** Is this line an [error] event (a run-time error, R7)? *)

val without_step : Yojson.Safe.t -> Yojson.Safe.t
(** A line's JSON without its [step] field (traces are compared so). *)

(** {1 Writing} *)

type writer
(** Numbers the lines and hands each, as one line of text with its newline,
    to an output function. *)

val writer : (string -> unit) -> writer
val to_channel : out_channel -> writer
(** Writes to the channel, buffered (whole lines only, 64 kB at a time),
    and flushes it when the program ends,
    however it ends ([exit], an uncaught exception; a command that turns
    signals into [exit], as [run] does, too): a run that dies leaves every
    event before its death. *)

val flush : writer -> unit
(** A writer to a channel holds its last lines (up to 64 kB, handed to the
    channel in one [output]): [flush] hands them over and flushes the
    channel. Nothing for other writers. Done at exit too (see
    {!to_channel}). *)

val nowhere : unit -> writer
(** Numbers the lines and writes nothing. *)

val write_header : writer -> header -> unit
val write : writer -> agent:string -> event -> unit
val lines_written : writer -> int

val writes : writer -> bool
(** Does the writer write anywhere? One from {!nowhere} does not: a caller
    may then skip what only the trace needs (D29). *)

val write_with : writer -> agent:string -> (unit -> event) -> unit
(** [write] of the event the function builds, built only when the writer
    writes somewhere; the line is numbered either way. *)

(** {1 Reading} *)

val fold_file : string -> ('a -> int -> Yojson.Safe.t -> 'a) -> 'a -> 'a
(** [fold_file path f init]: every non-blank line of the file as JSON, with
    its line number, one at a time (memory does not grow with the file).
    @raise Failure ["PATH:LINE:1: error: not JSON: ..."] *)

val read_located : string -> (header * (int * line) list, int * string) result
(** A whole trace, strictly read: its header (the first non-blank line) and
    its lines with their line numbers; [Error (line, message)] on the first
    line that is not JSON, not a header of version 1 or 2 with known values, or not
    an event with every field of the right type (docs/trace-format.md). *)

val stream : string -> header:(header -> unit) -> line:(int -> line -> unit) -> (bool, int * string) result
(** The trace one line at a time, read as {!read_located} reads it: [header]
    is called with the header, then [line] with each line and its number,
    as they are read (memory does not grow with the file; an exception they
    raise goes through). [Ok cut]: the file was read to its end; [cut] when
    its last line, with no newline, was not JSON (a run killed while it
    wrote that line: the lines before it stand). [Error (line, message)] on
    the first bad line. *)

val fast_line : string -> line option
(** A line as this module's writer writes it (the writer's order of fields,
    no space, no escape but a quote's and a backslash's) of one of the
    frequent events, read without a JSON tree: [Some l] exactly when the
    writer writes [l] as these bytes and the line is valid; then
    [line_of_json] of the line's JSON is [Ok l]. [None] for any other
    text, which the readers above read the general way (and may reject).
    The text must be valid UTF-8 (the readers check that first). *)

val stream_cut : string -> header:(header -> unit) -> line:(int -> line -> unit) ->
  (int option, int * string) result
(** {!stream}, with [Ok (Some n)] when the last line, line [n], is cut. *)

val read_file : string -> (header * (int * line) list, string) result
(** A whole trace: its header and its lines with their line numbers.
    [Error "PATH:LINE:COL: error: message"] on the first bad line. *)
