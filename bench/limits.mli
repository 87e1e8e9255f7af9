(** [bench.exe limits]: every reader and command at its documented limit
    (README.md, "Limits"), each in a child process under /usr/bin/time,
    printed as a table of time and peak memory (bench/README.md). *)

val run : string list -> unit
(** [run args]: [[]] every measure but [explore --max-states 25000000];
    [["all"]] every one; else the measures of these names. *)
