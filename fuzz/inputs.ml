(* The fuzz campaign's targets and oracles (see inputs.mli). *)

open Syntax
module TG = Test_support.Typed_gen
module EG = Test_support.Event_gen
module Ev = Interp.Events
module Rt = Interp.Runtime
module Mc = Semantics.Machine

module Tamper = Test_support.Tamper

type outcome = Pass | Finding of { kind : string; message : string }

type target = {
  name : string;
  limit : float;
  memory : int;
  run : keep:string option -> seed:int -> int -> outcome;
}

external setrlimit : int -> int -> bool = "fuzz_setrlimit"

let memory_bound = ref 0
let run_memory_bound () = !memory_bound
external die_with_parent : unit -> bool = "fuzz_die_with_parent"
let bound_memory bytes =
  memory_bound := bytes; ignore (setrlimit 0 bytes); ignore (setrlimit 2 0); ignore (die_with_parent ())

(* D22, as run's --max-memory: the runs in this child stop at half its
   address space, an exhaustion error, before the system refuses memory *)
let run_memory () = if !memory_bound > 0 then Some (max 16 (!memory_bound / 2 / 1_048_576)) else None

let finding kind message =
  Finding { kind; message = String.map (function '\n' | '\r' -> ' ' | c -> c) message }

exception Found of outcome
let fail kind fmt = Printf.ksprintf (fun m -> raise (Found (finding kind m))) fmt

let int rs n = Random.State.int rs n
let chance rs p = Random.State.float rs 1.0 < p
let pick rs l = List.nth l (int rs (List.length l))

let rng ~seed target index = Random.State.make [| seed; Hashtbl.hash target; index |]

(* ------------------------------------------------------------ helpers *)

let valid_utf8 s = Utf8.first_invalid s = None

let write_file path s =
  let oc = open_out_bin path in
  Fun.protect ~finally:(fun () -> close_out_noerr oc) (fun () -> output_string oc s)

let read_file path =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () -> really_input_string ic (in_channel_length ic))

let lines_of s = List.filter (fun l -> l <> "") (String.split_on_char '\n' s)

let contains s sub =
  let n = String.length s and m = String.length sub in
  let rec go i = i + m <= n && (String.sub s i m = sub || go (i + 1)) in
  go 0

let starts_with p s = String.length s >= String.length p && String.sub s 0 (String.length p) = p

(* FILE:LINE:COL: error: ... (or warning), with LINE >= 1 and COL >= 1 *)
let located_line l =
  let re_ok =
    match String.split_on_char ':' l with
    | _file :: line :: col :: rest ->
      (match int_of_string_opt line, int_of_string_opt col with
       | Some ln, Some c when ln >= 1 && c >= 1 ->
         let rest = String.concat ":" rest in
         starts_with " error: " rest || starts_with " warning: " rest
       | _ -> false)
    | _ -> false in
  re_ok || starts_with "jadescript-ref: error: " l || starts_with "error: " l
  || (starts_with "--agent " l && contains l ": error: ")
  || starts_with "host: " l

let rec remove_tree p =
  match (Unix.lstat p).st_kind with
  | Unix.S_DIR ->
    Array.iter (fun f -> remove_tree (Filename.concat p f)) (Sys.readdir p);
    (try Unix.rmdir p with Unix.Unix_error _ -> ())
  | _ -> (try Sys.remove p with Sys_error _ -> ())
  | exception Unix.Unix_error _ -> ()

(* What a child killed in the middle of an input left in the temporary
   folder: every name there starts with jsref-fuzz-PID-. *)
let remove_leftovers pid =
  let base = Filename.get_temp_dir_name () in
  let prefix = Printf.sprintf "jsref-fuzz-%d-" pid in
  let n = String.length prefix in
  Array.iter (fun f -> if String.length f > n && String.sub f 0 n = prefix then remove_tree (Filename.concat base f))
    (try Sys.readdir base with Sys_error _ -> [||])

let fresh_dir () =
  let base = Filename.get_temp_dir_name () in
  let rec go k =
    let d = Filename.concat base (Printf.sprintf "jsref-fuzz-%d-%d" (Unix.getpid ()) k) in
    if Sys.file_exists d then go (k + 1) else (Unix.mkdir d 0o700; d) in
  go 0

(* Work in a fresh folder (or [keep]), removed afterwards unless kept. *)
let in_dir keep f =
  match keep with
  | Some d -> (if not (Sys.file_exists d) then Unix.mkdir d 0o755); f d
  | None ->
    let d = fresh_dir () in
    Fun.protect ~finally:(fun () -> remove_tree d) (fun () -> f d)

let jsref () =
  match Sys.getenv_opt "JSREF_EXE" with
  | Some e when e <> "" -> e
  | _ ->
    let exe = Sys.executable_name in
    let exe = if Filename.is_relative exe then Filename.concat (Sys.getcwd ()) exe else exe in
    Filename.concat (Filename.dirname (Filename.dirname exe)) "bin/main.exe"

(* ---------------------------------------------------------- processes *)

let read_all_fd fd max =
  let b = Buffer.create 4096 and chunk = Bytes.create 65536 in
  let rec go () =
    match Unix.read fd chunk 0 65536 with
    | 0 -> ()
    | n -> if Buffer.length b < max then Buffer.add_subbytes b chunk 0 n; go ()
    | exception Unix.Unix_error (Unix.EINTR, _, _) -> go () in
  go (); Buffer.contents b

