(** The judge: a run's trace replayed through the reference semantics of
    the program that ran ([jadescript-ref judge]; docs/trace-format.md,
    "Judging a run").

    The trace gives only the choices the rulings leave open: which agent's
    rule comes next (R6 revised: the rules of different agents interleave
    in any order), when each host event and each delivery comes (any time
    after its send, possibly during the receiver's behaviour step,
    [SendInStep], R5d revised), and which entry of the highest priority a
    Dequeue takes under unstable ties. The program gives everything else:
    what each handler and behaviour step does, which lines its body writes,
    what the platform answers (a [failure] from [ams] for a message to an
    absent agent, D43; nothing for messages to [ams] and [df], D44). The
    verdict is the first line that no run of the program explains, or
    acceptance. *)

(** {1 Levels} *)

type level =
  | Full         (** every rule of the agent loop has its line *)
  | Observable   (** the loop's own steps have none: the judge searches for
                     them (docs/trace-format.md, "Observable traces") *)

val level_of_string : string -> level option
(** ["full"] or ["observable"], the header's [level] field; [None] for any
    other text. *)

val string_of_level : level -> string
(** The header's spelling of a level. *)

(** {1 Judging} *)

type options = {
  fuel : int;
      (** statements one handler or behaviour step may execute (R7): the
          run's [--fuel] *)
  max_memory : int option;
      (** the run's [--max-memory] in megabytes (D22); [None]: no bound *)
  bound : int;
      (** the search bound: how many configurations of one agent may
          explain the trace so far (more is a rejection); the hidden steps
          explored before one line are bounded by 100 times this *)
}

val default_options : options
(** Fuel 100,000 (run's default), no memory bound, bound 64 ([--bound]'s
    default). *)

type verdict =
  | Accepted of { lines : int; complete : bool; cut : bool; level : level; containers : int }
      (** the program explains every line: [lines] the lines read (the
          header counts as line 1); [complete] when every agent was
          destroyed (the run ended: every message was then delivered or
          reported undeliverable, and every line a rule owed is written,
          D26); [cut] when the last line, with no newline, was not JSON and
          was left out (a run killed while writing it); [containers] how
          many containers the header names (1 without [containers]): with
          more than one, messages to a receiver keep the order of the sends
          made in one container only (D47) *)
  | Rejected of { line : int; message : string }
      (** the first line (of the file, the header is 1) the program does
          not explain, and why: what the program does there instead. A
          trace that cannot be read (not the format, docs/trace-format.md)
          is rejected at its first bad line; a complete trace that misses
          lines owed at its end is rejected at the line after its last. *)

val judge : Typing.Tenv.t -> agents:(string * string * Interp.Value.t list) list ->
  ?options:options -> string -> verdict
(** [judge env ~agents path]: the trace in file [path] judged against the
    checked program [env], run with [agents] (name, agent type, the
    arguments of [on create]), in the order the run created them. The
    header must be the program's (its behaviours and percept types) and
    name these agents, in this order; its variant, tie policy, budget and
    O2A capacity are taken as the run's. Reads the trace one line at a
    time. Never raises on a bad trace: every fault of the trace is a
    [Rejected]. *)
