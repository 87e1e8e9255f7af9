(* jadescript-ref run FILE... --agent NAME:TYPE[:ARG,...] ... [--events FILE]
   [--trace FILE] [--seed N] [--max-steps N] [--variant V] [--fuel N]
   [--o2a-capacity N] [--max-memory MB] *)

open Syntax
open Cmdliner
module V = Interp.Value
module Mc = Semantics.Machine

exception Stop of int

let report_at file line col msg =
  prerr_endline (Printf.sprintf "%s:%d:%d: error: %s" file line col msg)

(* A command-line value that is not good: one line, exit status 1. *)
let usage_error fmt =
  Printf.ksprintf (fun m -> prerr_endline ("jadescript-ref: error: " ^ m); raise (Stop 1)) fmt

(* The number options of run and their ranges (README, "The command line"):
   each a whole number in [lo, hi]; those the JADE harness also takes are
   Java ints (D8). *)
let int_max = 0x7FFF_FFFF

let number ~opt ~lo ~hi ~what = function
  | None -> None
  | Some s ->
    (match int_of_string_opt (String.trim s) with
     | Some n when n >= lo && n <= hi -> Some n
     | _ -> usage_error "option --%s: %S is not a whole number from %d to %d (%s)" opt s lo hi what)

(* Check the parsed files; print every diagnostic; stop on an error. *)
let check parsed =
  let syntax = List.filter_map (function Error d -> Some d | Ok _ -> None) parsed in
  let ok = List.filter_map (function Ok r -> Some r | Error _ -> None) parsed in
  let env, diags = Typing.check ok in
  let errors = List.filter (fun d -> d.Diag.severity = Diag.Error) (syntax @ diags) in
  List.iter (fun d -> prerr_endline (Diag.to_string d)) (List.sort Diag.compare errors);
  if errors <> [] then raise (Stop 1);
  env

