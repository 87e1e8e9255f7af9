(** The JADE back end: Java 17 source for a checked Jadescript program.

    The generated classes (package [jsgen]) run on the runtime of
    [runtime/jade] and follow its contract ([runtime/jade/CONTRACT.md]): one
    class per schema (extending [jsref.values.Schema] or the class of its
    super schema), per agent type (extending [jsref.runtime.JadescriptAgent]
    or its super agent's class), per behaviour type (extending
    [jsref.runtime.JadescriptBehaviour] or its super's class), and
    [Program.java] implementing [jsref.runtime.ProgramInfo].

    The semantics are the reference interpreter's ([lib/interp/eval.ml]):
    values are dynamic [Object]s, operators go through [jsref.values.Ops] with
    the source position of the node ([FILE:LINE:COL], the file as given), fuel
    is ticked where the interpreter ticks, and operands are evaluated in the
    interpreter's order. Every generated statement is preceded by a comment
    with its source line. *)

exception Unsupported of Syntax.Source.region * string
(** A construct the back end does not translate (raised inside {!generate}
    and turned into its [Error]). *)

val java_string : string -> string
(** A Java string literal of a (UTF-8) text: quotes, backslashes and control
    characters escaped, non-ASCII characters as [\uXXXX] escapes, so that the
    source is ASCII. *)

val comment_text : string -> string
(** Source text made safe for a Java line comment: no backslash can start a
    unicode escape, control characters become spaces, non-ASCII characters
    escapes, and [*/] never appears (so that it may go in a block comment). *)

val generate :
  Typing.Tenv.t -> files:string list ->
  ((string * string) list, Syntax.Source.region * string) result
(** [generate env ~files] is the Java compilation units of the checked
    program [env] (whose files, as given on the command line, are [files]):
    pairs of a file name ([position.java], [Program.java]) and its text. An
    [Error] gives the place and the reason of the first construct that the
    back end does not support. [env] must come from a check without errors. *)

val write : out:string -> (string * string) list -> unit
(** [write ~out units] writes the units into [out/jsgen/], creating the
    folders as needed and removing the [.java] files an earlier compilation
    left there. @raise Sys_error when a file cannot be written. *)
