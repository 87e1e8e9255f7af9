(* The bug catalogue's table, the refused put in the trace (R2d), and
   {"run": {"rules": n}} (R3d). The catalogue's kill count itself is the
   suite "defects killed by the vectors" of scripts/test
   (jadescript-ref defects --first). *)

open Test_support.Support

let with_file name text f =
  let p = Filename.concat (Filename.get_temp_dir_name ()) name in
  let oc = open_out_bin p in output_string oc text; close_out oc;
  Fun.protect ~finally:(fun () -> Sys.remove p) (fun () -> f p)

let lines s = List.filter (( <> ) "") (String.split_on_char '\n' s)

let is_diag l =
  match String.split_on_char ':' l with
  | _ :: line :: col :: rest -> int_of_string_opt line <> None && int_of_string_opt col <> None
                               && (match rest with r :: _ -> String.trim r = "error" | [] -> false)
  | _ -> false

let prog = "ontology O\n\
           \tproposition job extends percept with priority = 1\n\
           \tproposition alarm extends percept with priority = 9\n\
            agent A uses ontology O\n\
           \ton create do\n\t\tactivate behaviour B\n\
            cyclic behaviour B for agent A\n\
           \ton percept when content matches job do\n\t\tlog \"job\"\n\
           \ton percept when content matches alarm do\n\t\tlog \"alarm\"\n"

(* run the program with these events; (status, stdout, stderr, trace lines without the header) *)
let run ?(args = "") events =
  with_file "jsref_defects.jade" prog (fun p ->
      with_file "jsref_defects.jsonl" events (fun ev ->
          let tr = Filename.temp_file "jsref_defects" ".trace" in
          Fun.protect ~finally:(fun () -> Sys.remove tr) (fun () ->
              let (status, out, err) =
                run_command (Printf.sprintf "%s run %s --agent a:A %s --events %s --trace %s" exe p args ev tr) in
              let trace = match lines (read_file tr) with _ :: l -> l | [] -> [] in
              (status, out, err, trace))))

let without_step l =
  Yojson.Safe.to_string (Trace.without_step (Yojson.Safe.from_string l))

(* ------------------------------------------------------------ catalogue *)

let catalogue () =
  let names = List.map (fun (d : Defects.t) -> d.name) Defects.all in
  Alcotest.(check bool) "at least 30 defects" true (List.length names >= 30);
  Alcotest.(check int) "names are unique" (List.length names) (List.length (List.sort_uniq compare names));
  List.iter (fun (d : Defects.t) ->
      let ruling_like r = String.length r >= 2 && (r.[0] = 'R' || r.[0] = 'D') in
      Alcotest.(check bool) ("a ruling: " ^ d.name) true (ruling_like d.ruling);
      Alcotest.(check bool) ("one line: " ^ d.name) true (d.about <> "" && not (String.contains d.about '\n'));
      Alcotest.(check bool) ("found by name: " ^ d.name) true (match Defects.find d.name with Some d2 -> d2 == d | None -> false)) Defects.all

let unknown_defect () =
  let (status, _, err, _) = run ~args:"--defect no-such-defect" "{\"run\": \"idle\"}\n" in
  Alcotest.(check int) "exit 1" 1 status;
  Alcotest.(check (list string)) "one line"
    [ "jadescript-ref: error: unknown defect no-such-defect (jadescript-ref defects lists them)" ] (lines err)

