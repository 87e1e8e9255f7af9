(* Tests of lib/interp: evaluation, run-time errors, the run command, and
   traces validated by TLC. *)

open Syntax
open Test_support
open Support
module V = Interp.Value
module Mc = Semantics.Machine

let long = Sys.getenv_opt "JSREF_LONG" = Some "1"

(* Run a program; return the log lines and the trace events. *)
let run_program ?(variant = Mc.Reference) ?(fuel = 10_000) ?(events = fun _ -> ()) text agents =
  let r = Parse.string ~file:"t.jade" text in
  let env, diags = Typing.check [ r ] in
  (match List.filter (fun d -> d.Diag.severity = Diag.Error) diags with
   | [] -> ()
   | d :: _ -> Alcotest.failf "the test program does not check: %s" (Diag.to_string d));
  let logs = ref [] in
  let trace = Filename.temp_file "jsref" ".jsonl" in
  let oc = open_out_bin trace in
  let params = { Mc.default_params with variant } in
  let opts = { Interp.Runtime.params; engine = Interp.Runtime.Fast; max_memory = None; level = "full"; seed = None; interleave = None; fuel; max_steps = 100_000; trace = Some oc;
               on_log = (fun a s -> logs := (a ^ ": " ^ s) :: !logs); on_error = (fun _ _ _ -> ()) } in
  let rt = Interp.Runtime.create env opts agents in
  events rt;
  Interp.Runtime.run_until_idle rt;
  Interp.Runtime.finish rt;
  close_out oc;
  let evs = Interp.Oracle.read_trace trace in
  Sys.remove trace;
  (List.rev !logs, evs)

let logs_of text = fst (run_program text [ ("a", "A", []) ])

let program body = "agent A\n\ton create do\n" ^ body

let check_logs name body expected =
  Alcotest.(check (list string)) name (List.map (fun s -> "a: " ^ s) expected) (logs_of (program body))

(* ------------------------------------------------------------- values *)

(* Java's int: wrap-around, truncating division, remainder with the sign of
   the dividend (JLS 15.17). *)
let integers () =
  check_logs "Java int" "\t\tx = 2147483647\n\t\tlog x + 1\n\t\tlog -7 / 2\n\t\tlog -7 % 2\n\t\tlog 7 % -2\n\t\ty = -2147483647 - 1\n\t\tlog y / -1\n\t\tlog 65536 * 65536\n"
    [ "-2147483648"; "-3"; "-1"; "1"; "-2147483648"; "0" ]

(* float is binary32 after every operation; double is binary64. *)
let floats () =
  (* 0.1f + 0.1f + 0.1f rounds to 0.3f, and the literal 0.3 beside a float is
     0.3f; as doubles the sum is 0.30000000000000004 (Java prints the same).
     2^24 + 1 is not a binary32 value: it rounds to 2^24. Java's toString uses
     E notation from 10^7 on. *)
  check_logs "binary32 and binary64"
    "\t\tf as float = 0.1\n\t\tg as float = f + f + f\n\t\tlog g = 0.3\n\t\tlog g\n\t\td as double = 0.1\n\t\tlog d + d + d\n\t\tlog 1.0 / 3.0\n\t\tlog 16777216.0 + 1.0\n\t\th as float = 16777216.0\n\t\tlog h + 1\n\t\tlog 0.0001\n\t\tlog 100.0\n"
    [ "true"; "0.3"; "0.30000000000000004"; "0.3333333333333333"; "1.6777217E7"; "1.6777216E7"; "1.0E-4"; "100.0" ]

let texts () =
  check_logs "text concatenation and of" "\t\tlog \"a\" + 1 + 2\n\t\tlog 1 + 2 + \"a\"\n\t\tlog length of \"hello\"\n\t\tl = [1, 2, 3]\n\t\tlog size of l\n\t\tlog \"x\" + 2.5\n"
    [ "a12"; "3a"; "5"; "3"; "x2.5" ]

(* A map against an association list, through many inserts, updates and
   look-ups: integer keys (their own hash), texts, doubles equal to
   integers (the same key, R1c), past every growth of its table. *)
