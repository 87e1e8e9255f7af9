(* The fuzz campaign's driver (fuzz/README.md).

     fuzz.exe [--inputs N] [--seconds S] [--seed K] [--jobs J] [--only T,...]
              [--tlc-every K] [--out DIR]        the campaign (make fuzz)
     fuzz.exe --sample                            the short sample (make test)
     fuzz.exe --replay TARGET:SEED:INDEX [--keep DIR]
                                                  one input, in this process
     fuzz.exe --regressions DIR                   replay the regression cases

   The inputs of each target are cut into chunks; each chunk runs in a
   forked child with bounded memory (setrlimit) that reports every input
   over a pipe as it starts and ends it. A child that dies (a signal, an
   abort, an exit) is a crash of the input it was running; a child whose
   input runs past the target's time limit is killed: a hang. Either way
   the chunk resumes after that input in a new child. *)

module I = Inputs

(* every target: those of inputs.ml and the hostile classes of hostile.ml *)
let all_targets = I.targets @ Hostile.targets
let find_target n = List.find_opt (fun (t : I.target) -> t.name = n) all_targets

type stats = {
  mutable inputs : int;
  mutable crashes : int;
  mutable hangs : int;
  mutable wrong : int;     (* wrongly accepted traces or implementations *)
  mutable other : int;     (* every other finding: unlocated errors, bad traces ... *)
}

type finding_record = {
  f_target : string; f_kind : string; f_message : string;
  mutable f_count : int; mutable f_examples : int list; f_seed : int }

let stats : (string, stats) Hashtbl.t = Hashtbl.create 8
let findings : (string, finding_record) Hashtbl.t = Hashtbl.create 16
let finding_order = ref []

let stat t = match Hashtbl.find_opt stats t with
  | Some s -> s
  | None -> let s = { inputs = 0; crashes = 0; hangs = 0; wrong = 0; other = 0 } in Hashtbl.replace stats t s; s

