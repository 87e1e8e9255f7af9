{
open Parser

type comment = { region : Source.region; text : string }
type state = { mutable comments : comment list }
type raw = Tok of Parser.token | Newline of string | End

let create () = { comments = [] }

let region lexbuf =
  Source.region_of_lexing (Lexing.lexeme_start_p lexbuf) (Lexing.lexeme_end_p lexbuf)

let error lexbuf fmt = Diag.errorf Diag.Syntax (region lexbuf) fmt

(* Every occurrence of a name is one string: the interpreter then compares
   names by address first (schema names of values against patterns, say).
   The table holds its names weakly, so a long-lived host that parses many
   programs does not keep every name it ever saw. *)
module Names = Weak.Make (struct
    type t = string
    let equal = String.equal
    let hash = Strtbl.hash
  end)
let names = Names.create 256
let intern id = Names.merge names id

let keywords = [
  "module", MODULE; "ontology", ONTOLOGY; "ontologies", ONTOLOGIES;
  "extends", EXTENDS; "concept", CONCEPT; "predicate", PREDICATE;
  "proposition", PROPOSITION; "action", ACTION; "agent", AGENT; "uses", USES;
  "behaviour", BEHAVIOUR; "behavior", BEHAVIOUR; "cyclic", CYCLIC; "one", ONE;
  "shot", SHOT; "oneshot", ONESHOT; "for", FOR; "property", PROPERTY;
  "function", FUNCTION; "procedure", PROCEDURE; "on", ON; "create", CREATE;
  "destroy", DESTROY; "percept", PERCEPT; "message", MESSAGE; "when", WHEN;
  "do", DO; "as", AS; "with", WITH; "return", RETURN; "break", BREAK;
  "continue", CONTINUE; "if", IF; "else", ELSE; "while", WHILE; "in", IN;
  "nothing", NOTHING; "invoke", INVOKE; "activate", ACTIVATE;
  "deactivate", DEACTIVATE; "this", THIS; "send", SEND; "to", TO; "log", LOG;
  "content", CONTENT; "matches", MATCHES; "and", AND; "or", OR; "not", NOT;
  "of", OF; "true", TRUE; "false", FALSE;
]

let keyword_table =
  let t = Hashtbl.create 64 in
  List.iter (fun (k, v) -> Hashtbl.replace t k v) keywords;
  t

let keyword_of_string s = Hashtbl.find_opt keyword_table s

let describe = function
  | IDENT s -> Printf.sprintf "the name '%s'" s
  | INT i -> Printf.sprintf "the number %d" i
  | REAL r -> Printf.sprintf "the number %s" r
  | TEXT _ -> "a text literal"
  | NEWLINE -> "the end of the line"
  | INDENT -> "an indented line"
  | DEDENT -> "the end of the block"
  | EOF -> "the end of the file"
  | LPAREN -> "'('" | RPAREN -> "')'" | LBRACKET -> "'['" | RBRACKET -> "']'"
  | LBRACE -> "'{'" | RBRACE -> "'}'" | COMMA -> "','" | COLON -> "':'"
  | DOT -> "'.'" | UNDERSCORE -> "'_'" | EQ -> "'='" | NEQ -> "'!='"
  | LT -> "'<'" | GT -> "'>'" | LE -> "'<='" | GE -> "'>='" | PLUS -> "'+'"
  | MINUS -> "'-'" | STAR -> "'*'" | SLASH -> "'/'" | PERCENT -> "'%'"
  | tok ->
    (match List.find_opt (fun (_, t) -> t = tok) keywords with
     | Some (k, _) -> Printf.sprintf "'%s'" k
     | None -> "a token")

let printable c =
  if c >= ' ' && c <= '~' then Printf.sprintf "'%c'" c
  else Printf.sprintf "'\\x%02X'" (Char.code c)

(* The offset of the first byte of [s] that does not begin a well-formed
   UTF-8 character (RFC 3629: no overlong forms, no surrogates, nothing
   above U+10FFFF), if any. Text values are valid UTF-8, so that every
   trace is JSON (docs/syntax.md, "Text literals"). *)
let add_comment st lexbuf text =
  st.comments <- { region = region lexbuf; text } :: st.comments
}

let digit = ['0'-'9']
let alpha = ['a'-'z' 'A'-'Z' '_']
let ident = alpha (alpha | digit)*
let exponent = ['e' 'E'] ['+' '-']? digit+
let blank = [' ' '\t']