let map_model () =
  let rand = Random.State.make [| seed |] in
  for round = 1 to 20 do
    let m = match V.map_empty () with V.Map m -> m | _ -> assert false in
    let model = ref [] in
    let key () = match Random.State.int rand 4 with
      | 0 | 1 -> V.Int (Random.State.int rand (50 * round) - 10)
      | 2 -> V.Text (string_of_int (Random.State.int rand 300))
      | _ -> V.Double (float_of_int (Random.State.int rand 100)) in
    let find k = List.find_opt (fun (k', _) -> V.equal k k') !model in
    for i = 1 to 200 * round do
      let k = key () in
      if Random.State.bool rand then begin
        V.map_set m k (V.Int i);
        (match find k with
         | Some _ -> model := List.map (fun (k', v) -> if V.equal k k' then (k', V.Int i) else (k', v)) !model
         | None -> model := !model @ [ (k, V.Int i) ])
      end else begin
        let want = Option.map snd (find k) and got = V.map_find m k in
        if want <> got then
          Alcotest.failf "round %d: look-up of %s: %s, not %s" round (V.to_literal k)
            (match got with Some v -> V.to_literal v | None -> "none")
            (match want with Some v -> V.to_literal v | None -> "none")
      end
    done;
    Alcotest.(check int) "size" (List.length !model) m.size;
    Alcotest.(check (list string)) "the bindings in insertion order"
      (List.map (fun (k, v) -> V.to_literal k ^ ":" ^ V.to_literal v) !model)
      (List.map (fun (k, v) -> V.to_literal k ^ ":" ^ V.to_literal v) (V.map_bindings m));
    List.iter (fun (k, v) ->
        if V.map_find m k <> Some v then Alcotest.failf "round %d: %s lost" round (V.to_literal k)) !model
  done

let maps_structural () =
  (* R1c: percepts and concepts as map keys, by structural equality. *)
  let text = "ontology O\n\tpredicate position(x as double, y as double) extends percept with priority = 2\n\n\
              agent A uses ontology O\n\tproperty worldMap as map of position:text = {}\n\n\ton create do\n\
              \t\tworldMap[position(1, 2)] = \"A7\"\n\t\tworldMap[position(1.0, 2.0)] = \"B2\"\n\
              \t\tlog size of worldMap\n\t\tlog worldMap[position(1, 2.0)]\n\t\tlog keys of worldMap\n" in
  Alcotest.(check (list string)) "one key, widened, structural"
    [ "a: 1"; "a: B2"; "a: [position(1.0, 2.0)]" ] (logs_of text)

(* D11: [priority of] a percept is its type's default priority (R1a), not a
   host's override; D12: [for] goes over a map's keys in insertion order. *)
let decisions_of_and_for () =
  let text = "ontology O\n\tproposition base extends percept with priority = 5\n\tproposition sub extends base\n\n\
              agent A uses ontology O\n\ton create do\n\t\tlog priority of sub\n\t\tm = {\"b\": 1, \"a\": 2}\n\
              \t\tfor k in m do\n\t\t\tlog k\n" in
  Alcotest.(check (list string)) "priority of, for over a map"
    [ "a: 5"; "a: b"; "a: a" ] (logs_of text)

(* A message handler reads its message's performative and sender. *)
(* D40: an instance's number comes from its agent's own supply: two agents
   created one after the other both number their first instance 1, and a
   second activation in an agent is 2, whatever ran between. *)
let d40_numbers_per_agent () =
  let text = "agent A\n\ton create do\n\t\tactivate behaviour B\n\t\tactivate behaviour B\n\n\
              one shot behaviour B for agent A\n\tdo\n\t\tlog this\n" in
  let (logs, _) = run_program text [ ("a", "A", []); ("b", "A", []) ] in
  Alcotest.(check (list string)) "each agent's instances numbered from 1"
    [ "a: behaviour #1"; "b: behaviour #1"; "a: behaviour #2"; "b: behaviour #2" ] logs

(* D41: a when condition changes no behaviour. A guard that calls a function
   that activates fails there with an error (the handler is not applicable);
   the activation is not made, now or later; the log the function made
   before it stays. *)
let d41_guard_cannot_activate () =
  let text = "ontology O\n\tproposition ping extends percept\n\n\
              agent A uses ontology O\n\ton create do\n\t\tactivate behaviour W\n\n\
              \tfunction sneaky() as boolean do\n\t\tlog \"sneaky\"\n\t\tactivate behaviour X\n\t\treturn true\n\n\
              cyclic behaviour W for agent A\n\ton percept when content matches ping and sneaky() do\n\t\tlog \"ran\"\n\n\
              one shot behaviour X for agent A\n\tdo\n\t\tlog \"X stepped\"\n" in
  let (logs, evs) = run_program text [ ("a", "A", []) ] ~events:(fun rt ->
      let env = Interp.Runtime.env rt in
      let (v, d) = Interp.Eval.percept_value env ~agent_type:"A" (Parse.expr ~file:"e" "ping") in
      ignore (Interp.Runtime.notify rt ~agent:"a" v ~default:d ~priority:None)) in
  Alcotest.(check (list string)) "the function's log, no handler, no X" [ "a: sneaky" ] logs;
  let msgs = List.filter_map (function
      | `Assoc f -> (match List.assoc_opt "event" f, List.assoc_opt "message" f with
          | Some (`String "error"), Some (`String m) -> Some m | _ -> None)
      | _ -> None) evs in
  Alcotest.(check (list string)) "the error at the activate"
    [ "a when condition cannot activate or deactivate a behaviour" ] msgs;
  Alcotest.(check bool) "no activate line" false
    (List.exists (function `Assoc f -> List.assoc_opt "event" f = Some (`String "activate")
                                        && List.assoc_opt "behaviour" f = Some (`String "X") | _ -> false) evs)

let message_fields () =
  let text = "ontology O\n\tpredicate hello(who as text)\n\nagent A uses ontology O\n\ton create do\n\t\tactivate behaviour B\n\n\
              cyclic behaviour B for agent A\n\ton message when content matches hello(w) do\n\
              \t\tlog performative of message + \" \" + w + \" from \" + (sender of message)\n" in
  let (logs, _) = run_program text [ ("a", "A", []) ]
      ~events:(fun rt -> ignore (Interp.Runtime.message rt ~agent:"a" ~perf:"inform"
                                   (V.Schema { sname = "hello"; slots = [| ("who", ref (V.Text "you")) |] }))) in
  Alcotest.(check (list string)) "performative, content, sender" [ "a: inform you from aid(\"host\")" ] logs

let control () =
  check_logs "loops, break, continue, functions" "\t\ts = 0\n\t\tfor i in [1, 2, 3, 4, 5] do\n\t\t\tif i = 2 do\n\t\t\t\tcontinue\n\t\t\tif i = 5 do\n\t\t\t\tbreak\n\t\t\ts = s + i\n\t\tlog s\n\t\tn = 0\n\t\twhile n < 10 do\n\t\t\tn = n + 3\n\t\tlog n\n"
    [ "8"; "12" ]

(* ----------------------------------------------------- R7 errors *)

let error_events evs = List.filter (fun e -> Interp.Oracle.check_expectations [ `Assoc [ "has", `Assoc [ "event", `String "error" ] ] ] [ e ] = Ok ()) evs

let runtime_errors_located () =
  let text = "ontology O\n\tproposition p extends percept\n\nagent A uses ontology O\n\tproperty m as map of text:integer = {}\n\n\ton create do\n\t\tactivate behaviour B\n\n\
              cyclic behaviour B for agent A\n\ton percept when content matches p do\n\t\tlog m[\"missing\"]\n\t\tlog \"not reached\"\n\n\
              \ton percept when content matches p do\n\t\tlog 1 / (size of m)\n\n\ton percept when content matches p do\n\t\tlog \"third handler still runs\"\n" in
  let (logs, evs) = run_program text [ ("a", "A", []) ]
      ~events:(fun rt -> ignore (Interp.Runtime.notify rt ~agent:"a" (V.Schema { sname = "p"; slots = [||] }) ~default:0 ~priority:None)) in
  Alcotest.(check (list string)) "the agent carries on (R7)" [ "a: third handler still runs" ] logs;
  let errs = error_events evs in
  Alcotest.(check int) "two errors recorded" 2 (List.length errs);
  let at e = match e with `Assoc f -> (match List.assoc_opt "at" f with Some (`String s) -> s | _ -> "") | _ -> "" in
  (* at the start of the failing expression: m["missing"], 1 / (size of m) *)
  Alcotest.(check (list string)) "located" [ "t.jade:12:7"; "t.jade:16:7" ] (List.map at errs)

(* The resolved forms (Eval: a guard [content matches S(x, _) and rest]
   evaluated by slot position, properties found by address) give what the
   general rules give: a percept of a subtype of S takes the general rules
   (slots by name), the rest of the guard is evaluated after the bindings and
   its error located, [_] binds nothing, and a behaviour property hides the
   agent's property of the same name. *)
let resolved_forms () =
  let text = "ontology O\n\tpredicate q1(x as integer) extends percept with priority = 3\n\
              \tpredicate q2(y as integer) extends q1 with priority = 2\n\
              \tpredicate pair(a as integer, b as integer) extends percept\n\n\
              agent A uses ontology O\n\tproperty n as integer = 7\n\n\ton create do\n\t\tactivate behaviour B\n\n\
              cyclic behaviour B for agent A\n\tproperty n as integer = 100\n\n\
              \ton percept when content matches q1(v) and v > 0 do\n\t\tlog \"q1 \" + v + \" n \" + n\n\t\tn = n + 1\n\n\
              \ton percept when content matches pair(u, _) do\n\t\tlog \"pair \" + u + \" \" + (n of agent)\n\n\
              \ton percept when content matches q1(w) and (w / 0) > 1 do\n\t\tlog \"never\"\n" in
  let schema name ints = V.Schema { sname = name; slots = Array.of_list (List.mapi (fun i k ->
      ((match name, i with "q1", _ -> "x" | "q2", 0 -> "x" | "q2", _ -> "y" | _, 0 -> "a" | _ -> "b"), ref (V.Int k))) ints) } in
  let (logs, evs) = run_program text [ ("a", "A", []) ] ~events:(fun rt ->
      List.iter (fun (p, d) -> ignore (Interp.Runtime.notify rt ~agent:"a" p ~default:d ~priority:None))
        [ (schema "q1" [ 5 ], 3); (schema "q2" [ 6; 9 ], 2); (schema "q1" [ -1 ], 3); (schema "pair" [ 1; 2 ], 0) ]) in
  Alcotest.(check (list string)) "logs"
    [ "a: q1 5 n 100"; "a: q1 6 n 101"; "a: pair 1 7" ] logs;
  let at e = match e with `Assoc f -> (match List.assoc_opt "at" f with Some (`String s) -> s | _ -> "") | _ -> "" in
  Alcotest.(check (list string)) "the guard's error, once per percept of q1 or a subtype"
    [ "t.jade:22:45"; "t.jade:22:45"; "t.jade:22:45" ] (List.map at (error_events evs))

let fuel_exhausted () =
  let text = program "\t\tactivate behaviour Spin\n\ncyclic behaviour Spin\n\tdo\n\t\twhile true do\n\t\t\tx = 1\n\t\tlog \"never\"\n" in
  let (logs, evs) = run_program ~fuel:500 text [ ("a", "A", []) ] in
  Alcotest.(check (list string)) "no log" [] logs;
  Alcotest.(check bool) "step budget exhausted, recorded" true
    (List.exists (fun e -> Interp.Oracle.check_expectations [ `Assoc [ "has", `Assoc [ "event", `String "error" ] ] ] [ e ] = Ok ()
                           && (match e with `Assoc f -> (match List.assoc_opt "message" f with
                               | Some (`String m) -> String.length m > 10 && String.sub m 0 11 = "step budget" | _ -> false) | _ -> false)) evs)

(* --------------------------------------------------------- the CLI *)

let with_file = Support.with_file

let robome = Filename.concat root "examples/paper/robome_completed.jade"

let is_diag l =
  match String.split_on_char ':' l with
  | _ :: line :: col :: rest -> int_of_string_opt line <> None && int_of_string_opt col <> None
                               && (match rest with r :: _ -> String.trim r = "error" | [] -> false)
  | _ -> false

let cli_bad_events () =
  let bad = "{\"agent\": \"r\", \"notify\": \"qrCodeRead(42)\"}\n{\"agent\": \"zz\", \"notify\": \"obstacle\"}\nnot json\n\
             {\"agent\": \"r\", \"notify\": \"position(1, 2\"}\n{\"agent\": \"r\", \"notify\": \"obstacle\", \"priority\": -3}\n\
             {\"agent\": \"r\", \"notify\": \"nothing(1)\"}\n{\"run\": \"forever\"}\n" in
  with_file "jsref_bad_events.jsonl" bad (fun ev ->
      let (status, out, err) = run_command (Printf.sprintf "%s run %s --agent r:RoboMe:@robome --events %s" exe robome ev) in
      Alcotest.(check int) "exit 1" 1 status;
      Alcotest.(check string) "nothing ran: no log" "" out;
      let ls = List.filter (( <> ) "") (String.split_on_char '\n' err) in
      Alcotest.(check int) ("one line per bad line:\n" ^ err) 7 (List.length ls);
      List.iteri (fun i l ->
          Alcotest.(check bool) ("located: " ^ l) true (is_diag l);
          let line = int_of_string (List.nth (String.split_on_char ':' l) 1) in
          Alcotest.(check int) ("at its line: " ^ l) (i + 1) line) ls)

let cli_bad_program () =
  with_file "jsref_bad_prog.jade" "agent A\n\tproperty x as integer = \"no\"\n" (fun p ->
      let (status, _, err) = run_command (Printf.sprintf "%s run %s --agent a:A" exe p) in
      Alcotest.(check int) "exit 1" 1 status;
      Alcotest.(check bool) ("a type error, located: " ^ err) true (is_diag (String.trim err)));
  let (status, _, err) = run_command (Printf.sprintf "%s run %s --agent r:NoSuchAgent" exe robome) in
  Alcotest.(check int) "unknown agent type: exit 1" 1 status;
  Alcotest.(check bool) ("one line, no backtrace: " ^ err) true
    (List.length (List.filter (( <> ) "") (String.split_on_char '\n' err)) = 1)

(* D15: a run-time error is reported as it happens, the run carries on
   (the later log line is printed), and the exit status is 1. *)
let cli_runtime_error () =
  let prog = "ontology O\n\tproposition tick extends percept\n\
              agent A uses ontology O\n\tproperty n as integer = 0\n\
              \ton create do\n\t\tactivate behaviour B\n\
              cyclic behaviour B for agent A\n\
              \ton percept when content matches tick do\n\t\tn = n + 1\n\t\tlog 10 / (2 - n)\n" in
  with_file "jsref_rt.jade" prog (fun p ->
      with_file "jsref_rt.jsonl" "{\"agent\": \"a\", \"notify\": \"tick\"}\n{\"run\": \"idle\"}\n\
                                 {\"agent\": \"a\", \"notify\": \"tick\"}\n{\"run\": \"idle\"}\n\
                                 {\"agent\": \"a\", \"notify\": \"tick\"}\n" (fun ev ->
          let (status, out, err) = run_command (Printf.sprintf "%s run %s --agent a:A --events %s" exe p ev) in
          Alcotest.(check int) "exit 1" 1 status;
          Alcotest.(check string) "the other handlers ran" "a: 10\na: -10\n" out;
          Alcotest.(check string) "one located line" (p ^ ":10:7: error: division by zero\n")  (* the division, 10 / (2 - n) *) err))

(* The kinds of run-time errors (R7): each its own exception and wording;
   the trace's error line the same for all. Deep recursion is an exhaustion
   error at the call, never an OCaml stack overflow (even on a small stack);
   a host object without the method is a link error; a broken invariant of
   the machine is a crash. *)
let error_kinds () =
  let deep = "agent A\n\tfunction f(n as integer) as integer do\n\t\treturn f(n + 1)\n\n\ton create do\n\t\tlog f(1)\n" in
  with_file "jsref_deep.jade" deep (fun p ->
      (* 8 MB of stack is the default; 1 MB is enough for the call depth *)
      let (status, _, err) = run_command (Printf.sprintf "ulimit -s 1024; %s run %s --agent a:A" exe p) in
      Alcotest.(check int) "exit 1 (D15)" 1 status;
      Alcotest.(check string) "an exhaustion error, located at the call"
        (Printf.sprintf "%s:3:10: error: exhaustion: recursion too deep: more than %d nested calls of functions and procedures\n"
           p Interp.Eval.default_config.max_call_depth) err);
  let (_, evs) = run_program deep [ ("a", "A", []) ] in
  let msg e = match e with `Assoc f -> (match List.assoc_opt "message" f with Some (`String m) -> m | _ -> "") | _ -> "" in
  Alcotest.(check (list string)) "the trace's error line: the message alone"
    [ Printf.sprintf "recursion too deep: more than %d nested calls of functions and procedures" Interp.Eval.default_config.max_call_depth ]
    (List.map msg (error_events evs));
  let link = "agent A\n\tproperty r as any\n\ton create with r as any do\n\t\tinvoke \"fly\" on r\n" in
  with_file "jsref_link.jade" link (fun p ->
      let (status, _, err) = run_command (Printf.sprintf "%s run %s --agent a:A:@robome" exe p) in
      Alcotest.(check int) "exit 1 (D15)" 1 status;
      Alcotest.(check string) "a link error" (p ^ ":4:10: error: link error: RoboMe has no method \"fly\"\n") err);
  let fuel = program "\t\twhile true do\n\t\t\tx = 1\n" in
  with_file "jsref_fuel.jade" fuel (fun p ->
      let (_, _, err) = run_command (Printf.sprintf "%s run %s --agent a:A --fuel 50" exe p) in
      Alcotest.(check string) "fuel: an exhaustion error"
        (p ^ ":4:4: error: exhaustion: step budget exhausted: more than 50 statements in one handler or step (--fuel)\n") err);
  Alcotest.(check bool) "a trap is worded as its message" true
    (Interp.Eval.wording Interp.Eval.Trap_error "division by zero" = "division by zero");
  let p = Mc.default_params in
  let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 10 } (fst (Typing.check [ Parse.string ~file:"c.jade" "agent A\n" ])) ~name:"a" ~atype:"A" ~args:[] in
  let module RM = Interp.Runtime.P.M in
  let c = { (RM.init p ~world:a behs) with phase = Mc.Handle_phase; cur = None } in
  Alcotest.check_raises "a broken invariant is a crash"
    (Semantics.Fault.Crash "Machine: phase handle without a dispatch in progress")
    (fun () -> ignore (RM.step p c))