(* the kill count's command: bad inputs are one line; a survivor fails it *)
let defects_command () =
  let (status, _, err) = run_command (Printf.sprintf "%s defects no-such-defect" exe) in
  Alcotest.(check int) "unknown defect: exit 1" 1 status;
  Alcotest.(check (list string)) "one line" [ "jadescript-ref: error: unknown defect no-such-defect" ] (lines err);
  let (status, _, err) = run_command (Printf.sprintf "%s defects --vectors /nonexistent/dir" exe) in
  Alcotest.(check int) "no vectors folder: exit 1" 1 status;
  Alcotest.(check int) ("one line: " ^ err) 1 (List.length (lines err));
  Alcotest.(check bool) ("located: " ^ err) true (is_diag (String.trim err));
  let empty = Filename.concat (Filename.get_temp_dir_name ()) "jsref_no_vectors" in
  (try Sys.mkdir empty 0o755 with Sys_error _ -> ());
  let (status, out, _) = run_command (Printf.sprintf "%s defects --vectors %s put-ignores-capacity" exe empty) in
  Alcotest.(check int) "a survivor: exit 1" 1 status;
  Alcotest.(check bool) ("reported:\n" ^ out) true
    (List.mem "0 of 1 defects killed by the vectors alone (0 vectors; 1 defects can show in a trace)" (lines out)
     && List.mem "0 passed, 1 failed" (lines out))

(* The judged kill counts: a defect the judge rejects is killed by the
   first case that shows it, a bad count is one line. *)
let judged_counts () =
  let (status, _, err) = run_command (Printf.sprintf "%s defects --generated 0" exe) in
  Alcotest.(check int) "--generated 0: exit 1" 1 status;
  Alcotest.(check int) ("one line: " ^ err) 1 (List.length (lines err));
  let (status, out, _) = run_command (Printf.sprintf "%s defects --generated 12 lowest-priority-first seed-ignored" exe) in
  Alcotest.(check int) "generated: exit 0" 0 status;
  Alcotest.(check bool) ("generated, reported:\n" ^ out) true
    (List.mem "1 of 2 defects killed by 12 generated programs (seed 1), judged (2 defects can show in a trace)" (lines out)
     (* a change of schedule alone: counted as a survivor the judge cannot see, not run *)
     && List.exists (fun l -> String.length l > 12 && String.sub l 0 12 = "seed-ignored"
                              && Option.is_some (String.index_opt l '(')
                              && List.mem "survives" (String.split_on_char ' ' l)) (lines out)
     && not (List.exists (fun l -> String.length l > 9 && String.sub l 0 9 = "survivors") (lines out)));
  (* one vector, judged: the lowest priority first is not what the program does *)
  let dir = Filename.concat (Filename.get_temp_dir_name ()) "jsref_one_vector" in
  let v = Filename.concat dir "001-r3b-priority-order" in
  let src = Filename.concat root "conformance/001-r3b-priority-order" in
  ignore (Sys.command (Printf.sprintf "rm -rf %s && mkdir -p %s && cp %s/* %s/" (Filename.quote dir) (Filename.quote v)
                         (Filename.quote src) (Filename.quote v)));
  let (status, out, _) = run_command (Printf.sprintf "%s defects --judge --vectors %s lowest-priority-first" exe dir) in
  ignore (Sys.command ("rm -rf " ^ Filename.quote dir));
  Alcotest.(check int) "judged: exit 0" 0 status;
  Alcotest.(check bool) ("judged, reported:\n" ^ out) true
    (List.mem "1 of 1 defects killed by the vectors, judged (1 vectors; 1 defects can show in a trace)" (lines out))

(* a defect changes the run: the same events, a different trace *)
let defect_changes_run () =
  let ev = "{\"agent\": \"a\", \"notify\": \"job\"}\n{\"agent\": \"a\", \"notify\": \"alarm\"}\n{\"run\": \"idle\"}\n" in
  let (_, out, _, _) = run ev in
  let (_, out', _, _) = run ~args:"--defect lowest-priority-first" ev in
  Alcotest.(check string) "reference: alarm first (R3b)" "a: alarm\na: job\n" out;
  Alcotest.(check string) "the defect: job first" "a: job\na: alarm\n" out'

(* ------------------------------------------------------------ refused put *)

let refused_put () =
  let ev = "{\"agent\": \"a\", \"notify\": \"job\"}\n{\"agent\": \"a\", \"put\": \"\\\"box\\\"\"}\n{\"run\": \"idle\"}\n" in
  let (status, _, err, trace) = run ~args:"--o2a-capacity 1" ev in
  Alcotest.(check int) "a refusal is the host's answer: exit 0" 0 status;
  Alcotest.(check (list string)) "stderr names the agent and the object"
    [ "host: agent a refused the object \"box\": the O2A queue is full (R2d)" ] (lines err);
  let refused = List.filter (fun l -> without_step l |> fun s ->
      String.length s > 0 && (match Yojson.Safe.from_string s with
          | `Assoc f -> List.assoc_opt "event" f = Some (`String "refused") | _ -> false)) trace in
  Alcotest.(check (list string)) "the trace's refused line, field for field"
    [ "{\"agent\":\"a\",\"event\":\"refused\",\"action\":null,\"object\":\"\\\"box\\\"\",\"reason\":\"the O2A queue is full (R2d)\"}" ]
    (List.map without_step refused);
  (* it comes right after the notify, before the transfer *)
  let events = List.map (fun l -> match Yojson.Safe.from_string l with
      | `Assoc f -> (match List.assoc_opt "event" f with Some (`String e) -> e | _ -> "?") | _ -> "?") trace in
  Alcotest.(check (list string)) "in order" [ "create"; "activate"; "notify"; "refused"; "transfer" ]
    (List.filteri (fun i _ -> i < 5) events)

let refused_notify_names_agent () =
  let ev = "{\"agent\": \"a\", \"notify\": \"job\"}\n{\"agent\": \"a\", \"notify\": \"alarm\"}\n" in
  let (_, _, err, trace) = run ~args:"--o2a-capacity 1" ev in
  Alcotest.(check (list string)) "stderr names the agent and the percept"
    [ "host: agent a refused the percept alarm: the O2A queue is full (R2d)" ] (lines err);
  Alcotest.(check bool) "a refused notify keeps \"percept\"" true
    (List.exists (fun l -> without_step l =
                           "{\"agent\":\"a\",\"event\":\"refused\",\"action\":null,\"percept\":\"alarm\",\"reason\":\"the O2A queue is full (R2d)\"}") trace)