rule token st = parse
  | blank+ { token st lexbuf }
  | '\r'? '\n' { Lexing.new_line lexbuf; line_start st lexbuf }
  | '#' [^ '\n' '\r']* as c { add_comment st lexbuf c; token st lexbuf }
  | digit+ as i
      { match int_of_string_opt i with
        | Some n -> Tok (INT n)
        | _ -> error lexbuf "integer literal %s is too large" i }
  | (digit+ '.' digit+ exponent? | digit+ exponent) as r { Tok (REAL r) }
  | digit+ '.' { error lexbuf "a decimal number needs digits after the '.'" }
  | '"' { let start = Lexing.lexeme_start_p lexbuf in
          let s = text st start (Buffer.create 16) lexbuf in
          lexbuf.Lexing.lex_start_p <- start;
          Tok (TEXT s) }
  | '_' { Tok UNDERSCORE }
  | ident as id
      { match keyword_of_string id with Some k -> Tok k | None -> Tok (IDENT (intern id)) }
  | "!=" { Tok NEQ } | "<=" { Tok LE } | ">=" { Tok GE }
  | "==" { error lexbuf "'==' is not Jadescript: equality is written '='" }
  | '<' { Tok LT } | '>' { Tok GT } | '=' { Tok EQ }
  | '+' { Tok PLUS } | '-' { Tok MINUS } | '*' { Tok STAR } | '/' { Tok SLASH }
  | '%' { Tok PERCENT }
  | '(' { Tok LPAREN } | ')' { Tok RPAREN } | '[' { Tok LBRACKET }
  | ']' { Tok RBRACKET } | '{' { Tok LBRACE } | '}' { Tok RBRACE }
  | ',' { Tok COMMA } | ':' { Tok COLON } | '.' { Tok DOT }
  | eof { End }
  | _ as c { error lexbuf "unexpected character %s" (printable c) }

and line_start st = parse
  | blank* '\r'? '\n' { Lexing.new_line lexbuf; line_start st lexbuf }
  | blank* ('#' [^ '\n' '\r']* as c)
      { st.comments <-
          { region = Source.region_of_lexing
                (let p = Lexing.lexeme_end_p lexbuf in
                 { p with pos_cnum = p.pos_cnum - String.length c })
                (Lexing.lexeme_end_p lexbuf);
            text = c } :: st.comments;
        line_start st lexbuf }
  | blank* eof { End }
  | blank* as ws { Newline ws }

and text st start buf = parse
  | '"' { Buffer.contents buf }
  | '\\' '"' { Buffer.add_char buf '"'; text st start buf lexbuf }
  | '\\' '\\' { Buffer.add_char buf '\\'; text st start buf lexbuf }
  | '\\' 'n' { Buffer.add_char buf '\n'; text st start buf lexbuf }
  | '\\' 't' { Buffer.add_char buf '\t'; text st start buf lexbuf }
  | '\\' 'r' { Buffer.add_char buf '\r'; text st start buf lexbuf }
  | '\\' '\'' { Buffer.add_char buf '\''; text st start buf lexbuf }
  | '\\' 'u' (['0'-'9' 'a'-'f' 'A'-'F'] ['0'-'9' 'a'-'f' 'A'-'F']
              ['0'-'9' 'a'-'f' 'A'-'F'] ['0'-'9' 'a'-'f' 'A'-'F'] as h)
      { let code = int_of_string ("0x" ^ h) in
        if code >= 0xD800 && code <= 0xDFFF then
          error lexbuf "\\u%s is a surrogate, not a character" h;
        Buffer.add_utf_8_uchar buf (Uchar.of_int code);
        text st start buf lexbuf }
  | '\\' (_ as c)
      { error lexbuf "unknown escape '\\%c' in text (known: \\\" \\\\ \\n \\t \\r \\' \\uXXXX)" c }
  | '\\' eof | '\r'? '\n' | eof
      { Diag.error Diag.Syntax
          (Source.region_of_lexing start (Lexing.lexeme_start_p lexbuf))
          "this text literal is never closed: a '\"' is missing before the end of the line" }
  | ['\000'-'\008' '\011'-'\031' '\127'] as c
      { error lexbuf "control character %s inside a text literal" (printable c) }
  | [^ '"' '\\' '\n' '\r' '\000'-'\008' '\011'-'\031' '\127']+ as s
      { (match Utf8.first_invalid s with
         | Some k ->
           let p = Lexing.lexeme_start_p lexbuf in
           let p = { p with pos_cnum = p.pos_cnum + k } in
           Diag.errorf Diag.Syntax (Source.region_of_lexing p { p with pos_cnum = p.pos_cnum + 1 })
             "byte 0x%02X in a text literal is not UTF-8: texts are UTF-8 (docs/syntax.md)" (Char.code s.[k])
         | None -> ());
        Buffer.add_string buf s; text st start buf lexbuf }