(* A run that dies leaves every event before its death: stopped by a signal
   in the middle of an endless run, its trace is whole lines, numbered 1, 2,
   ... without a gap, and long. *)
let trace_survives_death () =
  let prog = program "\t\tactivate behaviour Spin\n\ncyclic behaviour Spin\n\tdo\n\t\tlog \"spin\"\n" in
  with_file "jsref_spin.jade" prog (fun p ->
      let trace = Filename.temp_file "jsref-spin" ".jsonl" in
      let (status, _, _) = run_command (Printf.sprintf "timeout --preserve-status -s TERM 2 %s run %s --agent a:A --max-steps 100000000 --trace %s"
                                          exe p (Filename.quote trace)) in
      Alcotest.(check int) "stopped by the signal (exit 143)" 143 status;
      (* the header, then lines numbered 1, 2, ...: count those in order *)
      let (n, gap) = Trace.fold_file trace (fun (n, gap) k j ->
          if k = 1 then (n, gap)
          else match j with
            | `Assoc f when List.assoc_opt "step" f = Some (`Int (n + 1)) -> (n + 1, gap)
            | _ -> (n + 1, true)) (0, false) in
      Sys.remove trace;
      Alcotest.(check bool) (Printf.sprintf "many events (%d)" n) true (n > 1000);
      Alcotest.(check bool) "every event, whole and numbered without a gap" false gap)