(* a finding's identity: target, kind and message with its numbers blanked *)
let normalise m =
  let b = Buffer.create 80 in
  String.iteri (fun i c ->
      match c with
      | '0' .. '9' -> if i = 0 || not (match m.[i - 1] with '0' .. '9' -> true | _ -> false) then Buffer.add_char b '#'
      | c -> Buffer.add_char b c) m;
  let s = Buffer.contents b in
  if String.length s > 90 then String.sub s 0 90 else s

let record ~seed target index kind message =
  let s = stat target in
  (match kind with
   | "crash" | "stack overflow" | "out of memory" | "exception" -> s.crashes <- s.crashes + 1
   | "hang" -> s.hangs <- s.hangs + 1
   | "wrongly accepted" -> s.wrong <- s.wrong + 1
   | _ -> s.other <- s.other + 1);
  let key = target ^ "|" ^ kind ^ "|" ^ normalise message in
  match Hashtbl.find_opt findings key with
  | Some f -> f.f_count <- f.f_count + 1; if List.length f.f_examples < 3 then f.f_examples <- f.f_examples @ [ index ]
  | None ->
    Hashtbl.replace findings key { f_target = target; f_kind = kind; f_message = message; f_count = 1;
                                   f_examples = [ index ]; f_seed = seed };
    finding_order := key :: !finding_order;
    Printf.printf "  new finding [%s] %s: %s\n    replay: fuzz.exe --replay %s:%d:%d\n%!" target kind
      (if String.length message > 300 then String.sub message 0 300 ^ "..." else message) target seed index

(* --------------------------------------------------------- the children *)

let write_line fd s =
  let s = s ^ "\n" in
  let rec go off = if off < String.length s then go (off + Unix.write_substring fd s off (String.length s - off)) in
  go 0

let child (t : I.target) ~seed ~from ~upto fd =
  I.bound_memory t.memory;
  (* nothing the inputs print reaches the campaign's output *)
  let nul = Unix.openfile "/dev/null" [ Unix.O_WRONLY ] 0 in
  Unix.dup2 nul Unix.stdout; Unix.dup2 nul Unix.stderr;
  let fatal = ref false in
  let i = ref from in
  while !i < upto && not !fatal do
    write_line fd (Printf.sprintf "S %d" !i);
    (match t.run ~keep:None ~seed !i with
     | I.Pass -> write_line fd (Printf.sprintf "D %d" !i)
     | I.Finding { kind; message } ->
       write_line fd (Printf.sprintf "F %d %s\t%s" !i kind message);
       (* after an exhausted machine, this process is not to be trusted *)
       if kind = "stack overflow" || kind = "out of memory" then fatal := true);
    incr i
  done;
  Unix._exit (if !fatal then 3 else 0)

type running = {
  target : I.target;
  pid : int;
  fd : Unix.file_descr;
  buf : Buffer.t;
  upto : int;
  mutable current : int option;   (* started, not ended *)
  mutable started : float;
  mutable next : int;             (* the first input not yet ended *)
}

let spawn (t : I.target) ~seed ~from ~upto =
  (* close-on-exec: the processes an input starts (TLC, a subprocess) must
     not hold the pipe open after the child ends *)
  let (r, w) = Unix.pipe ~cloexec:true () in
  flush stdout; flush stderr;
  match Unix.fork () with
  | 0 -> Unix.close r; (try child t ~seed ~from ~upto w with _ -> Unix._exit 2)
  | pid ->
    Unix.close w;
    { target = t; pid; fd = r; buf = Buffer.create 256; upto; current = None;
      started = Unix.gettimeofday (); next = from }

let status_text = function
  | Unix.WEXITED k -> Printf.sprintf "the child exited with status %d" k
  | Unix.WSIGNALED s ->
    let name = if s = Sys.sigsegv then "SIGSEGV" else if s = Sys.sigabrt then "SIGABRT"
      else if s = Sys.sigkill then "SIGKILL" else if s = Sys.sigxcpu then "SIGXCPU" else string_of_int s in
    "the child died of " ^ name
  | Unix.WSTOPPED s -> Printf.sprintf "the child stopped (%d)" s

(* One line from a child. *)
let handle_line ~seed r line =
  let target = r.target.name in
  match String.index_opt line ' ' with
  | None -> ()
  | Some sp ->
    let tag = String.sub line 0 sp and rest = String.sub line (sp + 1) (String.length line - sp - 1) in
    match tag with
    | "S" -> r.current <- int_of_string_opt rest; r.started <- Unix.gettimeofday ()
    | "D" ->
      (stat target).inputs <- (stat target).inputs + 1;
      r.current <- None; Option.iter (fun i -> r.next <- i + 1) (int_of_string_opt rest)
    | "F" ->
      (stat target).inputs <- (stat target).inputs + 1;
      r.current <- None;
      let (idx, body) = match String.index_opt rest ' ' with
        | Some k -> (int_of_string (String.sub rest 0 k), String.sub rest (k + 1) (String.length rest - k - 1))
        | None -> (0, rest) in
      r.next <- idx + 1;
      let (kind, msg) = match String.index_opt body '\t' with
        | Some k -> (String.sub body 0 k, String.sub body (k + 1) (String.length body - k - 1))
        | None -> (body, "") in
      record ~seed target idx kind msg
    | _ -> ()

let campaign ~seed ~jobs ~deadline ~sample (plan : (I.target * int * int) list) =
  (* chunks: (target, from, upto) *)
  let queue = Queue.create () in
  List.iter (fun (t, n, chunk) ->
      let k = ref 0 in
      while !k < n do Queue.add (t, !k, min n (!k + chunk)) queue; k := !k + chunk done) plan;
  (* interleave: the slow targets first, so that they overlap the others *)
  let chunks = List.of_seq (Queue.to_seq queue) in
  let weight (t : I.target) = match t.name with "differential" | "jade" | "hostile" | "validate" | "conform" | "engine" -> 0 | "cli" | "limits" -> 1 | _ -> 2 in
  let chunks = List.stable_sort (fun (a, _, _) (b, _, _) -> compare (weight a) (weight b)) chunks in
  let pending = ref chunks and running = ref [] in
  let t0 = Unix.gettimeofday () in
  let last_report = ref t0 in
  let over () = match deadline with Some s -> Unix.gettimeofday () -. t0 > s | None -> false in
  let rec loop () =
    (* start children *)
    while List.length !running < jobs && !pending <> [] && not (over ()) do
      match !pending with
      | (t, from, upto) :: rest -> pending := rest; running := spawn t ~seed ~from ~upto :: !running
      | [] -> ()
    done;
    if !running <> [] then begin
      let fds = List.map (fun r -> r.fd) !running in
      let (ready, _, _) = try Unix.select fds [] [] 0.5 with Unix.Unix_error (Unix.EINTR, _, _) -> ([], [], []) in
      let chunk = Bytes.create 65536 in
      List.iter (fun r ->
          if List.mem r.fd ready then begin
            let n = try Unix.read r.fd chunk 0 65536 with Unix.Unix_error _ -> 0 in
            if n = 0 then begin
              (* the child has ended *)
              Unix.close r.fd;
              let (_, st) = Unix.waitpid [] r.pid in
              I.remove_leftovers r.pid;
              running := List.filter (fun r' -> r'.pid <> r.pid) !running;
              (match r.current with
               | Some i ->
                 (stat r.target.name).inputs <- (stat r.target.name).inputs + 1;
                 record ~seed r.target.name i "crash" (status_text st);
                 r.next <- i + 1
               | None -> ());
              if r.next < r.upto && not (over ()) then pending := (r.target, r.next, r.upto) :: !pending
            end else begin
              Buffer.add_subbytes r.buf chunk 0 n;
              let s = Buffer.contents r.buf in
              let lines = String.split_on_char '\n' s in
              let rec eat = function
                | [ last ] -> Buffer.clear r.buf; Buffer.add_string r.buf last
                | l :: rest -> handle_line ~seed r l; eat rest
                | [] -> () in
              eat lines
            end
          end) !running;
      (* hangs *)
      let now = Unix.gettimeofday () in
      List.iter (fun r ->
          match r.current with
          | Some i when now -. r.started > r.target.limit ->
            (try Unix.kill r.pid Sys.sigkill with Unix.Unix_error _ -> ());
            r.current <- None;
            (stat r.target.name).inputs <- (stat r.target.name).inputs + 1;
            record ~seed r.target.name i "hang" (Printf.sprintf "over %.0f s" r.target.limit);
            r.next <- i + 1
          | _ -> ()) !running;
      if not sample && now -. !last_report > 30.0 then begin
        last_report := now;
        let total = Hashtbl.fold (fun _ s a -> a + s.inputs) stats 0 in
        Printf.printf "  ... %.0f s: %d inputs, %d findings\n%!" (now -. t0) total (Hashtbl.length findings)
      end;
      loop ()
    end in
  loop ();
  Unix.gettimeofday () -. t0

(* -------------------------------------------------------- regressions *)

(* A regression case is a folder: [command] (the arguments of jadescript-ref,
   one per line, paths relative to the folder) and [expect]: a line
   ["status N"] or ["status N|M"] (the exit statuses allowed), lines
   ["trace FILE"] (a trace the run writes: if it exists, it must be valid
   UTF-8 and JSON, line by line, and read by lib/trace), and fragments that
   standard error must contain, one per line. Lines starting with # are
   comments; a line ["line PREFIX"]: some line of standard error starts
   with PREFIX. Files the run writes are removed afterwards. *)
let regressions dir =
  let cases = try List.sort compare (Array.to_list (Sys.readdir dir)) with Sys_error _ -> [] in
  let cases = List.filter (fun c -> Sys.is_directory (Filename.concat dir c)) cases in
  let exe = I.jsref () in
  List.map (fun c ->
      let d = Filename.concat dir c in
      let lines f = List.filter (fun l -> l <> "" && l.[0] <> '#')
          (String.split_on_char '\n' (try I.read_file (Filename.concat d f) with Sys_error _ -> "")) in
      let args = lines "command" in
      let expect = lines "expect" in
      let word w l = String.length l > String.length w && String.sub l 0 (String.length w + 1) = w ^ " " in
      let rest w l = String.sub l (String.length w + 1) (String.length l - String.length w - 1) in
      let statuses = List.concat_map (fun l -> if word "status" l then
                                         List.filter_map int_of_string_opt (String.split_on_char '|' (rest "status" l))
                                       else []) expect in
      let statuses = if statuses = [] then [ 0 ] else statuses in
      let traces = List.filter_map (fun l -> if word "trace" l then Some (Filename.concat d (rest "trace" l)) else None) expect in
      let starts = List.filter_map (fun l -> if word "line" l then Some (rest "line" l) else None) expect in
      let fragments = List.filter (fun l -> not (word "status" l || word "trace" l || word "line" l)) expect in
      let argv = [| "/bin/sh"; "-c"; "cd " ^ Filename.quote d ^ " && exec " ^ Filename.quote exe ^ " "
                                        ^ String.concat " " (List.map Filename.quote args) |] in
      let (st, _, err) = I.run_command ~timeout:30.0 argv in
      let verdict =
        match I.judge_process ~status:st ~stderr:err () with
        | I.Finding { kind; message } -> Error (kind ^ ": " ^ message)
        | I.Pass ->
          if not (List.exists (fun k -> st = Unix.WEXITED k) statuses) then
            Error (Printf.sprintf "expected status %s; stderr: %s"
                     (String.concat " or " (List.map string_of_int statuses)) (String.trim err))
          else match List.find_opt (fun f -> not (I.contains err f)) fragments with
            | Some f -> Error (Printf.sprintf "standard error lacks %S: %s" f (String.trim err))
            | None ->
              let lines = String.split_on_char '\n' err in
              let starts_with p l = String.length l >= String.length p && String.sub l 0 (String.length p) = p in
              match List.find_opt (fun p -> not (List.exists (starts_with p) lines)) starts with
              | Some p -> Error (Printf.sprintf "no line of standard error starts with %S: %s" p (String.trim err))
              | None ->
              match List.find_map (fun t -> if Sys.file_exists t then I.trace_problem t else None) traces with
              | Some m -> Error m
              | None -> Ok () in
      List.iter (fun t -> try Sys.remove t with Sys_error _ -> ()) traces;
      (c, verdict)) cases

(* --------------------------------------------------------------- main *)

let () =
  let inputs = ref 1_000_000 and seconds = ref None and seed = ref 1 and jobs = ref 2 in
  let only = ref [] and sample = ref false and replay = ref None and keep = ref None in
  let regr = ref None and out = ref "_fuzz" and differential = ref None in
  let spec = [
    "--inputs", Arg.Int (fun n -> inputs := n), "N  inputs in all (default 1000000)";
    "--seconds", Arg.Float (fun s -> seconds := Some s), "S  stop starting new chunks after S seconds";
    "--seed", Arg.Int (fun s -> seed := s), "K  the campaign's seed (default 1)";
    "--jobs", Arg.Int (fun j -> jobs := max 1 j), "J  children at once (default 2)";
    "--only", Arg.String (fun s -> only := String.split_on_char ',' s), "T,...  only these targets";
    "--tlc-every", Arg.Int (fun k -> I.tlc_every := k), "K  one run trace in K goes to TLC (0: none)";
    "--differential", Arg.Int (fun k -> differential := Some (max 0 k)),
    "N  programs run on the interpreter and on JADE (default 20; each starts a JVM)";
    "--out", Arg.String (fun d -> out := d), "DIR  where findings.txt is written (default _fuzz)";
    "--sample", Arg.Set sample, " the short sample of make test";
    "--replay", Arg.String (fun s -> replay := Some s), "TARGET:SEED:INDEX  one input, in this process";
    "--keep", Arg.String (fun d -> keep := Some d), "DIR  with --replay: write the input's files there";
    "--regressions", Arg.String (fun d -> regr := Some d), "DIR  replay the regression cases of DIR";
  ] in
  Arg.parse spec (fun a -> raise (Arg.Bad ("unexpected argument " ^ a))) "fuzz.exe [OPTIONS]";
  Sys.set_signal Sys.sigpipe Sys.Signal_ignore;
  match !replay, !regr with
  | Some r, _ ->
    (match String.split_on_char ':' r with
     | [ t; s; i ] ->
       (match find_target t, int_of_string_opt s, int_of_string_opt i with
        | Some t, Some s, Some i ->
          (match t.run ~keep:!keep ~seed:s i with
           | I.Pass -> print_endline "pass"; exit 0
           | I.Finding { kind; message } -> Printf.printf "finding [%s] %s\n" kind message; exit 1)
        | _ -> prerr_endline "fuzz: error: --replay TARGET:SEED:INDEX"; exit 1)
     | _ -> prerr_endline "fuzz: error: --replay TARGET:SEED:INDEX"; exit 1)
  | None, Some d ->
    let rs = regressions d in
    let bad = List.filter (fun (_, v) -> v <> Ok ()) rs in
    List.iter (fun (c, v) -> match v with
        | Ok () -> Printf.printf "  regression %s: ok\n" c
        | Error m -> Printf.printf "  regression %s: FAILED: %s\n" c m) rs;
    Printf.printf "%d passed, %d failed\n" (List.length rs - List.length bad) (List.length bad);
    exit (if bad = [] then 0 else 1)
  | None, None ->
    let share name n chunk = match find_target name with
      | Some t when !only = [] || List.mem name !only -> [ (t, n, chunk) ]
      | _ -> [] in
    let n = !inputs in
    let scaled k = max 1 (k * n / 1_000_000) in
    let plan =
      if !sample then begin
        if !I.tlc_every = 2000 then I.tlc_every := 150;
        share "validate" 6 3 @ share "tamper" 100 50 @ share "conform" 12 6 @ share "engine" 10 5 @ share "cli" 60 20
        @ share "limits" 40 10 @ share "run" 400 100 @ share "check" 1000 500 @ share "parse" 2500 1250
      end else begin
        let v = scaled 30 and c = max 12 (scaled 24) and cl = scaled 3_000 and l = scaled 300
        and r = scaled 20_000 and ch = scaled 340_000 and tm = scaled 3_000 in
        (* the hostile classes (hostile.ml); JADE's JVM costs seconds an
           input, so the jade and differential targets have few *)
        let h = max 90 (scaled 4_500) and jv = max 10 (scaled 60)
        and df = match !differential with Some k -> k | None -> 20 in
        let p = max 1 (n - v - tm - c - scaled 500 - cl - l - r - ch - h - jv - df) in
        share "differential" df 2 @ share "jade" jv 5 @ share "hostile" h 18 @ share "validate" v 3 @ share "tamper" tm 100 @ share "conform" c 6 @ share "engine" (scaled 500) 25 @ share "cli" cl 50 @ share "limits" l 10
        @ share "run" r 200 @ share "check" ch 1000 @ share "parse" p 4000
      end in
    Printf.printf "fuzz: seed %d, %d jobs, %s\n%!" !seed !jobs
      (String.concat ", " (List.map (fun ((t : I.target), k, _) -> Printf.sprintf "%s %d" t.name k) plan));
    let took = campaign ~seed:!seed ~jobs:!jobs ~deadline:!seconds ~sample:!sample plan in
    let regression_failures =
      if !sample then begin
        let dir = let rec up d = let p = Filename.concat d "fuzz/regressions" in
                    if Sys.file_exists p then p else let u = Filename.dirname d in if u = d then p else up u in
          up (Sys.getcwd ()) in
        let rs = regressions dir in
        List.iter (fun (c, v) -> match v with
            | Ok () -> ()
            | Error m -> Printf.printf "  regression %s: FAILED: %s\n" c m) rs;
        Printf.printf "  regressions: %d replayed, %d failed\n" (List.length rs)
          (List.length (List.filter (fun (_, v) -> v <> Ok ()) rs));
        List.length (List.filter (fun (_, v) -> v <> Ok ()) rs), List.length rs
      end else (0, 0) in
    Printf.printf "\n  %-12s %9s %8s %6s %9s %6s %9s\n" "target" "inputs" "crashes" "hangs" "accepted" "other" "findings";
    let total = ref 0 in
    List.iter (fun ((t : I.target), _, _) ->
        let s = stat t.name in
        total := !total + s.inputs;
        let distinct = Hashtbl.fold (fun _ f a -> if f.f_target = t.name then a + 1 else a) findings 0 in
        Printf.printf "  %-12s %9d %8d %6d %9d %6d %9d\n" t.name s.inputs s.crashes s.hangs s.wrong s.other distinct) plan;
    let keys = List.rev !finding_order in
    (try
       if not (Sys.file_exists !out) then Unix.mkdir !out 0o755;
       let oc = open_out (Filename.concat !out "findings.txt") in
       List.iter (fun k -> let f = Hashtbl.find findings k in
                   Printf.fprintf oc "[%s] %s (%d inputs): %s\n  replay: %s\n" f.f_target f.f_kind f.f_count
                     f.f_message
                     (String.concat "  " (List.map (fun i -> Printf.sprintf "fuzz.exe --replay %s:%d:%d" f.f_target f.f_seed i)
                                            f.f_examples))) keys;
       close_out oc
     with Sys_error _ | Unix.Unix_error _ -> ());
    if keys <> [] then begin
      Printf.printf "\n  distinct findings (also in %s/findings.txt):\n" !out;
      List.iter (fun k -> let f = Hashtbl.find findings k in
                  Printf.printf "  [%s] %s x%d: %s\n    replay: fuzz.exe --replay %s:%d:%d\n" f.f_target f.f_kind f.f_count
                    (if String.length f.f_message > 200 then String.sub f.f_message 0 200 ^ "..." else f.f_message)
                    f.f_target f.f_seed (List.hd f.f_examples)) keys
    end;
    let nf = List.length keys in
    Printf.printf "fuzz: %d inputs, %d findings (%.0f s)\n" !total nf took;
    if !sample then begin
      let (rf, rn) = regression_failures in
      let bad = Hashtbl.fold (fun _ s a -> a + s.crashes + s.hangs + s.wrong + s.other) stats 0 in
      Printf.printf "%d passed, %d failed\n" (!total - bad + (rn - rf)) (bad + rf);
      exit (if bad + rf = 0 then 0 else 1)
    end;
    exit (if nf = 0 then 0 else 1)
