(* Tests of lib/syntax and of the parse/fmt commands. *)

open Syntax
open Test_support
open Support

let examples_dir = Filename.concat root "examples"

let example_files =
  let rec walk dir =
    Sys.readdir dir |> Array.to_list |> List.sort compare
    |> List.concat_map (fun f ->
        let p = Filename.concat dir f in
        if Sys.is_directory p then walk p
        else if Filename.check_suffix f ".jade" then [p] else []) in
  walk examples_dir

let parse_ok file text =
  match Parse.string ~file text with
  | r -> r
  | exception Diag.Failed d -> Alcotest.failf "%s" (Diag.to_string d)

let fmt r = Print.program ~comments:r.Parse.comments r.Parse.program

(* ------------------------------------------------------------ examples *)

let example_cases =
  List.concat_map (fun file ->
      let short = Filename.basename file in
      let text = read_file file in
      [ Alcotest.test_case ("parses: " ^ short) `Quick (fun () ->
            let r = parse_ok file text in
            Alcotest.(check bool) "has declarations" true (r.program.decls <> []));
        Alcotest.test_case ("fmt is idempotent: " ^ short) `Quick (fun () ->
            let once = fmt (parse_ok file text) in
            let twice = fmt (parse_ok file once) in
            Alcotest.(check string) "fmt (fmt x) = fmt x" once twice);
        Alcotest.test_case ("fmt keeps the tree: " ^ short) `Quick (fun () ->
            let r = parse_ok file text in
            let r' = parse_ok file (fmt r) in
            Alcotest.(check bool) "parse (fmt x) = parse x, up to regions" true
              (Ast_util.strip r.program = Ast_util.strip r'.program));
        Alcotest.test_case ("fmt keeps the comments: " ^ short) `Quick (fun () ->
            let r = parse_ok file text in
            let r' = parse_ok file (fmt r) in
            let texts r = List.map (fun c -> c.Lexer.text) r.Parse.comments in
            Alcotest.(check (list string)) "same comments, same order" (texts r) (texts r'));
      ]) example_files

(* The figures that the paper prints are all there, and say what they should. *)
let figure_facts () =
  let r = parse_ok "fig5" (read_file (Filename.concat examples_dir "paper/fig5_robome_ontology.jade")) in
  let priorities =
    List.concat_map (fun (d : Ast.decl) -> match d.it with
        | Ast.DOntology o ->
          List.map (fun (s : Ast.schema) ->
              (s.it.sname.it,
               List.map (fun ((n : Ast.name), (e : Ast.expr)) -> (n.it, Print.expr e)) s.it.defaults))
            o.schemas
        | _ -> []) r.program.decls in
  Alcotest.(check (list (pair string (list (pair string string)))))
    "Figure 5's percepts and priorities (with on a continuation line)"
    [ ("falling", [("priority", "10")]); ("obstacle", [("priority", "8")]);
      ("qrCodeRead", [("priority", "4")]); ("position", [("priority", "2")]) ]
    priorities

let spellings () =
  (* Jadescript 1.0 spellings parse to the same trees as the paper's. *)
  let a = "one shot behaviour B uses ontology O\n\ton create do\n\t\tactivate behaviour C\n\t\tdo nothing\n" in
  let b = "oneshot behavior B uses ontologies O\n\ton create do\n\t\tactivate C\n\t\tdo nothing\n" in
  let pa = parse_ok "a" a and pb = parse_ok "b" b in
  Alcotest.(check bool) "same tree" true (Ast_util.strip pa.program = Ast_util.strip pb.program);
  let s1 = "cyclic behaviour B\n\ton message inform when true do\n\t\tlog 1\n" in
  let s2 = "cyclic behaviour B\n\ton inform when true do\n\t\tlog 1\n" in
  Alcotest.(check bool) "on message inform = on inform" true
    (Ast_util.strip (parse_ok "1" s1).program = Ast_util.strip (parse_ok "2" s2).program)

let crlf () =
  let unix = "agent A\n\tproperty x = 1\n\n\ton create do\n\t\tlog x\n" in
  let dos = String.concat "\r\n" (String.split_on_char '\n' unix) in
  Alcotest.(check bool) "CRLF line ends parse as LF ones" true
    (Ast_util.strip (parse_ok "u" unix).program = Ast_util.strip (parse_ok "d" dos).program)

let spaces_or_tabs () =
  let tabs = "agent A\n\ton create do\n\t\tlog 1\n" in
  let spaces = "agent A\n    on create do\n        log 1\n" in
  Alcotest.(check bool) "one block structure" true
    (Ast_util.strip (parse_ok "t" tabs).program = Ast_util.strip (parse_ok "s" spaces).program)

let precedence () =
  let e s = Ast_util.strip_expr (Parse.expr ~file:"e" s) in
  let same a b =
    Alcotest.(check string) (a ^ " reads as " ^ b) (Print.expr (e b)) (Print.expr (e a));
    Alcotest.(check bool) (a ^ " = " ^ b) true (e a = e b) in
  same "a or b and c" "a or (b and c)";
  same "a and b = c" "a and (b = c)";
  same "a = b < c" "a = (b < c)";
  same "a < b + c" "a < (b + c)";
  same "a + b * c" "a + (b * c)";
  same "a - b - c" "(a - b) - c";
  same "a * b matches p" "a * (b matches p)";
  same "not a matches p" "(not a) matches p";
  same "- x of y" "-(x of y)";
  same "x of corner of boxes[0]" "x of (corner of (boxes[0]))";
  same "length of l + 1" "(length of l) + 1"

(* ------------------------------------------------------- malformed input *)

(* (name, source, line of the error, fragment of the message) *)
let malformed = [
  "tab and space in one indentation", "agent A\n\t property x = 1\n", 2, "mixes tabs and spaces";
  "spaces after tabs", "agent A\n\tproperty x = 1\n    property y = 2\n", 3, "indented with spaces";
  "tabs after spaces", "agent A\n  property x = 1\n\tproperty y = 2\n", 3, "indented with tabs";
  "dedent to no level", "agent A\n\t\tproperty x = 1\n\tproperty y = 2\n", 3, "does not line up";
  "dedent between levels", "agent A\n    on create do\n        log 1\n      log 2\n", 4, "does not line up";
  "indented first line", "  agent A\n", 1, "first line";
  "unexpected indented line", "agent A\n\tproperty x = 1\n\t\tproperty y = 2\n", 3, "indented";
  "unterminated text", "agent A\n\ton create do\n\t\tlog \"abc\n\t\tlog 1\n", 3, "never closed";
  "text not closed at end of file", "agent A\n\ton create do\n\t\tlog \"abc", 3, "never closed";
  "unknown character", "agent A\n\tproperty x = 1 $ 2\n", 2, "unexpected character '$'";
  "binary garbage", "agent A\n\x00\x01\xff\xfe", 2, "unexpected character";
  "garbage inside a line", "agent A\n\tproperty x = \x07\n", 2, "unexpected character";
  "missing do after when", "cyclic behaviour B\n\ton percept when content matches obstacle\n\t\tlog 1\n", 2, "expected 'do'";
  "missing do after if", "agent A\n\ton create do\n\t\tif x > 1\n\t\t\tlog 1\n", 3, "expected 'do'";
  "missing do after while", "agent A\n\ton create do\n\t\twhile true\n\t\t\tlog 1\n", 3, "expected 'do'";
  "missing do after for", "agent A\n\ton create do\n\t\tfor x in l\n\t\t\tlog 1\n", 3, "expected 'do'";
  "missing do in a procedure", "agent A\n\tprocedure p\n\t\tlog 1\n", 2, "'do'";
  "missing do in on create", "agent A\n\ton create with x as integer\n\t\tlog 1\n", 2, "'do'";
  "missing do after on percept", "cyclic behaviour B\n\ton percept\n\t\tlog 1\n", 2, "'when' or 'do'";
  "unclosed bracket at end of file", "agent A\n\tproperty x = foo(1, 2\n", 2, "never closed";
  "unclosed bracket before next line", "agent A\n\tproperty x = [1, 2\n\tproperty y = 3\n", 2, "not closed";
  "wrong closing bracket", "agent A\n\tproperty x = [1, 2)\n", 2, "does not match";
  "closing bracket with none open", "agent A\n\tproperty x = 1)\n", 2, "closes no open bracket";
  "missing priority value", "ontology O\n\tproposition p extends percept with priority =\n", 2, "expected a value after '='";
  "missing priority value (next line)", "ontology O\n\tproposition p extends percept\n\t\twith priority =\n\tproposition q\n", 3, "expected a value";
  "missing = in priority", "ontology O\n\tproposition p extends percept with priority 4\n", 2, "expected '='";
  "missing slot after with", "ontology O\n\tproposition p extends percept with\n", 2, "expected a slot name";
  "stray operator at end", "agent A\n\tproperty x = 1 +\n\tproperty y = 2\n", 2, "no right operand";
  "stray operator at start", "agent A\n\tproperty x = * 2\n", 2, "expected an expression after '='";
  "doubled operator", "agent A\n\ton create do\n\t\tx = 1 * / 2\n", 3, "no right operand";
  "== for equality", "agent A\n\ton create do\n\t\tif x == 1 do\n\t\t\tlog 1\n", 3, "'=='";
  "missing block after do", "agent A\n\ton create do\n\tproperty x = 1\n", 3, "indented block";
  "block on the same line", "agent A\n\ton create do log 1\n", 2, "end of the line after 'do'";
  "unknown performative", "cyclic behaviour B\n\ton infrom when true do\n\t\tlog 1\n", 2, "not a performative";
  "percept handler in an agent", "agent A\n\ton percept do\n\t\tlog 1\n", 2, "belongs in a behaviour";
  "two action sections", "cyclic behaviour B\n\tdo\n\t\tlog 1\n\tdo\n\t\tlog 2\n", 4, "appears twice";
  "proposition with slots", "ontology O\n\tproposition p(x as integer)\n", 2, "proposition has no slots";
  "two extends clauses", "cyclic behaviour B extends C extends D\n", 1, "more than one 'extends'";
  "for agent on an agent", "agent A for agent B\n", 1, "no 'for agent'";
  "unknown escape", "agent A\n\tproperty x = \"a\\qb\"\n", 2, "unknown escape";
  "decimal without digits", "agent A\n\tproperty x = 1.\n", 2, "digits after";
  "missing type after as", "agent A\n\tproperty x as = 1\n", 2, "expected";
  "map type without key", "agent A\n\tproperty m as map of integer\n", 2, "map of K:V";
  "list type with key", "agent A\n\tproperty m as list of text:integer\n", 2, "list of T";
  "else without do", "agent A\n\ton create do\n\t\tif a do\n\t\t\tlog 1\n\t\telse\n\t\t\tlog 2\n", 5, "'do' or 'if'";
  "assignment to a literal", "agent A\n\ton create do\n\t\t3 = x\n", 3, "cannot assign";
  "integer literal too large", "agent A\n\tproperty x = 99999999999999999999999\n", 2, "too large";
  "one without shot", "one behaviour B\n", 1, "'shot'";
  "statement at top level", "x = 1\n", 1, "expected a declaration";
  "deactivate without this", "cyclic behaviour B\n\tdo\n\t\tdeactivate\n", 3, "'this'";
  "send without to", "cyclic behaviour B\n\tdo\n\t\tsend inform x\n", 3, "'to'";
  "invoke without a method text", "agent A\n\ton create do\n\t\tinvoke stop on x\n", 3, "text literal";
  "chained comparison", "agent A\n\tproperty x = 1 < 2 < 3\n", 2, "do not chain";
  "brackets nested too deep", "agent A\n\tproperty x = " ^ String.make 300 '(' ^ "1\n", 2, "nested more than";
  "matches without a pattern", "cyclic behaviour B\n\ton percept when content matches do\n\t\tlog 1\n", 2, "pattern";
]

let malformed_case (name, src, line, fragment) =
  Alcotest.test_case name `Quick (fun () ->
      match Parse.string ~file:"bad.jade" src with
      | _ -> Alcotest.failf "accepted a malformed program"
      | exception Diag.Failed d ->
        let s = Diag.to_string d in
        Alcotest.(check int) ("line of: " ^ s) line d.at.left.line;
        Alcotest.(check bool) ("message of: " ^ s ^ " mentions: " ^ fragment) true
          (let n = String.length fragment and m = String.length s in
           let rec go i = i + n <= m && (String.sub s i n = fragment || go (i + 1)) in
           go 0);
        Alcotest.(check bool) "one line" false (String.contains s '\n');
        Alcotest.(check bool) "FILE:LINE:COL: error: prefix" true
          (String.length s > 9 && String.sub s 0 9 = "bad.jade:"))

(* ------------------------------------------------------------- fuzzing *)

let mutate rand text =
  let b = Bytes.of_string text in
  let n = Bytes.length b in
  let tokens = [| "("; ")"; "["; "\t"; "\n"; " "; "do"; "\""; "#"; "with"; "="; "\xff"; "\t\t";
                  "matches"; ","; "if "; "else"; "\r"; "-"; "0.5"; "{"; "}" |] in
  let s = Bytes.to_string b in
  let k = 1 + Random.State.int rand 4 in
  let rec go s k =
    if k = 0 || String.length s = 0 then s
    else
      let n = String.length s in
      let i = Random.State.int rand n in
      let s' = match Random.State.int rand 4 with
        | 0 -> String.sub s 0 i ^ String.sub s (i + 1) (n - i - 1)
        | 1 -> String.sub s 0 i ^ String.make 1 (Char.chr (Random.State.int rand 256)) ^ String.sub s i (n - i)
        | 2 -> String.sub s 0 i ^ tokens.(Random.State.int rand (Array.length tokens)) ^ String.sub s i (n - i)
        | _ -> let j = min n (i + Random.State.int rand 20) in String.sub s 0 i ^ String.sub s j (n - j) in
      go s' (k - 1) in
  ignore n;
  go s k

let fuzz () =
  let rand = Random.State.make [| seed |] in
  let texts = List.map read_file example_files in
  let rounds = if Sys.getenv_opt "JSREF_LONG" = Some "1" then 20_000 else 3_000 in
  let accepted = ref 0 and rejected = ref 0 in
  for _ = 1 to rounds do
    let text = List.nth texts (Random.State.int rand (List.length texts)) in
    let m = mutate rand text in
    match Parse.string ~file:"m.jade" m with
    | r ->
      incr accepted;
      (* What parses must also print and parse back to the same tree. *)
      let again = Parse.string ~file:"m.jade" (fmt r) in
      if Ast_util.strip again.program <> Ast_util.strip r.program then
        Alcotest.failf "fmt changed the tree of a mutant:\n%s" m
    | exception Diag.Failed d ->
      incr rejected;
      if d.at.left.line < 1 then Alcotest.failf "unlocated error %s for:\n%s" (Diag.to_string d) m
    | exception e -> Alcotest.failf "exception %s on mutant:\n%s" (Printexc.to_string e) m
  done;
  Alcotest.(check bool) (Printf.sprintf "both outcomes seen (%d accepted, %d rejected)" !accepted !rejected)
    true (!accepted > 0 && !rejected > 0)

(* --------------------------------------------------------- round trips *)

(* Print.text_literal, the one writer of Jadescript text literals (the
   printer, Value.to_literal, the simulation's percepts), read back by the
   lexer: one text token holding the same text (docs/syntax.md, "Texts are
   UTF-8"). *)
let text_literal_round_trip s =
  let l = Syntax.Print.text_literal s in
  let lb = Lexing.from_string l in
  match Syntax.Lexer.token (Syntax.Lexer.create ()) lb with
  | Syntax.Lexer.Tok (Syntax.Parser.TEXT t) when t = s && lb.Lexing.lex_curr_pos = String.length l -> true
  | Syntax.Lexer.Tok (Syntax.Parser.TEXT t) -> QCheck.Test.fail_reportf "%S written %s, read back as %S" s l t
  | _ -> QCheck.Test.fail_reportf "%S written %s: not one text token" s l
  | exception e -> QCheck.Test.fail_reportf "%S written %s: %s" s l (Printexc.to_string e)

let roundtrip p =
  let text = Print.program p in
  match Parse.string ~file:"gen.jade" text with
  | r -> Ast_util.strip r.program = Ast_util.strip p
  | exception Diag.Failed d ->
    QCheck.Test.fail_reportf "%s\n%s" (Diag.to_string d) text

let fmt_idempotent p =
  let text = Print.program p in
  let r = Parse.string ~file:"gen.jade" text in
  fmt r = text

(* ----------------------------------------------------------------- CLI *)

let with_files contents f =
  let paths = List.map (fun (name, text) ->
      let p = Filename.concat (Filename.get_temp_dir_name ()) name in
      let oc = open_out_bin p in output_string oc text; close_out oc; p) contents in
  Fun.protect ~finally:(fun () -> List.iter Sys.remove paths) (fun () -> f paths)

let lines s = List.filter (( <> ) "") (String.split_on_char '\n' s)

let is_diag_line file l =
  let prefix = file ^ ":" in
  String.length l > String.length prefix && String.sub l 0 (String.length prefix) = prefix
  && (try Scanf.sscanf (String.sub l (String.length prefix) (String.length l - String.length prefix))
            "%d:%d: error: %_s@\n" (fun a b -> a > 0 && b > 0) with _ -> false)

let cli_errors () =
  with_files [ ("jsref_bad1.jade", "agent A\n\tproperty x = (1\n");
               ("jsref_good.jade", "agent A\n\tproperty x = 1\n");
               ("jsref_bad2.jade", "agent B\n\ton percept do\n\t\tlog 1\n") ] (fun paths ->
      let cmd = exe ^ " parse " ^ String.concat " " (List.map Filename.quote paths) in
      let (status, out, err) = run_command cmd in
      Alcotest.(check int) "exit status 1" 1 status;
      Alcotest.(check string) "nothing on stdout" "" out;
      let ls = lines err in
      Alcotest.(check int) ("one line per bad file: " ^ err) 2 (List.length ls);
      List.iter2 (fun l file ->
          Alcotest.(check bool) ("FILE:LINE:COL: error: " ^ l) true (is_diag_line file l))
        ls [List.nth paths 0; List.nth paths 2]);
  let (status, _, err) = run_command (exe ^ " parse /nonexistent/x.jade") in
  Alcotest.(check int) "missing file: exit 1" 1 status;
  Alcotest.(check bool) ("missing file reported: " ^ err) true
    (is_diag_line "/nonexistent/x.jade" (String.trim err))

let cli_fmt () =
  with_files [ ("jsref_fmt.jade", "agent   A\n    property x=1+2*3 # c\n") ] (fun paths ->
      let p = List.hd paths in
      let (status, out, _) = run_command (exe ^ " fmt " ^ p) in
      Alcotest.(check int) "fmt exits 0" 0 status;
      Alcotest.(check bool) "comment kept" true (String.length out > 0 && String.contains out '#');
      let (st, _, err) = run_command (exe ^ " fmt --check " ^ p) in
      Alcotest.(check int) "--check on a file to format: exit 1" 1 st;
      Alcotest.(check bool) ("--check says where: " ^ err) true (is_diag_line p (String.trim err));
      let (st, _, _) = run_command (exe ^ " fmt -i " ^ p) in
      Alcotest.(check int) "fmt -i exits 0" 0 st;
      let (st, _, _) = run_command (exe ^ " fmt --check " ^ p) in
      Alcotest.(check int) "--check after fmt -i: exit 0" 0 st;
      Alcotest.(check string) "fmt -i wrote fmt's output" out (read_file p))

let cli_no_backtrace () =
  (* Every mutant, through the real executable: never a backtrace or an
     uncaught exception, always one diagnostic line or success. *)
  let rand = Random.State.make [| seed + 1 |] in
  let text = read_file (Filename.concat examples_dir "paper/robome_completed.jade") in
  let contents = List.init 20 (fun i -> (Printf.sprintf "jsref_mut%d.jade" i, mutate rand text)) in
  with_files contents (fun paths ->
      let (status, _, err) = run_command (exe ^ " parse " ^ String.concat " " paths) in
      Alcotest.(check bool) "exit 0 or 1" true (status = 0 || status = 1);
      List.iter (fun l ->
          Alcotest.(check bool) ("a diagnostic line: " ^ l) true
            (List.exists (fun p -> is_diag_line p l) paths)) (lines err))

(* ---------------------------------------------------------- edges (D27, D28) *)

module Str_has = struct
  let has s sub =
    let n = String.length sub in
    let rec go i = i + n <= String.length s && (String.sub s i n = sub || go (i + 1)) in
    go 0
end

let deep_plus n = "agent A\n\ton create do\n\t\tlog " ^ String.concat " + " (List.init n (fun _ -> "1")) ^ "\n"
let deep_not n =
  "agent A\n\ton create do\n\t\tlog " ^ String.concat "" (List.init n (fun _ -> "not ")) ^ "true\n"
let deep_type n =
  "agent A\n\ton create do\n\t\tx as " ^ String.concat "" (List.init n (fun _ -> "list of "))
  ^ "integer = []\n"

(* the single line of [err], which must be exactly "FILE:LINE:COL: error: ..." *)
let one_error_at ~what file ~line ~col err =
  match lines err with
  | [ l ] ->
    let prefix = Printf.sprintf "%s:%d:%d: error: " file line col in
    Alcotest.(check bool) (what ^ ": located at " ^ prefix ^ " : " ^ l) true
      (String.length l > String.length prefix && String.sub l 0 (String.length prefix) = prefix)
  | ls -> Alcotest.failf "%s: expected one line, got %d: %s" what (List.length ls) err

(* D27: 100k operators, not's and a deep type: every command that reads the
   program says one located line, exit 1, and never overflows the stack. *)
let deep_nesting () =
  let col_not = 7 + 4 * (Nesting.max_depth + 1) in   (* the node at depth 1001 *)
  let col_ty = 8 + 8 * (Nesting.max_depth + 1) in
  List.iter (fun (name, text, col) ->
      with_files [ (name, text) ] (fun paths ->
          let p = List.hd paths in
          List.iter (fun cmd ->
              let (status, _, err) =
                run_command (Printf.sprintf "%s %s %s" exe cmd (Filename.quote p)) in
              Alcotest.(check int) (cmd ^ " " ^ name ^ ": exit 1") 1 status;
              one_error_at ~what:(cmd ^ " " ^ name) p ~line:3 ~col err)
            [ "parse"; "parse --ast"; "check"; "fmt"; "run --agent a:A";
              "compile --out " ^ Filename.quote (Filename.get_temp_dir_name () ^ "/jsref_deep_out") ]))
    [ ("jsref_plus.jade", deep_plus 100_000, 7);
      ("jsref_not.jade", deep_not 100_000, col_not);
      ("jsref_type.jade", deep_type 100_000, col_ty) ];
  (* the limit itself: max_depth levels are accepted, one more is not *)
  let ok text = match Parse.string ~file:"t.jade" text with _ -> true | exception Diag.Failed _ -> false in
  Alcotest.(check bool) "1000 '+' accepted" true (ok (deep_plus (Nesting.max_depth + 1)));
  Alcotest.(check bool) "1001 '+' rejected" false (ok (deep_plus (Nesting.max_depth + 2)));
  Alcotest.(check bool) "1000 'not' accepted" true (ok (deep_not Nesting.max_depth));
  Alcotest.(check bool) "1001 'not' rejected" false (ok (deep_not (Nesting.max_depth + 1)));
  Alcotest.(check bool) "a 1000-deep type accepted" true (ok (deep_type (Nesting.max_depth - 1)));
  Alcotest.(check bool) "a 1002-deep type rejected" false (ok (deep_type (Nesting.max_depth + 1)));
  (* and a literal on the command line (Parse.expr) *)
  Alcotest.(check bool) "Parse.expr bounded" true
    (match Parse.expr ~file:"--agent" (String.concat "" (List.init 2000 (fun _ -> "not ")) ^ "true") with
     | _ -> false | exception Diag.Failed _ -> true)

(* fmt on the deepest accepted input: the same one line back, no parentheses
   added; a long else-if chain keeps its shape. *)
let fmt_deep_shape () =
  let text = deep_plus (Nesting.max_depth + 1) in
  let r = Parse.string ~file:"t.jade" text in
  Alcotest.(check string) "1000 '+': printed as read" text (Print.program r.program);
  let text = deep_not Nesting.max_depth in
  Alcotest.(check string) "1000 'not': printed as read" text
    (Print.program (Parse.string ~file:"t.jade" text).program);
  let n = 3000 in
  let b = Buffer.create 100_000 in
  Buffer.add_string b "agent A\n\ton create do\n\t\tx = 1\n\t\tif x = 0 do\n\t\t\tlog 0\n";
  for i = 1 to n - 1 do Printf.bprintf b "\t\telse if x = %d do\n\t\t\tlog %d\n" i i done;
  Buffer.add_string b "\t\telse do\n\t\t\tlog -1\n";
  let text = Buffer.contents b in
  Alcotest.(check string) "a 3000-branch else-if chain: printed as read" text
    (Print.program (Parse.string ~file:"t.jade" text).program)

(* D28: what cannot be a source file is one located line, exit 1. *)
let bad_sources () =
  let check_one what cmd file =
    let (status, out, err) = run_command (Printf.sprintf "%s %s" exe cmd) in
    Alcotest.(check int) (what ^ ": exit 1") 1 status;
    Alcotest.(check string) (what ^ ": nothing on stdout") "" out;
    one_error_at ~what file ~line:1 ~col:1 err;
    err in
  let err = check_one "/dev/zero" "parse /dev/zero" "/dev/zero" in
  Alcotest.(check bool) ("/dev/zero: too large: " ^ err) true (Str_has.has err "64 MB");
  ignore (check_one "fmt /dev/zero" "fmt /dev/zero" "/dev/zero");
  ignore (check_one "check /dev/zero" "check /dev/zero" "/dev/zero");
  let dir = Filename.get_temp_dir_name () in
  ignore (check_one "a directory" ("parse " ^ dir) dir);
  ignore (check_one "a directory to fmt" ("fmt " ^ dir) dir);
  ignore (check_one "an unreadable file" "parse /proc/self/mem" "/proc/self/mem");
  (* a NUL byte, even in a comment, is a located lexical error *)
  with_files [ ("jsref_nul.jade", "agent A\n\tproperty x = 1  # a\000b\n") ] (fun paths ->
      let p = List.hd paths in
      List.iter (fun cmd ->
          let (status, _, err) = run_command (Printf.sprintf "%s %s %s" exe cmd p) in
          Alcotest.(check int) (cmd ^ " NUL: exit 1") 1 status;
          one_error_at ~what:(cmd ^ " NUL") p ~line:2 ~col:21 err) [ "parse"; "fmt"; "check" ]);
  (* a pipe is read to its end (its size reads as 0) *)
  with_files [ ("jsref_pipe.jade", "agent   A\n") ] (fun paths ->
      let (status, out, _) = run_command (Printf.sprintf "(cat %s | %s fmt /dev/stdin)" (List.hd paths) exe) in
      Alcotest.(check int) "fmt of a pipe: exit 0" 0 status;
      Alcotest.(check string) "fmt of a pipe: its text" "agent A\n" out)

(* Write errors: one line "jadescript-ref: error: ...", exit 1. *)
let write_errors () =
  let small = "agent A\n\tproperty x = 1\n" in
  let big = "agent A\n\ton create do\n" ^ String.concat "" (List.init 50_000 (fun _ -> "\t\tlog 1\n")) in
  with_files [ ("jsref_w1.jade", small); ("jsref_w2.jade", big) ] (fun paths ->
      let q = String.concat " " paths in
      List.iter (fun cmd ->
          let (status, _, err) = run_command (Printf.sprintf "(%s %s > /dev/full)" exe cmd) in
          Alcotest.(check int) (cmd ^ " > /dev/full: exit 1") 1 status;
          (match lines err with
           | [ l ] -> Alcotest.(check bool) ("one error line: " ^ l) true
                        (Str_has.has l "jadescript-ref: error: cannot write the standard output")
           | _ -> Alcotest.failf "%s > /dev/full: expected one line, got: %s" cmd err))
        [ "fmt " ^ List.hd paths; "fmt " ^ q; "parse --ast " ^ q;
          "run " ^ List.nth paths 1 ^ " --agent a:A";
          "explore " ^ Filename.quote (Filename.concat root "spec/models/MCReference.tla") ];
      (* fmt -i on a disk that takes no more (a file size limit): the file is
         left as it was, one located line, and the next file is still done *)
      let ugly = "agent   A\n\ton create do\n" ^ String.concat "" (List.init 300 (fun _ -> "\t\tlog   1\n")) in
      with_files [ ("jsref_w3.jade", "agent   B\n"); ("jsref_w4.jade", ugly) ] (fun small ->
          let big = List.nth small 1 and before = ugly in
          let (status, _, err) = run_command (Printf.sprintf
              "(trap '' XFSZ; ulimit -f 1; %s fmt -i %s %s)" exe big (List.hd small)) in
          Alcotest.(check int) "fmt -i, file too large: exit 1" 1 status;
          one_error_at ~what:"fmt -i, file too large" big ~line:1 ~col:1 err;
          Alcotest.(check string) "fmt -i: the file is left as it was" before (read_file big);
          Alcotest.(check string) "fmt -i: the next file is formatted" "agent B\n" (read_file (List.hd small)));
      Alcotest.(check bool) "fmt -i: no temporary file left" false
        (Array.exists (fun f -> String.length f > 6 && String.sub f 0 6 = ".jsref")
           (Sys.readdir (Filename.get_temp_dir_name ())));
      let (status, _, err) =
        run_command (Printf.sprintf "%s compile %s --out /proc/jsref_no" exe (List.hd paths)) in
      Alcotest.(check int) "compile --out unwritable: exit 1" 1 status;
      (match lines err with
       | [ l ] -> Alcotest.(check bool) ("one error line: " ^ l) true
                    (Str_has.has l "jadescript-ref: error: cannot write the Java sources into /proc/jsref_no")
       | _ -> Alcotest.failf "compile: expected one line, got: %s" err))

(* sim: a scenario out of range, not JSON or not a file, a bad --batch, an
   unwritable --out: one line each, exit 1 (docs/simulation.md, "Ranges"). *)
let sim_errors () =
  let ok = {|{"name": "x", "duration_s": 1, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}}|} in
  with_files [ ("jsref_sc_range.json", {|{"name": "x", "duration_s": 1e12, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}}|});
               ("jsref_sc_syntax.json", "{\"name\": \"x\",\n  \"duration_s\": 5,, }");
               ("jsref_sc_ok.json", ok) ] (fun paths ->
      let run what cmd =
        let (status, _, err) = run_command (Printf.sprintf "(%s sim %s --controller reference)" exe cmd) in
        Alcotest.(check int) (what ^ ": exit 1") 1 status;
        match lines err with
        | [ l ] -> l
        | _ -> Alcotest.failf "%s: expected one line, got: %s" what err in
      let l = run "1e12 s" (List.nth paths 0) in
      Alcotest.(check bool) ("1e12 s: located, names the field: " ^ l) true
        (Str_has.has l (List.nth paths 0 ^ ":1:1: error: duration_s: "));
      let l = run "JSON syntax" (List.nth paths 1) in
      Alcotest.(check bool) ("JSON syntax: its line and column: " ^ l) true
        (Str_has.has l (List.nth paths 1 ^ ":2:"));
      let l = run "/dev/zero" "/dev/zero" in
      Alcotest.(check bool) ("/dev/zero: printable: " ^ l) true
        (String.for_all (fun c -> c >= ' ' && c <= '~') l);
      let l = run "--batch 0" (List.nth paths 2 ^ " --batch 0") in
      Alcotest.(check bool) ("--batch 0: " ^ l) true (Str_has.has l "jadescript-ref: error: --batch 0");
      let l = run "--out unwritable" (List.nth paths 2 ^ " --out /proc/jsref_no/x") in
      Alcotest.(check bool) ("--out: " ^ l) true
        (Str_has.has l "jadescript-ref: error: cannot write the simulation's outputs"))

let () =
  Alcotest.run "syntax" [
    ("examples", example_cases @ [
         Alcotest.test_case "Figure 5 priorities" `Quick figure_facts;
         Alcotest.test_case "Jadescript 1.0 spellings" `Quick spellings;
         Alcotest.test_case "CRLF line ends" `Quick crlf;
         Alcotest.test_case "tabs or spaces" `Quick spaces_or_tabs;
         Alcotest.test_case "precedence table" `Quick precedence ]);
    ("malformed", List.map malformed_case malformed);
    ("fuzz", [ Alcotest.test_case "byte mutations never raise" `Quick fuzz ]);
    ("roundtrip", [
        qcheck ~count:300 "parse (print ast) = ast" Ast_gen.arb_program roundtrip;
        qcheck ~count:200 "fmt (print ast) = print ast" Ast_gen.arb_program fmt_idempotent;
        qcheck ~count:2000 "the lexer reads Print.text_literal back" Support.tricky_text text_literal_round_trip ]);
    ("cli", [
        Alcotest.test_case "errors: one line each, every file" `Quick cli_errors;
        Alcotest.test_case "fmt, --check, -i" `Quick cli_fmt;
        Alcotest.test_case "mutants through the executable" `Quick cli_no_backtrace ]);
    ("edges", [
        Alcotest.test_case "D27 deep nesting: one located line" `Quick deep_nesting;
        Alcotest.test_case "fmt of deep input keeps its shape" `Quick fmt_deep_shape;
        Alcotest.test_case "D28 /dev/zero, directories, NUL, pipes" `Quick bad_sources;
        Alcotest.test_case "write errors are one line" `Quick write_errors;
        Alcotest.test_case "sim: bad scenarios and outputs are one line" `Quick sim_errors ]);
  ]