let run_command ?(timeout = 30.0) ?(memory = 2_000_000_000) argv =
  let prefix = Printf.sprintf "jsref-fuzz-%d-" (Unix.getpid ()) in
  let out = Filename.temp_file prefix ".out" and err = Filename.temp_file prefix ".err" in
  Fun.protect ~finally:(fun () -> List.iter (fun f -> try Sys.remove f with Sys_error _ -> ()) [ out; err ])
    (fun () ->
       let fo = Unix.openfile out [ Unix.O_WRONLY; Unix.O_TRUNC ] 0o600
       and fe = Unix.openfile err [ Unix.O_WRONLY; Unix.O_TRUNC ] 0o600 in
       let pid = Unix.fork () in
       if pid = 0 then begin
         (try
            ignore (setrlimit 0 memory); ignore (setrlimit 2 0);
            Unix.dup2 fo Unix.stdout; Unix.dup2 fe Unix.stderr;
            let nul = Unix.openfile "/dev/null" [ Unix.O_RDONLY ] 0 in
            Unix.dup2 nul Unix.stdin;
            ignore (Unix.setsid ());
            Unix.execv argv.(0) argv
          with _ -> ());
         Unix._exit 127
       end;
       Unix.close fo; Unix.close fe;
       let t0 = Unix.gettimeofday () in
       let rec wait () =
         match Unix.waitpid [ Unix.WNOHANG ] pid with
         | (0, _) ->
           if Unix.gettimeofday () -. t0 > timeout then begin
             (try Unix.kill (-pid) Sys.sigkill with Unix.Unix_error _ -> ());
             (try Unix.kill pid Sys.sigkill with Unix.Unix_error _ -> ());
             ignore (Unix.waitpid [] pid);
             Unix.WSIGNALED Sys.sigkill
           end else (Unix.sleepf 0.002; wait ())
         | (_, st) -> st
         | exception Unix.Unix_error (Unix.EINTR, _, _) -> wait () in
       let st = wait () in
       let slurp f = let fd = Unix.openfile f [ Unix.O_RDONLY ] 0 in
         Fun.protect ~finally:(fun () -> Unix.close fd) (fun () -> read_all_fd fd 1_000_000) in
       (st, slurp out, slurp err))

let judge_process ?(expect_error = false) ~status ~stderr () =
  let lines = lines_of stderr in
  let first_bad = List.find_opt (fun l -> not (located_line l)) lines in
  match status with
  | Unix.WSIGNALED s when s = Sys.sigkill -> finding "hang" "killed after its time limit"
  | Unix.WSIGNALED s | Unix.WSTOPPED s -> finding "crash" (Printf.sprintf "signal %d; stderr: %s" s (String.concat " | " lines))
  | Unix.WEXITED k when k <> 0 && k <> 1 ->
    finding "crash" (Printf.sprintf "exit %d; stderr: %s" k
                       (String.sub stderr 0 (min 300 (String.length stderr))))
  | Unix.WEXITED k ->
    (match first_bad with
     | Some l -> finding "unlocated error" (Printf.sprintf "exit %d, stderr line: %s" k
                                              (String.sub l 0 (min 200 (String.length l))))
     | None ->
       if expect_error && k = 0 then finding "accepted bad input" "exit 0 on an input that must be refused"
       else if k = 1 && lines = [] then finding "unlocated error" "exit 1 with nothing on stderr"
       else Pass)

(* ------------------------------------------------------------- parse *)

let keywords = [ "agent"; "behaviour"; "cyclic"; "one"; "shot"; "on"; "percept"; "when"; "content";
                 "matches"; "do"; "if"; "else"; "while"; "for"; "in"; "return"; "activate";
                 "deactivate"; "ontology"; "predicate"; "proposition"; "concept"; "action";
                 "extends"; "with"; "priority"; "function"; "procedure"; "as"; "of"; "send";
                 "message"; "log"; "and"; "or"; "not"; "="; "("; ")"; "["; "]"; ":"; ","; "\t"; "\n" ]

let splice_at s pos ins = String.sub s 0 pos ^ ins ^ String.sub s pos (String.length s - pos)

let deep rs =
  (* 100,000 deep is the size of the first reports, and costly: rare *)
  let d = if int rs 300 = 0 then 100_000 else pick rs [ 50; 50; 190; 190; 500; 500; 2_000; 5_000; 20_000 ] in
  match int rs 6 with
  | 0 -> String.make d '(' ^ "1" ^ String.make d ')'
  | 1 -> String.concat "" (List.init d (fun _ -> "not ")) ^ "true"
  | 2 -> String.make d '[' ^ "1" ^ String.make d ']'
  | 3 -> String.concat " + " (List.init d (fun _ -> "1"))
  | 4 -> String.concat "" (List.init (min d 2_000) (fun k -> "\n" ^ String.make (k + 2) '\t' ^ "if true do"))
         ^ "\n" ^ String.make (min d 2_000 + 2) '\t' ^ "log 1"
  | _ -> String.concat "" (List.init d (fun _ -> "-")) ^ "1"

