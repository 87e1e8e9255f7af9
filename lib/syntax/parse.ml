module I = Parser.MenhirInterpreter

type result = { program : Ast.program; comments : Lexer.comment list }

(* Every terminal, with a dummy payload, to ask the automaton which it accepts. *)
let terminals = Parser.[
  IDENT "x"; INT 0; REAL "0.0"; TEXT ""; TRUE; FALSE; MODULE; ONTOLOGY; ONTOLOGIES;
  EXTENDS; CONCEPT; PREDICATE; PROPOSITION; ACTION; AGENT; USES; BEHAVIOUR;
  CYCLIC; ONE; SHOT; ONESHOT; FOR; PROPERTY; FUNCTION; PROCEDURE; ON; CREATE;
  DESTROY; PERCEPT; MESSAGE; WHEN; DO; AS; WITH; RETURN; BREAK; CONTINUE; IF;
  ELSE; WHILE; IN; NOTHING; INVOKE; ACTIVATE; DEACTIVATE; THIS; SEND; TO; LOG;
  CONTENT; MATCHES; AND; OR; NOT; OF; LPAREN; RPAREN; LBRACKET; RBRACKET; LBRACE;
  RBRACE; COMMA; COLON; DOT; UNDERSCORE; EQ; NEQ; LT; GT; LE; GE; PLUS; MINUS;
  STAR; SLASH; PERCENT; NEWLINE; INDENT; DEDENT; EOF ]

let expected_name = function
  | Parser.IDENT _ -> "a name"
  | Parser.INT _ | Parser.REAL _ -> "a number"
  | tok -> Lexer.describe tok

(* The tokens that can start an expression: when all are acceptable, the
   message says "an expression" instead of listing them. *)
let expression_starts = Parser.[
  IDENT "x"; INT 0; TEXT ""; TRUE; FALSE; THIS; AGENT; CONTENT; MESSAGE; LPAREN;
  LBRACKET; LBRACE; NOT; MINUS ]

(* Likewise the tokens that continue an expression. *)
let operators = Parser.[
  OR; AND; EQ; NEQ; LT; GT; LE; GE; PLUS; MINUS; STAR; SLASH; PERCENT; MATCHES;
  LBRACKET ]

let expected checkpoint pos =
  let ok tok = I.acceptable checkpoint tok pos in
  let acceptable = ref (List.filter ok terminals) and summary = ref [] in
  let summarise group ?(also = []) label =
    if List.for_all ok group then begin
      summary := label :: !summary;
      acceptable := List.filter (fun t -> not (List.mem t group || List.mem t also)) !acceptable
    end in
  summarise expression_starts ~also:[Parser.REAL "0.0"] "an expression";
  summarise [Parser.OR; Parser.AND; Parser.PLUS; Parser.STAR] ~also:operators "an operator";
  List.rev !summary @ (List.map expected_name !acceptable |> List.sort_uniq compare)

let join = function
  | [] -> ""
  | [x] -> x
  | xs ->
    let rev = List.rev xs in
    String.concat ", " (List.rev (List.tl rev)) ^ " or " ^ List.hd rev

let replace_all ~sub ~by s =
  let n = String.length sub in
  let b = Buffer.create (String.length s) in
  let rec go i =
    if i > String.length s - n then Buffer.add_string b (String.sub s i (String.length s - i))
    else if String.sub s i n = sub then (Buffer.add_string b by; go (i + n))
    else (Buffer.add_char b s.[i]; go (i + 1)) in
  go 0;
  Buffer.contents b

(* D28: the largest source file read. Read in chunks up to this size, not by
   the size the file system reports: a pipe or a device such as /dev/zero
   reports 0 and may never end. *)
let max_source_bytes = 64 * 1024 * 1024

let read_all path =
  match open_in_bin path with
  | exception Sys_error msg -> Error msg
  | ic ->
    Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
        let b = Buffer.create 65536 and chunk = Bytes.create 65536 in
        let rec go () =
          if Buffer.length b > max_source_bytes then
            Error (Printf.sprintf "the file is larger than %d MB, the most a source \
                                   file may hold (D28)" (max_source_bytes / 1024 / 1024))
          else match input ic chunk 0 (Bytes.length chunk) with
            | 0 -> Ok (Buffer.contents b)
            | n -> Buffer.add_subbytes b chunk 0 n; go () in
        match go () with
        | r -> r
        | exception Sys_error msg -> Error msg)

(* A NUL byte is a lexical error wherever it stands, comments included (D28):
   a source file is text. *)
let check_no_nul ~file text =
  match String.index_opt text '\000' with
  | None -> ()
  | Some i ->
    let line = ref 1 and bol = ref 0 in
    for j = 0 to i - 1 do
      if text.[j] = '\n' then (incr line; bol := j + 1)
    done;
    let p = { Source.file; line = !line; column = i - !bol + 1 } in
    Diag.error Diag.Syntax { Source.left = p; right = p }
      "unexpected character '\\x00' (a NUL byte): a Jadescript file is text"

let message checkpoint env (tok, s, _) =
  let found = Lexer.describe tok in
  match Parser_messages.message (I.current_state_number env) with
  | m ->
    let m = String.trim m in
    (* "$found" in a hand-written message names the offending token. *)
    replace_all ~sub:"$found" ~by:found m
  | exception Not_found ->
    let exp = expected checkpoint s in
    if exp = [] || List.length exp > 7 then Printf.sprintf "%s is not expected here" found
    else Printf.sprintf "expected %s, found %s" (join exp) found

let run entry ~file text =
  let lexbuf = Lexing.from_string text in
  Lexing.set_filename lexbuf file;
  let lexer = Lexer.create () in
  let layout = Layout.create lexer lexbuf in
  let rec loop last_input checkpoint =
    match checkpoint with
    | I.InputNeeded _ ->
      let token = Layout.next layout in
      loop (Some (checkpoint, token)) (I.offer checkpoint token)
    | I.Shifting _ | I.AboutToReduce _ -> loop last_input (I.resume checkpoint)
    | I.HandlingError env ->
      (match last_input with
       | Some (cp, ((_, s, e) as token)) ->
         (match Layout.open_bracket layout with
          | Some (b, bs, be) when bs.Lexing.pos_lnum < s.Lexing.pos_lnum ->
            (* The error is on a later line than an open bracket: the likely
               mistake is the bracket, so point at it. *)
            Diag.errorf Diag.Syntax (Source.region_of_lexing bs be)
              "this %s is not closed, so line %d is read as part of it (there: %s)"
              (Lexer.describe b) s.Lexing.pos_lnum (message cp env token)
          | _ ->
            Diag.error Diag.Syntax (Source.region_of_lexing s e) (message cp env token))
       | None -> Diag.error Diag.Syntax Source.no_region "syntax error")
    | I.Accepted v -> v
    | I.Rejected -> Diag.error Diag.Syntax Source.no_region "syntax error" in
  let v = loop None (entry lexbuf.Lexing.lex_curr_p) in
  (v, List.rev lexer.Lexer.comments)

let string ~file text =
  check_no_nul ~file text;
  let (program, comments) = run Parser.Incremental.program ~file text in
  Nesting.check_program program;   (* D27 *)
  { program; comments }

let expr ~file text =
  let e = fst (run Parser.Incremental.expr_only ~file text) in
  Nesting.check_expr e;   (* D27 *)
  e

let file path =
  let start = { Source.file = path; line = 1; column = 1 } in
  let at = { Source.left = start; right = start } in
  match read_all path with
  | Ok text -> string ~file:path text
  | Error msg -> Diag.errorf Diag.Syntax at "cannot read this file: %s" msg
