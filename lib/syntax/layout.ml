open Parser

type tok = Parser.token * Lexing.position * Lexing.position

type t = {
  lexer : Lexer.state;
  lexbuf : Lexing.lexbuf;
  pending : tok Queue.t;                  (* tokens decided but not yet returned *)
  mutable levels : int list;              (* indentation widths, innermost first *)
  mutable brackets : tok list;            (* open brackets, innermost first *)
  mutable indent_char : (char * int) option;  (* the file's indentation, and where seen *)
  mutable last : Parser.token option;     (* the last real token returned *)
  mutable last_end : Lexing.position;
  mutable started : bool;
  mutable finished : bool;
}

let max_depth = 200

let create lexer lexbuf = {
  lexer; lexbuf; pending = Queue.create (); levels = [0]; brackets = [];
  indent_char = None; last = None; last_end = lexbuf.Lexing.lex_curr_p;
  started = false; finished = false;
}

let error s e fmt = Diag.errorf Diag.Syntax (Source.region_of_lexing s e) fmt

(* A line that ends with one of these continues on the next, deeper line. *)
let trailing_joiner = function
  | WITH | COMMA | EQ | NEQ | LT | GT | LE | GE | PLUS | MINUS | STAR | SLASH
  | PERCENT | AND | OR | NOT | OF | MATCHES | AS | TO -> true
  | _ -> false

(* A deeper line that starts with one of these continues the line before. *)
let leading_joiner = function
  | WITH | USES | EXTENDS | AND | OR -> true
  | _ -> false

let closing_of = function
  | LPAREN -> Some RPAREN | LBRACKET -> Some RBRACKET | LBRACE -> Some RBRACE
  | _ -> None

let raw t =
  let r =
    if t.started then Lexer.token t.lexer t.lexbuf
    else (t.started <- true; Lexer.line_start t.lexer t.lexbuf) in
  (r, Lexing.lexeme_start_p t.lexbuf, Lexing.lexeme_end_p t.lexbuf)

(* Bracket bookkeeping for a real token; then queue it. *)
let push_token t ((tok, s, e) as x) =
  (match tok with
   | LPAREN | LBRACKET | LBRACE ->
     if List.length t.brackets >= max_depth then
       error s e "brackets are nested more than %d deep" max_depth;
     t.brackets <- x :: t.brackets
   | RPAREN | RBRACKET | RBRACE ->
     (match t.brackets with
      | [] -> error s e "%s closes no open bracket" (Lexer.describe tok)
      | (o, os, _) :: rest ->
        if closing_of o <> Some tok then
          error s e "%s does not match the %s opened at line %d, column %d"
            (Lexer.describe tok) (Lexer.describe o) os.pos_lnum
            (os.pos_cnum - os.pos_bol + 1);
        t.brackets <- rest)
   | _ -> ());
  t.last <- Some tok;
  t.last_end <- e;
  Queue.push x t.pending

let check_indent_chars t ws (s : Lexing.position) =
  if ws <> "" then begin
    let e = { s with pos_cnum = s.pos_cnum + String.length ws } in
    let has c = String.contains ws c in
    if has ' ' && has '\t' then
      error s e "this line's indentation mixes tabs and spaces (use one or the other)";
    let c = ws.[0] in
    match t.indent_char with
    | None -> t.indent_char <- Some (c, s.pos_lnum)
    | Some (c0, line) when c0 <> c ->
      let name = function '\t' -> "tabs" | _ -> "spaces" in
      error s e "this line is indented with %s, but this file indents with %s \
                 (since line %d)" (name c) (name c0) line
    | Some _ -> ()
  end

let layout_tok t tok (p : Lexing.position) = Queue.push (tok, p, p) t.pending

let rec fill t =
  match raw t with
  | (Lexer.Tok tok, s, e) -> push_token t (tok, s, e)
  | (Lexer.Newline _, _, _) when t.brackets <> [] -> fill t
  | (Lexer.Newline ws, line_s, _) ->
    check_indent_chars t ws line_s;
    let width = String.length ws in
    let top = List.hd t.levels in
    (match t.last with
     | None ->
       if width > 0 then
         error line_s { line_s with pos_cnum = line_s.pos_cnum + width }
           "unexpected indentation: the first line of a file starts at column 1";
       fill t
     | Some last when width > top && trailing_joiner last -> fill t
     | Some _ ->
       (match raw t with
        | (Lexer.Tok tok, s, e) when width > top && leading_joiner tok ->
          push_token t (tok, s, e)
        | (Lexer.Tok tok, s, e) ->
          layout_tok t NEWLINE t.last_end;
          if width > top then begin
            if List.length t.levels > max_depth then
              error s e "blocks are nested more than %d deep" max_depth;
            t.levels <- width :: t.levels;
            layout_tok t INDENT s
          end else if width < top then begin
            let rec close = function
              | l :: rest when l > width -> layout_tok t DEDENT s; close rest
              | l :: _ as levels when l = width -> levels
              | _ ->
                error line_s s
                  "this line's indentation (%d) does not line up with any \
                   enclosing block" width in
            t.levels <- close t.levels
          end;
          push_token t (tok, s, e)
        | (_, s, e) -> error s e "internal: a code line without a token"))
  | (Lexer.End, s, _) ->
    (match t.brackets with
     | (o, os, oe) :: _ ->
       error os oe "this %s is never closed" (Lexer.describe o)
     | [] -> ());
    if not t.finished then begin
      t.finished <- true;
      (match t.last with
       | None -> ()
       | Some _ -> layout_tok t NEWLINE t.last_end);
      List.iter (fun l -> if l > 0 then layout_tok t DEDENT s) t.levels;
      t.levels <- [0]
    end;
    layout_tok t EOF s

let next t =
  if Queue.is_empty t.pending then fill t;
  Queue.pop t.pending

let open_bracket t = match t.brackets with b :: _ -> Some b | [] -> None
