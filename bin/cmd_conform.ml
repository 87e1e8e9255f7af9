(* jadescript-ref conform [--impl 'COMMAND'] [--vectors DIR] [--update]
   [--judge] [--generated N [--seed S]] *)

open Cmdliner
module O = Interp.Oracle

let self_run () =
  let exe = Sys.executable_name in
  let exe = if Filename.is_relative exe then Filename.concat (Sys.getcwd ()) exe else exe in
  Filename.quote exe ^ " run"

(* A signal's number as the shell shows it (OCaml numbers signals its own way). *)
let signal_number s =
  List.assoc_opt s [ (Sys.sighup, 1); (Sys.sigint, 2); (Sys.sigquit, 3); (Sys.sigill, 4);
                     (Sys.sigabrt, 6); (Sys.sigfpe, 8); (Sys.sigkill, 9); (Sys.sigsegv, 11);
                     (Sys.sigpipe, 13); (Sys.sigalrm, 14); (Sys.sigterm, 15); (Sys.sigbus, 7) ]
  |> Option.value ~default:0

(* Run [sh -c cmd] under timeout(1), standard output to /dev/null and standard
   error to [errs]; its status as the shell gives it (Oracle.run_vector's
   [spawn]). Not Sys.command: system() ignores SIGINT while it waits, so ^C or
   a SIGINT to conform would be lost. When conform is interrupted here
   (Sys.Break, raised by the handler [run] installs), the implementation is
   stopped before the exception goes on, so that the oracle's cleanup removes
   the temporary files of a finished process. *)
let spawn ~timeout ~errs cmd =
  let null = Unix.openfile "/dev/null" [ Unix.O_RDWR ] 0 in
  let err = Unix.openfile errs [ Unix.O_WRONLY; Unix.O_TRUNC; Unix.O_CREAT ] 0o600 in
  let pid =
    Fun.protect ~finally:(fun () -> Unix.close null; Unix.close err) (fun () ->
        Unix.create_process "timeout"
          [| "timeout"; "--kill-after=5"; Printf.sprintf "%g" timeout; "/bin/sh"; "-c"; cmd |]
          null null err) in
  let rec wait () =
    match Unix.waitpid [] pid with
    | (_, status) -> status
    | exception Unix.Unix_error (Unix.EINTR, _, _) -> wait () in
  match wait () with
  | Unix.WEXITED c -> c
  | Unix.WSIGNALED s | Unix.WSTOPPED s -> 128 + signal_number s
  | exception e ->
    (* timeout(1) passes the signal on to the implementation's processes *)
    (try Unix.kill pid Sys.sigterm with Unix.Unix_error _ -> ());
    (try ignore (Unix.waitpid [] pid) with Unix.Unix_error _ -> ());
    raise e

let find_vectors = function
  | Some d -> d
  | None ->
    let rec up d = let p = Filename.concat d "conformance" in
      if Sys.file_exists p then p else let u = Filename.dirname d in if u = d then p else up u in
    up (Sys.getcwd ())

let rec run impl vectors update only timeout keep judge generated seed =
  (* ^C or a SIGTERM stops conform between two vectors or while one runs:
     the implementation is stopped and the temporary files removed
     (Oracle.run_vector), then exit 130. *)
  List.iter (fun s -> Sys.set_signal s (Sys.Signal_handle (fun _ -> raise Sys.Break)))
    [ Sys.sigint; Sys.sigterm ];
  match
    match generated with
    | Some n -> run_generated impl n seed timeout keep
    | None -> run_vectors impl vectors update only timeout keep judge
  with
  | code -> code
  | exception Sys.Break -> prerr_endline "jadescript-ref: error: conform interrupted"; 130

(* --generated N: N programs of lib/gen with random hosts, each run by the
   implementation and judged (bin/judged.ml); nothing to compare with. *)
and run_generated impl n seed timeout keep =
  if n < 1 || n > 1_000_000 then begin
    prerr_endline (Printf.sprintf "jadescript-ref: error: --generated %d: a number of programs from 1 to 1000000" n); 1
  end else begin
    let impl = match impl with Some c -> c | None -> self_run () in
    let timeout = Option.value timeout ~default:60. in
    (match keep with Some d when not (Sys.file_exists d) -> (try Sys.mkdir d 0o755 with Sys_error _ -> ()) | _ -> ());
    let failed = ref 0 in
    for k = 1 to n do
      let case = Judged.generated ~seed k in
      match Judged.judge_case ~spawn ~timeout ~impl ?keep case with
      | Ok () -> Printf.printf "%-44s pass\n%!" case.name
      | Error m -> incr failed; Printf.printf "%-44s FAIL: %s\n%!" case.name m
    done;
    Printf.printf "%d generated programs (seed %d): %d pass, %d fail\n" n seed (n - !failed) !failed;
    if !failed = 0 then 0 else 1
  end

and run_vectors impl vectors update only timeout keep judge =
  match timeout with
  | Some t when not (t > 0. && t <= 86400.) ->
    prerr_endline (Printf.sprintf "jadescript-ref: error: --timeout %g: a number of seconds above 0 and at most 86400" t); 1
  | _ ->
  let dir = find_vectors vectors in
  match O.load dir with
  | exception Failure m ->
    (* Oracle.load's failures are located at the vector.json already: one
       location, not the folder's before it *)
    let located = match String.split_on_char ':' m with
      | _ :: l :: c :: " error" :: _ -> int_of_string_opt l <> None && int_of_string_opt c <> None
      | _ -> false in
    prerr_endline (if located then m else dir ^ ":1:1: error: " ^ m); 1
  | exception Sys_error m -> prerr_endline (dir ^ ":1:1: error: " ^ m); 1
  | vs ->
    let vs = if only = [] then vs else List.filter (fun (v : O.vector) -> List.mem v.name only) vs in
    let impl = match impl with Some c -> c | None -> self_run () in
    (match keep with Some d when not (Sys.file_exists d) -> (try Sys.mkdir d 0o755 with Sys_error _ -> ()) | _ -> ());
    let failed = ref 0 in
    List.iter (fun (v : O.vector) ->
        if update then begin
          let out = Filename.concat v.dir "expected.jsonl" in
          let cmd = Printf.sprintf "cd %s && %s %s %s --events events.jsonl --trace expected.jsonl > /dev/null 2>&1"
              (Filename.quote v.dir) (self_run ())
              (String.concat " " (List.map Filename.quote v.files))
              (String.concat " " (List.map Filename.quote v.args)) in
          ignore (Sys.command cmd);
          ignore out
        end;
        let expectations =
          match O.check_expectations v.expect (O.read_trace (Filename.concat v.dir "expected.jsonl")) with
          | Ok () -> None
          | Error e -> Some e
          | exception (Failure e | Sys_error e) -> Some e in
        match expectations with
        | Some e ->
          incr failed;
          Printf.printf "%-44s %-14s BROKEN VECTOR: its expected trace fails its assertions: %s\n%!"
            v.name (String.concat "," v.rulings) e
        | None when judge ->
          let timeout = match timeout with Some t -> t | None -> O.default_timeout v in
          (match Judged.judge_case ~spawn ~timeout ~impl ?keep (Judged.of_vector v) with
           | Ok () -> Printf.printf "%-44s %-14s pass (judged)\n%!" v.name (String.concat "," v.rulings)
           | Error m ->
             incr failed;
             Printf.printf "%-44s %-14s FAIL: %s\n%!" v.name (String.concat "," v.rulings) m)
        | None ->
          (* a fresh directory with only the program and the events: the
             expected trace is not where the implementation runs *)
          let workdir = Judged.fresh_dir () in
          let outcome =
            Fun.protect ~finally:(fun () -> Judged.remove_tree workdir) (fun () ->
                List.iter (fun f ->
                    Judged.write_file (Filename.concat workdir (Filename.basename f)) (Judged.read_file (Filename.concat v.dir f)))
                  (v.files @ (if Sys.file_exists (Filename.concat v.dir "events.jsonl") then [ "events.jsonl" ] else []));
                O.run_vector ~spawn ?timeout ?keep ~workdir ~impl v) in
          match outcome with
          | O.Pass -> Printf.printf "%-44s %-14s pass\n%!" v.name (String.concat "," v.rulings)
          | O.Diverge { index; expected; got } ->
            incr failed;
            Printf.printf "%-44s %-14s FAIL at event %d\n    expected: %s\n    got:      %s\n%!"
              v.name (String.concat "," v.rulings) index expected got
          | O.Failed m ->
            incr failed;
            Printf.printf "%-44s %-14s FAIL: %s\n%!" v.name (String.concat "," v.rulings) m) vs;
    Printf.printf "%d vectors: %d pass, %d fail\n" (List.length vs) (List.length vs - !failed) !failed;
    if !failed = 0 then 0 else 1

let cmd =
  let impl = Arg.(value & opt (some string) None & info ["impl"] ~docv:"COMMAND"
                    ~doc:"The implementation: a command taking run's arguments (FILES --agent ... \
                          --events F --trace F) and writing a trace. Default: jadescript-ref run.") in
  let vectors = Arg.(value & opt (some string) None & info ["vectors"] ~docv:"DIR"
                       ~doc:"The folder of vectors (default: conformance/ of the repository).") in
  let update = Arg.(value & flag & info ["update"]
                      ~doc:"Rewrite each expected.jsonl with jadescript-ref (for vector authors); \
                            the vector's assertions are still checked.") in
  let only = Arg.(value & pos_all string [] & info [] ~docv:"VECTOR" ~doc:"Only these vectors.") in
  let keep = Arg.(value & opt (some string) None & info ["keep"] ~docv:"DIR"
                    ~doc:"Keep each trace the implementation wrote as DIR/VECTOR.jsonl (for validate).") in
  let timeout = Arg.(value & opt (some float) None & info ["timeout"] ~docv:"SECONDS"
                       ~doc:"Time limit of one vector's run (default: 30 s plus 0.05 s per expected \
                             event); an implementation still running then is killed and fails.") in
  let judge = Arg.(value & flag & info ["judge"]
                     ~doc:"Judge each run by the program's semantics (jadescript-ref judge) instead of \
                           comparing it with the expected trace: any schedule the rulings allow passes \
                           (R6). The implementation runs in a fresh directory that holds only the \
                           program and the events file.") in
  let generated = Arg.(value & opt (some int) None & info ["generated"] ~docv:"N"
                         ~doc:"Instead of the vectors, N generated well-typed programs with random hosts \
                               (lib/gen), each run by the implementation in a fresh directory and judged: \
                               there is no expected trace to copy. Case K of seed S is named \
                               generated-S-K and is the same on every machine.") in
  let seed = Arg.(value & opt int 1 & info ["seed"] ~docv:"S" ~doc:"The seed of --generated (default 1).") in
  Cmd.v (Cmd.info "conform" ~doc:"Run an implementation on the conformance vectors."
           ~man:[`S Manpage.s_description;
                 `P "Runs the implementation on every vector of conformance/ and compares \
                     its trace with the expected one, event by event; reports each vector's \
                     pass or failure with the first diverging event. Each vector's expected \
                     trace is first checked against the vector's own assertions \
                     (docs/trace-format.md). The implementation must also end within \
                     $(b,--timeout), exit with status 0 (or 1 exactly when its trace records \
                     a run-time error, D15) and write the expected header. Exit status 1 \
                     when a vector fails.";
                 `P "With $(b,--judge), each run is judged by the program's semantics instead \
                     (docs/trace-format.md, \"Judging a run\"); with $(b,--generated) N, N \
                     generated programs take the place of the vectors."])
    Term.(const run $ impl $ vectors $ update $ only $ timeout $ keep $ judge $ generated $ seed)