let cli_logs () =
  with_file "jsref_ev.jsonl" "{\"agent\": \"r\", \"notify\": \"falling\"}\n" (fun ev ->
      let (status, out, _) = run_command (Printf.sprintf "%s run %s --agent r:RoboMe:@robome --events %s" exe robome ev) in
      Alcotest.(check int) "exit 0" 0 status;
      Alcotest.(check string) "log e prints NAME: text" "r: falling: stopped and backing off\n" out)

(* ------------------------------------------------ traces and TLC *)

let validate_file trace =
  List.iter (function
      | Explore.Validate.Accepted _ -> ()
      | Explore.Validate.Rejected { line; step; _ } -> Alcotest.failf "TLC rejects line %d: %s" line step
      | Explore.Validate.Cannot { line; reason; _ } -> Alcotest.failf "cannot validate (line %d): %s" line reason
      | Explore.Validate.Invalid { line; message } -> Alcotest.failf "invalid (line %d): %s" line message)
    (Explore.Validate.trace trace)

let paper_run_validated () =
  let events = "{\"agent\": \"r\", \"notify\": \"position(1.5, 2.0)\"}\n{\"agent\": \"r\", \"notify\": \"qrCodeRead(\\\"A7\\\")\"}\n\
                {\"agent\": \"r\", \"notify\": \"obstacle\"}\n{\"run\": 1}\n{\"agent\": \"r\", \"notify\": \"falling\", \"priority\": 1}\n\
                {\"agent\": \"r\", \"notify\": \"position(2, 3)\"}\n" in
  List.iter (fun variant ->
      with_file "jsref_pev.jsonl" events (fun ev ->
          let trace = Filename.temp_file "jsref" ".jsonl" in
          let (status, _, err) = run_command (Printf.sprintf "%s run %s --agent r:RoboMe:@robome --events %s --trace %s --variant %s --max-steps 300"
                                                exe robome ev trace variant) in
          Alcotest.(check int) ("run exits 0: " ^ err) 0 status;
          validate_file trace;
          (* and a tampered trace is rejected *)
          let lines = String.split_on_char '\n' (read_file trace) in
          let swapped = List.map (fun l ->
              let rep a b s = match Explore.Str_find.find s a with
                | k -> String.sub s 0 k ^ b ^ String.sub s (k + String.length a) (String.length s - k - String.length a)
                | exception Not_found -> s in
              if String.length l > 0 && (try ignore (Explore.Str_find.find l "\"event\":\"transfer\""); true with Not_found -> false)
              then rep "\"moved\":" "\"moved\":1" l else l) lines in
          let oc = open_out_bin trace in output_string oc (String.concat "\n" swapped); close_out oc;
          (match Explore.Validate.trace trace with
           | [ Explore.Validate.Rejected _ ] | [ Explore.Validate.Invalid _ ] -> ()
           | _ -> Alcotest.failf "a tampered %s trace was not rejected" variant);
          Sys.remove trace)) [ "reference"; "budgeted"; "native" ]

