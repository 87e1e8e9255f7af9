(** A broken invariant of the implementation: the one error kind that is
    never the program's or the host's fault (as [Crash] of the WebAssembly
    reference interpreter's [util/error.ml]). Raised instead of
    [assert false]; the command line reports it as an internal error. *)

exception Crash of string
(** What the implementation expected and did not find. *)

val crash : ('a, unit, string, 'b) format4 -> 'a
(** [crash fmt ...] raises {!Crash} with the formatted message. *)
