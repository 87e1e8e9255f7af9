(** The [sim] subcommand of [jadescript-ref] (the lead wires {!cmd} into
    bin/main.ml):

    {v jadescript-ref sim SCENARIO [--seed N] [--out DIR] [--batch N] v}

    SCENARIO is a scenario file, or the name of one in scenarios/ (e.g.
    [paper]). A single run prints its metrics and writes the report, the
    map, the timeline and the trace into DIR (default [out/sim/NAME-sSEED]);
    [--batch N] runs N seeds from the given one with a progress bar on
    stderr and prints the table of metrics. [--controller jadescript] (the
    default) runs examples/robome/robome.jade on the interpreter;
    [--controller reference] the OCaml mirror. Exit status 0, or 1 with one
    line FILE:LINE:COL: error: message when the scenario or the program
    cannot be read. *)

val cmd : int Cmdliner.Cmd.t

val main : ?controller:string -> ?program:string -> scenario:string -> seed:int option ->
  out:string option -> batch:int option -> unit -> int
(** What the command does, for callers without Cmdliner. *)
