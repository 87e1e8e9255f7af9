(* jadescript-ref validate TRACE...: is the run a behaviour of spec/AgentLoop.tla? *)

open Cmdliner
open Explore

(* Every rejection is one line (docs/trace-format.md). *)
let one_line m = String.concat " " (List.filter (( <> ) "") (List.map String.trim (String.split_on_char '\n' m)))

let report trace verdicts =
  List.fold_left (fun code v ->
      match v with
      | Validate.Accepted { agent; steps } ->
        Printf.printf "%s: agent %s: TLC accepts the %d steps as a behaviour of spec/AgentLoop.tla\n%!"
          trace agent steps;
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

let run_one keep trace =
  match Validate.trace ?keep ~on_cut trace with
  | verdicts -> report trace verdicts
  | exception Failure msg -> failed trace msg
  | exception Tlc.Error msg -> failed trace msg
  | exception Model.Error msg -> failed trace msg
  | exception Sys_error msg -> failed trace msg

(* Every trace is validated, even after a rejection; the status is 1 when any
   step of any trace was rejected. All the traces share one TLC run; if that
   fails, each is validated alone, so that the failure is told for its
   trace. *)
let run traces keep =
  match Validate.traces ?keep ~on_cut traces with
  | results -> List.fold_left (fun code (t, vs) -> max code (report t vs)) 0 results
  | exception (Failure _ | Tlc.Error _ | Model.Error _ | Sys_error _) ->
    List.fold_left (fun code t -> max code (run_one keep t)) 0 traces

let cmd =
  let trace = Arg.(non_empty & pos_all string [] & info [] ~docv:"TRACE"
                     ~doc:"Traces written by jadescript-ref run --trace (or by another \
                           implementation, docs/trace-format.md).") in
  let keep = Arg.(value & opt (some string) None & info ["keep"] ~docv:"DIR"
                    ~doc:"Also write the generated TLA+ modules into DIR.") in
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
                     writes a TLA+ module whose behaviours follow the trace's steps, and \
                     runs TLC on it (one TLC run for all the agents of all the traces \
                     given). Reports each agent accepted, or the first step the spec \
                     cannot take as $(i,TRACE:LINE:1: error: ...): every rejection is one \
                     line. Exit status 1 when a trace is rejected. docs/trace-format.md \
                     says what is checked where."])
    Term.(const run $ trace $ keep)