let vectors_validated () =
  let dir = Filename.concat root "conformance" in
  let vs = Interp.Oracle.load dir in
  let vs = if long then vs else List.filteri (fun i _ -> i mod 10 = 0) vs in
  Alcotest.(check bool) "some vectors" true (vs <> []);
  List.iter (fun (v : Interp.Oracle.vector) -> validate_file (Filename.concat v.dir "expected.jsonl")) vs

let conform_passes () =
  let (status, out, _) = run_command (Printf.sprintf "%s conform" exe) in
  Alcotest.(check int) ("every vector passes:\n" ^ out) 0 status;
  let (status, out, _) = run_command (Printf.sprintf "%s conform --impl '%s run --variant native'" exe exe) in
  Alcotest.(check int) ("native fails the suite:\n" ^ out) 1 status

(* conform judges what an implementation does, not only the events it
   writes: each fake implementation below plants one fault of a second
   implementer (wrong status, a signal, a hang, no header, another format
   version, a missing event), and conform must reject it; the honest fake
   (the expected trace, copied) must pass. *)
let conform_judges () =
  let dir = Filename.concat root "conformance" in
  let vector = "001-r3b-priority-order" in
  let expected = Filename.concat (Filename.concat dir vector) "expected.jsonl" in
  let fake name body =
    let f = Filename.temp_file ("jsref-fake-" ^ name) ".sh" in
    let oc = open_out_bin f in
    (* the trace file is the argument after --trace *)
    output_string oc ("#!/bin/sh\nwhile [ $# -gt 0 ]; do if [ \"$1\" = --trace ]; then out=\"$2\"; fi; shift; done\n"
                      ^ body ^ "\n");
    close_out oc; Unix.chmod f 0o755; f in
  let judge ?(timeout = "") f =
    let (status, out, _) = run_command (Printf.sprintf "%s conform %s --impl %s %s" exe timeout f vector) in
    (status, out) in
  let honest = fake "honest" (Printf.sprintf "cp %s \"$out\"" (Filename.quote expected)) in
  let (status, out) = judge honest in
  Alcotest.(check int) ("the expected trace, copied, passes:\n" ^ out) 0 status;
  (* D47: where an implementation ran its agents is its own; a header that
     names containers still equals the expected one *)
  let first_agent = match Yojson.Safe.from_string (List.hd (lines_of expected)) with
    | `Assoc f -> (match List.assoc_opt "agents" f with
        | Some (`List (`Assoc a :: _)) -> (match List.assoc_opt "name" a with Some (`String n) -> n | _ -> "a")
        | _ -> "a")
    | _ -> "a" in
  let deployed = fake "deployed" (Printf.sprintf "sed '1s/,\"program\":/,\"containers\":{\"%s\":\"peripheral\"},\"program\":/' %s > \"$out\""
                                    first_agent (Filename.quote expected)) in
  let (status, out) = judge deployed in
  Alcotest.(check int) ("the expected trace with containers in its header passes (D47):\n" ^ out) 0 status;
  let bad = [
    ("exit 3", Printf.sprintf "cp %s \"$out\"; exit 3" (Filename.quote expected), "exited with status 3");
    ("exit 1 without an error event", Printf.sprintf "cp %s \"$out\"; exit 1" (Filename.quote expected), "records no run-time error");
    ("a signal", Printf.sprintf "cp %s \"$out\"; kill -SEGV $$" (Filename.quote expected), "signal 11");
    ("no header", Printf.sprintf "tail -n +2 %s > \"$out\"" (Filename.quote expected), "header");
    ("version 999", Printf.sprintf "sed -E '1s/\"version\":[0-9]+/\"version\":999/' %s > \"$out\"" (Filename.quote expected), "version 999");
    ("another variant in the header", Printf.sprintf "sed '1s/\"reference\"/\"budgeted\"/' %s > \"$out\"" (Filename.quote expected), "header differs");
    ("an event missing", Printf.sprintf "sed '5d' %s > \"$out\"" (Filename.quote expected), "FAIL at event");
    ("one event too many", Printf.sprintf "cp %s \"$out\"; tail -n 1 %s >> \"$out\"" (Filename.quote expected) (Filename.quote expected), "FAIL at event");
    ("nothing written", "true", "empty trace");
  ] in
  List.iter (fun (what, body, why) ->
      let (status, out) = judge (fake "bad" body) in
      Alcotest.(check int) (what ^ " fails:\n" ^ out) 1 status;
      Alcotest.(check bool) (Printf.sprintf "%s: the report says %S:\n%s" what why out) true
        (try ignore (Explore.Str_find.find out why); true with Not_found -> false)) bad;
  let t0 = Unix.gettimeofday () in
  let (status, out) = judge ~timeout:"--timeout 1" (fake "hang" "sleep 60") in
  Alcotest.(check int) ("a hang fails:\n" ^ out) 1 status;
  Alcotest.(check bool) ("a hang is stopped by --timeout:\n" ^ out) true
    (Unix.gettimeofday () -. t0 < 20. && (try ignore (Explore.Str_find.find out "timed out"); true with Not_found -> false))