let huge rs =
  match int rs 6 with
  | 0 -> String.init (pick rs [ 11; 20; 400; 5_000 ]) (fun i -> if i = 0 then '9' else Char.chr (48 + int rs 10))
  | 1 -> "\"" ^ String.make (pick rs [ 1_000; 1_000; 100_000; 1_000_000 ]) 'x' ^ "\""
  | 2 -> String.make (pick rs [ 1_000; 50_000 ]) 'a'
  | 3 -> "1e" ^ String.make (pick rs [ 3; 400 ]) '9'
  | 4 -> "0." ^ String.make 10_000 '1'
  | _ -> "\"" ^ String.concat "" (List.init 2_000 (fun _ -> "\\n\\t\\\"")) ^ "\""

let mutate_text rs text other =
  let n = String.length text in
  let pos () = if n = 0 then 0 else int rs (n + 1) in
  (* deep nesting and huge literals cost far more than the rest: rarer *)
  match pick rs [ 0; 0; 0; 1; 1; 1; 2; 2; 2; 3; 4; 4; 5; 5; 5; 6; 6; 6; 7; 7; 7; 8; 8; 8; 9; 9; 9 ] with
  | 0 ->
    let b = Bytes.of_string text in
    for _ = 1 to 1 + int rs 8 do
      if n > 0 then Bytes.set b (int rs n) (Char.chr (pick rs [ int rs 256; 9; 10; 32; 34; 40; 41; 0xC3; 0xFF ]))
    done;
    Bytes.to_string b
  | 1 ->
    let m = String.length other in
    if m = 0 then text else
      let a = int rs m in
      let len = min (m - a) (1 + int rs 80) in
      splice_at text (pos ()) (String.sub other a len)
  | 2 -> String.sub text 0 (pos ())
  | 3 ->
    (* an expression or block nested deeply, where an expression may stand *)
    let lines = String.split_on_char '\n' text in
    let k = int rs (max 1 (List.length lines)) in
    String.concat "\n" (List.mapi (fun i l -> if i = k then l ^ "\n\t\tlog " ^ deep rs else l) lines)
  | 4 ->
    (* a literal replaced by a huge one *)
    let lines = String.split_on_char '\n' text in
    let k = int rs (max 1 (List.length lines)) in
    String.concat "\n" (List.mapi (fun i l -> if i = k then l ^ "\n\t\tlog " ^ huge rs else l) lines)
  | 5 ->
    let lines = Array.of_list (String.split_on_char '\n' text) in
    let m = Array.length lines in
    if m < 2 then text else begin
      let i = int rs m and j = int rs m in
      (match int rs 3 with
       | 0 -> let t = lines.(i) in lines.(i) <- lines.(j); lines.(j) <- t
       | 1 -> lines.(i) <- ""
       | _ -> lines.(i) <- lines.(j));
      String.concat "\n" (Array.to_list lines)
    end
  | 6 ->
    (* indentation damage *)
    String.concat "\n" (List.map (fun l ->
        if chance rs 0.1 then (match int rs 3 with 0 -> "\t" ^ l | 1 -> "  " ^ l
                                                 | _ -> if l <> "" && l.[0] = '\t' then String.sub l 1 (String.length l - 1) else l)
        else l) (String.split_on_char '\n' text))
  | 7 -> String.init (int rs 300) (fun _ -> Char.chr (int rs 256))
  | 8 -> splice_at text (pos ()) (" " ^ pick rs keywords ^ " ")
  | _ ->
    (* invalid UTF-8 or control bytes inside a text literal *)
    (match String.index_opt text '"' with
     | Some i -> splice_at text (i + 1) (pick rs [ "\xff\xfe"; "\xc3"; "\xed\xa0\x80"; "\x00"; "\x1b[0m"; "\xf4\x90\x80\x80" ])
     | None -> text ^ "\n\xff")

let located_diag ~file (d : Diag.t) =
  d.at.left.line >= 1 && d.at.left.column >= 1 && d.at.left.file = file

let check_diags ~file what diags =
  List.iter (fun (d : Diag.t) ->
      if d.severity = Diag.Error && not (located_diag ~file d) then
        fail "unlocated error" "%s: %s" what (Diag.to_string d)) diags

let parse_and_check ~file text =
  match Parse.string ~file text with
  | exception Diag.Failed d ->
    if not (located_diag ~file d) then fail "unlocated error" "parse: %s" (Diag.to_string d);
    None
  | r ->
    (* the printer: what it prints parses back and prints the same *)
    let printed = Print.program ~comments:r.comments r.program in
    (match Parse.string ~file printed with
     | exception Diag.Failed d -> fail "fmt" "the printed program does not parse: %s" (Diag.to_string d)
     | r2 ->
       let again = Print.program ~comments:r2.comments r2.program in
       if again <> printed then fail "fmt" "printing is not stable (print . parse . print differs)");
    let (env, diags) = Typing.check [ r ] in
    check_diags ~file "check" diags;
    Some (env, diags)

