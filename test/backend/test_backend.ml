(* The JADE back end (lib/backend, `jadescript-ref compile`): every
   conformance program and every example that type-checks compiles; bad input
   gives one located line and exit 1; the generated Java reads next to its
   source. That the Java compiles with javac -Xlint:all -Werror against the
   runtime is scripts/jade-compile-check's job (it needs a JDK and Maven). *)

open Syntax
module S = Test_support.Support

let root = S.root

(* The jadescript-ref built beside this test, whatever the build folder. *)
let exe =
  let here = Filename.dirname Sys.executable_name in
  let beside = Filename.concat here "../../bin/main.exe" in
  if Sys.file_exists beside then beside else S.exe

let q = Filename.quote

let rec walk dir =
  Sys.readdir dir |> Array.to_list |> List.sort compare
  |> List.concat_map (fun f ->
      let p = Filename.concat dir f in
      if Sys.is_directory p then walk p else if Filename.check_suffix f ".jade" then [p] else [])

let conformance_dir = Filename.concat root "conformance"

(* Each vector's program: its .jade files in name order, named relative to
   the vector's folder (as conform runs them). *)
let vectors =
  Sys.readdir conformance_dir |> Array.to_list |> List.sort compare
  |> List.filter (fun d -> Sys.is_directory (Filename.concat conformance_dir d))
  |> List.map (fun d ->
      let dir = Filename.concat conformance_dir d in
      let files = Sys.readdir dir |> Array.to_list |> List.sort compare
                  |> List.filter (fun f -> Filename.check_suffix f ".jade") in
      (d, dir, files))

let paper f = Filename.concat root ("examples/paper/" ^ f)
let robome_figures = List.map paper ["fig5_robome_ontology.jade"; "fig6_robome_agent.jade"; "fig7_handle_percepts.jade"]
let shapes_figures = List.map paper ["fig1_shapes_ontology.jade"; "fig2_shape_requester.jade"; "fig3_shape_behaviours.jade"]

(* Parse and check in-process; None when the program does not type-check. *)
let check files =
  match List.map (fun f -> Parse.file f) files with
  | exception Diag.Failed _ -> None
  | parsed ->
    let env, ds = Typing.check parsed in
    if Typing.has_errors ds then None else Some env

let examples =
  let grouped = robome_figures @ shapes_figures in
  ("paper figures 5-7", robome_figures)
  :: List.filter_map (fun f -> if List.mem f grouped then None else Some (Filename.basename f, [ f ]))
    (walk (Filename.concat root "examples"))

let temp_dir () =
  let d = Filename.temp_file "jsref-backend" "" in
  Sys.remove d; Sys.mkdir d 0o755; d

let rec rm_rf p =
  if Sys.file_exists p then
    if Sys.is_directory p then begin
      Array.iter (fun f -> rm_rf (Filename.concat p f)) (Sys.readdir p); Sys.rmdir p
    end else Sys.remove p

let generate files =
  match check files with
  | None -> Alcotest.failf "%s does not type-check" (String.concat " " files)
  | Some env ->
    match Backend.Jade.generate env ~files with
    | Ok units -> (env, units)
    | Error (at, m) -> Alcotest.failf "%s: %s" (Source.string_of_region at) m

let contains s sub =
  let n = String.length s and m = String.length sub in
  let rec go i = i + m <= n && (String.sub s i m = sub || go (i + 1)) in
  go 0

(* One class per schema, agent and behaviour, and Program.java. *)
let check_units (env : Typing.Tenv.t) units =
  let module T = Typing.Tenv in
  let expected = List.length (T.schemas env) + List.length (T.agents env) + List.length (T.behaviours env) + 1 in
  Alcotest.(check int) "number of classes" expected (List.length units);
  Alcotest.(check bool) "Program.java" true (List.mem_assoc "Program.java" units);
  List.iter (fun (name, text) ->
      Alcotest.(check bool) (name ^ " is in package jsgen") true
        (String.length text > 14 && String.sub text 0 14 = "package jsgen;");
      (* the source is ASCII: javac reads it in any locale *)
      String.iter (fun c -> if Char.code c > 127 then Alcotest.failf "%s is not ASCII" name) text) units;
  List.iter (fun (s : T.schema) ->
      if not (List.exists (fun (_, t) -> contains t (Printf.sprintf "public String schemaName() { return %s; }"
                                                   (Backend.Jade.java_string s.s_name))) units)
      then Alcotest.failf "no class for schema %s" s.s_name) (T.schemas env)

(* Every fuel tick of a statement is preceded by the comment with the
   statement's source line. *)
let check_comments units =
  List.iter (fun (name, text) ->
      let lines = Array.of_list (String.split_on_char '\n' text) in
      Array.iteri (fun i l ->
          let l = String.trim l in
          let is_tick = (String.length l > 6 && String.sub l 0 6 = "tick(\"")
                        || (String.length l > 14 && String.sub l 0 14 = "agent().tick(\"") in
          if is_tick && not (contains l "loop's") && not (contains l ":0:0") && not (contains l "jsCreateAt$") then begin
            (* the position "FILE:LINE:COL" in the tick, and "// FILE:LINE:" just above *)
            let q1 = String.index l '"' in
            let q2 = String.index_from l (q1 + 1) '"' in
            let pos = String.sub l (q1 + 1) (q2 - q1 - 1) in
            let upto_line = String.sub pos 0 (String.rindex pos ':') in
            let above = if i = 0 then "" else String.trim lines.(i - 1) in
            if not (String.length above > 3 && String.sub above 0 3 = "// " && contains above (upto_line ^ ": ")) then
              Alcotest.failf "%s:%d: tick %s is not preceded by its source comment (%S)" name (i + 1) pos above
          end) lines) units

let vector_cases =
  List.map (fun (d, dir, files) ->
      Alcotest.test_case ("compiles: " ^ d) `Quick (fun () ->
          let cwd = Sys.getcwd () in
          Sys.chdir dir;
          Fun.protect ~finally:(fun () -> Sys.chdir cwd) (fun () ->
              let env, units = generate files in
              check_units env units;
              check_comments units;
              (* the positions name the files exactly as given *)
              let f = List.hd files in
              if not (List.exists (fun (_, t) -> contains t (Printf.sprintf "\"%s:" f)) units) then
                Alcotest.failf "no position names %s" f))) vectors

let example_cases =
  List.filter_map (fun (name, files) ->
      match check files with
      | None -> None
      | Some _ ->
        Some (Alcotest.test_case ("compiles: example " ^ name) `Quick (fun () ->
            let env, units = generate files in
            check_units env units;
            check_comments units))) examples

(* The command line: the files written, exit 0. *)
let command_writes () =
  let out = temp_dir () in
  Fun.protect ~finally:(fun () -> rm_rf out) (fun () ->
      let (d, dir, files) = List.find (fun (d, _, _) -> contains d "047") vectors in
      ignore d;
      let (status, _, err) = S.run_command (Printf.sprintf "cd %s && %s compile %s --target jade --out %s"
                                              (q dir) (q exe) (String.concat " " (List.map q files)) (q out)) in
      Alcotest.(check int) ("exit status; stderr: " ^ err) 0 status;
      let written = Sys.readdir (Filename.concat out "jsgen") |> Array.to_list |> List.sort compare in
      Alcotest.(check (list string)) "files" [ "Play.java"; "Player.java"; "Program.java"; "ball.java" ] written;
      (* a second compilation into the same folder replaces the first *)
      let (status, _, _) = S.run_command (Printf.sprintf "cd %s && %s compile %s --out %s"
                                            (q dir) (q exe) (String.concat " " (List.map q files)) (q out)) in
      Alcotest.(check int) "again" 0 status)

(* Bad input: exactly one line FILE:LINE:COL: error: ..., exit 1, nothing written. *)
let bad_inputs = [
  ("syntax error", "agent A\n    on create do\n        log (\n", "bad.jade:3:");
  ("type error", "agent A\n    on create do\n        log y\n", "bad.jade:3:13: error: unknown name y");
  ("integer too large", "agent A\n    on create do\n        x = 3000000000\n", "bad.jade:3:13: error: integer literal");
  ("unsupported: a sub-behaviour's property named like a local",
   "agent A\n    on create do\n        activate behaviour B2\n\n\
    cyclic behaviour B for agent A\n    do\n        count = 1\n        log count\n\n\
    cyclic behaviour B2 extends B\n    property count as integer = 0\n",
   "bad.jade:7:9: error: the JADE back end does not support this: count is a local here");
  ("unsupported: a sub-behaviour's function named like the agent's",
   "agent A\n    function f() as integer do\n        return 1\n    on create do\n        activate behaviour B2\n\n\
    cyclic behaviour B for agent A\n    do\n        log f()\n\n\
    cyclic behaviour B2 extends B\n    function f() as integer do\n        return 2\n",
   "bad.jade:9:13: error: the JADE back end does not support this: f is the agent's function here");
  ("unsupported: a sub-agent's property named like a local of the super agent",
   "agent A\n    procedure p do\n        total = 1\n        log total\n\nagent A2 extends A\n    property total as integer = 0\n",
   "bad.jade:3:9: error: the JADE back end does not support this: total is a local here, but A2");
]

(* What javac or the JVM cannot take (docs/jade.md, "What Java can hold"):
   refused by compile with one located line. *)
let n_params n = String.concat ", " (List.init n (Printf.sprintf "x%d as integer"))
let java_limit_inputs =
  let unsup = "error: the JADE back end does not support this: " in [
  ("a text literal of 70,000 bytes",
   "agent A\n    on create do\n        log \"" ^ String.make 70_000 'a' ^ "\"\n", "bad.jade:3:13: " ^ unsup ^ "a text literal of more than 65534");
  ("a text literal of 22,000 characters beyond U+FFFF (88,000 bytes of UTF-8, 132,000 of Java's)",
   "agent A\n    on create do\n        log \"" ^ String.concat "" (List.init 22_000 (fun _ -> "\xf0\x9f\x98\x80")) ^ "\"\n",
   "bad.jade:3:13: " ^ unsup ^ "a text literal");
  ("a text literal of 65,535 bytes", "agent A\n    on create do\n        log \"" ^ String.make 65_535 'a' ^ "\"\n",
   "bad.jade:3:13: " ^ unsup ^ "a text literal of more than 65534");
  ("a body of 8,000 statements",
   "agent A\n    on create do\n" ^ String.concat "" (List.init 8000 (fun _ -> "        log 1\n")), "bad.jade:2:5: " ^ unsup ^ "this body is too large");
  ("a behaviour name of 250 characters",
   "agent A\n    on create do\n        log 1\n\none shot behaviour " ^ String.make 250 'B' ^ " for agent A\n    do\n        log 1\n",
   "bad.jade:5:20: " ^ unsup ^ "a name longer than 200");
  ("a log of 250 terms joined by +",
   "agent A\n    on create do\n        log " ^ String.concat " + " (List.init 250 (fun _ -> "1")) ^ "\n",
   "bad.jade:3:13: " ^ unsup ^ "an expression nested more than 100 deep");
  ("a function of 260 parameters",
   "agent A\n    function f(" ^ n_params 260 ^ ") as integer do\n        return 1\n", "bad.jade:2:5: " ^ unsup ^ "more than 250 parameters");
  ("a concept of 260 slots",
   "ontology O\n    concept c(" ^ n_params 260 ^ ")\nagent A uses ontology O\n", "bad.jade:2:13: " ^ unsup ^ "c has 260 slots");
  ("a concept of 251 slots, 200 of them inherited",
   "ontology O\n    concept c(" ^ n_params 200 ^ ")\n    concept d(y1 as integer" ^ String.concat "" (List.init 50 (Printf.sprintf ", z%d as integer")) ^ ") extends c\nagent A uses ontology O\n",
   "bad.jade:3:13: " ^ unsup ^ "d has 251 slots");
  ("1,001 behaviour types",
   "agent A\n" ^ String.concat "" (List.init 1001 (Printf.sprintf "\none shot behaviour B%d for agent A\n    do\n        log 1\n")),
   "bad.jade:3999:20: " ^ unsup ^ "more than 1000 schemas");
]

(* At each limit: accepted (javac takes these: scripts/jade-compile-check
   compiles test/backend/programs/). *)
let at_limit_inputs = [
  ("a text literal of 65,534 bytes", "agent A\n    on create do\n        log \"" ^ String.make 65_534 'a' ^ "\"\n");
  ("an expression 100 deep", "agent A\n    on create do\n        log " ^ String.concat " + " (List.init 100 (fun _ -> "1")) ^ "\n");
  ("250 parameters and 250 slots",
   "ontology O\n    concept c(" ^ n_params 250 ^ ")\nagent A uses ontology O\n    function f(" ^ n_params 250 ^ ") as integer do\n        return 1\n");
  ("a name of 200 characters", "agent " ^ String.make 200 'A' ^ "\n    on create do\n        log 1\n");
]

let at_limit (name, text) =
  Alcotest.test_case ("accepted: " ^ name) `Quick (fun () ->
      let dir = temp_dir () in
      Fun.protect ~finally:(fun () -> rm_rf dir) (fun () ->
          let oc = open_out_bin (Filename.concat dir "ok.jade") in
          output_string oc text; close_out oc;
          let (status, _, err) = S.run_command (Printf.sprintf "cd %s && %s compile ok.jade --out gen" (q dir) (q exe)) in
          Alcotest.(check int) ("exit status: " ^ err) 0 status))

(* Names JADE's classes already use, and a local named like a property's
   field: the generated Java refers to the program's classes by their
   package (jsgen.Interrupted, not Agent.Interrupted) and renames the
   local. The program is test/backend/programs/jade_names.jade, which
   scripts/jade-compile-check also compiles with javac. *)
let jade_names () =
  let f = Filename.concat root "test/backend/programs/jade_names.jade" in
  let _, units = generate [ f ] in
  let a = List.assoc "A.java" units and h = List.assoc "H.java" units in
  let has t s = if not (contains t s) then Alcotest.failf "expected %S in:\n%s" s t in
  has a "jsgen.Interrupted.make(";
  has a "p_count$";
  has h "instanceof jsgen.RunnableChangedEvent";
  has h "instanceof jsgen.AP_ACTIVE";
  if contains a "Object p_count =" then Alcotest.fail "a local p_count hides the property's field"

let bad_case (name, text, prefix) =
  Alcotest.test_case ("refused: " ^ name) `Quick (fun () ->
      let dir = temp_dir () in
      Fun.protect ~finally:(fun () -> rm_rf dir) (fun () ->
          let oc = open_out_bin (Filename.concat dir "bad.jade") in
          output_string oc text; close_out oc;
          let (status, out, err) = S.run_command (Printf.sprintf "cd %s && %s compile bad.jade --out gen" (q dir) (q exe)) in
          Alcotest.(check int) "exit status" 1 status;
          Alcotest.(check string) "stdout" "" out;
          let lines = List.filter (fun l -> l <> "") (String.split_on_char '\n' err) in
          Alcotest.(check int) ("one line: " ^ err) 1 (List.length lines);
          let l = List.hd lines in
          if not (String.length l >= String.length prefix && String.sub l 0 (String.length prefix) = prefix) then
            Alcotest.failf "expected %S..., got %S" prefix l;
          Alcotest.(check bool) "nothing written" false (Sys.file_exists (Filename.concat dir "gen"))))

let missing_file () =
  let (status, _, err) = S.run_command (Printf.sprintf "%s compile /nonexistent/x.jade --out /tmp/jsref-none" (q exe)) in
  Alcotest.(check int) "exit status" 1 status;
  Alcotest.(check string) "message" "/nonexistent/x.jade:1:1: error: cannot read this file: /nonexistent/x.jade: No such file or directory\n" err

let bad_target () =
  let (status, _, err) = S.run_command (Printf.sprintf "%s compile x.jade --target llvm --out /tmp/jsref-none" (q exe)) in
  Alcotest.(check int) "a command-line error" 1 status;
  Alcotest.(check int) ("one line: " ^ err) 1 (List.length (List.filter (( <> ) "") (String.split_on_char '\n' err)))

(* Java text. *)
let java_strings () =
  let j = Backend.Jade.java_string in
  Alcotest.(check string) "plain" "\"abc\"" (j "abc");
  Alcotest.(check string) "escapes" "\"a\\\"b\\\\c\\nd\\te\\r\"" (j "a\"b\\c\nd\te\r");
  Alcotest.(check string) "control" "\"\\001\\177\"" (j "\001\127");
  Alcotest.(check string) "non-ASCII" "\"caf\\u00E9 \\uD83D\\uDE00\"" (j "caf\xc3\xa9 \xf0\x9f\x98\x80");
  Alcotest.(check string) "comment: backslashes doubled" "log \"\\\\u0041\"" (Backend.Jade.comment_text "log \"\\u0041\"");
  Alcotest.(check string) "comment: line ends" "a b" (Backend.Jade.comment_text "a\rb")

(* The same program compiled twice gives the same Java. *)
let deterministic () =
  let (_, dir, files) = List.find (fun (d, _, _) -> contains d "060") vectors in
  let cwd = Sys.getcwd () in
  Sys.chdir dir;
  Fun.protect ~finally:(fun () -> Sys.chdir cwd) (fun () ->
      let _, a = generate files and _, b = generate files in
      Alcotest.(check (list (pair string string))) "same units" a b)

(* What the Java says for chosen constructs: the operand order of the
   interpreter, fuel where it ticks, the positions of errors. *)
let shapes () =
  let dir = temp_dir () in
  Fun.protect ~finally:(fun () -> rm_rf dir) (fun () ->
      let f = Filename.concat dir "p.jade" in
      let oc = open_out_bin f in
      output_string oc
        "ontology O\n    predicate pos(x as float, y as float) extends percept with priority = 3\n\n\
         agent A uses ontology O\n    property m as map of integer:text = {}\n    on create do\n        \
         m[1] = \"a\"\n        for k in m do\n            if k = 2 do\n                continue\n            log k\n        \
         activate behaviour B\n\n\
         cyclic behaviour B for agent A\n    on percept when content matches pos(a, _) and a > 1.5 do\n        \
         log a + 1\n";
      close_out oc;
      let env, units = generate [ f ] in
      check_units env units;
      let a = List.assoc "A.java" units and b = List.assoc "B.java" units and pos = List.assoc "pos.java" units in
      let has t s = if not (contains t s) then Alcotest.failf "expected %S in:\n%s" s t in
      let at l c = Printf.sprintf "\"%s:%d:%d\"" f l c in
      (* the right operand of a comparison first, after the operator's
         position (D37: a comparison too large is an error there) *)
      has a (Printf.sprintf "Ops.eqRL(%s, Integer.valueOf(2), Ops.local(%s, \"k\", k))" (at 9 16) (at 9 16));
      (* for: the item, then the tick, then the body in a labelled block (continue) *)
      has a (Printf.sprintf "tick(%s);   // the loop's item" (at 8 9));
      has a "if (true) break body$";
      (* the map assignment: value first, at the left side's position *)
      has a (Printf.sprintf "Ops.setIndex(%s, Ops.prop(%s, \"m\", p_m), Integer.valueOf(1), v$" (at 7 9) (at 7 9));
      (* the percept's default priority (R1a) and structural equality through Schema *)
      has pos "public int defaultPriority() { return 3; }";
      has pos "public boolean isPercept() { return true; }";
      has pos "public Number x;";
      (* a when condition, its pattern method, fresh fuel before the body *)
      has b (Printf.sprintf "ok$ = Ops.whenCond(%s" (at 15 21));
      has b "agent().freshFuel();";
      has b "if (!(v$ instanceof jsgen.pos)) return false;")

let () =
  Alcotest.run "backend"
    [ ("conformance programs", vector_cases);
      ("examples", example_cases);
      ("command line", [ Alcotest.test_case "compile writes the classes" `Quick command_writes;
                         Alcotest.test_case "a missing file" `Quick missing_file;
                         Alcotest.test_case "an unknown target" `Quick bad_target ]
                       @ List.map bad_case bad_inputs
                       @ List.map bad_case java_limit_inputs
                       @ List.map at_limit at_limit_inputs
                       @ [ Alcotest.test_case "names JADE's classes use" `Quick jade_names ]);
      ("java", [ Alcotest.test_case "string literals and comments" `Quick java_strings;
                 Alcotest.test_case "deterministic" `Quick deterministic;
                 Alcotest.test_case "what the Java says" `Quick shapes ]) ]
