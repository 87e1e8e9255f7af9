(** The fuzz campaign's targets (fuzz/README.md): how each input is made
    from its seed and index, and the oracles that judge what the project
    did with it. One input is one call of {!run}; it is reproducible from
    [(target, seed, index)] alone ([fuzz.exe --replay TARGET:SEED:INDEX]).

    Targets:
    - [parse]: mutated and random program texts (byte flips, token splices,
      truncations, deep nesting, huge literals, line edits, invalid UTF-8)
      through the parser, the printer (a parsed program prints and parses
      back to the same text) and the type checker;
    - [check]: well-typed programs of {!Test_support.Typed_gen} (they must
      check) and their type-breaking mutations (each must be reported, with
      the expected message, located);
    - [run]: well-typed programs with generated host scenarios
      ({!Test_support.Event_gen}) run in-process on the runtime with a
      trace; on a sample, the trace goes to TLC ([validate]);
    - [limits]: the programs of {!Test_support.Typed_gen.limit};
    - [cli]: the command line as a user drives it, in a subprocess: [run]
      with generated programs and events, [check]/[fmt]/[parse] on mutated
      files, broken events files and bad command-line values;
    - [validate]: traces of generated runs, tampered (Tamper): each must be
      rejected;
    - [conform]: fake implementations that hang, crash, print garbage,
      write a bad header or none, exit with a bad status, write a huge
      trace (conform must judge them failed, in time), and a faithful one
      (it must pass). *)

type outcome =
  | Pass
  | Finding of { kind : string; message : string }
      (** what broke: ["exception"], ["unlocated error"], ["bad trace"],
          ["wrongly accepted"], ["generator"], ... and a one-line message *)

type target = {
  name : string;
  limit : float;     (** seconds one input may take before it is a hang *)
  memory : int;      (** bytes of address space of the child running it *)
  run : keep:string option -> seed:int -> int -> outcome;
      (** [keep]: also write the input's files into this folder (replay) *)
}

val targets : target list
val find : string -> target option

val jsref : unit -> string
(** The [jadescript-ref] executable the subprocess targets use: [$JSREF_EXE],
    else [bin/main.exe] of the build folder fuzz.exe is in. *)

val tlc_every : int ref
(** The [run] target sends one trace in this many to TLC (default 2000; the
    short sample: 150). *)

val valid_utf8 : string -> bool

val located_line : string -> bool
(** Is this line of standard error one of the project's located one-line
    reports ([FILE:LINE:COL: error: ...], [jadescript-ref: error: ...],
    [--agent ...: error: ...], [host: ...], a warning)? *)

val judge_process :
  ?expect_error:bool -> status:Unix.process_status -> stderr:string -> unit -> outcome
(** The command-line oracle: exit status 0 or 1 (1 when [expect_error]),
    no signal, and every line of standard error located. *)

val run_command : ?timeout:float -> ?memory:int -> string array -> Unix.process_status * string * string
(** Runs argv in a child with bounded memory and time (killed after
    [timeout], then reported as [WSIGNALED Sys.sigkill]); its standard
    output (first 1 MB) and error. *)

val contains : string -> string -> bool
(** [contains s sub]: [sub] occurs in [s]. *)

val read_file : string -> string
(** @raise Sys_error *)

val trace_problem : string -> string option
(** What is wrong with a trace file: not valid UTF-8, a line that is not
    JSON, no header, or a line the trace reader (lib/trace) rejects. *)

val bound_memory : int -> unit
(** Bounds this process's data (heap) to so many bytes (a soft limit,
    lifted while TLC runs), disables core dumps, and has the process killed
    when its parent dies: for the children that run the inputs. *)

val run_memory_bound : unit -> int
(** The bound {!bound_memory} set in this process (0: none). *)

val remove_tree : string -> unit
(** A file, or a folder and everything in it; what is not there, or cannot
    be removed, is left. *)

val remove_leftovers : int -> unit
(** Removes what the child of this process id left in the temporary folder
    (killed in the middle of an input, it could not clean up). *)