let bases_memo = ref None
let bases ~seed k =
  match !bases_memo with
  | Some (s, k', b) when s = seed && k' = k -> b
  | _ ->
    let b = (Print.program (TG.program (rng ~seed "parse-base" k)),
             Print.program (TG.program (rng ~seed "parse-base" (k + 1)))) in
    bases_memo := Some (seed, k, b); b

let parse_target ~keep ~seed index =
  let rs = rng ~seed "parse" index in
  (* the base programs change every 50 inputs (generating them costs more
     than parsing) *)
  let (base, other) = bases ~seed (index / 50) in
  let text = ref base in
  for _ = 1 to 1 + int rs 3 do text := mutate_text rs !text other done;
  Option.iter (fun d -> in_dir (Some d) (fun d -> write_file (Filename.concat d "program.jade") !text)) keep;
  ignore (parse_and_check ~file:"fuzz.jade" !text);
  Pass

(* ------------------------------------------------------------- check *)

let check_target ~keep ~seed index =
  let rs = rng ~seed "check" index in
  let p = TG.program rs in
  let mutated = chance rs 0.5 in
  let (prog, expect) =
    if mutated then let m = TG.mutate p rs in (m.program, Some (m.name, m.fragment)) else (p, None) in
  let text = Print.program prog in
  Option.iter (fun d -> in_dir (Some d) (fun d -> write_file (Filename.concat d "program.jade") text)) keep;
  (match parse_and_check ~file:"gen.jade" text with
   | None -> fail "generator" "a generated program does not parse"
   | Some (_, diags) ->
     let errors = List.filter (fun (d : Diag.t) -> d.severity = Diag.Error) diags in
     match expect with
     | None ->
       if errors <> [] then fail "generator" "a generated program does not check: %s"
           (Diag.to_string (List.hd errors))
     | Some (name, fragment) ->
       if not (List.exists (fun (d : Diag.t) ->
           contains d.message fragment) errors)
       then fail "mutation not caught" "mutation %s: no error containing %S%s" name fragment
           (match errors with d :: _ -> " (first: " ^ Diag.to_string d ^ ")" | [] -> ""));
  Pass

(* --------------------------------------------------------------- run *)

let tlc_every = ref 2000

let program_env ~file text =
  match Parse.string ~file text with
  | exception Diag.Failed d -> fail "generator" "does not parse: %s" (Diag.to_string d)
  | r ->
    let (env, diags) = Typing.check [ r ] in
    (match List.filter (fun (d : Diag.t) -> d.severity = Diag.Error) diags with
     | d :: _ -> fail "generator" "does not check: %s" (Diag.to_string d)
     | [] -> env)

(* The trace oracle: valid UTF-8 and JSON line by line, a header first, the
   trace reader (lib/trace) accepts it, and every agent was destroyed (D14):
   the run lost nothing. *)
let judge_trace ~agents path =
  let text = read_file path in
  if not (valid_utf8 text) then fail "bad trace" "the trace is not valid UTF-8";
  List.iteri (fun i l ->
      match Yojson.Safe.from_string l with
      | exception Yojson.Json_error m -> fail "bad trace" "line %d is not JSON: %s" (i + 1) m
      | j -> if i = 0 && not (Trace.is_header j) then fail "bad trace" "no header") (lines_of text);
  match Trace.read_file path with
  | Error m -> fail "bad trace" "the trace reader rejects it: %s" m
  | Ok (_, lines) ->
    List.iter (fun a ->
        if not (List.exists (fun (_, (l : Trace.line)) -> l.agent = a && l.event = Trace.Destroy) lines) then
          fail "bad trace" "agent %s has no destroy event (the run lost its end)" a) agents

let trace_problem path =
  match judge_trace ~agents:[] path with
  | () -> None
  | exception Found (Finding f) -> Some f.message
  | exception Found Pass -> None

let agent_value env a =
  match List.assoc_opt a (Interp.Host.objects ()) with
  | Some v -> v
  | None -> Interp.Eval.literal_value env (Parse.expr ~file:"--agent" a)

(* Runs a program on a scenario in-process, as [run] does, trace to [trace]. *)
let run_scenario env (sc : EG.scenario) ~events ~trace =
  write_file events (EG.events_file sc);
  let agents = List.map (fun (n, ty, _) -> (n, ty)) sc.agents in
  let problems = ref [] in
  let report ~line ~col m = problems := Printf.sprintf "%d:%d: %s" line col m :: !problems in
  let kept = match Ev.read env ~agents events ~report with
    | Ok f -> f
    | Error _ -> fail "generator" "the generated events file is rejected: %s" (List.hd (List.rev !problems)) in
  let specs = List.map (fun (n, ty, args) ->
      match List.map (agent_value env) args with
      | vs -> (n, ty, vs)
      | exception Diag.Failed d -> fail "generator" "agent argument: %s" (Diag.to_string d)
      | exception (Interp.Eval.Trap (_, m) | Interp.Eval.Link (_, m)) -> fail "generator" "agent argument: %s" m)
      sc.agents in
  let oc = open_out_bin trace in
  let errors = ref 0 in
  let on_error _ (_ : Source.region) msg =
    incr errors;
    if String.contains msg '\n' then fail "unlocated error" "a run-time error of several lines: %s" msg in
  let params = { Mc.default_params with variant = sc.variant; tie = sc.tie; budget = sc.budget;
                                        o2a_capacity = sc.capacity } in
  let opts = { Rt.params; engine = Rt.Fast; seed = sc.seed; interleave = None; fuel = sc.fuel; max_steps = sc.max_steps;
               max_memory = run_memory (); level = "full"; trace = Some oc; on_log = (fun _ _ -> ()); on_error } in
  let rt = match Rt.create env opts specs with
    | rt -> rt
    | exception Interp.Eval.Link (_, m) -> close_out_noerr oc; fail "generator" "link error at creation: %s" m in
  let apply : Ev.t -> unit = function
    | Notify { agent; percept; default; priority } -> ignore (Rt.notify rt ~agent percept ~default ~priority)
    | Put { agent; obj } -> ignore (Rt.put rt ~agent obj)
    | Message { agent; perf; content; during_step } -> ignore (Rt.message ~during_step rt ~agent ~perf content)
    | Run k -> Rt.run_rounds rt k
    | Run_rules k -> Rt.run_rules rt k
    | Run_idle -> Rt.run_until_idle rt in
  Ev.iter kept apply;
  Rt.run_until_idle rt;
  Rt.finish rt;
  close_out_noerr oc;
  judge_trace ~agents:(List.map fst agents) trace

(* TLC's JVM runs without the child's memory bound (its heap is its own). *)
let without_memory_bound f =
  let bound = !memory_bound in
  ignore (setrlimit 0 (-1));
  Fun.protect ~finally:(fun () -> if bound > 0 then ignore (setrlimit 0 bound)) f

let validate path = without_memory_bound (fun () -> Explore.Validate.trace path)

let tlc_judge trace =
  match validate trace with
  | verdicts ->
    List.iter (function
        | Explore.Validate.Rejected { agent; line; step; _ } ->
          fail "rejected by TLC" "agent %s, line %d: %s" agent line step
        | _ -> ()) verdicts
  | exception Failure m -> fail "rejected by TLC" "validate: %s" m
  | exception Explore.Tlc.Error m -> fail "tlc" "TLC failed: %s" m

(* A well-typed program of Typed_gen, printed and checked, with a host
   scenario of Event_gen for its agent type Ag: what the run, cli, validate
   and tamper targets start from. *)
let generated rs =
  let text = Print.program (TG.program rs) in
  let env = program_env ~file:"gen.jade" text in
  (text, env, EG.scenario env ~agent_type:"Ag" rs)

let run_target ~keep ~seed index =
  let rs = rng ~seed "run" index in
  let (text, env, sc) = generated rs in
  in_dir keep (fun d ->
      write_file (Filename.concat d "program.jade") text;
      let trace = Filename.concat d "trace.jsonl" in
      if keep <> None then
        write_file (Filename.concat d "command")
          (String.concat " " (List.map Filename.quote
                                ([ "jadescript-ref"; "run"; "program.jade" ]
                                 @ List.concat_map (fun a -> [ "--agent"; a ]) (EG.agent_args sc)
                                 @ EG.run_args sc @ [ "--events"; "events.jsonl"; "--trace"; "trace.jsonl" ]))
           ^ Printf.sprintf "\n# tie policy %s, budget %d (no command-line option)\n"
             (match sc.tie with Mc.Stable -> "stable" | Mc.Unstable -> "unstable") sc.budget);
      run_scenario env sc ~events:(Filename.concat d "events.jsonl") ~trace;
      if !tlc_every > 0 && index mod !tlc_every = 0 then tlc_judge trace);
  Pass

(* ------------------------------------------------------------ limits *)

let limits_target ~keep ~seed index =
  let rs = rng ~seed "limits" index in
  let l = TG.limit rs in
  (* raw bytes in a text literal may be refused at the source, and an
     expression nested more than 1,000 deep is (D27), located *)
  if (l.kind = "raw bytes" || l.kind = "deep expression") && (match parse_and_check ~file:"limit.jade" l.text with
      | None -> true
      | Some (_, diags) -> Typing.has_errors diags) then raise (Found Pass);
  let env = program_env ~file:"limit.jade" l.text in
  let n_agents = 1 + int rs 2 in
  let names = [ "g"; "Bob" ] in
  let agents = List.init n_agents (fun i -> (List.nth names i, "Ag", [])) in
  let events = List.init (1 + int rs 3) (fun _ ->
      Ev.Notify_text { agent = List.nth names (int rs n_agents);
                       percept = Printf.sprintf "tick(%d)" (pick rs [ 0; 5; 300; 100_000 ]); priority = None })
               @ (if chance rs 0.3 then
                    (* rounds where every agent is idle: they count against --max-steps *)
                    [ Ev.Run_rounds (if chance rs 0.05 then max_int else pick rs [ 1_000; 1_000_000 ]) ]
                  else [])
               @ [ Ev.Run_until_idle ] in
  let sc = { EG.agents; events; variant = pick rs [ Mc.Reference; Mc.Native; Mc.Budgeted ]; tie = Mc.Stable;
             budget = 1; capacity = None; seed = None;
             fuel = pick rs [ 100_000; 100_000; 1_000_000; 1_000 ];
             max_steps = pick rs [ 1_000_000; 1_000; 10 ] } in
  in_dir keep (fun d ->
      write_file (Filename.concat d "program.jade") l.text;
      if keep <> None then
        write_file (Filename.concat d "command")
          (Printf.sprintf "# limit: %s, size %d\n%s\n" l.kind l.size
             (String.concat " " (List.map Filename.quote
                                   ([ "jadescript-ref"; "run"; "program.jade" ]
                                    @ List.concat_map (fun a -> [ "--agent"; a ]) (EG.agent_args sc)
                                    @ EG.run_args sc @ [ "--events"; "events.jsonl"; "--trace"; "trace.jsonl" ]))));
      (try run_scenario env sc ~events:(Filename.concat d "events.jsonl") ~trace:(Filename.concat d "trace.jsonl")
       with Found (Finding f) -> raise (Found (Finding { f with message = l.kind ^ ": " ^ f.message }))));
  Pass

(* --------------------------------------------------------------- cli *)

(* Bad values at the edges of an events file: each line must be refused
   with a located error, or accepted if it is in fact good. *)
(* Each must be refused with a located error (docs/trace-format.md): the
   second field says so; the texts with bad UTF-8 may instead be escaped. *)
let bad_event_lines = [
  {|{"agent": "g", "notify": "r1", "priority": -1}|}, true;
  {|{"agent": "g", "notify": "r1", "priority": 4611686018427387903}|}, true;
  {|{"agent": "g", "notify": "r1", "priority": 1e30}|}, true;
  {|{"agent": "g", "notify": "r1", "priority": "high"}|}, true;
  {|{"agent": "g", "notify": "r1", "priority": 2147483648}|}, true;
  {|{"run": -5}|}, true;
  {|{"run": 1.5}|}, true;
  {|{"run": "forever"}|}, true;
  {|{"agent": "nobody", "notify": "r1"}|}, true;
  {|{"agent": "g", "notify": "c1"}|}, true;
  {|{"agent": "g", "notify": "q1(\"x\")"}|}, true;
  {|{"agent": "g", "message": "r1", "performative": "bogus"}|}, true;
  {|{"agent": "g", "put": "1 +"}|}, true;
  {|{"agent": "g", "put": "99999999999999999999"}|}, true;
  "{\"agent\": \"g\", \"put\": \"\\\"\xff\xfe\\\"\"}", false;
  "{\"agent\": \"g\", \"put\": \"\\\"\\ud800\\\"\"}", false;
  {|{"agent": "g"|}, true;
  {|[1, 2]|}, true;
  {|{"agent": "g", "notify": "r1", "put": "1"}|}, true;
]

(* Each must be refused: one line, exit 1 (the first agent is g). *)
let bad_cli_args = [
  [ "--fuel=-1" ]; [ "--max-steps=-5" ]; [ "--o2a-capacity=-1" ];
  [ "--variant=zigzag" ]; [ "--agent=g:Ag" ]; [ "--agent=host:Ag" ];
  [ "--agent=x:Nope" ]; [ "--agent=:Ag" ]; [ "--trace=/nonexistent/dir/t.jsonl" ];
  [ "--events=/nonexistent/e.jsonl" ];
]

let cli_target ~keep ~seed index =
  let rs = rng ~seed "cli" index in
  let exe = jsref () in
  let (text, _, sc) = generated rs in
  in_dir keep (fun d ->
      let pj = Filename.concat d "program.jade" and ev = Filename.concat d "events.jsonl"
      and tr = Filename.concat d "trace.jsonl" in
      let agents = List.concat_map (fun a -> [ "--agent"; a ]) (EG.agent_args sc) in
      let kind = index mod 4 in
      let what = ref "" in
      let (argv, expect_error, trace) = match kind with
        | 0 ->
          (* a good program and events, through the command line *)
          write_file pj text; write_file ev (EG.events_file sc);
          ([ exe; "run"; pj ] @ agents @ EG.run_args sc @ [ "--events"; ev; "--trace"; tr ], false, true)
        | 1 ->
          (* a mutated program file through check, fmt or parse *)
          let t = ref text in
          for _ = 1 to 1 + int rs 2 do t := mutate_text rs !t text done;
          write_file pj !t;
          let cmd = pick rs [ "check"; "fmt"; "parse"; "run" ] in
          ([ exe; cmd; pj ] @ (if cmd = "run" then agents @ [ "--max-steps"; "2000" ] else []), false, false)
        | 2 ->
          (* an events file with one bad line: refused, located, nothing runs *)
          write_file pj text;
          let lines = List.map Ev.source_to_line sc.events in
          let (bad, refuse) = pick rs bad_event_lines in
          what := " (events line " ^ String.escaped bad ^ ")";
          let k = int rs (List.length lines + 1) in
          let lines = List.filteri (fun i _ -> i < k) lines @ [ bad ] @ List.filteri (fun i _ -> i >= k) lines in
          write_file ev (String.concat "\n" lines ^ "\n");
          ([ exe; "run"; pj ] @ agents @ [ "--max-steps"; "2000"; "--events"; ev; "--trace"; tr ], refuse, not refuse)
        | _ ->
          (* a bad value on the command line *)
          write_file pj text; write_file ev (EG.events_file sc);
          (* a second agent named as the first, or "host", with the same arguments *)
          let first = List.hd (EG.agent_args sc) in
          let rest = String.sub first 1 (String.length first - 1) in   (* ":Ag..." after "g" *)
          let bad = pick rs ([ [ "--agent=" ^ first ]; [ "--agent=host" ^ rest ] ] @ bad_cli_args) in
          what := " (" ^ String.concat " " bad ^ ")";
          let events = if List.exists (starts_with "--events") bad then [] else [ "--events"; ev ] in
          let steps = if List.exists (starts_with "--max-steps") bad then [] else [ "--max-steps"; "2000" ] in
          ([ exe; "run"; pj; "--agent"; List.hd (EG.agent_args sc) ] @ bad @ steps @ events, true, false) in
      if keep <> None then write_file (Filename.concat d "command") (String.concat " " (List.map Filename.quote argv) ^ "\n");
      let (status, _, err) = run_command ~timeout:20.0 ~memory:2_000_000_000 (Array.of_list argv) in
      (match judge_process ~expect_error ~status ~stderr:err () with
       | Pass -> ()
       | Finding f -> raise (Found (Finding { f with message = List.nth argv 1 ^ !what ^ ": " ^ f.message })));
      if trace && (kind = 0 || Sys.file_exists tr) then begin
        (match status with
         | Unix.WEXITED (0 | 1) -> judge_trace ~agents:(List.map (fun (n, _, _) -> n) sc.agents) tr
         | _ -> ())
      end);
  Pass

(* ---------------------------------------------------------- validate *)

let validate_target ~keep ~seed index =
  let rs = rng ~seed "validate" index in
  let (text, env, sc) = generated rs in
  (* small runs of the loops TLC models *)
  let sc = { sc with variant = pick rs [ Mc.Reference; Mc.Reference; Mc.Budgeted; Mc.Native ];
                     max_steps = 300; fuel = 100_000 } in
  in_dir keep (fun d ->
      let trace = Filename.concat d "trace.jsonl" in
      write_file (Filename.concat d "program.jade") text;
      run_scenario env sc ~events:(Filename.concat d "events.jsonl") ~trace;
      let lines = lines_of (read_file trace) in
      let tampers = Array.of_list Tamper.all in
      let t = tampers.(index mod Array.length tampers) in
      match t.apply rs lines with
      | None -> ()   (* not applicable to this trace *)
      | Some tampered ->
        let path = Filename.concat d "tampered.jsonl" in
        write_file path (String.concat "\n" tampered ^ "\n");
        match validate path with
        | verdicts ->
          if List.for_all (function Explore.Validate.Accepted _ -> true | _ -> false) verdicts then
            fail "wrongly accepted" "tamper %S: validate accepts the tampered trace" t.name
        | exception (Failure _ | Explore.Tlc.Error _ | Explore.Model.Error _ | Sys_error _) ->
          ()   (* rejected as validate rejects it (bin/cmd_validate.ml) *));
  Pass

(* Every kind of tampering on the trace of a generated run, judged by the
   OCaml checks of validate alone (in-process, no TLC: thousands per
   minute): each tampered trace that the kind applies to must be rejected,
   but for the kinds only TLC can see (Tamper.tlc_only), which the validate
   target sends to TLC. *)
let tamper_target ~keep ~seed index =
  let rs = rng ~seed "tamper" index in
  let (text, env, sc) = generated rs in
  let sc = { sc with max_steps = min sc.max_steps 300 } in   (* some tamperings are quadratic in the trace *)
  in_dir keep (fun d ->
      let trace = Filename.concat d "trace.jsonl" in
      write_file (Filename.concat d "program.jade") text;
      run_scenario env sc ~events:(Filename.concat d "events.jsonl") ~trace;
      let lines = lines_of (read_file trace) in
      (match Explore.Validate.check trace with
       | Ok () -> ()
       | Error (line, m) -> fail "rejected" "validate's OCaml checks reject a run's own trace, line %d: %s" line m);
      let path = Filename.concat d "tampered.jsonl" in
      List.iter (fun (t : Tamper.t) ->
          if not (List.mem t.name Tamper.tlc_only) then
            match t.apply rs lines with
            | None -> ()
            | Some tampered ->
              write_file path (String.concat "\n" tampered ^ "\n");
              match Explore.Validate.check path with
              | Error _ -> ()
              | Ok () -> fail "wrongly accepted" "tamper %S: the OCaml checks accept the tampered trace" t.name)
        Tamper.all);
  Pass

(* ----------------------------------------------------------- conform *)

(* Fake implementations: [name], the shell script's body (it is given run's
   arguments; $T is the --trace file, $JSREF the reference), and whether
   conform must pass it. *)
let fakes = [
  "hangs", "sleep 600", false;
  "dies of SIGSEGV", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; kill -SEGV $$", false;
  "dies of SIGSEGV, no header", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; tail -n +2 \"$T\" > \"$T.x\"; mv \"$T.x\" \"$T\"; kill -SEGV $$", false;
  "prints garbage", "head -c 3000 /dev/urandom > \"$T\"", false;
  "writes version 999", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; sed -i '1s/\"version\":[0-9]*/\"version\":999/' \"$T\"", false;
  "writes no header", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; tail -n +2 \"$T\" > \"$T.x\"; mv \"$T.x\" \"$T\"", false;
  "exits 3", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; exit 3", false;
  "writes no trace", "exit 0", false;
  "writes a huge trace", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; yes '{\"step\":1,\"agent\":\"x\",\"event\":\"idle\",\"action\":null}' | head -c 300000000 >> \"$T\"", false;
  "drops the last event", "\"$JSREF\" run \"$@\" >/dev/null 2>&1; head -n -1 \"$T\" > \"$T.x\"; mv \"$T.x\" \"$T\"", false;
  "floods stdout", "\"$JSREF\" run \"$@\" 2>&1; head -c 20000000 /dev/zero | tr '\\000' x", true;
  "is faithful", "exec \"$JSREF\" run \"$@\"", true;
]

let conform_target ~keep ~seed index =
  let rs = rng ~seed "conform" index in
  let (name, body, must_pass) = List.nth fakes (index mod List.length fakes) in
  let root = let rec up d = let p = Filename.concat d "conformance" in
               if Sys.file_exists p then p else let u = Filename.dirname d in if u = d then p else up u in
    up (Sys.getcwd ()) in
  let vectors = Interp.Oracle.load root in
  (* vectors whose run is not expected to fail (D15 exit 1 is fine too) *)
  let v = pick rs vectors in
  in_dir keep (fun d ->
      let script = Filename.concat d "impl.sh" in
      write_file script
        (Printf.sprintf "#!/bin/sh\n# a fake implementation: %s\nJSREF=%s\nT=\nprev=\nfor a in \"$@\"; do [ \"$prev\" = --trace ] && T=$a; prev=$a; done\n%s\n"
           name (Filename.quote (jsref ())) body);
      Unix.chmod script 0o755;
      (* the oracle's temporary files go to a folder of their own: none may be left *)
      let tmp = Filename.concat d "tmp" in
      Unix.mkdir tmp 0o700;
      let saved = Filename.get_temp_dir_name () in
      Filename.set_temp_dir_name tmp;
      Unix.putenv "TMPDIR" tmp;
      let t0 = Unix.gettimeofday () in
      let outcome = Fun.protect ~finally:(fun () -> Filename.set_temp_dir_name saved; Unix.putenv "TMPDIR" saved)
          (fun () -> Interp.Oracle.run_vector ~timeout:4.0 ~impl:script v) in
      let took = Unix.gettimeofday () -. t0 in
      let left = Array.to_list (Sys.readdir tmp) in
      if left <> [] then fail "temp files left" "fake %S on %s: %s left behind" name v.name (String.concat ", " left);
      if took > 30.0 then fail "hang" "fake %S on %s: conform took %.0f s with a 4 s limit" name v.name took;
      match outcome, must_pass with
      | Interp.Oracle.Pass, false -> fail "wrongly accepted" "conform passes the fake implementation that %s (vector %s)" name v.name
      | (Interp.Oracle.Failed m | Interp.Oracle.Diverge { expected = m; _ }), true ->
        fail "wrongly rejected" "conform fails the fake implementation that %s (vector %s): %s" name v.name m
      | _ -> ());
  Pass

(* ------------------------------------------------------------ engine *)

(* The fast engine (lib/engine) against the reference on generated
   programs: the engine's property test "engine = reference: steps,
   dispatches observed and not, random programs" (test/fastpath/
   test_engine.ml: 60 programs of Typed_gen, each with random host
   operations, run both ways; labels, body events, configurations and
   properties must be equal), run with a seed of this input's own. *)
let engine_target ~keep ~seed index =
  let exe = Filename.concat (Filename.dirname (Filename.dirname (jsref ()))) "test/fastpath/test_engine.exe" in
  if not (Sys.file_exists exe) then fail "setup" "%s is not built" exe;
  let qseed = (seed * 1_000_003 + index) land 0x3FFFFFFF in
  if keep <> None then Printf.printf "QCHECK_SEED=%d %s test runs 0\n" qseed exe;
  let (status, out, err) = in_dir None (fun d ->
      run_command ~timeout:120.0
        [| "/usr/bin/env"; Printf.sprintf "QCHECK_SEED=%d" qseed; "JSREF_QCHECK_COUNT=60"; exe; "test"; "runs"; "0"; "--color=never";
           "-o"; d |]) in
  (match status with
   | Unix.WEXITED 0 -> ()
   | Unix.WSIGNALED s when s = Sys.sigkill -> fail "hang" "the engine comparison ran past 120 s (QCHECK_SEED=%d)" qseed
   | _ ->
     let lines = lines_of (out ^ "\n" ^ err) in
     let interesting = List.filter (fun l -> contains l "differ" || contains l "exception" || contains l "FAIL") lines in
     fail "engine differs" "QCHECK_SEED=%d: %s" qseed
       (String.concat " | " (List.filteri (fun i _ -> i < 3) (if interesting = [] then lines else interesting))));
  Pass

(* ----------------------------------------------------------- targets *)

let guard f ~keep ~seed index =
  match f ~keep ~seed index with
  | o -> o
  | exception Found o -> o
  | exception Stack_overflow -> finding "stack overflow" "Stack_overflow escaped"
  | exception Out_of_memory -> finding "out of memory" "Out_of_memory escaped"
  | exception e -> finding "exception" (Printexc.to_string e)

let gb = 1_000_000_000

let targets = [
  { name = "parse"; limit = 60.0; memory = 2 * gb; run = guard parse_target };
  { name = "check"; limit = 60.0; memory = 2 * gb; run = guard check_target };
  { name = "run"; limit = 30.0; memory = 2 * gb; run = guard run_target };
  { name = "limits"; limit = 20.0; memory = 2 * gb; run = guard limits_target };
  { name = "cli"; limit = 60.0; memory = 3 * gb; run = guard cli_target };
  { name = "engine"; limit = 180.0; memory = 3 * gb; run = guard engine_target };
  { name = "validate"; limit = 180.0; memory = 3 * gb; run = guard validate_target };
  { name = "tamper"; limit = 60.0; memory = 2 * gb; run = guard tamper_target };
  { name = "conform"; limit = 120.0; memory = 3 * gb; run = guard conform_target };
]

let find n = List.find_opt (fun t -> t.name = n) targets