(* conform --judge and --generated (bin/judged.ml): a run is judged by its
   program's semantics, so any schedule R6 allows passes (the reference's
   finer interleaving, run --interleave); each case runs in a fresh
   directory with no expected trace, and a generated case has none at all.
   Implementations that cheat fail: one that copies the expected trace it
   finds beside the program, one that copies another vector's trace, one
   that writes the trace of one fixed generated program for every case, and
   one with a defect of the bug catalogue (lib/defects). *)
let conform_judged () =
  let dir = Filename.concat root "conformance" in
  let fake name body =
    let f = Filename.temp_file ("jsref-fake-" ^ name) ".sh" in
    let oc = open_out_bin f in
    output_string oc ("#!/bin/sh\nwhile [ $# -gt 0 ]; do if [ \"$1\" = --trace ]; then out=\"$2\"; fi; shift; done\n"
                      ^ body ^ "\n");
    close_out oc; Unix.chmod f 0o755; f in
  let conform args = let (status, out, _) = run_command (Printf.sprintf "%s conform %s" exe args) in (status, out) in
  let says out why = try ignore (Explore.Str_find.find out why); true with Not_found -> false in
  let vectors = "047-r6-ping-pong 048-r6-three-agent-ring 067-r5e-failure-wakes-sender 085-r5d-message-during-step-keeps-place" in
  let (status, out) = conform ("--judge " ^ vectors) in
  Alcotest.(check int) ("the reference, judged, passes:\n" ^ out) 0 status;
  let (status, out) = conform (Printf.sprintf "--judge --impl %s %s" (Filename.quote (exe ^ " run --interleave 5")) vectors) in
  Alcotest.(check int) ("another schedule (run --interleave), judged, passes:\n" ^ out) 0 status;
  let (status, out) = conform "--generated 12 --seed 4" in
  Alcotest.(check int) ("the reference on generated programs passes:\n" ^ out) 0 status;
  Alcotest.(check bool) "a summary of the generated programs" true (says out "12 generated programs (seed 4): 12 pass, 0 fail");
  let (status, out) = conform (Printf.sprintf "--generated 12 --seed 4 --impl %s" (Filename.quote (exe ^ " run --interleave 9"))) in
  Alcotest.(check int) ("another schedule on generated programs passes:\n" ^ out) 0 status;
  (* the cheaters *)
  let copy_here = fake "copy-here" "cp expected.jsonl \"$out\"" in
  let (status, out) = conform ("--judge --impl " ^ copy_here ^ " 047-r6-ping-pong") in
  Alcotest.(check int) ("copying the expected trace beside the program fails:\n" ^ out) 1 status;
  (* and when traces are compared too: the implementation runs in a fresh
     directory, not the vector's *)
  let (status, out) = conform ("--impl " ^ copy_here ^ " 047-r6-ping-pong 001-r3b-priority-order") in
  Alcotest.(check int) ("copying the expected trace beside the program fails, compared:\n" ^ out) 1 status;
  Alcotest.(check bool) ("... on every vector:\n" ^ out) true (says out "2 vectors: 0 pass, 2 fail");
  let other = Filename.concat (Filename.concat dir "048-r6-three-agent-ring") "expected.jsonl" in
  let copy_other = fake "copy-other" (Printf.sprintf "cp %s \"$out\"" (Filename.quote other)) in
  let (status, out) = conform ("--judge --impl " ^ copy_other ^ " 047-r6-ping-pong") in
  Alcotest.(check int) ("another vector's trace fails:\n" ^ out) 1 status;
  Alcotest.(check bool) ("... at the header:\n" ^ out) true (says out "line 1:");
  let keep = Filename.temp_file "jsref-judged" "" in
  Sys.remove keep;
  ignore (conform (Printf.sprintf "--generated 1 --seed 4 --keep %s" (Filename.quote keep)));
  let fixed = Filename.concat (Filename.concat keep "generated-4-1") "trace.jsonl" in
  Alcotest.(check bool) "--keep keeps the case and its trace" true (Sys.file_exists fixed);
  (* the kept run's exit status replayed too: 1 when its trace records a
     run-time error (D15) *)
  let replay = fake "replay" (Printf.sprintf "cp %s \"$out\"\nif grep -q '\"event\":\"error\"' \"$out\"; then exit 1; fi"
                                (Filename.quote fixed)) in
  let (status, out) = conform ("--generated 12 --seed 4 --impl " ^ replay) in
  Alcotest.(check int) ("one fixed trace for every generated program fails:\n" ^ out) 1 status;
  Alcotest.(check bool) ("... except the program it was written for:\n" ^ out) true (says out "generated-4-1                                pass");
  let (status, out) = conform (Printf.sprintf "--generated 12 --seed 4 --impl %s" (Filename.quote (exe ^ " run --defect first-handler-only"))) in
  Alcotest.(check int) ("a defect of the catalogue fails:\n" ^ out) 1 status;
  ignore (Sys.command ("rm -rf " ^ Filename.quote keep))

(* conform's resources: a huge trace is read with bounded memory
   (a 2M-line trace and a 100 MB line: conform's peak RSS stays small); its
   temporary files are removed after a pass, a failure, a timeout and a
   SIGINT of conform itself, which also stops the implementation. *)
let conform_resources () =
  let dir = Filename.concat root "conformance" in
  let vector = "001-r3b-priority-order" in
  let expected = Filename.quote (Filename.concat (Filename.concat dir vector) "expected.jsonl") in
  let tmp = Filename.temp_file "jsref-conform-tmp" "" in
  Sys.remove tmp; Unix.mkdir tmp 0o700;
  let fakes = ref [] in
  let fake name body =
    let f = Filename.concat (Filename.dirname tmp) (Filename.basename tmp ^ "-" ^ name ^ ".sh") in
    fakes := f :: !fakes;
    let oc = open_out_bin f in
    output_string oc ("#!/bin/sh\nwhile [ $# -gt 0 ]; do if [ \"$1\" = --trace ]; then out=\"$2\"; fi; shift; done\n"
                      ^ body ^ "\n");
    close_out oc; Unix.chmod f 0o755; f in
  let left () = Array.length (Sys.readdir tmp) in
  let conform ?(opts = "") f =
    run_command (Printf.sprintf "TMPDIR=%s /usr/bin/time -f 'RSS %%M' %s conform %s --impl %s %s"
                   (Filename.quote tmp) exe opts f vector) in
  let rss err =
    match List.find_opt (fun l -> String.length l > 4 && String.sub l 0 4 = "RSS ") (String.split_on_char '\n' err) with
    | Some l -> int_of_string (String.trim (String.sub l 4 (String.length l - 4)))
    | None -> Alcotest.failf "no RSS in: %s" err in
  let cases = [
    ("passes", fake "honest" (Printf.sprintf "cp %s \"$out\"" expected), 0);
    ("2M lines", fake "long" (Printf.sprintf "cp %s \"$out\"; seq 2000000 >> \"$out\"" expected), 1);
    ("a 100 MB line", fake "wide"
       (Printf.sprintf "head -n 1 %s > \"$out\"; head -c 100000000 /dev/zero | tr '\\000' a >> \"$out\"" expected), 1);
    ("a 100 MB stderr line", fake "noisy"
       (Printf.sprintf "cp %s \"$out\"; head -c 100000000 /dev/zero | tr '\\000' a >&2; exit 3" expected), 1);
  ] in
  List.iter (fun (what, f, want) ->
      let (status, out, err) = conform f in
      Alcotest.(check int) (what ^ ": exit status\n" ^ out ^ err) want status;
      let kb = rss err in
      Alcotest.(check bool) (Printf.sprintf "%s: conform's peak RSS %d kB < 60 MB" what kb) true (kb < 60_000);
      Alcotest.(check int) (what ^ ": no temporary file left") 0 (left ())) cases;
  let (status, _, _) = conform ~opts:"--timeout 1" (fake "hang" "sleep 60") in
  Alcotest.(check int) "a hang: exit 1" 1 status;
  Alcotest.(check int) "a hang: no temporary file left" 0 (left ());
  (* SIGINT to conform alone (not its process group) while a vector runs *)
  (* a sleep of its own (another run of this test may be under way) *)
  let sleep = Printf.sprintf "sleep 61.%05d" (Unix.getpid () mod 100000) in
  let hang = fake "hang2" sleep in
  let pid = Unix.create_process_env exe [| exe; "conform"; "--impl"; hang; vector |]
      (Array.append [| "TMPDIR=" ^ tmp |] (Unix.environment ())) Unix.stdin Unix.stdout Unix.stdout in
  let rec until n = if left () >= 2 || n = 0 then () else (Unix.sleepf 0.05; until (n - 1)) in
  until 200;
  Alcotest.(check bool) "the vector runs (its temporary files exist)" true (left () >= 2);
  Unix.kill pid Sys.sigint;
  (match Unix.waitpid [] pid with
   | (_, Unix.WEXITED c) -> Alcotest.(check int) "SIGINT: exit 130" 130 c
   | _ -> Alcotest.fail "SIGINT: conform died of the signal");
  Alcotest.(check int) "SIGINT: no temporary file left" 0 (left ());
  let (_, ps, _) = run_command "ps -eo args" in
  Alcotest.(check bool) "SIGINT: the implementation is stopped" false
    (List.exists (fun l -> String.trim l = sleep) (String.split_on_char '\n' ps));
  Unix.rmdir tmp;
  List.iter Sys.remove !fakes

(* ------------------------------------- random programs, random hosts *)

let percept_types = Test_support.Event_gen.percept_types

let literal_of = Test_support.Event_gen.small_literal

(* A percept of one of the program's percept types, in Jadescript syntax. *)
let random_percept_text rand env =
  let ps = percept_types env in
  let s = List.nth ps (Random.State.int rand (List.length ps)) in
  let args = List.map (fun (_, ty) -> literal_of rand ty) s.s_slots in
  if args = [] then s.s_name else s.s_name ^ "(" ^ String.concat ", " args ^ ")"

let random_run_validates =
  let arb = QCheck.pair Typed_gen.arb_program QCheck.small_nat in
  fun (prog, seed) ->
    let text = Print.program prog in
    let r = Parse.string ~file:"gen.jade" text in
    let env, diags = Typing.check [ r ] in
    if List.exists (fun d -> d.Diag.severity = Diag.Error) diags then
      QCheck.Test.fail_reportf "the generated program does not check";
    let rand = Random.State.make [| seed |] in
    let events = List.init (1 + Random.State.int rand 6) (fun _ ->
        if Random.State.int rand 4 = 0 then "{\"run\": 1}"
        else
          let p = random_percept_text rand env in
          let prio = if Random.State.int rand 3 = 0 then Printf.sprintf ", \"priority\": %d" (Random.State.int rand 9) else "" in
          Printf.sprintf "{\"agent\": \"g\", \"notify\": %s%s}" (Yojson.Safe.to_string (`String p)) prio) in
    let params = match Typing.Tenv.agent_create env "Ag" with Some r -> r.r_params | None -> [] in
    let args = List.map (fun (_, ty) -> literal_of rand ty) params in
    let dir = Filename.get_temp_dir_name () in
    let prog_file = Filename.concat dir (Printf.sprintf "jsref_gen_%d.jade" seed) in
    let ev_file = Filename.concat dir (Printf.sprintf "jsref_gen_%d.jsonl" seed) in
    let trace = Filename.concat dir (Printf.sprintf "jsref_gen_%d.trace" seed) in
    let write p s = let oc = open_out_bin p in output_string oc s; close_out oc in
    write prog_file text; write ev_file (String.concat "\n" events ^ "\n");
    let variant = List.nth [ "reference"; "budgeted"; "native" ] (seed mod 3) in
    let (status, _, err) = run_command (Printf.sprintf "%s run %s --agent %s --events %s --trace %s --variant %s --max-steps 2000"
                                          exe prog_file (Filename.quote ("g:Ag" ^ (if args = [] then "" else ":" ^ String.concat "," args)))
                                          ev_file trace variant) in
    (* D15: status 1 exactly when the run recorded a run-time error (a
       generated program may raise one: an invoke on a value that is not
       a host object, a missing map key); its trace is validated all the same *)
    let recorded_error () =
      Sys.file_exists trace
      && (let t = read_file trace in
          let k = "\"event\":\"error\"" in
          let n = String.length k in
          let rec has i = i + n <= String.length t && (String.sub t i n = k || has (i + 1)) in
          has 0) in
    if status <> 0 && not (status = 1 && recorded_error ()) then
      QCheck.Test.fail_reportf "run failed (%d): %s\n%s" status err text;
    (match Explore.Validate.trace trace with
     | [ Explore.Validate.Accepted _ ] -> ()
     | [ Explore.Validate.Rejected { line; step; _ } ] ->
       QCheck.Test.fail_reportf "TLC rejects line %d of the %s trace: %s\nprogram:\n%s\nevents:\n%s" line variant step text (String.concat "\n" events)
     | [ Explore.Validate.Cannot { reason; _ } ] -> ignore reason   (* documented limits *)
     | [ Explore.Validate.Invalid { line; message } ] ->
       QCheck.Test.fail_reportf "validate finds line %d of the %s trace invalid: %s\nprogram:\n%s\nevents:\n%s" line variant message text (String.concat "\n" events)
     | _ -> QCheck.Test.fail_reportf "one agent expected");
    List.iter (fun f -> try Sys.remove f with Sys_error _ -> ()) [ prog_file; ev_file; trace ];
    ignore arb;
    true

let () =
  Alcotest.run "interp" [
    ("values", [
        Alcotest.test_case "integers are Java ints" `Quick integers;
        Alcotest.test_case "float is binary32" `Quick floats;
        Alcotest.test_case "texts and of" `Quick texts;
        Alcotest.test_case "R1c structural map keys" `Quick maps_structural;
        Alcotest.test_case "a map = an association list, through its growth" `Quick map_model;
        Alcotest.test_case "loops and control" `Quick control;
        Alcotest.test_case "D11 priority of, D12 for over a map" `Quick decisions_of_and_for;
        Alcotest.test_case "performative and sender of message" `Quick message_fields;
        Alcotest.test_case "D40 instance numbers per agent" `Quick d40_numbers_per_agent;
        Alcotest.test_case "D41 a guard cannot activate" `Quick d41_guard_cannot_activate ]);
    ("errors", [
        Alcotest.test_case "R7 errors located, agent carries on" `Quick runtime_errors_located;
        Alcotest.test_case "R7 step budget" `Quick fuel_exhausted;
        Alcotest.test_case "resolved guards and properties = the general rules" `Quick resolved_forms ]);
    ("cli", [
        Alcotest.test_case "bad events lines, each located, nothing runs" `Quick cli_bad_events;
        Alcotest.test_case "bad programs and agents" `Quick cli_bad_program;
        Alcotest.test_case "log prints NAME: text" `Quick cli_logs;
        Alcotest.test_case "D15 run-time errors on stderr, exit 1" `Quick cli_runtime_error;
        Alcotest.test_case "R7 error kinds: trap, exhaustion, link, crash" `Quick error_kinds;
        Alcotest.test_case "a run that dies leaves its events in the trace" `Quick trace_survives_death ]);
    ("tlc", [
        Alcotest.test_case "paper runs validated; tampering rejected" `Slow paper_run_validated;
        Alcotest.test_case "conformance vectors' traces validated" `Slow vectors_validated;
        Alcotest.test_case "conform: reference passes, native fails" `Slow conform_passes;
        Alcotest.test_case "conform judges status, signals, hangs, headers, events" `Slow conform_judges;
        Alcotest.test_case "conform --judge, --generated: other schedules pass, cheaters fail" `Slow conform_judged;
        Alcotest.test_case "conform: bounded memory, temporary files, SIGINT" `Slow conform_resources;
        qcheck ~count:3 ~long_factor:15 "random programs' traces validated by TLC"
          (QCheck.pair Typed_gen.arb_program QCheck.small_nat) random_run_validates ]);
  ]
