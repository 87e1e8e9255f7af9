(* The hostile classes of the fuzz campaign (see hostile.mli). *)

module TG = Test_support.Typed_gen
module EG = Test_support.Event_gen
module I = Inputs

exception Found of I.outcome
let fail kind fmt =
  Printf.ksprintf (fun m -> raise (Found (I.Finding { kind; message = String.map (function '\n' | '\r' -> ' ' | c -> c) m }))) fmt

let int rs n = Random.State.int rs n
let pick rs l = List.nth l (int rs (List.length l))
let rng ~seed target index = Random.State.make [| seed; Hashtbl.hash target; index |]

let write_file path s =
  let oc = open_out_bin path in
  Fun.protect ~finally:(fun () -> close_out_noerr oc) (fun () -> output_string oc s)

let remove_tree = Inputs.remove_tree

(* a fresh folder named as Inputs.remove_leftovers expects *)
let in_dir keep f =
  match keep with
  | Some d -> (if not (Sys.file_exists d) then Unix.mkdir d 0o755); f d
  | None ->
    let base = Filename.get_temp_dir_name () in
    let rec go k =
      let d = Filename.concat base (Printf.sprintf "jsref-fuzz-%d-h%d" (Unix.getpid ()) k) in
      if Sys.file_exists d then go (k + 1) else (Unix.mkdir d 0o700; d) in
    let d = go 0 in
    Fun.protect ~finally:(fun () -> remove_tree d) (fun () -> f d)

