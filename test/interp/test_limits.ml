(* Limits that hold and bad values at the edge of run: D19
   (active behaviours per agent, activation without cubic cost), D20 (rounds
   end when nothing can change), D21 (the size of texts and maps), and the
   one-line errors of bad command-line values, events and bytes. Each case
   runs the real binary. *)

open Test_support
open Support

let with_file = Support.with_file

let lines s = List.filter (( <> ) "") (String.split_on_char '\n' s)

(* Every line of a trace file is a JSON object. *)
let trace_is_json path =
  let ic = open_in_bin path in
  let ok = ref true and n = ref 0 in
  (try while true do
       let l = input_line ic in
       incr n;
       match Yojson.Safe.from_string l with `Assoc _ -> () | _ -> ok := false | exception _ -> ok := false
     done with End_of_file -> ());
  close_in ic;
  !ok && !n > 0

let run ?(timeout = 60) args =
  (* a guard against a hang, not a timed assertion: 124 is a hang *)
  run_command (Printf.sprintf "timeout %d %s run %s" timeout exe args)

let one_error_line name (status, _, err) expect =
  Alcotest.(check int) (name ^ ": exit 1\n" ^ err) 1 status;
  Alcotest.(check int) (name ^ ": one line\n" ^ err) 1 (List.length (lines err));
  Alcotest.(check bool) (Printf.sprintf "%s: %S in %S" name expect err) true
    (Str_contains.contains err expect)

(* ---------------------------------------------------------------- D19 *)

let activations =
  "ontology O\n\tpredicate go(n as integer) extends percept\n\n\
   agent A uses ontology O\n\ton create do\n\t\tactivate behaviour Main\n\n\
   cyclic behaviour Main for agent A\n\
   \ton percept when content matches go(n) do\n\t\ti = 0\n\t\twhile i < n do\n\t\t\tactivate behaviour H\n\t\t\ti = i + 1\n\
   \t\tlog \"done \" + n\n\n\
   one shot behaviour H for agent A\n\tdo\n\t\tx = 1\n"

(* 4,000 activations in one handler (22 s before D19's NewId) complete; the
   10,000th active instance is the last: the next activate is an exhaustion
   error at its statement, and the handler stops there. *)
let d19_bound () =
  with_file "jsref_act.jade" activations (fun p ->
      with_file "jsref_act.jsonl" "{\"agent\": \"a\", \"notify\": \"go(4000)\"}\n{\"run\": 1}\n" (fun ev ->
          let (status, out, err) = run (Printf.sprintf "%s --agent a:A --events %s --max-steps 10" p ev) in
          Alcotest.(check int) ("4000: exit 0\n" ^ err) 0 status;
          Alcotest.(check string) "4000: done" "a: done 4000\n" out);
      with_file "jsref_act2.jsonl" "{\"agent\": \"a\", \"notify\": \"go(10000)\"}\n{\"run\": 1}\n" (fun ev ->
          let r = run (Printf.sprintf "%s --agent a:A --events %s --max-steps 10" p ev) in
          let (_, out, _) = r in
          one_error_line "10000" r
            (Printf.sprintf "%s:12:4: error: exhaustion: too many behaviours: an agent has at most %d active behaviour instances"
               p Interp.Eval.default_config.max_behaviours);
          Alcotest.(check string) "the handler stopped" "" out))

(* The bound counts what is active, not every activation ever made: 10,005
   one-shot instances, activated one per percept, each gone after its step,
   never meet it (the count is brought up to date after each rule). *)
let d19_counts_active () =
  let prog = "ontology O\n\tproposition tick extends percept\n\n\
              agent A uses ontology O\n\tproperty n as integer = 0\n\ton create do\n\t\tactivate behaviour Main\n\n\
              cyclic behaviour Main for agent A\n\ton percept when content matches tick do\n\t\tactivate behaviour H\n\n\
              one shot behaviour H for agent A\n\tdo\n\t\tn = n + 1\n\n\
              agent B uses ontology O\n" in
  let prog = prog ^ "" in
  let ev = Buffer.create 100_000 in
  for _ = 1 to 10_005 do Buffer.add_string ev "{\"agent\": \"a\", \"notify\": \"tick\"}\n{\"run\": 2}\n" done;
  with_file "jsref_act3.jade" (prog ^ "") (fun p ->
      with_file "jsref_act3.jsonl" (Buffer.contents ev) (fun ev ->
          let (status, _, err) = run (Printf.sprintf "%s --agent a:A --events %s" p ev) in
          Alcotest.(check string) "no error" "" err;
          Alcotest.(check int) "exit 0" 0 status))

(* With 10,000 active, a body that deactivates its own instance may then
   activate one (the count is what JADE's agent sees: the deactivation
   counts at once); the handler logs "after". *)
let d19_deactivate_then_activate () =
  let prog = "ontology O\n\tpredicate go(n as integer) extends percept\n\tproposition stop extends percept\n\n\
              agent A uses ontology O\n\ton create do\n\t\tactivate behaviour Main\n\n\
              cyclic behaviour Main for agent A\n\
              \ton percept when content matches go(n) do\n\t\ti = 0\n\t\twhile i < n do\n\t\t\tactivate behaviour H\n\t\t\ti = i + 1\n\n\
              \ton percept when content matches stop do\n\t\tdeactivate this\n\t\tactivate behaviour H\n\t\tlog \"after\"\n\n\
              one shot behaviour H for agent A\n\tdo\n\t\tx = 1\n" in
  with_file "jsref_act4.jade" prog (fun p ->
      with_file "jsref_act4.jsonl" "{\"agent\": \"a\", \"notify\": \"go(9999)\"}\n{\"agent\": \"a\", \"notify\": \"stop\"}\n{\"run\": 1}\n" (fun ev ->
          let (status, out, err) = run (Printf.sprintf "%s --agent a:A --events %s --max-steps 10" p ev) in
          Alcotest.(check string) "no error" "" err;
          Alcotest.(check int) "exit 0" 0 status;
          Alcotest.(check string) "the activation after the deactivation" "a: after\n" out))

(* ---------------------------------------------------------------- D20 *)

(* A run count of 2^62 - 1 ends at once when every agent is idle; an agent
   that never idles (the printed loop, D4) is stopped by --max-steps. *)
let d20_rounds () =
  let prog = "agent A\n\ton create do\n\t\tlog \"hi\"\n" in
  with_file "jsref_idle.jade" prog (fun p ->
      with_file "jsref_idle.jsonl" "{\"run\": 4611686018427387903}\n{\"run\": 1000000000}\n" (fun ev ->
          let (status, out, _) = run ~timeout:20 (Printf.sprintf "%s --agent a:A --events %s" p ev) in
          Alcotest.(check int) "idle: ends, exit 0" 0 status;
          Alcotest.(check string) "idle: ran" "a: hi\n" out;
          let trace = Filename.temp_file "jsref-printed" ".jsonl" in
          let (status, _, _) = run ~timeout:20 (Printf.sprintf "%s --agent a:A --events %s --variant printed --max-steps 500 --trace %s"
                                                  p ev trace) in
          Alcotest.(check int) "printed: ends at --max-steps, exit 0" 0 status;
          (* the header, create, log, 500 steps, destroy *)
          let n = List.length (lines (read_file trace)) in
          Sys.remove trace;
          Alcotest.(check int) "printed: 500 steps" (1 + 2 + 500 + 1) n))

(* ---------------------------------------------------------------- D21 *)

(* s = s + s stops at the limit, at the +, and the run carries on (R7): the
   next handler runs, and the trace is JSON. A map that grows the same. *)
let d21_sizes () =
  let prog = "ontology O\n\tproposition tick extends percept\n\n\
              agent A uses ontology O\n\tproperty m as map of integer:integer\n\ton create do\n\t\tactivate behaviour B\n\n\
              cyclic behaviour B for agent A\n\
              \ton percept when content matches tick do\n\t\ts = \"ab\"\n\t\twhile true do\n\t\t\ts = s + s\n\n\
              \ton percept when content matches tick do\n\t\ti = 0\n\t\twhile true do\n\t\t\tm[i] = i\n\t\t\ti = i + 1\n\n\
              \ton percept when content matches tick do\n\t\tlog \"still here \" + (size of m)\n" in
  with_file "jsref_grow.jade" prog (fun p ->
      with_file "jsref_grow.jsonl" "{\"agent\": \"a\", \"notify\": \"tick\"}\n" (fun ev ->
          let trace = Filename.temp_file "jsref-grow" ".jsonl" in
          let (status, out, err) = run (Printf.sprintf "%s --agent a:A --events %s --fuel 5000000 --trace %s" p ev trace) in
          let json = trace_is_json trace in
          Sys.remove trace;
          Alcotest.(check int) "exit 1 (D15)" 1 status;
          let limits = Printf.sprintf "(at most %d bytes in a text, %d entries in a map)" Interp.Eval.max_text Interp.Eval.max_map_size in
          Alcotest.(check (list string)) "two exhaustion errors, located"
            [ Printf.sprintf "%s:13:8: error: exhaustion: value too large: the text would be too long %s" p limits;
              Printf.sprintf "%s:18:4: error: exhaustion: value too large: the map would have too many entries %s" p limits ]
            (lines err);
          Alcotest.(check string) "the run carried on" (Printf.sprintf "a: still here %d\n" Interp.Eval.max_map_size) out;
          Alcotest.(check bool) "the trace is JSON" true json))

(* ---------------------------------------------------------------- D37 *)

(* A list of two copies of a list of two copies of ... d levels above [1]:
   d + 1 lists in memory, 3 * 2^d - 1 parts (the innermost list and its 1
   are 2). Comparing two such (built apart, so that no part is physically
   shared between them) visits every pair of parts, and hashing one every
   part: 3 * 2^d - 1 visits each. At d = 21 that is 6,291,455, within the
   10,000,000 of D37; at d = 22, 12,582,911, past it. *)
let rec shared_list d = if d = 0 then Interp.Value.list_of [ Interp.Value.Int 1 ]
  else let x = shared_list (d - 1) in Interp.Value.list_of [ x; x ]

let d37_bound () =
  let module V = Interp.Value in
  Alcotest.(check int) "the bound" 10_000_000 V.max_visits;
  let too_large f = match f () with _ -> false | exception V.Too_large -> true in
  Alcotest.(check bool) "d = 21: compares, equal" true (V.equal (shared_list 21) (shared_list 21));
  Alcotest.(check bool) "d = 21: hashes" false (too_large (fun () -> V.hash (shared_list 21)));
  Alcotest.(check bool) "d = 22: comparing is too large" true
    (too_large (fun () -> V.equal (shared_list 22) (shared_list 22)));
  Alcotest.(check bool) "d = 22: hashing is too large" true (too_large (fun () -> V.hash (shared_list 22)));
  (* a value compared with itself stops at once, and each call has its own budget *)
  let x = shared_list 40 in
  Alcotest.(check bool) "the same value: equal at once" true (V.equal x x);
  Alcotest.(check bool) "a budget per call" true (V.equal (shared_list 21) (shared_list 21));
  (* two maps of 1,000,000 entries each (D21's most) compare within the bound *)
  let big () = let m = V.map_empty () in
    (match m with V.Map mv -> for i = 0 to Interp.Eval.max_map_size - 1 do V.map_set mv (V.Int i) (V.Int i) done
                | _ -> ());
    m in
  Alcotest.(check bool) "two full maps compare" true (V.equal (big ()) (big ()));
  (* through the command line: located exhaustion errors, the run carries on *)
  let b = Buffer.create 4096 in
  Buffer.add_string b "ontology O\n\tproposition tick extends percept\n\n\
                       agent A uses ontology O\n\ton create do\n\t\tactivate behaviour B\n\n\
                       cyclic behaviour B for agent A\n\ton percept when content matches tick do\n\t\ta0 = [1]\n\t\tb0 = [1]\n";
  for i = 1 to 40 do Printf.bprintf b "\t\ta%d = [a%d, a%d]\n\t\tb%d = [b%d, b%d]\n" i (i - 1) (i - 1) i (i - 1) (i - 1) done;
  Buffer.add_string b "\t\tlog \"equal \" + (a40 = b40)\n\n\ton percept when content matches tick do\n\t\tlog \"still here\"\n";
  with_file "jsref_shared.jade" (Buffer.contents b) (fun p ->
      with_file "jsref_shared.jsonl" "{\"agent\": \"a\", \"notify\": \"tick\"}\n" (fun ev ->
          let (status, out, err) = run (Printf.sprintf "%s --agent a:A --events %s" p ev) in
          Alcotest.(check int) "exit 1 (D15)" 1 status;
          Alcotest.(check (list string)) "one exhaustion error, at the ="
            [ Printf.sprintf "%s:92:19: error: exhaustion: value too large: comparing or hashing it would visit more than 10000000 values" p ]
            (lines err);
          Alcotest.(check string) "the run carried on" "a: still here\n" out))

(* ---------------------------------------------------------------- D22 *)

(* Distinct texts of 128 KB kept in a map pass 64 MB: an exhaustion error
   of the handler, somewhere in its loop (where depends on the garbage
   collector), and the run carries on. *)
let d22_memory () =
  let prog = "ontology O\n\tproposition tick extends percept\n\n\
              agent A uses ontology O\n\tproperty m as map of integer:text\n\ton create do\n\t\tactivate behaviour B\n\n\
              cyclic behaviour B for agent A\n\
              \ton percept when content matches tick do\n\t\ts = \"x\"\n\t\twhile length of s < 100000 do\n\t\t\ts = s + s\n\
              \t\ti = 0\n\t\twhile true do\n\t\t\tm[i] = s + i\n\t\t\ti = i + 1\n\n\
              \ton percept when content matches tick do\n\t\tlog \"still here\"\n" in
  with_file "jsref_mem.jade" prog (fun p ->
      with_file "jsref_mem.jsonl" "{\"agent\": \"a\", \"notify\": \"tick\"}\n" (fun ev ->
          let trace = Filename.temp_file "jsref-mem" ".jsonl" in
          (* 1.5 GB of address space at most: without the bound, the run
             dies of it instead of taking the machine's memory *)
          let (status, out, err) = run_command (Printf.sprintf "ulimit -v 1500000; timeout 60 %s run %s --agent a:A --events %s --fuel 100000000 --max-memory 64 --trace %s"
                                                  exe p ev trace) in
          let json = trace_is_json trace in
          Sys.remove trace;
          Alcotest.(check int) "exit 1 (D15)" 1 status;
          Alcotest.(check int) ("one error\n" ^ err) 1 (List.length (lines err));
          let line = try int_of_string (List.nth (String.split_on_char ':' err) 1) with _ -> 0 in
          Alcotest.(check bool) ("in the loop, lines 15-17: " ^ err) true (line >= 15 && line <= 17);
          Alcotest.(check bool) ("the message: " ^ err) true
            (Str_contains.contains err "error: exhaustion: out of memory: the run takes more than 64 MB (--max-memory)");
          Alcotest.(check string) "the run carried on" "a: still here\n" out;
          Alcotest.(check bool) "the trace is JSON" true json));
  let r = run (Printf.sprintf "%s --agent s:Spinner --max-memory 8" (Filename.concat root "conformance/055-r7-fuel-exhausted/program.jade")) in
  one_error_line "max-memory 8" r "jadescript-ref: error: option --max-memory: \"8\" is not a whole number from 16 to 1048576"

(* ------------------------------------------------------- bad values *)

let spinner = Filename.concat root "conformance/055-r7-fuel-exhausted/program.jade"

let cli_values () =
  let r args = run (Printf.sprintf "%s --agent s:Spinner %s" spinner args) in
  one_error_line "duplicate" (r "--agent s:Spinner") "--agent s:Spinner: error: there is already an agent s";
  one_error_line "host" (run (Printf.sprintf "%s --agent host:Spinner" spinner)) "the name host is reserved";
  List.iter (fun (opt, v, range) ->
      one_error_line (opt ^ "=" ^ v) (r (Printf.sprintf "--%s=%s" opt v))
        (Printf.sprintf "jadescript-ref: error: option --%s: %S is not a whole number from %s" opt v range))
    [ ("fuel", "-1", "1 to 2147483647"); ("fuel", "0", "1 to 2147483647"); ("fuel", "abc", "1 to 2147483647");
      ("fuel", "2147483648", "1 to 2147483647");
      ("max-steps", "-5", "0 to 4611686018427387903"); ("max-steps", "99999999999999999999", "0 to 4611686018427387903");
      ("o2a-capacity", "-1", "1 to 2147483647"); ("o2a-capacity", "0", "1 to 2147483647"); ("o2a-capacity", "4611686018427387903", "1 to 2147483647");
      ("seed", "-3", "0 to 2147483647"); ("seed", "2147483648", "0 to 2147483647") ];
  one_error_line "trace in no directory" (r "--trace /nonexistent/t.jsonl")
    "/nonexistent/t.jsonl:1:1: error: cannot write the trace: /nonexistent/t.jsonl: No such file or directory";
  one_error_line "trace to /dev/full" (r "--trace /dev/full") "/dev/full:1:1: error: cannot write the trace: No space left on device";
  let (status, _, err) = run (Printf.sprintf "%s --agent a:A > /dev/full" (Filename.concat root "conformance/057-r8-log-and-invoke/program.jade")) in
  ignore status;
  Alcotest.(check bool) ("stdout full: no crash\n" ^ err) true
    (not (Str_contains.contains err "Fatal error") && not (Str_contains.contains err "exception"))

let events_values () =
  let bad = "{\"agent\": \"s\", \"notify\": \"spin(1)\", \"priority\": 4611686018427387903}\n\
             {\"agent\": \"s\", \"message\": \"spin(1)\", \"performative\": \"bogus\"}\n\
             {\"agent\": \"s\", \"notify\": \"spin(1)\", \"priority\": -1}\n\
             {\"agent\": \"s\", \"notify\": \"spin(1)\", \"priority\": 2147483648}\n\
             {\"agent\": \"s\", \"notify\": \"spin(1)\", \"priority\": 2147483647}\n\
             {\"agent\": \"s\", \"message\": \"spin(1)\", \"performative\": \"inform_if\"}\n\
             {\"agent\": \"s\", \"notify\": \"spin(1)\", \"priority\": 2.5}\n\
             {\"agent\": \"s\", \"notify\": \"spin(4611686018427387903)\"}\n\
             {\"agent\":\"s\",\"notify\":\"spin(-2147483649)\"}\n\
             {\"agent\":\"s\",\"notify\":\"spin(-2147483648)\"}\n" in
  with_file "jsref_badev.jsonl" bad (fun ev ->
      let (status, out, err) = run (Printf.sprintf "%s --agent s:Spinner --events %s" spinner ev) in
      Alcotest.(check int) "exit 1" 1 status;
      Alcotest.(check string) "nothing ran" "" out;
      let range = "error: \"priority\" is a natural number of 32 bits (R2a, D8): 0 to 2147483647" in
      Alcotest.(check (list string)) "each bad line, at its field"
        [ ev ^ ":1:37: " ^ range;
          ev ^ ":2:38: error: \"performative\" is one of the FIPA performatives the language knows: "
          ^ String.concat ", " Typing.performatives;
          ev ^ ":3:37: " ^ range; ev ^ ":4:37: " ^ range;
          ev ^ ":7:37: error: \"priority\" is a natural number (R2a)";
          (* D8: an integer literal of an events file is 32-bit, as in a
             program; the second line takes the quick reader's path *)
          ev ^ ":8:6: error: integer literal 4611686018427387903 is out of range: integer is 32-bit (-2147483648..2147483647)";
          ev ^ ":9:7: error: integer literal 2147483649 is out of range: integer is 32-bit (-2147483648..2147483647)" ]
        (lines err))

(* Texts are UTF-8: a byte that is not is a located syntax error in a
   program and in an events file; UTF-8 texts (and \u escapes) reach the
   trace, which stays JSON. *)
let utf_8 () =
  with_file "jsref_bad8.jade" "agent A\n\ton create do\n\t\tlog \"ab\xffc\"\n" (fun p ->
      one_error_line "program" (run (p ^ " --agent a:A"))
        (p ^ ":3:10: error: byte 0xFF in a text literal is not UTF-8"));
  List.iter (fun (what, bytes) ->
      with_file "jsref_bad8b.jade" ("agent A\n\ton create do\n\t\tlog \"" ^ bytes ^ "\"\n") (fun p ->
          let (status, _, _) = run (p ^ " --agent a:A") in
          Alcotest.(check int) (what ^ ": rejected") 1 status))
    [ ("overlong", "\xc0\xaf"); ("surrogate", "\xed\xa0\x80"); ("above U+10FFFF", "\xf4\x90\x80\x80");
      ("cut short", "\xe2\x82"); ("lone continuation", "\x80") ];
  let ok = "ontology O\n\tpredicate said(t as text) extends percept\n\n\
            agent A uses ontology O\n\ton create do\n\t\tlog \"h\xc3\xa9llo \\u00e9 \xe2\x82\xac \xf0\x9f\x98\x80\"\n\t\tactivate behaviour B\n\n\
            cyclic behaviour B for agent A\n\ton percept when content matches said(t) do\n\t\tlog t\n" in
  with_file "jsref_ok8.jade" ok (fun p ->
      with_file "jsref_bad8.jsonl" "{\"agent\": \"a\", \"notify\": \"said(\\\"x\xfey\\\")\"}\n" (fun ev ->
          let (status, _, err) = run (Printf.sprintf "%s --agent a:A --events %s" p ev) in
          Alcotest.(check int) "events file: exit 1" 1 status;
          Alcotest.(check bool) ("events file: located\n" ^ err) true
            (* the events line is not JSON (JSON is UTF-8): located at the byte *)
            (Str_contains.contains err (ev ^ ":1:35: error: not JSON: byte 35 is not valid UTF-8")));
      with_file "jsref_ok8.jsonl" "{\"agent\": \"a\", \"notify\": \"said(\\\"\xc3\xa9t\xc3\xa9 \\\\u00e9\\\")\"}\n" (fun ev ->
          let trace = Filename.temp_file "jsref-utf8" ".jsonl" in
          let (status, out, err) = run (Printf.sprintf "%s --agent a:A --events %s --trace %s" p ev trace) in
          let json = trace_is_json trace in
          Sys.remove trace;
          Alcotest.(check int) ("valid UTF-8: exit 0\n" ^ err) 0 status;
          Alcotest.(check string) "the texts" "a: h\xc3\xa9llo \xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\na: \xc3\xa9t\xc3\xa9 \xc3\xa9\n" out;
          Alcotest.(check bool) "the trace is JSON" true json))

(* The playground shares run's rules: the same names refused, and D20's
   rounds (a count of 2^62 - 1 ends once the agent is idle). *)
let playground () =
  let module S = Playground_core.Session in
  let files = [ ("p.jade", "agent A\n\ton create do\n\t\tlog \"hi\"\n") ] in
  let boot agents = S.create { S.default_setup with files; agents } in
  (match boot [ "a:A"; "a:A" ] with
   | Error [ m ] -> Alcotest.(check string) "duplicate" "--agent a:A: error: there is already an agent a (agent names are unique)" m
   | _ -> Alcotest.fail "a duplicate agent name is accepted");
  (match boot [ "host:A" ] with
   | Error [ m ] -> Alcotest.(check bool) ("host: " ^ m) true (Str_contains.contains m "the name host is reserved")
   | _ -> Alcotest.fail "an agent named host is accepted");
  (match S.create { S.default_setup with files = [ ("p.jade", activations) ]; agents = [ "a:A" ] } with
   | Error ms -> Alcotest.failf "does not boot: %s" (String.concat "; " ms)
   | Ok t ->
     (match S.host t (S.Notify { agent = "a"; percept = "go(100)"; priority = None }) with Ok () -> () | Error m -> Alcotest.fail m);
     S.run_rounds t 4611686018427387903;
     let has s = List.exists (fun l -> Str_contains.contains l s) (S.trace t) in
     Alcotest.(check bool) "D20: the rounds ended, the handler ran" true (has "\"text\":\"done 100\""))

let () =
  Alcotest.run "limits" [
    ("limits", [
        Alcotest.test_case "D19 activation bound, no cubic cost" `Quick d19_bound;
        Alcotest.test_case "D19 counts active instances" `Quick d19_counts_active;
        Alcotest.test_case "D19 a deactivation counts at once" `Quick d19_deactivate_then_activate;
        Alcotest.test_case "D20 rounds end when nothing can change" `Quick d20_rounds;
        Alcotest.test_case "D21 texts and maps bounded" `Quick d21_sizes;
        Alcotest.test_case "D22 --max-memory" `Quick d22_memory;
        Alcotest.test_case "D37 comparisons bounded" `Quick d37_bound ]);
    ("edges", [
        Alcotest.test_case "run: bad command-line values" `Quick cli_values;
        Alcotest.test_case "run: bad events values" `Quick events_values;
        Alcotest.test_case "texts are UTF-8" `Quick utf_8;
        Alcotest.test_case "the playground: names, D20" `Quick playground ]);
  ]
