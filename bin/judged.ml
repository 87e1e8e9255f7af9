(* conform --judge and conform --generated N: an implementation's runs
   decided by their program's semantics (lib/judge), not compared with the
   reference's own trace (docs/trace-format.md, "Judging a run").

   Each case is run in a fresh directory holding only the program and the
   events file: the implementation cannot find an expected trace to copy,
   and a generated case has none anywhere. Its trace must be one the judge
   accepts, of a run that ended (every agent destroyed, D14), and its exit
   status 0, or 1 exactly when the trace records a run-time error (D15). *)

type case = {
  name : string;
  files : (string * string) list;   (* file name, text *)
  events : string;                  (* the events file's text *)
  args : string list;               (* run's options: --agent ..., --fuel ... *)
}

(* The values of [--opt V] and [--opt=V] among [args], in order. *)
let option_values opt args =
  let eq = opt ^ "=" in
  let rec go acc = function
    | o :: v :: rest when o = opt -> go (v :: acc) rest
    | a :: rest when String.length a > String.length eq && String.sub a 0 (String.length eq) = eq ->
      go (String.sub a (String.length eq) (String.length a - String.length eq) :: acc) rest
    | _ :: rest -> go acc rest
    | [] -> List.rev acc in
  go [] args

let read_file path =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () -> really_input_string ic (in_channel_length ic))

let write_file path text =
  let oc = open_out_bin path in
  Fun.protect ~finally:(fun () -> close_out_noerr oc) (fun () -> output_string oc text)

(* A new empty directory of the system's temporary ones. *)
let fresh_dir () =
  let rec go k =
    let d = Filename.concat (Filename.get_temp_dir_name ())
        (Printf.sprintf "jsref-judged-%d-%d-%d" (Unix.getpid ()) k (Random.bits ())) in
    match Unix.mkdir d 0o700 with
    | () -> d
    | exception Unix.Unix_error (Unix.EEXIST, _, _) -> go (k + 1) in
  go 0

let remove_tree d =
  Array.iter (fun f -> try Sys.remove (Filename.concat d f) with Sys_error _ -> ()) (try Sys.readdir d with Sys_error _ -> [||]);
  try Unix.rmdir d with Unix.Unix_error _ -> ()

(* A conformance vector as a case: its program files and events, its
   options; nothing of its expected trace. *)
let of_vector (v : Interp.Oracle.vector) =
  { name = v.name;
    files = List.map (fun f -> (Filename.basename f, read_file (Filename.concat v.dir f))) v.files;
    events = (let e = Filename.concat v.dir "events.jsonl" in if Sys.file_exists e then read_file e else "");
    args = v.args }

(* Generated case [k] of seed [seed]: a well-typed program of lib/gen and a
   random host for it (agents, events, options), drawn from (seed, k) alone,
   so that "generated-S-K" names it for good. *)
let generated ~seed k =
  let rand = Random.State.make [| seed; k |] in
  let prog = QCheck.Gen.generate1 ~rand Gen.Typed_gen.program in
  let text = Syntax.Print.program prog in
  let env, _ = Typing.check [ Syntax.Parse.string ~file:"program.jade" text ] in
  let sc = QCheck.Gen.generate1 ~rand (Gen.Event_gen.scenario env ~agent_type:"Ag") in
  { name = Printf.sprintf "generated-%d-%d" seed k;
    files = [ ("program.jade", text) ];
    events = Gen.Event_gen.events_file sc;
    args = List.concat_map (fun a -> [ "--agent"; a ]) (Gen.Event_gen.agent_args sc) @ Gen.Event_gen.run_args sc }

(* The implementation on [case]; [Ok ()] when the judge accepts its run. *)
let judge_case ~spawn ~timeout ~impl ?keep case =
  let dir = fresh_dir () in
  Fun.protect ~finally:(fun () ->
      (match keep with
       | Some k ->
         (* the case and the implementation's trace, to judge or replay again *)
         let into = Filename.concat k case.name in
         (try Unix.mkdir into 0o755 with Unix.Unix_error _ -> ());
         Array.iter (fun f -> try write_file (Filename.concat into f) (read_file (Filename.concat dir f)) with Sys_error _ -> ())
           (try Sys.readdir dir with Sys_error _ -> [||])
       | None -> ());
      remove_tree dir) (fun () ->
      List.iter (fun (f, text) -> write_file (Filename.concat dir f) text) case.files;
      write_file (Filename.concat dir "events.jsonl") case.events;
      let trace = Filename.concat dir "trace.jsonl" and errs = Filename.concat dir "stderr.txt" in
      let cmd = Printf.sprintf "cd %s && %s %s %s --events events.jsonl --trace trace.jsonl"
          (Filename.quote dir) impl
          (String.concat " " (List.map (fun (f, _) -> Filename.quote f) case.files))
          (String.concat " " (List.map Filename.quote case.args)) in
      let code = spawn ~timeout ~errs cmd in
      let because m = match Interp.Oracle.first_line errs with "" -> m | l -> m ^ " (its stderr: " ^ l ^ ")" in
      if code <> 0 && code <> 1 then Error (because ("the implementation " ^ Interp.Oracle.describe_status ~timeout code))
      else if not (Sys.file_exists trace) then Error (because "the implementation wrote no trace")
      else
        match
          (* the program as the implementation was given it: file names
             relative to the case's directory, as its errors' positions *)
          let env = Cmd_run.load_texts case.files in
          let agents = List.map (Cmd_run.agent_spec env) (option_values "--agent" case.args) in
          let fuel = match option_values "--fuel" case.args with
            | f :: _ -> Option.value (int_of_string_opt f) ~default:Judge.default_options.fuel
            | [] -> Judge.default_options.fuel in
          Judge.judge env ~agents ~options:{ Judge.default_options with fuel } trace
        with
        | exception Cmd_run.Stop _ -> Error "the case's program or agents are not good (see above)"
        | Judge.Rejected { line; message } -> Error (because (Printf.sprintf "its trace, line %d: %s" line message))
        | Judge.Accepted { complete = false; _ } ->
          Error (because "its run did not end: not every agent was destroyed (D14)")
        | Judge.Accepted { cut = true; _ } -> Error (because "its trace's last line is cut")
        | Judge.Accepted _ ->
          (* D15: status 1 exactly when the run recorded a run-time error *)
          let errors = List.exists Trace.is_error (Interp.Oracle.read_trace trace) in
          if code = 1 && not errors then Error (because "the implementation exited with status 1, but its trace records no run-time error")
          else if code = 0 && errors then Error "the implementation exited with status 0, but its trace records a run-time error (D15: status 1)"
          else Ok ())