(* the project's root: the folder holding fuzz/ (for scripts/ and runtime/) *)
let root () =
  let rec up d = if Sys.file_exists (Filename.concat d "scripts/jade-run") then d
    else let u = Filename.dirname d in if u = d then Sys.getcwd () else up u in
  (* the source tree, not its copy in _build/default *)
  let source d =
    let marker = "/_build/" in
    let n = String.length d and m = String.length marker in
    let rec find i = if i + m > n then d else if String.sub d i m = marker then String.sub d 0 i else find (i + 1) in
    find 0 in
  let exe = I.jsref () in
  let from_exe = source (up (Filename.dirname exe)) in
  if Sys.file_exists (Filename.concat from_exe "scripts/jade-run") then from_exe else source (up (Sys.getcwd ()))

(* One command, judged by the command-line oracle: exit 0 or 1, no signal,
   every line of standard error located; [expect_error]: it must refuse. *)
let command ?(expect_error = false) ?(timeout = 60.0) ?(memory = 3_000_000_000) what argv =
  let (st, out, err) = I.run_command ~timeout ~memory (Array.of_list argv) in
  (match I.judge_process ~expect_error ~status:st ~stderr:err () with
   | I.Pass -> ()
   | I.Finding f -> raise (Found (I.Finding { f with message = what ^ ": " ^ f.message })));
  (st, out, err)

(* ------------------------------------------------------------- names *)

(* Names that Java, JADE's classes and the back end's generated code use
   (lib/backend/jade.ml: java_keywords, used_names, the prefixes p_, fn_,
   do_ of members, the $ of renamed classes; JADE's Agent and Behaviour:
   docs/jade.md, "Names"). *)
let java_keywords = [
  "abstract"; "assert"; "boolean"; "break"; "byte"; "case"; "catch"; "char"; "class"; "const";
  "continue"; "default"; "double"; "enum"; "extends"; "final"; "finally"; "float"; "goto";
  "implements"; "import"; "instanceof"; "int"; "interface"; "long"; "native"; "new"; "package";
  "private"; "protected"; "public"; "short"; "static"; "strictfp"; "super"; "switch";
  "synchronized"; "this"; "throw"; "throws"; "transient"; "try"; "void"; "volatile"; "null";
  "var"; "yield"; "record"; "sealed"; "permits"; "_" ]

let jade_names = [
  "Interrupted"; "AP_ACTIVE"; "AP_DELETED"; "AP_SUSPENDED"; "RunnableChangedEvent"; "STATE_READY";
  "STATE_BLOCKED"; "STATE_RUNNING"; "NOTIFY_UP"; "NOTIFY_DOWN"; "myAgent"; "parent"; "done";
  "action"; "onStart"; "onEnd"; "getAID"; "setup"; "takeDown"; "block"; "restart"; "reset";
  "addBehaviour"; "removeBehaviour"; "doDelete"; "send"; "receive"; "getLocalName"; "getName";
  "isRunnable"; "root"; "getBehaviourName"; "setBehaviourName"; "getDataStore"; "myEvent";
  "toString"; "hashCode"; "equals"; "getClass"; "wait"; "notify"; "notifyAll"; "clone";
  "finalize"; "serialVersionUID"; "Agent"; "Behaviour"; "AID"; "ACLMessage"; "CyclicBehaviour";
  "OneShotBehaviour"; "Object"; "String"; "Integer"; "Double"; "Boolean"; "Math"; "System";
  "Ops"; "Text"; "Schema"; "JList"; "JMap"; "Aid"; "AgentRef"; "BehaviourRef"; "Nothing"; "Type";
  "JadescriptError"; "Literals"; "LiteralError"; "Scope"; "MessageValue"; "Program";
  "JadescriptAgent"; "JadescriptBehaviour"; "Message"; "ProgramInfo"; "BehaviourInfo"; "java";
  "jsgen"; "jsref"; "jade"; "List"; "ArrayList"; "LinkedHashMap"; "Map"; "Override";
  "StackOverflowError"; "RuntimeException"; "Class"; "Number"; "Float"; "main"; "args"; "e";
  "self"; "ctx"; "value"; "result"; "tmp"; "it"; "x$" ]

let generated_names = [
  "p_count"; "p_x"; "p_"; "fn_f"; "fn_"; "do_q"; "do_"; "p_p_count"; "fn_fn_f"; "A$A"; "B$B";
  "Program$S"; "count"; "f"; "q"; "x"; "k"; "m"; "v"; "O"; "A"; "H"; "C"; "P"; "Q" ]

let all_names = java_keywords @ jade_names @ generated_names

(* The roles a name may take in the template below, with their defaults. *)
let roles = [ "C", "Conc"; "P", "prop"; "Q", "pred"; "S", "s"; "A", "Ag"; "B", "Beh"; "PR", "count";
              "F", "f"; "PC", "q"; "PA", "n"; "L", "loc"; "V", "v"; "K", "k"; "M", "m" ]

let template names =
  let n r = List.assoc r names in
  String.concat "\n" [
    "ontology O";
    Printf.sprintf "\tconcept %s(%s as integer)" (n "C") (n "K");
    Printf.sprintf "\tproposition %s extends percept" (n "P");
    Printf.sprintf "\tpredicate %s(%s as integer) extends percept with priority = 3" (n "Q") (n "S");
    "";
    Printf.sprintf "agent %s uses ontology O" (n "A");
    Printf.sprintf "\tproperty %s as integer = 1" (n "PR");
    Printf.sprintf "\tfunction %s(%s as integer) as integer do" (n "F") (n "PA");
    Printf.sprintf "\t\treturn %s + %s" (n "PA") (n "PR");
    Printf.sprintf "\tprocedure %s with %s as integer do" (n "PC") (n "M");
    Printf.sprintf "\t\tlog %s" (n "M");
    "\ton create do";
    Printf.sprintf "\t\t%s = %s(2)" (n "L") (n "F");
    Printf.sprintf "\t\tlog %s" (n "L");
    Printf.sprintf "\t\tdo %s with %s = 3" (n "PC") (n "M");
    Printf.sprintf "\t\tlog %s(4)" (n "C");
    Printf.sprintf "\t\tactivate behaviour %s" (n "B");
    "";
    Printf.sprintf "cyclic behaviour %s for agent %s" (n "B") (n "A");
    Printf.sprintf "\ton percept when content matches %s do" (n "P");
    "\t\tlog \"p\"";
    Printf.sprintf "\ton percept when content matches %s(%s) do" (n "Q") (n "V");
    Printf.sprintf "\t\tlog %s + %s" (n "V") (n "PR");
    "" ]

(* A program of the template with hostile names in one to four roles;
   several roles may take the same name (a property and a local p_count). *)
let named_program rs =
  let names = ref roles in
  for _ = 1 to 1 + int rs 4 do
    let (r, _) = pick rs roles in
    names := (r, pick rs all_names) :: List.remove_assoc r !names
  done;
  (template !names, !names)

(* ------------------------------------------------------ big and flat *)

let big_program rs =
  match int rs 5 with
  | 0 ->
    (* many behaviours *)
    let n = pick rs [ 999; 1_000; 1_001; 3_000 ] in
    (Printf.sprintf "%d behaviours" n,
     "ontology O\n\tproposition tick extends percept\n\nagent Ag uses ontology O\n\ton create do\n\t\tactivate behaviour B0\n\n"
     ^ String.concat "" (List.init n (fun i ->
         Printf.sprintf "cyclic behaviour B%d for agent Ag\n\ton percept when content matches tick do\n\t\tlog %d\n\n" i i)))
  | 1 ->
    (* a long body *)
    let n = pick rs [ 1_000; 1_999; 2_001; 5_000; 20_000 ] in
    (Printf.sprintf "a body of %d statements" n,
     "agent Ag\n\ton create do\n" ^ String.concat "" (List.init n (fun i -> Printf.sprintf "\t\tlog %d\n" i)))
  | 2 ->
    (* a long text, about Java's limit of 65,535 bytes *)
    let n = pick rs [ 65_534; 65_535; 65_536; 32_767; 21_845; 1_000_000; 1_000_001 ] in
    let c = pick rs [ "a"; "\\u0000"; "\xc3\xa9"; "\xf0\x9f\x98\x80" ] in
    let unit = match c with "\\u0000" -> 2 | "\xc3\xa9" -> 2 | "\xf0\x9f\x98\x80" -> 6 | _ -> 1 in
    let k = max 1 (n / unit) in
    (Printf.sprintf "a text of %d x %S" k c,
     "agent Ag\n\ton create do\n\t\tlog \"" ^ String.concat "" (List.init k (fun _ -> c)) ^ "\"\n")
  | 3 ->
    (* many slots, many parameters *)
    let n = pick rs [ 249; 250; 251; 255; 256; 1_000 ] in
    let slots = String.concat ", " (List.init n (fun i -> Printf.sprintf "x%d as integer" i)) in
    let args = String.concat ", " (List.init n (fun i -> string_of_int i)) in
    (Printf.sprintf "%d slots and parameters" n,
     Printf.sprintf "ontology O\n\tconcept c(%s)\n\nagent Ag uses ontology O\n\tfunction f(%s) as integer do\n\t\treturn x0\n\ton create do\n\t\tlog c(%s)\n\t\tlog f(%s)\n"
       slots slots args args)
  | _ ->
    (* a long name *)
    let n = pick rs [ 199; 200; 201; 255; 256; 50_000 ] in
    let name = "A" ^ String.make (n - 1) 'a' in
    (Printf.sprintf "a name of %d bytes" n,
     Printf.sprintf "agent %s\n\tproperty %s as integer = 1\n\ton create do\n\t\tlog %s\n" name ("p" ^ name) ("p" ^ name))

(* -------------------------------------------------- nesting at limits *)

(* JSON nested [d] deep: arrays or objects *)
let json_nest rs d inner =
  if int rs 2 = 0 then String.make d '[' ^ inner ^ String.make d ']'
  else String.concat "" (List.init d (fun _ -> "{\"a\":")) ^ inner ^ String.make d '}'

let depths = [ 998; 999; 1_000; 1_001; 1_002; 5_000; 100_000 ]

let program_nest rs =
  let d = pick rs [ 99; 100; 101; 999; 1_000; 1_001; 100_000 ] in
  let e = match int rs 4 with
    | 0 -> String.make d '(' ^ "1" ^ String.make d ')'
    | 1 -> String.concat "" (List.init d (fun _ -> "not ")) ^ "true"
    | 2 -> String.make d '[' ^ "1" ^ String.make d ']'
    | _ -> String.concat " + " (List.init d (fun _ -> "1")) in
  (Printf.sprintf "an expression nested %d deep" d, "agent Ag\n\ton create do\n\t\tlog " ^ e ^ "\n")

(* ------------------------------------------------------- the target *)

let simple_program =
  "ontology O\n\tproposition tick extends percept\n\tpredicate t(x as integer) extends percept\n\n\
   agent Ag uses ontology O\n\ton create do\n\t\tactivate behaviour H\n\n\
   cyclic behaviour H for agent Ag\n\ton percept when content matches tick do\n\t\tlog \"tick\"\n\
   \ton percept when content matches t(x) do\n\t\tlog x\n"

(* Writes [data] into a FIFO from a forked child, runs [f], then reaps the
   writer. The writer gives up when nobody opens the FIFO. *)
let with_fifo path data f =
  Unix.mkfifo path 0o600;
  match Unix.fork () with
  | 0 ->
    (try
       Unix.sleepf 0.0;
       let fd = Unix.openfile path [ Unix.O_WRONLY ] 0 in
       let rec go off = if off < String.length data then
           go (off + Unix.write_substring fd data off (String.length data - off)) in
       (try go 0 with Unix.Unix_error _ -> ());
       Unix.close fd
     with _ -> ());
    Unix._exit 0
  | pid ->
    Fun.protect ~finally:(fun () ->
        (* a reader that never opened the FIFO leaves the writer blocked *)
        (try Unix.kill pid Sys.sigkill with Unix.Unix_error _ -> ());
        ignore (Unix.waitpid [] pid))
      f

(* [sh -c "cat DATA | jadescript-ref ARGS"]: the file given as /dev/stdin
   is a pipe *)
let piped exe data_file args =
  [ "/bin/sh"; "-c"; Printf.sprintf "cat %s | exec %s %s" (Filename.quote data_file) (Filename.quote exe)
                       (String.concat " " (List.map Filename.quote args)) ]

let kinds = [ "names"; "nesting"; "big"; "events"; "trace"; "vector"; "scenario"; "model"; "pipes" ]

let hostile_target ~keep ~seed index =
  let rs = rng ~seed "hostile" index in
  let exe = I.jsref () in
  let kind = List.nth kinds (index mod List.length kinds) in
  in_dir keep (fun d ->
      let pj = Filename.concat d "program.jade" in
      let cmd_file argv = if keep <> None then
          write_file (Filename.concat d "command") (String.concat " " (List.map Filename.quote argv) ^ "\n") in
      let check_then_run ?(events = "") what text =
        write_file pj text;
        let (st, _, _) = command (what ^ ", check") [ exe; "check"; pj ] in
        cmd_file [ exe; "check"; pj ];
        if st = Unix.WEXITED 0 then begin
          let ev = Filename.concat d "events.jsonl" in
          write_file ev events;
          let agent = (* the template's agent type is the name in role A *)
            match List.find_opt (fun l -> String.length l > 6 && String.sub l 0 6 = "agent ") (String.split_on_char '\n' text) with
            | Some l -> (match String.split_on_char ' ' l with _ :: a :: _ -> a | _ -> "Ag")
            | None -> "Ag" in
          ignore (command (what ^ ", run")
                    [ exe; "run"; pj; "--agent"; "g:" ^ agent; "--events"; ev; "--max-steps"; "5000";
                      "--trace"; Filename.concat d "trace.jsonl" ]);
          (if Sys.file_exists (Filename.concat d "trace.jsonl") then
             match I.trace_problem (Filename.concat d "trace.jsonl") with
             | Some m -> fail "bad trace" "%s: %s" what m
             | None -> ());
          ignore (command (what ^ ", compile --target jade")
                    [ exe; "compile"; pj; "--target"; "jade"; "--out"; Filename.concat d "java" ])
        end in
      (match kind with
       | "names" ->
         let (text, names) = named_program rs in
         let what = "names " ^ String.concat "," (List.filter_map (fun (r, n) ->
             if List.assoc r roles = n then None else Some (r ^ "=" ^ n)) names) in
         let events = "{\"agent\": \"g\", \"notify\": \"" ^ List.assoc "P" names ^ "\"}\n"
                      ^ "{\"agent\": \"g\", \"notify\": \"" ^ List.assoc "Q" names ^ "(5)\"}\n" in
         check_then_run ~events what text
       | "nesting" -> let (what, text) = program_nest rs in check_then_run what text
       | "big" ->
         let (what, text) = big_program rs in
         let events = if I.contains text "proposition tick" then "{\"agent\": \"g\", \"notify\": \"tick\"}\n" else "" in
         check_then_run ~events what text
       | "events" ->
         (* an events line nested at and past the JSON reader's 1,000, or
            near the line limit of 16 MB *)
         write_file pj simple_program;
         let ev = Filename.concat d "events.jsonl" in
         let (what, line) = match int rs 4 with
           | 0 | 1 ->
             let dp = pick rs depths in
             (Printf.sprintf "events nested %d deep" dp,
              "{\"agent\": \"g\", \"notify\": \"tick\", \"x\": " ^ json_nest rs dp "1" ^ "}")
           | 2 ->
             let n = pick rs [ 16 * 1024 * 1024 - 64; 16 * 1024 * 1024; 16 * 1024 * 1024 + 1 ] in
             let pad = n - 40 in
             (Printf.sprintf "an events line of about %d bytes" n,
              "{\"agent\": \"g\", \"notify\": \"t(1)\", \"x\": \"" ^ String.make (max 0 pad) ' ' ^ "\"}")
           | _ ->
             let n = pick rs [ 1_000; 100_000 ] in
             (Printf.sprintf "%d events" n,
              String.concat "\n" (List.init n (fun i -> Printf.sprintf "{\"agent\": \"g\", \"notify\": \"t(%d)\"}" i))) in
         write_file ev ("{\"agent\": \"g\", \"notify\": \"tick\"}\n" ^ line ^ "\n{\"run\": 2}\n");
         let argv = [ exe; "run"; pj; "--agent"; "g:Ag"; "--events"; ev; "--max-steps"; "2000";
                      "--trace"; Filename.concat d "trace.jsonl" ] in
         cmd_file argv;
         ignore (command what argv)
       | "trace" ->
         (* a trace given to validate, nested or long: refused before TLC *)
         let tr = Filename.concat d "trace.jsonl" in
         let dp = pick rs depths in
         let header = "{\"format\":\"jadescript-ref\",\"version\":2,\"variant\":\"reference\",\"level\":\"full\"}" in
         let line = match int rs 3 with
           | 0 -> json_nest rs dp "1"
           | 1 -> "{\"step\":1,\"agent\":\"g\",\"event\":\"log\",\"text\":" ^ json_nest rs dp "\"x\"" ^ "}"
           | _ -> "{\"step\":1,\"agent\":\"g\",\"event\":\"log\",\"text\":\"" ^ String.make (16 * 1024 * 1024 + 1) 'x' ^ "\"}" in
         write_file tr (header ^ "\n" ^ line ^ "\n");
         let argv = [ exe; "validate"; tr ] in
         cmd_file argv;
         ignore (command ~expect_error:true ~timeout:120.0 (Printf.sprintf "validate, a trace nested %d deep or long" dp) argv)
       | "vector" ->
         (* a vector.json for conform, nested or long *)
         let vd = Filename.concat d "vectors" in
         let v = Filename.concat vd "001-x" in
         Unix.mkdir vd 0o700; Unix.mkdir v 0o700;
         write_file (Filename.concat v "program.jade") simple_program;
         write_file (Filename.concat v "events.jsonl") "{\"agent\": \"g\", \"notify\": \"tick\"}\n";
         write_file (Filename.concat v "expected.jsonl") "";
         let dp = pick rs depths in
         let body = match int rs 3 with
           | 0 -> "{\"about\": \"x\", \"rulings\": [], \"args\": [\"--agent\", \"g:Ag\"], \"expect\": [" ^ json_nest rs dp "1" ^ "]}"
           | 1 -> "{\"about\": " ^ json_nest rs dp "\"x\"" ^ ", \"args\": []}"
           | _ -> json_nest rs dp "{}" in
         write_file (Filename.concat v "vector.json") body;
         let argv = [ exe; "conform"; "--vectors"; vd; "--timeout"; "20" ] in
         cmd_file argv;
         let what = Printf.sprintf "conform, a vector.json nested %d deep" dp in
         (* conform's verdict on a vector it cannot use is a FAIL line on
            standard output and exit 1, with nothing on standard error *)
         let (st, out, err) = I.run_command ~timeout:90.0 ~memory:3_000_000_000 (Array.of_list argv) in
         if not (st = Unix.WEXITED 1 && String.trim err = "" && I.contains out "001-x" && I.contains out "FAIL") then
           (match I.judge_process ~status:st ~stderr:err () with
            | I.Pass -> ()
            | I.Finding f -> raise (Found (I.Finding { f with message = what ^ ": " ^ f.message })))
       | "scenario" ->
         (* a scenario for sim: nested JSON, or a range passed by one *)
         let sc = Filename.concat d "scenario.json" in
         let dp = pick rs depths in
         let base = Printf.sprintf
             "{\"name\": \"x\", \"seed\": 1, \"duration_s\": %s, \"corridor\": {\"length_m\": 10.0, \"width_m\": 2.0}, \"cubes\": [], \"start\": {\"x\": 0.5, \"y\": 1.0, \"heading_deg\": 0}, \"sensors\": {\"position_rate_hz\": %s, \"proximity_rate_hz\": 1, \"camera_rate_hz\": 1, \"imu_rate_hz\": 1}, \"agent\": {\"loop\": \"reference\"}%s}" in
         let (what, text) = match int rs 4 with
           | 0 -> (Printf.sprintf "a scenario nested %d deep" dp, base "10" "10" (", \"x\": " ^ json_nest rs dp "1"))
           | 1 ->
             (* 2,000,000 samples is the limit: 2000 s x (997 + 1 + 1 + 1) Hz, and past it *)
             let (dur, hz) = pick rs [ ("2000", "997"); ("2000.001", "997"); ("3600", "1000"); ("3600.0001", "1") ] in
             (Printf.sprintf "a scenario of %s s at %s Hz" dur hz, base dur hz "")
           | 2 ->
             let (rate, dur) = pick rs [ ("20000", "50"); ("20000", "50.0001"); ("20000.1", "10"); ("1e308", "10") ] in
             (Printf.sprintf "a flood of %s Hz for %s s" rate dur,
              base dur "1" (Printf.sprintf ", \"flood\": {\"percept\": \"position\", \"rate_hz\": %s, \"start_s\": 0, \"end_s\": %s, \"priority\": 1}" rate dur))
           | _ -> (Printf.sprintf "a scenario with %d cubes" 1001,
                   base "10" "10" (", \"random_cubes\": {\"count\": 1001, \"size_m\": 0.1}")) in
         write_file sc text;
         let argv = [ exe; "sim"; sc; "--out"; Filename.concat d "out"; "--program"; Filename.concat (root ()) "examples/robome/robome.jade" ] in
         cmd_file argv;
         (* a scenario within the ranges may take a minute on a loaded
           machine, and 1.7 GB at 2,000,000 samples (bench.exe limits):
           under a bound of 3 GB of data it ran out of memory (exit 125) *)
         ignore (command ~timeout:170.0 ~memory:8_000_000_000 what argv)
       | "model" ->
         (* a TLA+ model for explore: a constant nested at and past 1,000,
            or --max-states at its edges *)
         let m = Filename.concat d "MCHostile.tla" in
         let dp = pick rs depths in
         let nest = String.concat "" (List.init dp (fun _ -> "<<")) ^ "1" ^ String.concat "" (List.init dp (fun _ -> ">>")) in
         let tla = String.concat "\n" [
             "---- MODULE MCHostile ----"; "EXTENDS AgentLoop"; "MCVariant == \"reference\"";
             "MCTiePolicy == \"Stable\""; "MCBudget == 1"; "MCPercepts == {\"obstacle\"}";
             "MCDefaultPriority == [obstacle |-> 8]"; "MCOverrides == {}"; "MCObjects == {}";
             "MCMessages == {}"; "MCMaxNotify == 1"; "MCMaxPut == 0"; "MCMaxSend == 0"; "MCFlood == FALSE";
             "MCO2ACapacity == 1"; "MCBehaviours == {\"Main\"}"; "MCKind == [Main |-> \"cyclic\"]";
             "MCHasAction == [Main |-> FALSE]";
             "MCActionEffects == [Main |-> " ^ (if int rs 2 = 0 then nest else "<<>>") ^ "]";
             "MCPerceptHandlers == [Main |-> <<[accepts |-> {\"obstacle\"}, effects |-> <<>>]>>]";
             "MCMessageHandlers == [Main |-> <<>>]"; "MCInitialBehaviours == <<\"Main\">>";
             "MCMaxActive == 1"; "MCInversionBound == 1"; "====" ] in
         write_file m tla;
         let ms = pick rs [ []; [ "--max-states"; "0" ]; [ "--max-states"; "1" ]; [ "--max-states"; "25000001" ];
                            [ "--max-states"; "-1" ]; [ "--max-states"; "99999999999999999999" ] ] in
         let argv = [ exe; "explore"; m ] @ ms in
         cmd_file argv;
         ignore (command ~timeout:120.0 (Printf.sprintf "explore, a model nested %d deep %s" dp (String.concat " " ms)) argv)
       | _ ->
         (* the program, the events and the agents file given as a pipe, a
            FIFO or a path that is not UTF-8 *)
         let events = "{\"agent\": \"g\", \"notify\": \"tick\"}\n{\"agent\": \"g\", \"notify\": \"t(3)\"}\n" in
         write_file pj simple_program;
         let ev = Filename.concat d "events.jsonl" in
         write_file ev events;
         let tr = Filename.concat d "trace.jsonl" in
         (match int rs 5 with
          | 0 ->
            let argv = piped exe ev [ "run"; pj; "--agent"; "g:Ag"; "--events"; "/dev/stdin"; "--trace"; tr ] in
            cmd_file argv; ignore (command "run --events /dev/stdin (a pipe)" argv)
          | 1 ->
            let argv = piped exe pj [ pick rs [ "check"; "fmt"; "parse" ]; "/dev/stdin" ] in
            cmd_file argv; ignore (command "a program from /dev/stdin (a pipe)" argv)
          | 2 ->
            let fifo = Filename.concat d "events.fifo" in
            with_fifo fifo events (fun () ->
                let argv = [ exe; "run"; pj; "--agent"; "g:Ag"; "--events"; fifo; "--trace"; tr ] in
                cmd_file argv; ignore (command "run --events FIFO" argv))
          | 3 ->
            let fifo = Filename.concat d "program.fifo" in
            with_fifo fifo simple_program (fun () ->
                let argv = [ exe; pick rs [ "check"; "fmt"; "parse" ]; fifo ] in
                cmd_file argv; ignore (command "a program from a FIFO" argv))
          | _ ->
            let bad = Filename.concat d (pick rs [ "\xff\xfe.jade"; "caf\xe9.jade"; "a\x01b.jade"; "\xed\xa0\x80.jade" ]) in
            write_file bad simple_program;
            let bad_ev = Filename.concat d "ev\xff.jsonl" in
            write_file bad_ev events;
            let argv = pick rs [ [ exe; "check"; bad ]; [ exe; "run"; bad; "--agent"; "g:Ag"; "--events"; bad_ev; "--trace"; tr ];
                                 [ exe; "run"; pj; "--agent"; "g:Ag"; "--events"; Filename.concat d "nope\xff.jsonl" ];
                                 [ exe; "check"; Filename.concat d "missing\xc3.jade" ] ] in
            cmd_file argv; ignore (command "a path that is not UTF-8" argv);
            (* the reports name the file: what they print must not break the
               one-line rule (checked above); a trace written is valid *)
            ());
         if Sys.file_exists tr then
           match I.trace_problem tr with Some m -> fail "bad trace" "pipes: %s" m | None -> ()));
  I.Pass

(* ---------------------------------------------------------- javac *)

let javac_classpath () =
  let r = root () in
  let rt = Filename.concat r "runtime/jade/target" in
  (Filename.concat rt "jadescript-runtime.jar", Filename.concat rt "lib/jade-4.3.jar")

(* A program check accepts either compiles with javac or is refused by
   compile with a located error: never Java that javac refuses. *)
let jade_target ~keep ~seed index =
  let rs = rng ~seed "jade" index in
  let exe = I.jsref () in
  let (jar, jade) = javac_classpath () in
  if not (Sys.file_exists jar && Sys.file_exists jade) then
    fail "setup" "%s or %s is missing (bash scripts/setup)" jar jade;
  let (what, text) = match index mod 3 with
    | 0 -> let (t, names) = named_program rs in
      ("names " ^ String.concat "," (List.filter_map (fun (r, n) -> if List.assoc r roles = n then None else Some (r ^ "=" ^ n)) names), t)
    | 1 -> big_program rs
    | _ -> ("a generated program", Syntax.Print.program (TG.program rs)) in
  in_dir keep (fun d ->
      let pj = Filename.concat d "program.jade" in
      write_file pj text;
      let (st, _, _) = command (what ^ ", check") [ exe; "check"; pj ] in
      if st = Unix.WEXITED 0 then begin
        let out = Filename.concat d "java" in
        let (st, _, _) = command (what ^ ", compile") [ exe; "compile"; pj; "--target"; "jade"; "--out"; out ] in
        if st = Unix.WEXITED 0 then begin
          let files = ref [] in
          let rec walk p = if Sys.is_directory p then Array.iter (fun f -> walk (Filename.concat p f)) (Sys.readdir p)
            else if Filename.check_suffix p ".java" then files := p :: !files in
          walk out;
          let classes = Filename.concat d "classes" in
          Unix.mkdir classes 0o700;
          let argv = [ "/usr/bin/env"; "javac"; "-J-Xss16m"; "-J-XX:+UseSerialGC"; "-J-XX:TieredStopAtLevel=1";
                       "-nowarn"; "-encoding"; "UTF-8"; "-d"; classes; "-cp"; jar ^ ":" ^ jade ] @ !files in
          if keep <> None then write_file (Filename.concat d "command")
              (String.concat " " (List.map Filename.quote ([ exe; "compile"; pj; "--target"; "jade"; "--out"; out ])) ^ "\n"
               ^ String.concat " " (List.map Filename.quote argv) ^ "\n");
          let (st, out_txt, err) = I.run_command ~timeout:170.0 ~memory:(-1) (Array.of_list argv) in
          match st with
          | Unix.WEXITED 0 -> ()
          | Unix.WSIGNALED s when s = Sys.sigkill -> fail "hang" "%s: javac ran past 170 s" what
          | _ ->
            let lines = List.filter (fun l -> I.contains l "error") (String.split_on_char '\n' (out_txt ^ "\n" ^ err)) in
            fail "javac refuses" "%s: %s" what
              (match lines with l :: _ -> String.sub l (max 0 (String.length l - 250)) (min 250 (String.length l)) | [] -> "javac failed")
        end
      end);
  I.Pass

(* ---------------------------------------------------- differential *)

(* the JVMs run without the child's bound on its heap (theirs is their own) *)
external setrlimit : int -> int -> bool = "fuzz_setrlimit"
let without_memory_bound f =
  let saved = Inputs.run_memory_bound () in
  ignore (setrlimit 0 (-1));
  Fun.protect ~finally:(fun () -> if saved > 0 then ignore (setrlimit 0 saved)) f

(* A generated program and host run on the interpreter (jadescript-ref run)
   and on JADE (scripts/jade-run, the JADE implementation of conform
   --impl), judged by conform's own oracle (Interp.Oracle.run_vector): the
   JADE run's trace must equal the interpreter's, step aside. *)
let differential_target ~keep ~seed index =
  let rs = rng ~seed "differential" index in
  let exe = I.jsref () in
  let r = root () in
  let text = Syntax.Print.program (TG.program rs) in
  let env = match Syntax.Parse.string ~file:"program.jade" text with
    | exception Syntax.Diag.Failed _ -> fail "generator" "a generated program does not parse"
    | p -> fst (Typing.check [ p ]) in
  let sc = EG.scenario env ~agent_type:"Ag" rs in
  (* JADE runs the loops of the rulings; small runs keep the JVM's time low *)
  let sc = { sc with max_steps = min sc.max_steps 500 } in
  in_dir keep (fun d ->
      write_file (Filename.concat d "program.jade") text;
      write_file (Filename.concat d "events.jsonl") (EG.events_file sc);
      let args = List.concat_map (fun a -> [ "--agent"; a ]) (EG.agent_args sc) @ EG.run_args sc in
      let (st, _, err) = I.run_command ~timeout:60.0
          (Array.of_list ([ "/bin/sh"; "-c"; "cd " ^ Filename.quote d ^ " && exec " ^ Filename.quote exe
                                             ^ " run program.jade " ^ String.concat " " (List.map Filename.quote args)
                                             ^ " --events events.jsonl --trace expected.jsonl" ])) in
      (match st with
       | Unix.WEXITED (0 | 1) -> ()
       | _ -> fail "crash" "the interpreter's run: %s" (String.trim err));
      let v = { Interp.Oracle.name = Printf.sprintf "differential-%d-%d" seed index; dir = d; about = "";
                rulings = []; args; files = [ "program.jade" ]; expect = [] } in
      let impl = Filename.quote (Filename.concat r "scripts/jade-run") in
      if keep <> None then write_file (Filename.concat d "command")
          (Printf.sprintf "cd %s && %s program.jade %s --events events.jsonl --trace jade.jsonl\n" (Filename.quote d) impl
             (String.concat " " (List.map Filename.quote args)));
      let jade_cache = Filename.concat (Filename.get_temp_dir_name ()) "jsref-fuzz-jade-cache" in
      Unix.putenv "JSREF_JADE_CACHE" jade_cache;
      (* jade-run compiles with the main.exe of this build dir: the one
         of [exe] when it is a build's, else the source tree's _build *)
      let b = Filename.dirname (Filename.dirname (Filename.dirname exe)) in
      Unix.putenv "JSREF_BUILD_DIR"
        (if Sys.file_exists (Filename.concat b "default/bin/main.exe") then b else Filename.concat r "_build");
      match without_memory_bound (fun () -> Interp.Oracle.run_vector ~timeout:150.0 ~workdir:d ~impl v) with
      | Interp.Oracle.Pass -> ()
      | Interp.Oracle.Diverge { index; expected; got } ->
        fail "differs" "event %d: interpreter %s, JADE %s" index expected got
      | Interp.Oracle.Failed m -> fail "jade failed" "%s" m);
  I.Pass

let guard f ~keep ~seed index =
  match f ~keep ~seed index with
  | o -> o
  | exception Found o -> o
  | exception Stack_overflow -> I.Finding { kind = "stack overflow"; message = "Stack_overflow escaped" }
  | exception Out_of_memory -> I.Finding { kind = "out of memory"; message = "Out_of_memory escaped" }
  | exception e -> I.Finding { kind = "exception"; message = Printexc.to_string e }

let targets : I.target list = [
  { name = "hostile"; limit = 200.0; memory = 2_000_000_000; run = guard hostile_target };
  { name = "jade"; limit = 240.0; memory = 2_000_000_000; run = guard jade_target };
  { name = "differential"; limit = 240.0; memory = 2_000_000_000; run = guard differential_target };
]
