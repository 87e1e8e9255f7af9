(* What an adversarial user tries: the one JSON reader (lib/json), the
   events file read once from a file, a pipe or a FIFO, every reader linear
   and bounded, the commands' one-line errors. *)

let check = Alcotest.(check bool)
let root = Test_support.Support.root

(* ------------------------------------------------------------ JSON *)

let read s = Json_read.of_string s

let short s = if String.length s > 60 then String.sub s 0 60 ^ "..." else s

let accepts s () =
  match read s, Yojson.Safe.from_string s with
  | Ok v, w -> Alcotest.(check string) (short s) (Yojson.Safe.to_string w) (Yojson.Safe.to_string v)
  | Error e, _ -> Alcotest.failf "%S refused: %s" (short s) (Json_read.to_string e)

let refuses ?at s () =
  match read s with
  | Ok v -> Alcotest.failf "%S accepted as %s" (short s) (short (Yojson.Safe.to_string v))
  | Error e ->
    check "one printable line" true (String.for_all (fun c -> c >= ' ' && c <= '~') e.message);
    Option.iter (fun (l, c) -> Alcotest.(check (pair int int)) ("where: " ^ e.message) (l, c) (e.line, e.column)) at

let deep d = String.make d '[' ^ String.make d ']'

let json_cases = [
  "an object", `Quick, accepts {|{"a": [1, -2, 3.5, 1e3, true, false, null], "b": {"c": "d\u00e9\n"}}|};
  "a pair of surrogates", `Quick, accepts {|"\ud83d\ude00"|};
  "an integer beyond int", `Quick, accepts "123456789012345678901234567890";
  "1,000 deep (the limit)", `Quick, accepts (deep 1000);
  "1,001 deep", `Quick, refuses ~at:(1, 1001) (deep 1001);
  "200,000 deep: an error, no stack overflow", `Quick, refuses (deep 200_000);
  "200,000 objects deep", `Quick, refuses (String.concat "" (List.init 200_000 (fun _ -> {|{"a":|})) ^ "1" ^ String.make 200_000 '}');
  "a raw NUL in a string", `Quick, refuses ~at:(1, 3) "\"a\000b\"";
  "a raw line feed in a string", `Quick, refuses "\"a\nb\"";
  "a raw tab in a string", `Quick, refuses "\"a\tb\"";
  "a raw NUL after the value", `Quick, refuses "{}\000";
  "invalid UTF-8 in a string", `Quick, refuses ~at:(1, 3) "\"a\xffb\"";
  "an overlong UTF-8 sequence", `Quick, refuses "\"\xc0\xaf\"";
  "an encoded surrogate", `Quick, refuses "\"\xed\xa0\x80\"";
  "a lone surrogate escape", `Quick, refuses {|"\ud800"|};
  "a lone second surrogate", `Quick, refuses {|"\udc00x"|};
  "a key twice", `Quick, refuses ~at:(1, 10) {|{"a": 1, "a": 2}|};
  "a key twice among many", `Quick,
  refuses ("{" ^ String.concat ", " (List.init 40 (fun i -> Printf.sprintf "\"k%d\": %d" i i)) ^ ", \"k7\": 0}");
  "NaN", `Quick, refuses "NaN";
  "Infinity", `Quick, refuses "[Infinity]";
  "a leading zero", `Quick, refuses "012";
  "a leading plus", `Quick, refuses "+1";
  "a bare point", `Quick, refuses ".5";
  "a point with no digit", `Quick, refuses "1.";
  "an exponent with no digit", `Quick, refuses "1e";
  "a trailing comma", `Quick, refuses "[1, 2,]";
  "a comment", `Quick, refuses "[1] // no";
  "single quotes", `Quick, refuses "['a']";
  "an unknown escape", `Quick, refuses {|"\x41"|};
  "two values", `Quick, refuses ~at:(1, 4) "{} {}";
  "nothing", `Quick, refuses "";
  "an unclosed string", `Quick, refuses "\"abc";
  "an unclosed array", `Quick, refuses "[1, 2";
  "a second line", `Quick, refuses ~at:(2, 4) "[1,\n 2 x]";
]

(* Any value Yojson writes, the reader reads back the same. *)
let yojson_gen =
  let open QCheck.Gen in
  let text = string_size ~gen:(oneof [ printable; char; return '\xc3' ]) (0 -- 12) in
  let valid t = match Utf8.first_invalid t with None -> t | Some _ -> "x" in
  sized_size (0 -- 6) (fix (fun self n ->
      let leaf = oneof [
          map (fun i -> `Int i) int; map (fun f -> `Float f) (float_range (-1e6) 1e6);
          map (fun s -> `String (valid s)) text; return `Null; map (fun b -> `Bool b) bool ] in
      if n = 0 then leaf
      else frequency [
          3, leaf;
          1, map (fun l -> `List l) (list_size (0 -- 4) (self (n / 2)));
          1, map (fun l ->
              let l = List.mapi (fun i (k, v) -> (valid k ^ string_of_int i, v)) l in
              `Assoc l) (list_size (0 -- 4) (pair text (self (n / 2)))) ]))

let round_trip =
  Test_support.Support.qcheck ~count:2000 "what Yojson writes, the reader reads the same"
    (QCheck.make ~print:Yojson.Safe.to_string yojson_gen) (fun (v : Yojson.Safe.t) ->
        let s = Yojson.Safe.to_string v in
        match Json_read.of_string s with
        | Ok w -> Yojson.Safe.to_string w = s
        | Error e -> QCheck.Test.fail_reportf "%s: %s" s (Json_read.to_string e))


(* ------------------------------------------------------------ helpers *)

let exe = Test_support.Support.exe
let run = Test_support.Support.run_command
let q = Filename.quote

let has s sub =
  let n = String.length s and m = String.length sub in
  let rec go i = i + m <= n && (String.sub s i m = sub || go (i + 1)) in
  go 0

let lines s = List.filter (( <> ) "") (String.split_on_char '\n' s)

(* [FILE:LINE:COL: error: ...] or [jadescript-ref: error: ...], one line,
   exit 1 *)
let one_error ?(says = "") ~what (status, _, err) =
  Alcotest.(check int) (what ^ ": exit 1 (" ^ err ^ ")") 1 status;
  match lines err with
  | [ l ] -> check (what ^ ": an error line: " ^ l) true
               (has l ": error: " && not (has l "internal error") && has l says)
  | _ -> Alcotest.failf "%s: expected one line, got: %s" what err

(* ------------------------------------------------------------ stack *)

(* A list literal of [n] items in a [log] (a wide program, not a deep one). *)
let wide_list n =
  "agent A\n\ton create do\n\t\tlog [" ^ String.concat ", " (List.init n (fun _ -> "1")) ^ "]\n"

(* The command starts again with a large stack (bin/main.ml, "the stack"):
   under a soft limit of 1 MB, which a list of 50,000 items overflows
   without it, the program runs; a hard limit below the 4 GiB it asks for
   is taken as it is, and the command does not start again and again. *)
let stack_cases = [
  "a wide program under a 1 MB soft stack limit", `Quick, (fun () ->
      Test_support.Support.with_file "wide.jade" (wide_list 50_000) (fun f ->
          let (status, out, err) =
            run (Printf.sprintf "ulimit -S -s 1024; %s run %s --agent a:A" exe (q f)) in
          Alcotest.(check int) ("exit 0: " ^ err) 0 status;
          check "the log written" true (String.length out > 100_000)));
  "a hard limit below 4 GiB: one start again, then the run", `Quick, (fun () ->
      Test_support.Support.with_file "small.jade" "agent A\n\ton create do\n\t\tlog 1\n" (fun f ->
          let (status, out, err) =
            run (Printf.sprintf "ulimit -S -s 1024; ulimit -H -s 2048; timeout 20 %s run %s --agent a:A" exe (q f)) in
          Alcotest.(check int) ("exit 0: " ^ err) 0 status;
          Alcotest.(check string) "the log" "a: 1\n" out));
  "stack already raised: no start again", `Quick, (fun () ->
      Test_support.Support.with_file "small.jade" "agent A\n\ton create do\n\t\tlog 2\n" (fun f ->
          let (status, out, _) =
            run (Printf.sprintf "ulimit -S -s unlimited 2>/dev/null; timeout 20 %s run %s --agent a:A" exe (q f)) in
          Alcotest.(check (pair int string)) "exit 0 and the log" (0, "a: 2\n") (status, out)));
]

(* ------------------------------------------------------------ events read once *)

(* The events file given as a regular file, a pipe on the standard input
   (/dev/stdin), a FIFO: the same trace each time, and every event in it
   (a file read twice would leave a pipe empty the second time). *)
let events_text =
  {|{"agent":"r","notify":"position(0, 1)"}
{"agent":"r","notify":"qrCodeRead(\"A7\")"}
{"agent":"r","notify":"obstacle"}
|}

let events_once () =
  let robome = q (Filename.concat root "examples/robome/robome.jade") in
  Test_support.Support.with_file "events.jsonl" events_text (fun ev ->
      let cmd events = Printf.sprintf "%s run %s --agent r:RoboMe:@robome --events %s --trace /dev/stdout"
          exe robome events in
      let (s0, file, e0) = run (cmd (q ev)) in
      Alcotest.(check int) ("a file: exit 0 " ^ e0) 0 s0;
      let notified = List.length (List.filter (fun l -> has l {|"notify"|} || has l "position(0, 1)") (lines file)) in
      check "the file's events are in the trace" true (notified >= 1);
      let (s1, piped, _) = run (Printf.sprintf "(cat %s | %s)" (q ev) (cmd "/dev/stdin")) in
      Alcotest.(check (pair int string)) "a pipe on /dev/stdin: the same trace" (0, file) (s1, piped);
      let fifo = Filename.concat (Filename.dirname ev) "events.fifo" in
      let (s2, fifoed, e2) = run (Printf.sprintf "(mkfifo %s && (cat %s > %s &) && timeout 20 %s)"
                                    (q fifo) (q ev) (q fifo) (cmd (q fifo))) in
      Sys.remove fifo;
      Alcotest.(check (pair int string)) ("a FIFO: the same trace " ^ e2) (0, file) (s2, fifoed))

(* --agents FILE: a run of many agents, given in a file (a file or a pipe
   alike), each line as --agent takes it; a bad line is an error at it. *)
let ring_program = {|ontology T
    predicate tok(n as integer)

agent R uses ontology T
    property next as text = ""
    on create with nxt as text do
        next = nxt
        activate behaviour Pass
        send inform tok(1) to aid(next)

cyclic behaviour Pass for agent R
    on inform when content matches tok(n) and n < 3 do
        send inform tok(n + 1) to aid(next of agent)
|}

let agents_from_file () =
  let n = 5_000 in
  let ring = String.concat "" ("# a ring\n\n" :: List.init n (fun i -> Printf.sprintf "a%d:R:\"a%d\"\n" i ((i + 1) mod n))) in
  Test_support.Support.with_file "ring.jade" ring_program (fun prog ->
      Test_support.Support.with_file "ring.txt" ring (fun agents ->
          let (s, out, e) = run (Printf.sprintf "%s run %s --agents %s --trace /dev/stdout" exe (q prog) (q agents)) in
          Alcotest.(check int) ("exit 0 " ^ e) 0 s;
          let ls = lines out in
          let count ev = List.length (List.filter (fun l -> has l (Printf.sprintf {|"event":"%s"|} ev)) ls) in
          Alcotest.(check int) "every agent created" n (count "create");
          Alcotest.(check int) "three messages each way round the ring" (3 * n) (count "deliver");
          check "the first agent is the file's first" true
            (List.exists (fun l -> has l {|"agent":"a0","event":"create"|}) ls);
          (* the same from a pipe, after one agent of --agent *)
          let (s1, out1, _) = run (Printf.sprintf "(tail -n +4 %s | %s run %s --agent 'a0:R:\"a1\"' --agents /dev/stdin --trace /dev/stdout)"
                                     (q agents) exe (q prog)) in
          Alcotest.(check (pair int string)) "a pipe after --agent: the same trace" (0, out) (s1, out1));
      Test_support.Support.with_file "bad.txt" "a:R:\"b\"\n\nb R\n" (fun bad ->
          let (s, _, e) = run (Printf.sprintf "%s run %s --agents %s" exe (q prog) (q bad)) in
          Alcotest.(check (pair int string)) "a bad line: one located error"
            (1, Printf.sprintf "%s:3:1: error: expected NAME:TYPE[:ARG,...]\n" bad) (s, e));
      Test_support.Support.with_file "dup.txt" "a:R:\"b\"\nb:R:\"a\"\na:R:\"a\"\n" (fun dup ->
          let (s, _, e) = run (Printf.sprintf "%s run %s --agents %s" exe (q prog) (q dup)) in
          Alcotest.(check (pair int string)) "a name twice: an error at the second"
            (1, Printf.sprintf "%s:3:1: error: there is already an agent a (agent names are unique)\n" dup) (s, e)))

(* ------------------------------------------------------------ TLA+ values *)

let tla_deep d = String.concat "" (List.init d (fun _ -> "<<")) ^ "1" ^ String.concat "" (List.init d (fun _ -> ">>"))

let tla_refuses s () =
  match Explore.Tla.parse s with
  | _ -> Alcotest.failf "%s accepted" (short s)
  | exception Explore.Tla.Parse_error m -> check ("an error: " ^ m) true (has m "nested")

let tla_cases = [
  "1,000 deep (the limit)", `Quick, (fun () -> ignore (Explore.Tla.parse (tla_deep Explore.Tla.max_depth)));
  "1,001 deep", `Quick, tla_refuses (tla_deep (Explore.Tla.max_depth + 1));
  "200,000 deep: an error, no stack overflow", `Quick, tla_refuses (tla_deep 200_000);
  "200,000 sets and records deep", `Quick,
  tla_refuses (String.concat "" (List.init 100_000 (fun _ -> "{[a |-> ")) ^ "1" ^ String.concat "" (List.init 100_000 (fun _ -> "]}")));
  "a set of 1,000,000 elements", `Quick, (fun () ->
      (* read, sorted, printed and compared in loops, within the test's
         own stack of 8 MB *)
      let n = 1_000_000 in
      let s = "{" ^ String.concat ", " (List.init n string_of_int) ^ "}" in
      match Explore.Tla.parse s with
      | Explore.Tla.Set l as v ->
        Alcotest.(check int) "its size" n (List.length l);
        Alcotest.(check int) "equal to itself" 0 (Explore.Tla.compare v v);
        Alcotest.(check string) "printed back" s (Explore.Tla.to_string v)
      | _ -> Alcotest.fail "not a set");
]

(* ------------------------------------------------------------ slots *)

(* The slots of a schema that extends another: the parent's, in their
   order, with the types of the overrides, then the new ones in theirs
   (read in one pass: a concept may have many). *)
let slots_of text name =
  let r = Syntax.Parse.string ~file:"slots.jade" text in
  let (env, ds) = Typing.check [ r ] in
  List.iter (fun d -> if d.Syntax.Diag.severity = Syntax.Diag.Error then
                Alcotest.failf "refused: %s" (Syntax.Diag.to_string d)) ds;
  match Typing.Tenv.schema env name with
  | Some s -> List.map fst s.Typing.Tenv.s_slots
  | None -> Alcotest.failf "no schema %s" name

let slot_cases = [
  "overrides keep the parent's order", `Quick, (fun () ->
      Alcotest.(check (list string)) "the slots of c" [ "x"; "y"; "w"; "z"; "v" ]
        (slots_of {|ontology P
    concept a(x as integer, y as integer)
    concept b(w as integer, y as integer) extends a
    concept c(z as integer, x as integer, v as integer) extends b
|} "c"));
  "10,000 slots, every one overridden", `Quick, (fun () ->
      let n = 10_000 in
      let names = List.init n (Printf.sprintf "s%d") in
      let decl = String.concat ", " (List.map (fun x -> x ^ " as integer") names) in
      let extra = String.concat ", " (List.map (fun x -> x ^ " as integer") (List.rev names) @ [ "t as integer" ]) in
      Alcotest.(check (list string)) "the slots of b" (names @ [ "t" ])
        (slots_of (Printf.sprintf "ontology P\n    concept a(%s)\n    concept b(%s) extends a\n" decl extra) "b"));
]

(* ------------------------------------------------------------ scenarios *)

let scenario_cases =
  let refused ?says what text () =
    Test_support.Support.with_file "scenario.json" text (fun f ->
        one_error ?says ~what (run (Printf.sprintf "%s sim %s" exe (q f)))) in [
    "nested 200,000 deep", `Quick, refused ~says:"nested" "deep" (String.make 200_000 '[' ^ String.make 200_000 ']');
    "longer than 1 MB", `Quick, refused ~says:"longer than 1048576 bytes" "long" ({|{"name": "|} ^ String.make 1_100_000 'a' ^ {|"}|});
    "NaN", `Quick, refused ~says:":1:" "NaN" {|{"name": "x", "seed": NaN}|};
  ]

(* ------------------------------------------------------------ a cut trace *)

(* A run killed with SIGKILL leaves its trace cut in the middle of a line:
   validate checks the lines before it and names the cut; a line cut so
   anywhere but last, or a cut header, is still an error. *)
let cut_trace () =
  let robome = q (Filename.concat root "examples/robome/robome.jade") in
  Test_support.Support.with_file "events.jsonl" events_text (fun ev ->
      let dir = Filename.dirname ev in
      let full = Filename.concat dir "full.jsonl" in
      let (s, _, e) = run (Printf.sprintf "%s run %s --agent r:RoboMe:@robome --events %s --trace %s"
                             exe robome (q ev) (q full)) in
      Alcotest.(check int) ("the run: " ^ e) 0 s;
      let text = Test_support.Support.read_file full in
      let ls = lines text in
      let n = List.length ls in
      let write name t = let f = Filename.concat dir name in
        let oc = open_out_bin f in output_string oc t; close_out oc; f in
      (* every cut inside the last line that leaves it not JSON *)
      let last = List.nth ls (n - 1) in
      let before = String.sub text 0 (String.length text - String.length last - 1) in
      List.iter (fun k ->
          let f = write "cut.jsonl" (before ^ String.sub last 0 k) in
          match Explore.Validate.check f with
          | Ok () -> ()
          | Error (l, m) -> Alcotest.failf "cut after %d bytes of the last line: line %d: %s" k l m)
        [ 1; 2; String.length last / 2; String.length last - 1 ];
      let f = write "cut.jsonl" (before ^ String.sub last 0 (String.length last / 2)) in
      let (s, _, e) = run (Printf.sprintf "%s validate %s" exe (q f)) in
      Alcotest.(check int) ("validate: exit 0: " ^ e) 0 s;
      (match lines e with
       | [ l ] -> check ("the cut named: " ^ l) true (has l (Printf.sprintf "cut.jsonl:%d:1: warning: the last line is cut" n))
       | _ -> Alcotest.failf "one warning line expected: %s" e);
      (* a cut line that is not the last: an error at it *)
      let second = List.nth ls 1 in
      let f = write "mid.jsonl" (List.hd ls ^ "\n" ^ String.sub second 0 10 ^ "\n"
                                 ^ String.concat "\n" (List.filteri (fun i _ -> i >= 2) ls) ^ "\n") in
      (match Explore.Validate.check f with
       | Error (2, _) -> ()
       | Error (l, m) -> Alcotest.failf "a cut line 2: error at line %d: %s" l m
       | Ok () -> Alcotest.fail "a line cut in the middle of the trace accepted");
      (* a cut header: no trace *)
      let f = write "head.jsonl" (String.sub (List.hd ls) 0 20) in
      (match Explore.Validate.check f with
       | Error (1, _) -> ()
       | _ -> Alcotest.fail "a cut header accepted"))

(* ------------------------------------------------------------ bodies and percepts *)

(* validate holds a body's activate and deactivate events to its step's
   effects, and parses every percept literal (lib/explore/trace_more.ml).
   The trace of test/hostile/programs/effects.jade is spoilt one way at a
   time, the steps numbered again, and validate's OCaml part must reject
   it at the line named. *)
let effects_trace () =
  let prog = Filename.concat root "test/hostile/programs/effects.jade" in
  let events = {|{"agent":"a","notify":"door(1)"}
{"agent":"a","notify":"door(2)"}
{"agent":"a","notify":"ping"}
|} in
  Test_support.Support.with_file "events.jsonl" events (fun ev ->
      let dir = Filename.dirname ev in
      let t0 = Filename.concat dir "t0.jsonl" in
      let (s, _, e) = run (Printf.sprintf "%s run %s --agent a:A --events %s --trace %s"
                             exe (q prog) (q ev) (q t0)) in
      Alcotest.(check int) ("the run: " ^ e) 0 s;
      let ls = Array.of_list (lines (Test_support.Support.read_file t0)) in
      (* the lines, edited, written with their steps numbered 1, 2, 3... *)
      let step_re = Str.regexp {|"step":[0-9]+|} in
      let write ls =
        let f = Filename.concat dir "t.jsonl" in
        let oc = open_out_bin f in
        List.iteri (fun i l ->
            output_string oc (if i = 0 then l else Str.replace_first step_re (Printf.sprintf "\"step\":%d" i) l);
            output_char oc '\n') ls;
        close_out oc; f in
      let all = Array.to_list ls in
      (match Explore.Validate.check (write all) with
       | Ok () -> ()
       | Error (l, m) -> Alcotest.failf "the run's trace: line %d: %s" l m);
      let find sub = let rec go i = if has ls.(i) sub then i else go (i + 1) in go 0 in
      let handle_door = find {|"effects":["activate Door"]|} in
      let act = find {|"event":"activate","action":"Handle"|} in
      let rejected ~what ?line ~says ls =
        match Explore.Validate.check (write ls) with
        | Ok () -> Alcotest.failf "%s: accepted" what
        | Error (l, m) ->
          check (what ^ ": " ^ m) true (has m says);
          Option.iter (fun line -> Alcotest.(check int) (what ^ ": the line") line l) line in
      let edit i f = List.mapi (fun j l -> if j = i then f l else l) all in
      let insert i x = List.concat (List.mapi (fun j l -> if j = i then [ l; x ] else [ l ]) all) in
      rejected ~what:"activate Till where the effects say Door" ~line:(handle_door + 1) ~says:"effects"
        (edit act (fun l -> Str.global_replace (Str.regexp_string {|"behaviour":"Door"|}) {|"behaviour":"Till"|} l));
      rejected ~what:"a dropped activate" ~line:(handle_door + 1) ~says:"effects"
        (List.filteri (fun j _ -> j <> act) all);
      rejected ~what:"a tripled activate" ~line:(handle_door + 1) ~says:"effects"
        (List.concat (List.mapi (fun j l -> if j = act then [ l; l; l ] else [ l ]) all));
      rejected ~what:"a deactivate the effects do not have" ~line:(handle_door + 1) ~says:"effects"
        (insert act {|{"step":0,"agent":"a","event":"deactivate","action":"Handle","instance":1}|});
      (* percept literals: replaced in every line of one seq (notify, dequeue, handle) *)
      let percept from into =
        let jfrom = Printf.sprintf "%S" from and jinto = Yojson.Safe.to_string (`String into) in
        List.map (fun l -> Str.global_replace (Str.regexp_string jfrom) jinto l) all in
      rejected ~what:"a percept that does not parse" ~line:(find "door(1)" + 1) ~says:"does not parse"
        (percept "door(1)" "door(<img src=x>, \"oops");
      rejected ~what:"a percept not closed" ~says:"does not parse" (percept "door(1)" "door(1");
      rejected ~what:"text after a percept" ~says:"does not parse" (percept "door(1)" "door(1) door(2)");
      rejected ~what:"a percept of another arity" ~line:(find "door(2)" + 1) ~says:"slots"
        (percept "door(2)" "door(2, 3)"))

let literal_cases = [
  "percept literals as the interpreter writes them", `Quick, (fun () ->
      List.iter (fun (l, expected) ->
          match Explore.Trace_more.literal_arity l with
          | Ok r -> Alcotest.(check (pair string int)) l expected r
          | Error m -> Alcotest.failf "%s: %s" l m) [
        "obstacle", ("obstacle", 0);
        "position(0.0, -1.5E10)", ("position", 2);
        {|qrCodeRead("A\"7\\")|}, ("qrCodeRead", 1);
        {|p([1, 2], {"a": [true, false]}, q(NaN, -Infinity, Infinity), aid("x@y"), <java.util.Random>, nothing, agent r, behaviour #3)|}, ("p", 8);
        "p([], {}, q)", ("p", 3) ]);
  "what is no percept literal", `Quick, (fun () ->
      List.iter (fun l ->
          match Explore.Trace_more.literal_arity l with
          | Ok (t, k) -> Alcotest.failf "%S read as %s of %d slots" l t k
          | Error _ -> ())
        [ ""; "1"; "\"a\""; "p("; "p(1,)"; "p(1 2)"; "p(\"a)"; "p(\"a\nb\")"; "p(<img src=x>)"; "p) ";
          "p(" ^ String.make 2000 '[' ^ String.make 2000 ']' ^ ")"; "p(1) x" ]);
]

(* ------------------------------------------------------------ option values *)

(* A bad value of an option of sim, explore or conform: one line, exit 1
   (not a usage of three lines and exit 124, which conform itself reads as
   "timed out"); --max-states past what 24 GB hold is refused so too. *)
let option_cases =
  let model = q (Filename.concat root "spec/models/MCReference.tla") in
  let bad what cmd = what, `Quick, (fun () -> one_error ~what (run (exe ^ " " ^ cmd))) in [
    bad "sim --seed abc" "sim paper --seed abc";
    bad "sim --seed -1" "sim paper --seed -1";
    bad "sim --batch x" "sim paper --batch x";
    bad "explore --max-states x" ("explore " ^ model ^ " --max-states x");
    bad "explore --max-states 0" ("explore " ^ model ^ " --max-states 0");
    bad "explore --max-states 50,000,000 (about 30 GB)" ("explore " ^ model ^ " --max-states 50000000");
    bad "explore --max-states beyond int" ("explore " ^ model ^ " --max-states 99999999999999999999999");
    bad "conform --timeout -3" "conform --impl true --timeout -3";
    bad "conform --timeout x" "conform --impl true --timeout x";
    "explore --max-states 25,000,000 (the largest)", `Quick, (fun () ->
        let (s, out, e) = run (Printf.sprintf "%s explore %s --max-states 25000000" exe model) in
        Alcotest.(check int) ("exit 0: " ^ e) 0 s;
        (* the same count as with the default bound (the model is far below both) *)
        let (_, out0, _) = run (Printf.sprintf "%s explore %s" exe model) in
        let count o = match String.index_opt o ':' with
          | Some i -> (try Scanf.sscanf (String.sub o (i + 1) (String.length o - i - 1)) " %d states" (fun n -> Some n) with _ -> None)
          | None -> None in
        check "the states counted, as with the default bound" true (count out <> None && count out = count out0));
  ]

(* ------------------------------------------------------------ a file name not UTF-8 *)

(* A program whose file name is not UTF-8 and that meets a run-time error:
   the trace's [at] has U+FFFD for the bad byte (as the JADE back end's
   Java has), and validate reads the interpreter's own trace. *)
let non_utf8_name () =
  let text = "agent A\n\ton create do\n\t\tx as integer = 0\n\t\tlog 1 / x\n" in
  Test_support.Support.with_file "ok.jade" text (fun ok ->
      let dir = Filename.dirname ok in
      let bad = Filename.concat dir "bad\xff.jade" and t = Filename.concat dir "t.jsonl" in
      Sys.rename ok bad;
      ignore (run (Printf.sprintf "%s run %s --agent a:A --trace %s" exe (q bad) (q t)));
      let trace = Test_support.Support.read_file t in
      check "the position has U+FFFD" true (has trace "bad\xef\xbf\xbd.jade:4:");
      (match Explore.Validate.check t with
       | Ok () -> ()
       | Error (l, m) -> Alcotest.failf "validate: line %d: %s" l m);
      Sys.rename bad ok)

let repair_cases = [
  "Utf8.repair", `Quick, (fun () ->
      List.iter (fun (x, y) -> Alcotest.(check string) (String.escaped x) y (Utf8.repair x)) [
        "abc", "abc"; "caf\xc3\xa9", "caf\xc3\xa9"; "a\xffb", "a\xef\xbf\xbdb";
        "\xc3(", "\xef\xbf\xbd("; "\xf0\x9f\x98", "\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd" ]);
  "a file name that is not UTF-8", `Quick, non_utf8_name;
]

let () =
  Alcotest.run "hostile"
    [ "json", json_cases @ [ round_trip ];
      "stack", stack_cases;
      "events read once", [ "a file, a pipe, a FIFO", `Quick, events_once ];
      "agents from a file", [ "5,000 agents in a ring, a pipe, bad lines", `Quick, agents_from_file ];
      "TLA+ values", tla_cases;
      "slots", slot_cases;
      "scenarios", scenario_cases;
      "a cut trace", [ "validate checks it as far as it goes", `Quick, cut_trace ];
      "validate: bodies and percepts", ("effects and literals of a spoilt trace", `Quick, effects_trace) :: literal_cases;
      "option values", option_cases;
      "file names", repair_cases ]