(* Parse and check the program's files. *)
let load files =
  check (List.map (fun f -> match Parse.file f with r -> Ok r | exception Diag.Failed d -> Error d) files)

(* The same for a program given as texts: (file name, text). *)
let load_texts files =
  check (List.map (fun (f, text) -> match Parse.string ~file:f text with r -> Ok r | exception Diag.Failed d -> Error d) files)

(* Where an agent was given: an --agent option, or a line of an --agents file. *)
type origin = Option of string | Line of string * int

let where = function
  | Option spec -> "--agent " ^ spec
  | Line (file, n) -> Printf.sprintf "%s:%d:1" file n

let agent_spec ?(origin : origin option) env spec =
  let origin = Option.value origin ~default:(Option spec) in
  let fail msg = prerr_endline (Printf.sprintf "%s: error: %s" (where origin) msg); raise (Stop 1) in
  match String.index_opt spec ':' with
  | None -> fail "expected NAME:TYPE[:ARG,...]"
  | Some i ->
    let name = String.sub spec 0 i in
    let rest = String.sub spec (i + 1) (String.length spec - i - 1) in
    let (ty, args) = match String.index_opt rest ':' with
      | None -> (rest, "")
      | Some j -> (String.sub rest 0 j, String.sub rest (j + 1) (String.length rest - j - 1)) in
    if name = "" || ty = "" then fail "expected NAME:TYPE[:ARG,...]";
    (* the sender of host messages (R5e) is host: no agent may be so named *)
    if name = "host" then fail "the name host is reserved: it is the sender of the host's messages (R5e)";
    (* every platform has its own agents (R5e) *)
    if name = "ams" || name = "df" then
      fail (Printf.sprintf "the name %s is the platform's own agent's (R5e): no agent of the program takes it" name);
    if Utf8.first_invalid name <> None then fail "an agent's name is UTF-8 text";
    if Typing.Tenv.agent env ty = None then fail (Printf.sprintf "there is no agent type %s" ty);
    let values = List.map (fun a ->
        match List.assoc_opt a (Interp.Host.objects ()) with
        | Some v -> v
        | None ->
          (match Interp.Eval.literal_value env (Parse.expr ~file:"--agent" a) with
           | v -> v
           | exception Diag.Failed d -> fail d.message
           | exception (Interp.Eval.Trap (_, m) | Interp.Eval.Link (_, m)) -> fail m)) (Interp.Host.split_args args) in
    (name, ty, values)

(* --agents FILE: one agent per line, NAME:TYPE[:ARG,...] as --agent takes
   it; blank lines and lines starting with # are left out. Read once, one
   line at a time (a file, a pipe or a FIFO alike); a bad line is an error
   at it. For runs of many agents, which a command line cannot hold. *)
let agents_file env file =
  let specs = ref [] in
  (match Interp.Events.fold_lines file (fun () n line ->
       match line with
       | None ->
         report_at file n 1 (Printf.sprintf "a line longer than %d bytes" Interp.Events.max_line); raise (Stop 1)
       | Some l ->
         let l = String.trim l in
         if l = "" || l.[0] = '#' then `Continue ()
         else begin
           specs := (Line (file, n), agent_spec ~origin:(Line (file, n)) env l) :: !specs;
           `Continue ()
         end) () with
   | () -> ()
   | exception Sys_error m -> report_at file 1 1 ("cannot read the agents file: " ^ m); raise (Stop 1));
  List.rev !specs

(* The agents of --agent, then those of each --agents file, in order; names
   unique. *)
let all_agents env options files =
  let specs = List.map (fun s -> (Option s, agent_spec env s)) options
              @ List.concat_map (agents_file env) files in
  let seen = Hashtbl.create 64 in
  List.iter (fun (origin, (n, _, _)) ->
      if Hashtbl.mem seen n then begin
        prerr_endline (Printf.sprintf "%s: error: there is already an agent %s (agent names are unique)" (where origin) n);
        raise (Stop 1)
      end;
      Hashtbl.replace seen n ()) specs;
  List.map snd specs

(* The events file, read once (a file, a pipe or a FIFO alike): every line
   is checked, and every bad one reported with its location, before
   anything runs; the good lines are kept for the run. *)
let read_events env agents file =
  match Interp.Events.read env ~agents file ~report:(fun ~line ~col m -> report_at file line col m) with
  | Ok f -> f
  | Error _ -> raise (Stop 1)
  | exception Sys_error m -> report_at file 1 1 ("cannot read the events file: " ^ m); raise (Stop 1)

(* Standard output that cannot be written is closed, its buffer dropped:
   nothing would ever write it, and the flush at exit would fail again. *)
let flush_stdout_quietly () = try flush stdout with Sys_error _ -> close_out_noerr stdout

(* What a failed write reports; set once the trace is open. *)
let try_writes : (string -> unit) ref =
  ref (fun m -> prerr_endline ("jadescript-ref: error: " ^ m); raise (Stop 1))

let run files agent_specs agent_files events_file trace_file seed max_steps variant fuel capacity max_memory defect reference level interleave =
  match
    let engine = if reference then Interp.Runtime.Reference else Interp.Runtime.Fast in
    let hooks = match defect with
      | None -> Interp.Runtime.hooks_of engine
      | Some name ->
        (match Defects.find name with
         | Some d -> d.hooks
         | None -> prerr_endline ("jadescript-ref: error: unknown defect " ^ name ^ " (jadescript-ref defects lists them)"); raise (Stop 1)) in
    let env = load files in
    let specs = all_agents env agent_specs agent_files in
    if specs = [] then (prerr_endline "error: no agent: give at least one --agent NAME:TYPE (or --agents FILE)"; raise (Stop 1));
    let seed = number ~opt:"seed" ~lo:0 ~hi:int_max ~what:"the scheduler's seed" seed in
    let max_steps = Option.get (number ~opt:"max-steps" ~lo:0 ~hi:max_int ~what:"agent steps in the whole run" (Some max_steps)) in
    let fuel = Option.get (number ~opt:"fuel" ~lo:1 ~hi:int_max ~what:"statements per handler or step" (Some fuel)) in
    let capacity = number ~opt:"o2a-capacity" ~lo:1 ~hi:int_max ~what:"places in each O2A queue" capacity in
    let max_memory = number ~opt:"max-memory" ~lo:16 ~hi:1_048_576 ~what:"megabytes of heap the run may take" (Some max_memory) in
    let agents = List.map (fun (n, ty, _) -> (n, ty)) specs in
    let events = Option.map (read_events env agents) events_file in
    let variant = match Mc.variant_of_string variant with
      | Some v -> v
      | None -> prerr_endline ("error: unknown variant " ^ variant ^ " (printed, reference, budgeted, native)"); raise (Stop 1) in
    let trace = Option.map (fun f ->
        try open_out_bin f with Sys_error m -> report_at f 1 1 ("cannot write the trace: " ^ m); raise (Stop 1))
        trace_file in
    (* a write that fails (a full disk, /dev/full) is a clean error: the
       trace's, or standard output's *)
    let write_failed m =
      flush_stdout_quietly ();
      (match trace_file, trace with
       | Some f, Some oc when (try flush oc; false with Sys_error _ -> true) ->
         report_at f 1 1 ("cannot write the trace: " ^ m)
       | _ -> prerr_endline ("jadescript-ref: error: cannot write the standard output: " ^ m));
      raise (Stop 1) in
    try_writes := write_failed;
    (* a run stopped by a signal (a timeout, ^C) ends through exit, which
       flushes the trace: every event before the signal is in it *)
    List.iter (fun (s, code) -> Sys.set_signal s (Sys.Signal_handle (fun _ -> exit code)))
      [ (Sys.sigterm, 143); (Sys.sigint, 130); (Sys.sighup, 129) ];
    Interp.Runtime.tune_gc ();
    let params = { Mc.default_params with variant; o2a_capacity = capacity } in
    (* R7: a run-time error is recorded and the run carries on; it is also
       reported here, one line each, and makes the exit status 1. An error
       with no place in the program (recursion too deep) is put at the start
       of the first file. *)
    let run_errors = ref 0 in
    let on_error kind (at : Syntax.Source.region) msg =
      incr run_errors;
      let (file, line, col) =
        if at.left.line = 0 then (List.hd files, 1, 1) else (at.left.file, at.left.line, at.left.column) in
      flush stdout;
      report_at file line col (Interp.Eval.wording kind msg) in
    let level = match level with
      | "full" | "observable" -> level
      | l -> usage_error "option --level: %S is not full or observable" l in
    let interleave = number ~opt:"interleave" ~lo:0 ~hi:int_max ~what:"the seed of the finer interleaving" interleave in
    let opts = { Interp.Runtime.params; engine; seed; interleave; fuel; max_steps; max_memory; trace; level;
                 on_log = (fun a s -> print_string (a ^ ": " ^ s ^ "\n"));
                 on_error } in
    let rt = match Interp.Runtime.create ~hooks env opts specs with
      | rt -> rt
      | exception Interp.Eval.Link (_, m) -> prerr_endline ("error: " ^ m); raise (Stop 1) in
    let host_error = ref false in
    let check = function
      | Ok () -> ()
      | Error m -> host_error := true; prerr_endline ("host: " ^ m) in
    (* each event applied in order, from the lines kept *)
    let apply : Interp.Events.t -> unit = function
      | Notify { agent; percept; default; priority } -> check (Interp.Runtime.notify rt ~agent percept ~default ~priority)
      | Put { agent; obj } -> check (Interp.Runtime.put rt ~agent obj)
      | Message { agent; perf; content; during_step } ->
        check (Interp.Runtime.message ~during_step rt ~agent ~perf content)
      | Run k -> Interp.Runtime.run_rounds rt k
      | Run_rules k -> Interp.Runtime.run_rules rt k
      | Run_idle -> Interp.Runtime.run_until_idle rt in
    Option.iter (fun e -> Interp.Events.iter e apply) events;
    Interp.Runtime.run_until_idle rt;
    Interp.Runtime.finish rt;
    Option.iter close_out trace;
    flush stdout;
    ignore !host_error;   (* a refused notify (R2d) is the host's answer, not an error *)
    if !run_errors > 0 then 1 else 0
  with
  | code -> code
  | exception Stop code -> code
  | exception Sys_error m -> (try !try_writes m; 1 with Stop code -> code)
  | exception Out_of_memory ->
    (* the machine's memory ran out before --max-memory's bound (D22) was
       seen: the trace so far is flushed at exit *)
    flush_stdout_quietly ();
    prerr_endline "jadescript-ref: error: out of memory (the machine's, below --max-memory)";
    1
  | exception Semantics.Fault.Crash m ->
    (* a broken invariant of ours, never the program's or the host's fault *)
    flush stdout;
    report_at (match files with f :: _ -> f | [] -> "run") 1 1 ("internal error (a broken invariant): " ^ m);
    125

let cmd =
  let files = Arg.(non_empty & pos_all string [] & info [] ~docv:"FILE" ~doc:"The program's files.") in
  let agents = Arg.(value & opt_all string [] & info ["agent"] ~docv:"NAME:TYPE[:ARG,...]"
                      ~doc:"Create an agent (in the order given). Arguments are Jadescript literals, \
                            or @robome for a host object recording RoboMe commands.") in
  let agent_files = Arg.(value & opt_all string [] & info ["agents"] ~docv:"FILE"
                           ~doc:"Create the agents of FILE, one per line as --agent takes them (NAME:TYPE[:ARG,...]; \
                                 blank lines and lines starting with # left out), after those of --agent.") in
  let events = Arg.(value & opt (some string) None & info ["events"] ~docv:"FILE"
                      ~doc:"Host events, JSON lines (docs/trace-format.md).") in
  let trace = Arg.(value & opt (some string) None & info ["trace"] ~docv:"FILE"
                     ~doc:"Write the trace, JSON lines (docs/trace-format.md).") in
  let seed = Arg.(value & opt (some string) None & info ["seed"] ~docv:"N"
                    ~doc:"Interleave the agents in a random order drawn from this seed (R6), 0 to 2147483647; \
                          default round-robin.") in
  let max_steps = Arg.(value & opt string "1000000" & info ["max-steps"] ~docv:"N"
                         ~doc:"Stop after N agent steps, 0 to 4611686018427387903 (D20: rounds where every \
                               agent is idle are not run).") in
  let variant = Arg.(value & opt string "reference" & info ["variant"] ~docv:"V"
                       ~doc:"The agent loop: reference (the rulings), printed, budgeted or native.") in
  let fuel = Arg.(value & opt string "100000" & info ["fuel"] ~docv:"N"
                    ~doc:"Statements one handler or behaviour step may execute (R7), 1 to 2147483647.") in
  let capacity = Arg.(value & opt (some string) None & info ["o2a-capacity"] ~docv:"N"
                        ~doc:"Capacity of each agent's O2A queue (R2d), 1 to 2147483647; default unbounded.") in
  let max_memory = Arg.(value & opt string "2048" & info ["max-memory"] ~docv:"MB"
                          ~doc:"Megabytes of heap the run may take, 16 to 1048576 (D22): over it, the statement \
                                running is an exhaustion error (R7) and the run carries on.") in
  (* hidden: a deliberately defective interpreter (lib/defects), for the
     vectors' kill count (jadescript-ref defects) *)
  let defect = Arg.(value & opt (some string) None & info ["defect"] ~docs:Manpage.s_none ~docv:"NAME"
                      ~doc:"Run with this deliberate defect of the bug catalogue (lib/defects).") in
  let reference = Arg.(value & flag & info ["reference"]
                         ~doc:"Take every rule on the reference alone (the rules of lib/semantics and the \
                               evaluator's bodies, one rule at a time), not on the fast engine beside it: \
                               the same output and the same trace, more slowly.") in
  let level = Arg.(value & opt string "full" & info ["level"] ~docv:"L"
                     ~doc:"The trace's level: full (every rule of the loop), or observable (not the loop's own \
                           steps: transfer, dequeue, skip, end_dispatch, next_iteration, idle; \
                           docs/trace-format.md).") in
  let interleave = Arg.(value & opt (some string) None & info ["interleave"] ~docv:"SEED"
                          ~doc:"Run with the finer interleaving of R6 (D45), drawn at random from SEED (0 to \
                                2147483647): rules of different agents in any order, each message delivered \
                                after a delay, possibly during its receiver's behaviour step (R5d). Every such \
                                run is one the rulings allow. Default: the deterministic schedule.") in
  Cmd.v (Cmd.info "run" ~doc:"Run a Jadescript program on the reference semantics."
           ~man:[`S Manpage.s_description;
                 `P "Type-checks the program, creates the agents in order, applies the host \
                     events of $(b,--events) in order, then runs until every agent is idle \
                     (or $(b,--max-steps)). $(i,log e) prints $(i,NAME: text) on standard \
                     output. $(b,--trace) writes every observable step (R8) as JSON lines; \
                     docs/trace-format.md defines the format. A run-time error (R7) stops \
                     its handler or step and the run carries on; it is reported on standard \
                     error as $(i,FILE:LINE:COL: error: message) when it happens, and the exit \
                     status is then 1. A program, agent or events-file error stops before \
                     anything runs, with exit status 1. The events file is read once (a file, \
                     a pipe or a FIFO): every line is checked as it is read, and the run applies \
                     the events only once every line was found good (a line of at most 16 MB, \
                     a file of at most 1 GiB)."])
    Term.(const run $ files $ agents $ agent_files $ events $ trace $ seed $ max_steps $ variant $ fuel $ capacity $ max_memory $ defect
          $ reference $ level $ interleave)
