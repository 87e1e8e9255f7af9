(* Tests of the engine's fast paths (D29, D30, D33, D34), each held equal
   to the path it stands beside: the events file's quick reader (Interp.Events.quick_notify)
   to the full one, the trace's direct encoder (Trace.line_to_buffer) to the
   JSON tree, and a run without a trace (the derived rule Dispatch) to a run
   with one (every rule a step). *)

open Syntax
open Test_support
open Support
module V = Interp.Value
module Ev = Interp.Events
module Mc = Semantics.Machine

(* ------------------------------------------------ the events file *)

let program_text = String.concat "\n" [
    "ontology O";
    "\tconcept point(x as integer, y as integer)";
    "\tpredicate position(k as integer) extends percept with priority = 2";
    "\tpredicate reading(v as double, f as float) extends percept";
    "\tpredicate seen(t as text, b as boolean) extends percept";
    "\tpredicate at(p as point) extends percept";
    "\tpredicate who(a as aid) extends percept";
    "\tproposition falling extends percept with priority = 10";
    "\tpredicate tags(l as list of integer) extends percept";
    "\tpredicate code(c as text, n as integer, d as text) extends percept";
    "\tproposition qrCodeReadX extends percept";
    "\tproposition aVeryLongPerceptName extends percept";
    "";
    "ontology Other";
    "\tproposition hidden extends percept";
    "";
    "agent A uses ontology O";
    "\ton create do";
    "\t\tlog \"a\"";
    "";
    "agent B uses ontology Other";
    "\ton create do";
    "\t\tlog \"b\"";
    "" ]

let env = lazy (
  let env, diags = Typing.check [ Parse.string ~file:"p.jade" program_text ] in
  (match List.filter (fun d -> d.Diag.severity = Diag.Error) diags with
   | [] -> ()
   | d :: _ -> failwith (Diag.to_string d));
  env)

let agents = [ ("a", "A"); ("b", "B") ]

let show_result = function
  | Ok None -> "nothing"
  | Ok (Some (Ev.Notify { agent; percept; default; priority })) ->
    Printf.sprintf "notify %s %s (%s) %d %s" agent (V.to_literal percept) (V.type_name percept) default
      (match priority with Some k -> string_of_int k | None -> "-")
  | Ok (Some _) -> "another event"
  | Error es -> String.concat "; " (List.map (fun (c, m) -> Printf.sprintf "%d: %s" c m) es)

(* The quick path takes the line only when the full path reads the same
   event from it (compared as values: Int 1 and Double 1.0 differ). *)