let refused_put_round_trip () =
  let l = { Trace.step = 4; agent = "a"; event = Trace.Refused_put { obj = "[1, 2]"; reason = "the O2A queue is full (R2d)" } } in
  let j = Trace.line_to_json l in
  Alcotest.(check string) "JSON"
    "{\"step\":4,\"agent\":\"a\",\"event\":\"refused\",\"action\":null,\"object\":\"[1, 2]\",\"reason\":\"the O2A queue is full (R2d)\"}"
    (Yojson.Safe.to_string j);
  Alcotest.(check bool) "read back as Refused_put" true (Trace.line_of_json j = Ok l);
  let n = { l with event = Trace.Refused { percept = "job"; reason = "r" } } in
  Alcotest.(check bool) "a refused notify reads back as Refused" true (Trace.line_of_json (Trace.line_to_json n) = Ok n)

(* ------------------------------------------------------------ run rules *)

let names trace = List.map (fun l -> match Yojson.Safe.from_string l with
    | `Assoc f -> (match List.assoc_opt "event" f with Some (`String e) -> e | _ -> "?") | _ -> "?") trace

(* R3d: after two single rules (Transfer, Dequeue of job) the alarm is
   notified; it waits for the next Transfer. *)
let run_rules () =
  let ev = "{\"agent\": \"a\", \"notify\": \"job\"}\n{\"run\": {\"rules\": 2}}\n\
            {\"agent\": \"a\", \"notify\": \"alarm\"}\n{\"run\": \"idle\"}\n" in
  let (status, out, _, trace) = run ev in
  Alcotest.(check int) "exit 0" 0 status;
  Alcotest.(check string) "job, then alarm (R3d)" "a: job\na: alarm\n" out;
  Alcotest.(check (list string)) "exactly two rules, then the notify"
    [ "create"; "activate"; "notify"; "transfer"; "dequeue"; "notify"; "handle" ]
    (List.filteri (fun i _ -> i < 7) (names trace));
  (* 0 rules: nothing; rules on an idle agent: nothing *)
  let (_, _, _, t0) = run "{\"run\": {\"rules\": 0}}\n{\"agent\": \"a\", \"notify\": \"job\"}\n" in
  Alcotest.(check (list string)) "0 rules take nothing" [ "create"; "activate"; "notify" ]
    (List.filteri (fun i _ -> i < 3) (names t0));
  let (_, _, _, t1) = run "{\"run\": \"idle\"}\n{\"run\": {\"rules\": 5}}\n" in
  Alcotest.(check int) "an idle agent takes no rule" 1 (List.length (List.filter (( = ) "idle") (names t1)))

let run_rules_bad () =
  let bad = "{\"run\": {\"rules\": -1}}\n{\"run\": {\"rules\": \"3\"}}\n{\"run\": {\"rules\": 1, \"x\": 2}}\n{\"run\": {}}\n" in
  let (status, out, err, _) = run bad in
  Alcotest.(check int) "exit 1" 1 status;
  Alcotest.(check string) "nothing ran" "" out;
  let ls = lines err in
  Alcotest.(check int) ("one line per bad line:\n" ^ err) 4 (List.length ls);
  List.iteri (fun i l ->
      Alcotest.(check bool) ("located: " ^ l) true (is_diag l);
      Alcotest.(check int) ("at its line: " ^ l) (i + 1) (int_of_string (List.nth (String.split_on_char ':' l) 1))) ls

let () =
  Alcotest.run "defects" [
    ("catalogue", [
        Alcotest.test_case "one typed table, 30 or more" `Quick catalogue;
        Alcotest.test_case "an unknown defect is one line" `Quick unknown_defect;
        Alcotest.test_case "defects: bad inputs, a survivor fails" `Quick defects_command;
        Alcotest.test_case "a defect changes the run" `Quick defect_changes_run;
        Alcotest.test_case "defects --judge, --generated: judged kills" `Quick judged_counts ]);
    ("refused", [
        Alcotest.test_case "R2d a refused put is in the trace" `Quick refused_put;
        Alcotest.test_case "R2d a refused notify names agent and percept" `Quick refused_notify_names_agent;
        Alcotest.test_case "Refused_put JSON round trip" `Quick refused_put_round_trip ]);
    ("run rules", [
        Alcotest.test_case "R3d the host acts between rules" `Quick run_rules;
        Alcotest.test_case "bad run rules lines, each located" `Quick run_rules_bad ]);
  ]
