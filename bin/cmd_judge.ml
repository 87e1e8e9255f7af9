(* jadescript-ref judge FILE... --agent NAME:TYPE[:ARG,...] ... [--fuel N]
   [--max-memory MB] [--bound N] TRACE: the trace replayed through the
   reference semantics of the program (docs/trace-format.md, "Judging a
   run"). *)

open Cmdliner

let judge files agent_specs agent_files trace fuel max_memory bound _seed _max_steps _variant _capacity _events =
  let module R = Cmd_run in
  match
    let env = R.load files in
    let specs = R.all_agents env agent_specs agent_files in
    if specs = [] then (prerr_endline "error: no agent: give the run's agents, --agent NAME:TYPE"; raise (R.Stop 1));
    let fuel = Option.get (R.number ~opt:"fuel" ~lo:1 ~hi:R.int_max ~what:"statements per handler or step" (Some fuel)) in
    let max_memory = R.number ~opt:"max-memory" ~lo:16 ~hi:1_048_576 ~what:"megabytes of heap the run may take" max_memory in
    let bound = Option.get (R.number ~opt:"bound" ~lo:1 ~hi:1_000_000 ~what:"configurations kept per agent" (Some bound)) in
    Interp.Runtime.tune_gc ();
    let options = { Judge.fuel; max_memory; bound } in
    match Judge.judge env ~agents:specs ~options trace with
    | Judge.Accepted { lines; complete; cut; level; containers } ->
      Printf.printf "%s: the program explains every line (%d lines, %s level%s%s%s)\n" trace lines
        (Judge.string_of_level level)
        (if containers > 1 then Printf.sprintf "; %d containers: each keeps its own order of sends (D47)" containers else "")
        (if complete then "" else "; the run did not end: not every agent was destroyed")
        (if cut then "; its last line was cut and is not read" else "");
      0
    | Judge.Rejected { line; message } ->
      prerr_endline (Printf.sprintf "%s:%d:1: error: %s" trace line message);
      1
  with
  | code -> code
  | exception R.Stop code -> code

let cmd =
  let files = Arg.(non_empty & pos_left ~rev:true 0 string [] & info [] ~docv:"FILE" ~doc:"The program's files.") in
  let trace = Arg.(required & pos ~rev:true 0 (some string) None & info [] ~docv:"TRACE" ~doc:"The trace to judge.") in
  let agents = Arg.(value & opt_all string [] & info ["agent"] ~docv:"NAME:TYPE[:ARG,...]"
                      ~doc:"The run's agents, as run takes them, in the order it created them.") in
  let agent_files = Arg.(value & opt_all string [] & info ["agents"] ~docv:"FILE"
                           ~doc:"The run's agents of run's --agents FILE, one per line, after those of --agent.") in
  let fuel = Arg.(value & opt string "100000" & info ["fuel"] ~docv:"N"
                    ~doc:"The run's --fuel: statements one handler or behaviour step may execute (R7).") in
  let max_memory = Arg.(value & opt (some string) None & info ["max-memory"] ~docv:"MB"
                          ~doc:"The run's --max-memory (D22); default: no bound.") in
  let bound = Arg.(value & opt string "64" & info ["bound"] ~docv:"N"
                     ~doc:"Configurations of one agent the search over hidden steps keeps (an observable trace).") in
  (* run's other options: the header says the loop and the schedule, the
     trace where the run stopped; accepted so that run's command line can be
     given as it was *)
  let ignored name docv = Arg.(value & opt (some string) None & info [name] ~docv
                                 ~doc:"As run takes it; the trace's header and its lines say what it did.") in
  Cmd.v (Cmd.info "judge" ~doc:"Judge a run: does the program explain every line of its trace?"
           ~man:[`S Manpage.s_description;
                 `P "Replays TRACE through the reference semantics (lib/semantics, lib/interp/eval.ml) \
                     of the program FILE..., run with the agents given. The trace gives the choices \
                     the rulings leave open: which agent's rule comes next (R6), when each host event \
                     and delivery comes, which percept of the highest priority a Dequeue takes under \
                     unstable ties. Everything else is the program's: the first line it does not \
                     explain is reported as TRACE:LINE:1: error: what the program does there, and \
                     the exit status is 1. A trace of level observable (its header says so) has no \
                     line for the loop's own steps; the judge finds them (docs/trace-format.md)."])
    Term.(const judge $ files $ agents $ agent_files $ trace $ fuel $ max_memory $ bound $ ignored "seed" "N"
          $ ignored "max-steps" "N" $ ignored "variant" "V" $ ignored "o2a-capacity" "N" $ ignored "events" "FILE")