let quick_agrees line =
  let env = Lazy.force env in
  let full = Ev.parse_line_full env ~agents ~file:"e.jsonl" line in
  match Ev.quick_notify env ~agents line with
  | None -> true
  | Some e ->
    (match full with
     | Ok (Some e') when compare e e' = 0 -> true
     | _ -> QCheck.Test.fail_reportf "line %S\nquick: %s\nfull:  %s" line
              (show_result (Ok (Some e))) (show_result full))

(* Lines the quick path must take, and what they mean. *)
let quick_taken () =
  let env = Lazy.force env in
  List.iter (fun (line, expected) ->
      (match Ev.quick_notify env ~agents line with
       | Some e -> Alcotest.(check string) line expected (show_result (Ok (Some e)))
       | None -> Alcotest.failf "the quick path does not take %s" line);
      ignore (quick_agrees line))
    [ ({|{"agent":"a","notify":"position(1)"}|}, "notify a position(1) (position) 2 -");
      ({|{ "notify" : "position(-7)" , "agent" : "a" }|}, "notify a position(-7) (position) 2 -");
      ({|{"agent":"a","notify":"falling"}|}, "notify a falling (falling) 10 -");
      ({|{"agent":"a","notify":"reading(1, 2.5)"}|}, "notify a reading(1.0, 2.5) (reading) 0 -");
      ({|{"agent":"a","notify":"reading(-1.5e3, 0.1)"}|}, "notify a reading(-1500.0, 0.1) (reading) 0 -");
      ({|{"agent":"a","notify":"seen(\"x y#\", true)"}|}, "notify a seen(\"x y#\", true) (seen) 0 -");
      ({|{"agent":"a","notify":"at(point(1,  2))"}|}, "notify a at(point(1, 2)) (at) 0 -");
      ({|{"agent":"b","notify":"hidden"}|}, "notify b hidden (hidden) 0 -");
      ({|{"agent":"a","notify":"code(\"x\", 12 ,\"\")"}|}, "notify a code(\"x\", 12, \"\") (code) 0 -");
      ({|{"agent":"a","notify":"code(\"x\", 12 ,\"\")"}|}, "notify a code(\"x\", 12, \"\") (code) 0 -");
      ({|{"agent":"a","notify":"code(\"x\", 2147483647, \"y\")"}|}, "notify a code(\"x\", 2147483647, \"y\") (code) 0 -") ]

(* Lines it must leave to the full path: other fields, escapes, forms it
   does not know, and every line that is an error. *)
let quick_refused () =
  let env = Lazy.force env in
  List.iter (fun line ->
      match Ev.quick_notify env ~agents line with
      | None -> ()
      | Some e -> Alcotest.failf "the quick path takes %s: %s" line (show_result (Ok (Some e))))
    [ {|{"agent":"a","notify":"position(1)","priority":3}|};
      {|{"agent":"a","notify":"seen(\"\u0041\", true)"}|};
      {|{"agent":"a","notify":"seen(\"a\\nb\", true)"}|};
      {|{"agent":"a","notify":"who(aid(\"x\"))"}|};
      {|{"agent":"a","notify":"tags([1, 2])"}|};
      {|{"agent":"a","notify":"hidden"}|};
      {|{"agent":"a","notify":"point(1, 2)"}|};
      {|{"agent":"a","notify":"position(\"x\")"}|};
      {|{"agent":"a","notify":"position(99999999999999999999)"}|};
      {|{"agent":"a","notify":"position(1.)"}|};
      {|{"agent":"a","notify":"code(\"x\", 2147483648, \"y\")"}|};
      {|{"agent":"a","notify":"code(\"x\", 1)"}|};
      {|{"agent":"a","notify":"position()"}|};
      {|{"agent":"a","notify":"falling()"}|};
      {|{"agent":"a","notify":"fallinh"}|};
      {|{"agent":"a","notify":"fallings"}|};
      {|{"agent":"a","notify":"positions(1)"}|};
      {|{"agent":"a","notify":"positiom(1)"}|};
      {|{"agenu":"a","notify":"position(1)"}|};
      {|{"agent":"a","notifz":"position(1)"}|};
      {|{"agent":"a","notify":"position (1)"}|};
      {|{"agent":"a","notify":"position(1) "}|};
      {|{"agent":"a","notify":"position(1) # c"}|};
      {|{"agent":"z","notify":"position(1)"}|};
      {|{"agent":"a","agent":"a","notify":"position(1)"}|};
      {|{"agent":"a","notify":"position(1)"} |};
      {|{"agent":"a","put":"position(1)"}|};
      {|{"agent":"a","notify":"agent"}|};
      "# a comment"; "" ]

(* Events.to_line writes what parse_line reads back as the same event
   (the bench writes its events file with it). *)
let to_line_round_trip () =
  let env = Lazy.force env in
  let read line = match Ev.parse_line env ~agents ~file:"e.jsonl" line with
    | Ok (Some e) -> e
    | r -> Alcotest.failf "%s: %s" line (show_result r) in
  List.iter (fun line ->
      let e = read line in
      let line' = Ev.to_line e in
      Alcotest.(check string) line (show_result (Ok (Some e))) (show_result (Ok (Some (read line'))));
      if compare e (read line') <> 0 then Alcotest.failf "%s: %s reads back differently" line line')
    [ {|{"agent":"a","notify":"position(-3)"}|};
      {|{"agent":"a","notify":"reading(1, 2.5)","priority":4}|};
      {|{"agent":"a","notify":"seen(\"a\\\"b\\nc\", false)"}|};
      {|{"agent":"a","notify":"who(aid(\"x\"))"}|};
      {|{"agent":"a","notify":"at(point(1, 2))"}|};
      {|{"agent":"a","put":"[1, 2]"}|};
      {|{"agent":"a","message":"position(1)","performative":"request"}|};
      {|{"run":3}|}; {|{"run":"idle"}|} ]

(* The events file's lines are those input_line reads, whatever their
   lengths (one longer than the reader's 64 kB buffer, lines across its
   edges), with or without a last newline. *)
let lines_as_input_line (pieces, last_newline) =
  let text = String.concat "\n" pieces ^ (if last_newline then "\n" else "") in
  let file = Filename.temp_file "jsref_lines" ".jsonl" in
  let oc = open_out_bin file in
  output_string oc text; close_out oc;
  let expected =
    let ic = open_in_bin file in
    let rec go acc = match input_line ic with l -> go (l :: acc) | exception End_of_file -> List.rev acc in
    let r = go [] in close_in ic; r in
  let got = List.rev (Ev.fold_lines file (fun acc n l ->
      if n <> List.length acc + 1 then QCheck.Test.fail_reportf "line %d numbered %d" (List.length acc + 1) n;
      match l with
      | Some l -> `Continue (l :: acc)
      | None -> QCheck.Test.fail_reportf "line %d read as too long" n) []) in
  Sys.remove file;
  if got <> expected then
    QCheck.Test.fail_reportf "%d lines read, %d by input_line (lengths %s)" (List.length got) (List.length expected)
      (String.concat "," (List.map (fun p -> string_of_int (String.length p)) pieces));
  true

let arb_pieces =
  let open QCheck.Gen in
  let piece = oneof [ string_size ~gen:(oneofl [ 'a'; '\r'; ' ' ]) (int_range 0 40);
                      map (fun n -> String.make n 'x') (oneofl [ 65535; 65536; 65537; 200_000 ]);
                      map (fun n -> String.make n 'y') (int_range 1000 30000) ] in
  QCheck.make ~print:(fun (l, b) -> Printf.sprintf "%d pieces %s" (List.length l) (if b then "+newline" else ""))
    (pair (list_size (int_range 0 12) piece) bool)

(* Random lines: well-formed ones of every shape the quick path knows and
   some it does not, then, one time in two, a few characters changed. *)
let gen_line =
  let open QCheck.Gen in
  let int_text = oneof [ map string_of_int (int_range 0 100);
                         map string_of_int (int_range 0 max_int);
                         return "2147483648"; return "007"; return "99999999999999999999" ] in
  let real_text = oneof [ map (fun (a, b) -> Printf.sprintf "%d.%d" a b) (pair (int_range 0 99) (int_range 0 999));
                          map (fun (a, e) -> Printf.sprintf "%de%d" a e) (pair (int_range 0 9) (int_range (-5) 40));
                          return "1.5E-3"; return "3.4e39"; return "1e400" ] in
  let num = oneof [ int_text; real_text ] in
  let signed = map2 (fun neg n -> if neg then "-" ^ n else n) bool num in
  let text_char = oneofl [ 'a'; 'Z'; ' '; '#'; '0'; '\\'; '"'; '\''; '{'; '\t'; '\xc3' ] in
  let text = map (fun l -> "\"" ^ String.of_seq (List.to_seq l) ^ "\"") (list_size (int_range 0 4) text_char) in
  let value = oneof [ signed; text; oneofl [ "true"; "false"; "falling"; "nothing"; "agent" ];
                      map2 (fun a b -> Printf.sprintf "point(%s, %s)" a b) signed signed ] in
  let sep = oneofl [ ","; ", "; " , "; ",  " ] in
  let call name n = map2 (fun args s -> name ^ "(" ^ String.concat s args ^ ")") (list_repeat n value) sep in
  let any_percept = oneof [
      call "position" 1; call "reading" 2; call "seen" 2; call "at" 1; call "who" 1; call "tags" 1;
      call "point" 2; call "position" 2; call "code" 3; call "code" 2;
      oneofl [ "falling"; "hidden"; "falling()"; "position"; "aid(\"a\")"; "tags([1, 2])";
               "qrCodeReadX"; "qrCodeReadY"; "qrCodeRdadX"; "aVeryLongPerceptName"; "aVeryLongPerceptNamf";
               "aVeryLongPercfptName"; "aVeryLongPerceptNam"; "fallinh"; "hiddem"; "positiom(1)"; "fallinG";
               "fallings"; "falling_"; "falling2"; "positions(1)"; "aVeryLongPerceptNameX" ] ] in
  (* percepts of the right types, so that most lines are good ones *)
  let small_int = map2 (fun neg n -> (if neg then "-" else "") ^ string_of_int n) bool (int_range 0 1000) in
  let good_text = map (fun l -> "\"" ^ String.of_seq (List.to_seq l) ^ "\"")
      (list_size (int_range 0 5) (oneofl [ 'a'; 'Z'; ' '; '#'; '0'; '\''; '{'; '~'; '!'; ',' ])) in
  let well_typed = oneof [
      map (fun n -> "position(" ^ n ^ ")") small_int;
      map3 (fun a s b -> "reading(" ^ a ^ s ^ b ^ ")") signed sep signed;
      map3 (fun t s b -> "seen(" ^ t ^ s ^ b ^ ")") good_text sep (oneofl [ "true"; "false" ]);
      map2 (fun a b -> Printf.sprintf "at(point(%s, %s))" a b) small_int small_int;
      map3 (fun a n b -> "code(" ^ a ^ ", " ^ n ^ "," ^ b ^ ")") good_text (oneof [ small_int; int_text ]) good_text;
      return "falling" ] in
  let percept = frequency [ 3, well_typed; 2, any_percept ] in
  let json_string s = Yojson.Safe.to_string (`String s) in
  let line = map3 (fun (agent, p) order extra ->
      let a = Printf.sprintf "\"agent\":%s" (json_string agent)
      and n = Printf.sprintf "\"notify\":%s" (json_string p) in
      let fields = (if order then [ a; n ] else [ n; a ]) @ extra in
      "{" ^ String.concat "," fields ^ "}")
      (pair (oneofl [ "a"; "a"; "a"; "b"; "c" ]) percept) bool
      (frequency [ 8, return []; 1, return [ "\"priority\":3" ]; 1, return [ "\"put\":\"1\"" ] ]) in
  let edit s =
    map2 (fun i c ->
        let i = i mod (String.length s + 1) in
        match c with
        | None -> if i < String.length s then String.sub s 0 i ^ String.sub s (i + 1) (String.length s - i - 1) else s
        | Some c -> String.sub s 0 i ^ String.make 1 c ^ String.sub s i (String.length s - i))
      nat (opt (oneofl [ ' '; '"'; '\\'; ','; ':'; '('; ')'; '-'; '.'; 'e'; '1'; 'x'; '{'; '}'; '\n'; '\r'; '\xff'; '#' ])) in
  line >>= fun l ->
  bool >>= fun mutate ->
  if mutate then edit l >>= edit else return l

let arb_line = QCheck.make ~print:(fun s -> s) gen_line

(* ------------------------------------------------------ the trace *)

(* A trace line of any event ([hot] false), or of the frequent events only,
   those the fast reading takes or nearly ([hot] true), with numbers from
   [int] and texts from [str]. *)
let gen_line_of ~hot ~int:int_gen ~str:str_gen =
  let open QCheck.Gen in
  let int = int_gen and str = str_gen in
  let strs = list_size (int_range 0 3) str in
  let entry = map3 (fun percept priority seq -> { Trace.percept; priority; seq }) str int int in
  let message = map3 (fun performative content from -> { Trace.performative; content; from }) str str str in
  let effect = oneof [ map (fun b -> Trace.Activated b) (oneofl [ "B"; "Watch" ]); return Trace.Deactivated ] in
  let effects = list_size (int_range 0 3) effect in
  let body = oneof [
      map (fun s -> Trace.Log s) str;
      map2 (fun (meth, obj) (args, result) -> Trace.Invoke { meth; obj; args; result }) (pair str str) (pair strs str);
      map3 (fun performative content receivers -> Trace.Send { performative; content; receivers }) str str strs;
      map (fun b -> Trace.Activate b) str;
      map (fun i -> Trace.Deactivate i) int;
      map2 (fun at message -> Trace.Error { at; message }) str str ] in
  let frequent = [
      map2 (fun entry overridden -> Trace.Notify { entry; overridden }) entry bool;
      map (fun n -> Trace.Transfer n) int;
      map (fun e -> Trace.Transfer_one e) entry;
      return Trace.Transfer_end;
      map (fun e -> Trace.Dequeue e) entry;
      map3 (fun (instance, behaviour) (handler, percept) (seq, effects) ->
          Trace.Handle { instance; behaviour; handler; percept; seq; effects })
        (pair int str) (pair int str) (pair int effects);
      map3 (fun instance behaviour handler -> Trace.Skip { instance; behaviour; handler }) int str int;
      map2 (fun seq discarded -> Trace.End_dispatch { seq; discarded }) int bool;
      map3 (fun (instance, behaviour) taken (action_effects, handler) ->
          Trace.Behaviour_step { instance; behaviour; taken; action_effects; handler })
        (pair int str)
        (opt (oneof [ map2 (fun m s -> Trace.Took_message (m, s)) message int;
                      map (fun e -> Trace.Took_percept e) entry ]))
        (pair (opt effects) (opt (pair int effects)));
      return Trace.Next_iteration; return Trace.Idle; return Trace.Destroy ] in
  let event = oneof (if hot then
      frequent @ [ map2 (fun action s -> Trace.Body { action; body = Trace.Log s }) (oneofl [ "Handle"; "destroy"; "Nope" ]) str ]
    else frequent @ [
      map3 (fun agent_type args behaviours -> Trace.Create { agent_type; args; behaviours }) str strs strs;
      map2 (fun percept reason -> Trace.Refused { percept; reason }) str str;
      map2 (fun obj index -> Trace.Put { obj; index }) str int;
      map3 (fun message seq in_step -> Trace.Deliver { message; seq; in_step }) message int bool;
      map3 (fun receiver performative content -> Trace.Undeliverable { receiver; performative; content }) str str str;
      map (fun o -> Trace.Transfer_spin o) str;
      map2 (fun action body -> Trace.Body { action; body }) (oneofl [ "Init"; "Handle"; "destroy" ]) body ]) in
  map3 (fun step agent event -> { Trace.step; agent; event }) int str event

let gen_trace_line =
  let open QCheck.Gen in
  gen_line_of ~hot:false
    ~int:(oneof [ int_range 0 20; int_range min_int max_int; oneofl [ 0; -1; max_int; min_int ] ])
    ~str:(oneof [ oneofl [ ""; "a"; "position(1)"; "seen(\"x\", true)"; "é"; "\u{1F600}" ];
                  string_size ~gen:char (int_range 0 6);
                  string_size ~gen:(oneofl [ '"'; '\\'; '\n'; '\t'; '\x00'; '\x1f'; '\x7f'; '/'; 'a' ]) (int_range 0 6) ])

let direct_equals_tree (l : Trace.line) =
  let b = Buffer.create 64 in
  Trace.line_to_buffer b l;
  let direct = Buffer.contents b and tree = Yojson.Safe.to_string (Trace.line_to_json l) in
  if direct <> tree then QCheck.Test.fail_reportf "direct: %s\ntree:   %s" direct tree;
  true

(* The readers take a line the writer wrote through [Trace.fast_line],
   without a JSON tree: it must read exactly what the general reader reads
   ([line_of_json] of the line's JSON), or leave the line to it ([None]).
   Checked on written lines and on the same lines with a few bytes
   changed (a changed number, quote or key must never be read otherwise
   than the general reader reads it, nor a line it rejects taken). *)
let general s =
  match Json_read.of_string s with
  | Ok j -> Trace.line_of_json j
  | Error e -> Error e.message

let fast_agrees s =
  match Utf8.first_invalid s with
  | Some _ -> true
  | None ->
    match Trace.fast_line s, general s with
    | None, _ -> true
    | Some x, Ok y when x = y -> true
    | Some _, Ok _ -> QCheck.Test.fail_reportf "fast_line reads %s otherwise than the general reader" s
    | Some _, Error m -> QCheck.Test.fail_reportf "fast_line takes %s, which the general reader rejects: %s" s m

let fast_equals_general ((l : Trace.line), changes) =
  let b = Buffer.create 64 in
  Trace.line_to_buffer b l;
  let s = Buffer.contents b in
  let changed = Bytes.of_string s in
  List.iter (fun (at, c) -> if Bytes.length changed > 0 then Bytes.set changed (at mod Bytes.length changed) c) changes;
  fast_agrees s && fast_agrees (Bytes.to_string changed)

(* Lines of the frequent events with numbers at the bounds (0, 1, 2^31-1,
   2^31, -1) and texts with quotes and backslashes: the ones the fast way
   takes, or nearly. *)
let gen_hot_line =
  let open QCheck.Gen in
  gen_line_of ~hot:true ~int:(oneofl [ 0; 1; 2; 7; 10; 0x7FFF_FFFF; 0x8000_0000; -1 ])
    ~str:(oneofl [ ""; "a"; "l"; "position(1)"; "qrCodeRead(\"A7\")"; "b\\s"; "\""; "é" ])

let arb_changed_line =
  let open QCheck.Gen in
  QCheck.make (pair (oneof [ gen_trace_line; gen_hot_line; gen_hot_line ])
                 (list_size (int_range 0 2)
                    (pair (int_range 0 400) (oneofl [ '0'; '1'; '9'; '-'; '"'; '\\'; ' '; ','; '}'; 'x'; 'n' ]))))

(* Lines of the frequent events, as written, are read the fast way (the
   judge's speed depends on it; their agreement is the property above). *)
let hot_lines_fast () =
  let e = { Trace.percept = "p(\"A7\")"; priority = 2; seq = 7 } in
  List.iteri (fun i event ->
      let l = { Trace.step = i + 1; agent = "a"; event } in
      let b = Buffer.create 64 in
      Trace.line_to_buffer b l;
      match Trace.fast_line (Buffer.contents b) with
      | Some x when x = l -> ()
      | _ -> Alcotest.failf "not read the fast way: %s" (Buffer.contents b))
    [ Trace.Notify { entry = e; overridden = false }; Notify { entry = e; overridden = true };
      Transfer 5; Transfer_one e; Transfer_end; Dequeue e;
      Handle { instance = 1; behaviour = "B"; handler = 2; percept = "p"; seq = 3; effects = [ Activated "C"; Deactivated ] };
      Skip { instance = 1; behaviour = "B"; handler = 2 };
      End_dispatch { seq = 3; discarded = false }; End_dispatch { seq = 3; discarded = true };
      Behaviour_step { instance = 1; behaviour = "B"; taken = None; action_effects = Some []; handler = None };
      Behaviour_step { instance = 1; behaviour = "B"; taken = Some (Took_percept e); action_effects = None;
                       handler = Some (1, [ Deactivated ]) };
      Behaviour_step { instance = 1; behaviour = "B";
                       taken = Some (Took_message ({ performative = "inform"; content = "x"; from = "h" }, 4));
                       action_effects = None; handler = Some (1, []) };
      Next_iteration; Idle; Destroy; Body { action = "Handle"; body = Log "a \"q\" \\ b" } ]

(* JSON has one escaping function, Yojson's [write_string]: the trace's
   direct writer copies a text that needs no escape and hands every other to
   it. A text of any bytes (valid UTF-8) written in a trace line is strict
   JSON (no raw control character) and Trace's reader reads the same text
   back, in a log (the direct writer) and in a refused put (the tree). *)
let json_header =
  lazy (List.hd (String.split_on_char '\n'
                   (Support.read_file (Filename.concat Support.root "conformance/001-r3b-priority-order/expected.jsonl"))))

let json_text_round_trip s =
  let lines = [ { Trace.step = 1; agent = "r"; event = Trace.Body { action = "Init"; body = Trace.Log s } };
                { Trace.step = 2; agent = "r"; event = Trace.Refused_put { obj = s; reason = "full" } } ] in
  let text = String.concat "" (List.map (fun l ->
      let b = Buffer.create 64 in Trace.line_to_buffer b l; Buffer.add_char b '\n'; Buffer.contents b) lines) in
  if String.exists (fun c -> c < ' ' && c <> '\n') text then
    QCheck.Test.fail_reportf "%S written with a raw control character: %S" s text;
  Support.with_file "t.jsonl" (Lazy.force json_header ^ "\n" ^ text) (fun path ->
      match Trace.read_located path with
      | Ok (_, [ (_, { event = Trace.Body { body = Trace.Log a; _ }; _ });
                 (_, { event = Trace.Refused_put { obj = b; _ }; _ }) ]) when a = s && b = s -> true
      | Ok _ -> QCheck.Test.fail_reportf "%S written %S, read back otherwise" s text
      | Error (n, m) -> QCheck.Test.fail_reportf "%S written %S: line %d: %s" s text n m)

(* A writer numbers its lines itself (their step, in decimal, counted
   without a division): each line it hands over is the direct encoding of
   the line of that number, across 9, 99, 999 and 9999. *)
let writer_numbers () =
  let got = ref [] in
  let w = Trace.writer (fun l -> got := l :: !got) in
  let event k = if k mod 2 = 0 then Trace.Transfer k else Trace.Skip { instance = k; behaviour = "B"; handler = 1 } in
  for k = 1 to 10_050 do Trace.write w ~agent:"a" (event k) done;
  Alcotest.(check int) "lines written" 10_050 (Trace.lines_written w);
  List.iteri (fun i l ->
      let k = i + 1 in
      let b = Buffer.create 64 in
      Trace.line_to_buffer b { Trace.step = k; agent = "a"; event = event k };
      Buffer.add_char b '\n';
      if l <> Buffer.contents b then Alcotest.failf "line %d: %S, not %S" k l (Buffer.contents b))
    (List.rev !got)

(* Every constructor at least once, whatever QCheck draws. *)
let every_event () =
  let e = { Trace.percept = "p(\"\\\"\")"; priority = 2; seq = 7 } in
  let m = { Trace.performative = "inform"; content = "x"; from = "host" } in
  let events = [
    Trace.Create { agent_type = "A"; args = [ "1"; "\"t\"" ]; behaviours = [ "B" ] };
    Notify { entry = e; overridden = false }; Notify { entry = e; overridden = true };
    Refused { percept = "p"; reason = "full" }; Put { obj = "o"; index = 3 };
    Deliver { message = m; seq = 4; in_step = false }; Deliver { message = m; seq = 5; in_step = true };
    Undeliverable { receiver = "z"; performative = "inform"; content = "c" };
    Transfer 5; Transfer_one e; Transfer_spin "o"; Transfer_end; Dequeue e;
    Handle { instance = 1; behaviour = "B"; handler = 2; percept = "p"; seq = 3; effects = [ Activated "C"; Deactivated ] };
    Skip { instance = 1; behaviour = "B"; handler = 2 };
    End_dispatch { seq = 3; discarded = false }; End_dispatch { seq = 3; discarded = true };
    Behaviour_step { instance = 1; behaviour = "B"; taken = None; action_effects = None; handler = None };
    Behaviour_step { instance = 1; behaviour = "B"; taken = Some (Took_message (m, 9));
                     action_effects = Some []; handler = Some (1, [ Deactivated ]) };
    Behaviour_step { instance = 1; behaviour = "B"; taken = Some (Took_percept e);
                     action_effects = Some [ Activated "D" ]; handler = None };
    Next_iteration; Idle; Destroy;
    Body { action = "Handle"; body = Log "l\n" };
    Body { action = "Init"; body = Invoke { meth = "m"; obj = "O"; args = [ "1" ]; result = "nothing" } };
    Body { action = "Handle"; body = Send { performative = "inform"; content = "c"; receivers = [ "a"; "b" ] } };
    Body { action = "Init"; body = Activate "B" }; Body { action = "Handle"; body = Deactivate 2 };
    Body { action = "Handle"; body = Error { at = "f:1:2"; message = "m\"" } } ] in
  List.iteri (fun i event -> ignore (direct_equals_tree { Trace.step = i + 1; agent = "a"; event })) events

(* ------------------------------------------ a value's literal text *)

(* Values of every kind, nested: the printer that writes into one buffer
   (Value.to_literal, Value.to_text) = the plain printer below, which
   concatenates strings as the rules of docs/trace-format.md read. *)
let gen_value =
  let open QCheck.Gen in
  let int = oneof [ int_range 0 20; int_range (-0x8000_0000) 0x7FFF_FFFF;
                    oneofl [ 0; 9; 10; 99; 100; -1; -10; 0x7FFF_FFFF; -0x8000_0000 ] ] in
  let text = string_size ~gen:(oneofl [ '"'; '\\'; '\n'; '\x00'; '\x7f'; 'a'; ' '; ',' ]) (int_range 0 5) in
  let leaf = oneof [
      map (fun i -> V.Int i) int; map (fun b -> V.Bool b) bool; map (fun s -> V.Text s) text;
      map (fun f -> V.Double f) (oneofl [ 0.; 1.5; -2.25; 1e10; nan ]);
      map (fun f -> V.Float (V.float32 f)) (oneofl [ 0.; 0.1; 3.5 ]);
      map (fun s -> V.Aid s) text; return V.Unit ] in
  sized_size (int_range 0 3) @@ fix (fun self n ->
      if n = 0 then leaf
      else oneof [
          leaf;
          map (fun vs -> V.Schema { sname = "p"; slots = Array.of_list (List.mapi (fun i v -> (string_of_int i, ref v)) vs) })
            (list_size (int_range 0 3) (self (n - 1)));
          map (fun vs -> V.list_of vs) (list_size (int_range 0 3) (self (n - 1)));
          map (fun kvs -> match V.map_empty () with
              | V.Map mv as m -> List.iter (fun (k, v) -> V.map_set mv k v) kvs; m
              | m -> m)
            (list_size (int_range 0 2) (pair leaf (self (n - 1)))) ])

let rec plain_show ~quote (v : V.t) = match v with
  | Bool b -> if b then "true" else "false"
  | Int i -> string_of_int i
  | Float _ | Double _ -> V.to_text v   (* Java's float texts: tested in test_interp "float is binary32" *)
  | Text s -> if quote then Syntax.Print.text_literal s else s
  | Aid a -> "aid(" ^ Syntax.Print.text_literal a ^ ")"
  | List l -> "[" ^ String.concat ", " (List.map (plain_show ~quote:true) (V.list_items l)) ^ "]"
  | Map m -> "{" ^ String.concat ", " (List.map (fun (k, v) -> plain_show ~quote:true k ^ ": " ^ plain_show ~quote:true v)
                                         (V.map_bindings m)) ^ "}"
  | Schema s when Array.length s.slots = 0 -> s.sname
  | Schema s -> s.sname ^ "(" ^ String.concat ", " (List.map (fun (_, v) -> plain_show ~quote:true !v) (Array.to_list s.slots)) ^ ")"
  | Native n -> "<" ^ n.cls ^ ">"
  | Agent_ref a -> "agent " ^ a
  | Behaviour_ref i -> "behaviour #" ^ string_of_int i
  | Unit -> "nothing"

let quick_literal_equal v =
  let q = V.to_literal v and l = plain_show ~quote:true v in
  if q <> l then QCheck.Test.fail_reportf "buffer: %s\nplain:  %s" q l;
  let q = V.to_text v and l = plain_show ~quote:false v in
  if q <> l then QCheck.Test.fail_reportf "text, buffer: %s\nplain:  %s" q l;
  true

(* The trace keeps a percept's text from one line to the next only while
   its slots hold the same values: a handler that sets a slot of its
   percept changes the text of the handle lines after it. *)
let percept_text_follows_its_slots () =
  let text = String.concat "\n" [
      "ontology O";
      "\tpredicate position(k as integer, t as text) extends percept";
      "";
      "agent A uses ontology O";
      "\ton create do";
      "\t\tactivate behaviour B1";
      "\t\tactivate behaviour B2";
      "";
      "cyclic behaviour B1 for agent A";
      "\ton percept when content matches position(k, t) do";
      "\t\tk of content = k + 1";
      "";
      "cyclic behaviour B2 for agent A";
      "\ton percept when content matches position(k, t) do";
      "\t\tlog \"seen \" + k";
      "" ] in
  let env, _ = Typing.check [ Parse.string ~file:"m.jade" text ] in
  let file = Filename.temp_file "jsref_text" ".jsonl" in
  let oc = open_out_bin file in
  let opts = { Interp.Runtime.params = Mc.default_params; engine = Interp.Runtime.Fast; max_memory = None; level = "full"; seed = None; interleave = None; fuel = 500; max_steps = 1000;
               trace = Some oc; on_log = (fun _ _ -> ()); on_error = (fun _ _ _ -> ()) } in
  let rt = Interp.Runtime.create env opts [ ("a", "A", []) ] in
  List.iter (fun p ->
      let (v, default) = Interp.Eval.percept_value env ~agent_type:"A" (Parse.expr ~file:"e" p) in
      match Interp.Runtime.notify rt ~agent:"a" v ~default ~priority:None with
      | Ok () -> ()
      | Error m -> Alcotest.fail m) [ {|position(1, "x")|}; {|position(7, "y")|} ];
  Interp.Runtime.run_until_idle rt;
  Interp.Runtime.finish rt;
  close_out oc;
  let percepts = List.filter_map (fun l ->
      match Yojson.Safe.from_string l with
      | `Assoc f ->
        (match List.assoc_opt "event" f, List.assoc_opt "percept" f with
         | Some (`String ("dequeue" | "handle" as e)), Some (`String p) -> Some (e ^ " " ^ p)
         | _ -> None)
      | _ -> None) (String.split_on_char '\n' (String.trim (read_file file))) in
  Sys.remove file;
  Alcotest.(check (list string)) "dequeue, then each handle line after B1 set k"
    [ {|dequeue position(1, "x")|}; {|handle position(2, "x")|}; {|handle position(2, "x")|};
      {|dequeue position(7, "y")|}; {|handle position(8, "y")|}; {|handle position(8, "y")|} ] percepts

(* --------------------------------------- a run without a trace *)

let literal_of = Test_support.Event_gen.small_literal

(* The same program, agents and host events, run once with a trace (every
   rule a step) and once without (the derived rule Dispatch where it may):
   the same logs and errors in the same order, the same number of steps
   (--max-steps stops at the same rule), the same properties and the same
   configuration at the end. *)
let rec same_without_trace (prog, seed) = same_runs `Quiet (prog, seed)

(* D33: with a trace, a percept's dispatch is the derived rule Dispatch too
   when no body sends a message (the generated program's send statements
   are made [do nothing]): the trace, byte for byte, the logs and errors and
   the configuration at the end are those of the run that takes every rule
   as a step of its own (hooks other than the reference's: each rule by
   [hooks.step]). *)
and same_traced_by_dispatch (prog, seed) = same_runs (`Traced true) (prog, seed)

(* ... and the programs as generated, most of which send: then every rule
   is a step of its own (each rule's messages are delivered, with their
   lines, right after it) *)
and same_traced_with_sends (prog, seed) = same_runs (`Traced false) (prog, seed)

and same_runs mode (prog, seed) =
  let text = Print.program prog in
  let text = match mode with
    | `Quiet | `Traced false -> text
    | `Traced true ->
      String.concat "\n" (List.map (fun l ->
          let t = String.trim l in
          if String.length t >= 5 && String.sub t 0 5 = "send " then
            String.sub l 0 (String.index l 's') ^ "do nothing"
          else l) (String.split_on_char '\n' text)) in
  let env, diags = Typing.check [ Parse.string ~file:"gen.jade" text ] in
  if List.exists (fun d -> d.Diag.severity = Diag.Error) diags then
    QCheck.Test.fail_reportf "the generated program does not check";
  let rand = Random.State.make [| seed |] in
  let percept_types = Test_support.Event_gen.percept_types env in
  let params = match Typing.Tenv.agent_create env "Ag" with Some r -> r.r_params | None -> [] in
  let args = List.map (fun (_, ty) -> Interp.Eval.literal_value env (Parse.expr ~file:"a" (literal_of rand ty))) params in
  let host = List.init (1 + Random.State.int rand 30) (fun _ ->
      match Random.State.int rand 6 with
      | 0 -> `Run (1 + Random.State.int rand 3)
      | 1 -> `Idle
      | _ ->
        let s = List.nth percept_types (Random.State.int rand (List.length percept_types)) in
        let a = List.map (fun (_, ty) -> literal_of rand ty) s.s_slots in
        let t = if a = [] then s.s_name else s.s_name ^ "(" ^ String.concat ", " a ^ ")" in
        let (v, default) = Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" t) in
        let agent = if Random.State.bool rand then "provider" else "Bob" in
        `Notify (agent, v, default, if Random.State.int rand 4 = 0 then Some (Random.State.int rand 9) else None)) in
  let max_steps = if seed mod 3 = 0 then 3_000 else 1 + Random.State.int rand 150 in
  let variant = List.nth [ Mc.Reference; Mc.Budgeted; Mc.Reference ] (seed mod 3) in
  let run traced =
    (* `Quiet: traced, then not (the engine either way); `Traced: the
       engine (its dispatches in one call), then the reference alone (one
       rule at a time) *)
    let hooks = Interp.Runtime.hooks_of
        (if traced || mode = `Quiet then Interp.Runtime.Fast else Interp.Runtime.Reference) in
    let traced = traced || mode <> `Quiet in
    let out = ref [] in
    let file = Filename.temp_file "jsref_fast" ".jsonl" in
    let oc = if traced then Some (open_out_bin file) else None in
    let opts = { Interp.Runtime.params = { Mc.default_params with variant; budget = 2 };
                 engine = Interp.Runtime.Fast; max_memory = None; level = "full"; seed = None; interleave = None;
                 fuel = 500; max_steps; trace = oc;
                 on_log = (fun a s -> out := Printf.sprintf "log %s: %s" a s :: !out);
                 on_error = (fun _ at m -> out := Printf.sprintf "error %s %s" (Source.string_of_region at) m :: !out) } in
    (* the generated bodies send to aid("Bob") and aid("provider"): two
       agents of those names receive them, one its own messages *)
    let rt = Interp.Runtime.create ~hooks env opts [ ("provider", "Ag", args); ("Bob", "Ag", args) ] in
    List.iter (function
        | `Run k -> Interp.Runtime.run_rounds rt k
        | `Idle -> Interp.Runtime.run_until_idle rt
        | `Notify (agent, v, default, priority) ->
          (match Interp.Runtime.notify rt ~agent v ~default ~priority with
           | Ok () -> ()
           | Error m -> out := ("refused " ^ m) :: !out)) host;
    Interp.Runtime.run_until_idle rt;
    let show_agent (ag : Interp.Runtime.P.agent) =
    let c = ag.config in
    let props = List.map (fun (pr : Typing.Tenv.property) ->
        pr.p_name ^ "=" ^ (match Interp.Eval.property c.world pr.p_name with Some v -> V.to_literal v | None -> "?"))
        (Typing.Tenv.agent_properties env "Ag") in
    Printf.sprintf "%s: phase=%s o2a=%d pq=%d next_seq=%d dispatched=%d active=[%s] last=%s props=[%s]"
        ag.name
        (match c.phase with Mc.Transfer_phase -> "transfer" | Dispatch_phase -> "dispatch"
                          | Handle_phase -> "handle" | Idle_phase -> "idle")
        (Semantics.Fqueue.length c.o2a) (List.length (Semantics.Pqueue.to_sorted_list c.pq))
        c.next_seq c.dispatched
        (String.concat ";" (List.map (fun (a : Interp.Eval.beh Mc.instance) -> string_of_int a.id) c.active))
        (Mc.action_name c.last) (String.concat ";" props) in
    let state = Printf.sprintf "steps=%d %s" (Interp.Runtime.steps rt)
        (String.concat " / " (Array.to_list (Array.map show_agent (Interp.Runtime.platform rt).agents))) in
    Interp.Runtime.finish rt;
    Option.iter close_out oc;
    let trace = if traced then read_file file else "" in
    Sys.remove file;
    (List.rev !out, state ^ "\n" ^ trace) in
  let (o1, s1) = run true and (o2, s2) = run false in
  let (s1, s2) = match mode with
    | `Quiet -> (List.hd (String.split_on_char '\n' s1), List.hd (String.split_on_char '\n' s2))
    | `Traced _ -> (s1, s2) in
  if o1 <> o2 then
    QCheck.Test.fail_reportf "logs and errors differ (max-steps %d):\ntraced: %s\nquiet:  %s\n%s"
      max_steps (String.concat " | " o1) (String.concat " | " o2) text;
  if s1 <> s2 then
    QCheck.Test.fail_reportf "the end differs (max-steps %d):\ntraced: %s\nquiet:  %s\n%s" max_steps s1 s2 text;
  true

let () =
  Alcotest.run "fastpath" [
    ("events", [
        Alcotest.test_case "quick path takes percept literals" `Quick quick_taken;
        Alcotest.test_case "quick path leaves the rest to the full path" `Quick quick_refused;
        Alcotest.test_case "to_line reads back as the same event" `Quick to_line_round_trip;
        qcheck ~count:3000 "events: quick path = full path" arb_line quick_agrees;
        qcheck ~count:200 "events: lines as input_line reads them" arb_pieces lines_as_input_line ]);
    ("trace", [
        Alcotest.test_case "direct encoding = JSON tree, every event" `Quick every_event;
        Alcotest.test_case "a writer numbers its lines" `Quick writer_numbers;
        Alcotest.test_case "a percept's text follows its slots" `Quick percept_text_follows_its_slots;
        qcheck ~count:3000 "trace: direct encoding = JSON tree" (QCheck.make gen_trace_line) direct_equals_tree;
        Alcotest.test_case "trace: the frequent lines are read the fast way" `Quick hot_lines_fast;
        qcheck ~count:5000 "trace: the fast reading = the general reading" arb_changed_line fast_equals_general;
        qcheck ~count:1000 "trace: Trace reads every text back" Support.tricky_text json_text_round_trip ]);
    ("value", [
        qcheck ~count:3000 "value: the literal and the text = the plain printer" (QCheck.make gen_value) quick_literal_equal ]);
    ("run", [
        qcheck ~count:60 "run: the same without a trace"
          (QCheck.pair Typed_gen.arb_program QCheck.small_nat) same_without_trace;
        qcheck ~count:60 "run: a traced dispatch = rule by rule (D33)"
          (QCheck.pair Typed_gen.arb_program QCheck.small_nat) same_traced_by_dispatch;
        qcheck ~count:60 "run: a traced dispatch that may send = rule by rule (D33)"
          (QCheck.pair Typed_gen.arb_program QCheck.small_nat) same_traced_with_sends ]);
  ]
