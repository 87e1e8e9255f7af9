(* jadescript-ref validate TRACE...: is the run a behaviour of spec/AgentLoop.tla? *)

open Cmdliner
open Explore

(* Every rejection is one line (docs/trace-format.md). *)
let one_line m = String.concat " " (List.filter (( <> ) "") (List.map String.trim (String.split_on_char '\n' m)))

(* Whether the judge read the traces (the program was given). *)
let judged = ref false

let report trace verdicts =
  List.fold_left (fun code v ->
      match v with
      | Validate.Accepted { agent; steps; total } when steps = total ->
        Printf.printf "%s: agent %s: TLC accepts the %d steps as a behaviour of spec/AgentLoop.tla\n%!"
          trace agent steps;
        code
      | Validate.Accepted { agent; steps; total } ->
        Printf.printf "%s: agent %s: TLC accepts its first %d steps of %d (the window, --window) as a behaviour \
                       of spec/AgentLoop.tla; the OCaml checks%s read all of them\n%!"
          trace agent steps total (if !judged then " and the judge" else "");
        code
      | Validate.Rejected { agent; line; step; after } ->
        prerr_endline (Printf.sprintf "%s:%d:1: error: the spec cannot take this step of agent %s (after %d it takes): last = %s"
                         trace line agent after step);
        1
      | Validate.Invalid { line; message } ->
        prerr_endline (Printf.sprintf "%s:%d:1: error: %s" trace line message);
        1
      | Validate.Cannot { agent; line; reason } ->
        prerr_endline (Printf.sprintf "%s:%d:1: error: agent %s: cannot validate: %s" trace line agent reason);
        1) 0 verdicts

let failed trace msg = prerr_endline (Printf.sprintf "%s:1:1: error: %s" trace (one_line msg)); 1

(* A trace whose last line is cut (a run killed while it wrote it): the
   lines before it are checked, and the cut is told, as a warning (the
   status is that of the lines checked). *)
let on_cut trace line =
  prerr_endline (Printf.sprintf "%s:%d:1: warning: the last line is cut (no newline, not JSON: a run killed \
                                 while it wrote it); the lines before it are checked" trace line)

(* With the program (--program, --agent): the judge decides every line of
   each trace first (docs/trace-format.md, "Judging a run"): the status, 0
   when it accepts every trace. *)
let judge programs agent_specs agent_files traces =
  match programs with
  | [] -> 0
  | files ->
    let module R = Cmd_run in
    match
      let env = R.load files in
      let specs = R.all_agents env agent_specs agent_files in
      if specs = [] then (prerr_endline "error: --program needs the run's agents, --agent NAME:TYPE"; raise (R.Stop 1));
      judged := true;
      List.fold_left (fun code trace ->
          match Judge.judge env ~agents:specs trace with
          | Judge.Accepted { lines; _ } ->
            Printf.printf "%s: the judge: the program explains every line (%d lines)\n%!" trace lines; code
          | Judge.Rejected { line; message } ->
            prerr_endline (Printf.sprintf "%s:%d:1: error: %s" trace line message); 1) 0 traces
    with
    | code -> code
    | exception R.Stop code -> code

let run_one keep window trace =
  match Validate.trace ?keep ~window ~on_cut trace with
  | verdicts -> report trace verdicts
  | exception Failure msg -> failed trace msg
  | exception Tlc.Error msg -> failed trace msg
  | exception Model.Error msg -> failed trace msg
  | exception Sys_error msg -> failed trace msg

(* Every trace is validated, even after a rejection; the status is 1 when any
   step of any trace was rejected. All the traces share one TLC run; if that
   fails, each is validated alone, so that the failure is told for its
   trace. *)
let run traces keep window programs agents agent_files =
  let judged = judge programs agents agent_files traces in
  let window = match window with
    | None -> Validate.default_window
    | Some "all" -> 0
    | Some w -> Option.get (Cmd_run.number ~opt:"window" ~lo:1 ~hi:Cmd_run.int_max ~what:"steps of each agent TLC follows" (Some w)) in
  max judged
    (match Validate.traces ?keep ~window ~on_cut traces with
     | results -> List.fold_left (fun code (t, vs) -> max code (report t vs)) 0 results
     | exception (Failure _ | Tlc.Error _ | Model.Error _ | Sys_error _) ->
       List.fold_left (fun code t -> max code (run_one keep window t)) 0 traces)

let run traces keep window programs agents agent_files =
  try run traces keep window programs agents agent_files with Cmd_run.Stop code -> code

let cmd =
  let trace = Arg.(non_empty & pos_all string [] & info [] ~docv:"TRACE"
                     ~doc:"Traces written by jadescript-ref run --trace (or by another \
                           implementation, docs/trace-format.md).") in
  let keep = Arg.(value & opt (some string) None & info ["keep"] ~docv:"DIR"
                    ~doc:"Also write the generated TLA+ modules into DIR.") in
  let window = Arg.(value & opt (some string) None & info ["window"] ~docv:"N"
                      ~doc:(Printf.sprintf "TLC follows the first N steps of each agent (default %d; $(b,all): every step). \
                                            The OCaml checks, and the judge with $(b,--program), read the whole trace."
                              Validate.default_window)) in
  let programs = Arg.(value & opt_all string [] & info ["program"] ~docv:"FILE"
                        ~doc:"The program that ran (its files, each with its own --program): the judge then \
                              decides every line of the trace first (docs/trace-format.md, \"Judging a run\").") in
  let agents = Arg.(value & opt_all string [] & info ["agent"] ~docv:"NAME:TYPE[:ARG,...]"
                      ~doc:"With --program: the run's agents, as run takes them, in the order it created them.") in
  let agent_files = Arg.(value & opt_all string [] & info ["agents"] ~docv:"FILE"
                           ~doc:"With --program: the run's agents of run's --agents FILE, after those of --agent.") in
  Cmd.v (Cmd.info "validate" ~doc:"Check traces: the format, agents, literals and messages in OCaml, then each agent against spec/AgentLoop.tla with TLC."
           ~man:[`S Manpage.s_description;
                 `P "First checks in OCaml what TLC does not see: the format (version 2 or 1, \
                     every field of the right type), the agents against the header, step \
                     numbers, the literals (a dequeue carries the percept notified with its \
                     seq, a handle the percept dequeued, a delivery the content sent), \
                     messages across agents (R5e), the O2A capacity (R2d), each body against its \
                     step's effects and every percept literal parsed (a last line cut by a \
                     killed run is left out, with a warning). Then, for each \
                     agent, projects the trace onto the spec (each percept and \
                     message its own value; the model's constants read off the trace), \
                     writes a TLA+ module whose behaviours follow the trace's first steps (at most \
                     --window of each agent), and runs TLC on it (one TLC run for all the agents of all the traces \
                     given). Reports each agent accepted, or the first step the spec \
                     cannot take as $(i,TRACE:LINE:1: error: ...): every rejection is one \
                     line. Exit status 1 when a trace is rejected. docs/trace-format.md \
                     says what is checked where."])
    Term.(const run $ trace $ keep $ window $ programs $ agents $ agent_files)
