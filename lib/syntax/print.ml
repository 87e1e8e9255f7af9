open Ast
open Source

(* ------------------------------------------------------------- literals *)

let text_literal s =
  let b = Buffer.create (String.length s + 2) in
  Buffer.add_char b '"';
  String.iter (function
      | '"' -> Buffer.add_string b "\\\""
      | '\\' -> Buffer.add_string b "\\\\"
      | '\n' -> Buffer.add_string b "\\n"
      | '\t' -> Buffer.add_string b "\\t"
      | '\r' -> Buffer.add_string b "\\r"
      | c when c < ' ' || c = '\127' -> Printf.bprintf b "\\u%04X" (Char.code c)
      | c -> Buffer.add_char b c) s;
  Buffer.add_char b '"';
  Buffer.contents b

let literal = function
  | Int i -> string_of_int i
  | Real r -> r
  | Text s -> text_literal s
  | Bool b -> if b then "true" else "false"

(* ---------------------------------------------------------------- types *)

let rec ty (t : Ast.ty) = match t.it with
  | TName x -> x
  | TList e -> "list of " ^ ty e
  | TMap (k, v) -> "map of " ^ key_ty k ^ ":" ^ ty v

and key_ty (t : Ast.ty) = match t.it with
  | TName x -> x
  | _ -> "(" ^ ty t ^ ")"

(* ---------------------------------------------------------- expressions *)

(* Precedence levels, loosest first, as in parser.mly and docs/syntax.md. *)
let l_or = 1 and l_and = 2 and l_eq = 3 and l_rel = 4 and l_add = 5 and l_mul = 6
and l_matches = 7 and l_unary = 8 and l_of = 9 and l_postfix = 10 and l_primary = 11

let binop_info = function
  | Or -> ("or", l_or, `Left) | And -> ("and", l_and, `Left)
  | Eq -> ("=", l_eq, `None) | Neq -> ("!=", l_eq, `None)
  | Lt -> ("<", l_rel, `None) | Gt -> (">", l_rel, `None)
  | Le -> ("<=", l_rel, `None) | Ge -> (">=", l_rel, `None)
  | Add -> ("+", l_add, `Left) | Sub -> ("-", l_add, `Left)
  | Mul -> ("*", l_mul, `Left) | Div -> ("/", l_mul, `Left) | Mod -> ("%", l_mul, `Left)

(* Patterns and expressions are written into one buffer, so that printing is
   linear in the size of the tree: concatenating the strings of the operands
   at every level would copy a long left-nested chain once per level. *)
let rec pattern_to b (p : Ast.pattern) = match p.it with
  | PWild -> Buffer.add_char b '_'
  | PLit l -> Buffer.add_string b (literal l)
  | PName x -> Buffer.add_string b x
  | PCons (f, ps) ->
    Buffer.add_string b f.it; Buffer.add_char b '(';
    List.iteri (fun i q -> if i > 0 then Buffer.add_string b ", "; pattern_to b q) ps;
    Buffer.add_char b ')'

let own_level (e : Ast.expr) = match e.it with
  | Lit _ | Name _ | This | Agent | Content | Message | List _ | Map _ | Call _ -> l_primary
  | Index _ -> l_postfix
  | Of _ -> l_of
  | Matches _ -> l_matches
  | Unop _ -> l_unary
  | Binop (op, _, _) -> let (_, lv, _) = binop_info op in lv
  | Invoke _ -> 0

let rec expr_to b level (e : Ast.expr) =
  let paren = own_level e < level in
  if paren then Buffer.add_char b '(';
  let str = Buffer.add_string b in
  (match e.it with
   | Lit l -> str (literal l)
   | Name x -> str x
   | This -> str "this"
   | Agent -> str "agent"
   | Content -> str "content"
   | Message -> str "message"
   | List es -> str "["; exprs_to b es; str "]"
   | Map kvs ->
     str "{";
     List.iteri (fun i (k, v) ->
         if i > 0 then str ", ";
         expr_to b 0 k; str ": "; expr_to b 0 v) kvs;
     str "}"
   | Call (f, args) -> str f.it; str "("; exprs_to b args; str ")"
   | Index (m, k) -> expr_to b l_postfix m; str "["; expr_to b 0 k; str "]"
   | Of (p, e') -> str p.it; str " of "; expr_to b l_of e'
   | Matches (e', p) -> expr_to b l_unary e'; str " matches "; pattern_to b p
   | Unop (Not, e') -> str "not "; expr_to b l_unary e'
   | Unop (Neg, e') -> str "-"; expr_to b l_unary e'
   | Binop (op, l, r) ->
     let (sym, lv, assoc) = binop_info op in
     let ll, rl = match assoc with `Left -> (lv, lv + 1) | `None -> (lv + 1, lv + 1) in
     expr_to b ll l; str " "; str sym; str " "; expr_to b rl r
   | Invoke i -> invoke_to b i);
  if paren then Buffer.add_char b ')'

and exprs_to b es =
  List.iteri (fun i e -> if i > 0 then Buffer.add_string b ", "; expr_to b 0 e) es

and invoke_to b i =
  Buffer.add_string b "invoke "; Buffer.add_string b (text_literal i.meth.it);
  Buffer.add_string b " on "; expr_to b 0 i.target;
  if i.args <> [] then (Buffer.add_string b " with "; exprs_to b i.args)

let to_string f x = let b = Buffer.create 64 in f b x; Buffer.contents b
let pattern p = to_string pattern_to p
let expr_at level e = to_string (fun b -> expr_to b level) e
let expr e = expr_at 0 e
let exprs es = to_string exprs_to es
let invoke i = to_string invoke_to i

(* A positional argument that reads "x = e" would parse as a named one. *)
let positional_arg e =
  let s = expr e in
  let n = String.length s in
  let rec ident_end i = if i < n && (match s.[i] with
      | 'a'..'z' | 'A'..'Z' | '0'..'9' | '_' -> true | _ -> false) then ident_end (i + 1) else i in
  let i = ident_end 0 in
  if i > 0 && i + 2 < n && String.sub s i 3 = " = " then "(" ^ s ^ ")" else s

let lvalue (l : Ast.lvalue) = match l.it with
  | LName x -> x
  | LOf (p, e) -> p.it ^ " of " ^ expr_at l_of e
  | LIndex (m, k) -> expr_at l_postfix m ^ "[" ^ expr k ^ "]"

let named (n, e) = n.it ^ " = " ^ expr e
let params ps = String.concat ", " (List.map (fun p -> p.pname.it ^ " as " ^ ty p.pty) ps)

(* ------------------------------------------------------------- comments *)

type printer = {
  buf : Buffer.t;
  mutable pending : Lexer.comment list;   (* not yet printed, in source order *)
  mutable last_line : int;                (* source line of the last output line; 0: none *)
}

let line_of (r : Source.region) = r.Source.left.line
let col_of (r : Source.region) = r.Source.left.column

let indent p n = for _ = 1 to n do Buffer.add_char p.buf '\t' done

let blank p =
  let b = p.buf in
  let n = Buffer.length b in
  if n > 0 && not (n >= 2 && Buffer.nth b (n - 1) = '\n' && Buffer.nth b (n - 2) = '\n') then
    Buffer.add_char b '\n'

(* Before an output line from source lines [first..last]: keep one blank line
   where the source had at least one. *)
let track ?(keep_blank = true) p first last =
  if first > 0 then begin
    if keep_blank && p.last_line > 0 && first > p.last_line + 1 then blank p;
    p.last_line <- last
  end

let comment_line p depth (c : Lexer.comment) =
  track p (line_of c.region) (line_of c.region);
  indent p depth; Buffer.add_string p.buf c.text; Buffer.add_char p.buf '\n'

(* Own-line comments that come before source line [line]. *)
let comments_before p depth line =
  let rec go () = match p.pending with
    | c :: rest when line_of c.Lexer.region < line ->
      p.pending <- rest; comment_line p depth c; go ()
    | _ -> () in
  if line > 0 then go ()

(* At the end of a block: comments before [bound] indented past the header. *)
let comments_closing p depth ~header_col ~bound =
  let rec go () = match p.pending with
    | c :: rest when line_of c.Lexer.region < bound && col_of c.region > header_col ->
      p.pending <- rest; comment_line p depth c; go ()
    | _ -> () in
  go ()

(* A line of code, with the comments that stood on the lines of [at]. *)
let line ?keep_blank p depth (at : Source.region) s =
  track ?keep_blank p at.left.line at.right.line;
  indent p depth;
  Buffer.add_string p.buf s;
  let rec trailing () = match p.pending with
    | c :: rest when at.left.line > 0 && line_of c.Lexer.region <= at.right.line ->
      Buffer.add_string p.buf "  "; Buffer.add_string p.buf c.text;
      p.pending <- rest; trailing ()
    | _ -> () in
  trailing ();
  Buffer.add_char p.buf '\n'

(* [head with a1, a2, ...]: on one line when it fits in [width] columns (a tab
   counts 4), else one argument per continuation line, as in Figure 2. *)
let width = 80

let with_args depth head args =
  let one = head ^ " with " ^ String.concat ", " args in
  if 4 * depth + String.length one <= width || List.length args < 2 then one
  else
    let sep = "\n" ^ String.make (depth + 1) '\t' in
    head ^ " with" ^ sep ^ String.concat ("," ^ sep) args

(* The first source line of what a block holds, to bound closing comments. *)
let stmt_line (s : stmt) = line_of s.at
let block_start = function s :: _ -> stmt_line s | [] -> max_int

(* --------------------------------------------------------- statements *)

let rec block p depth ~header ~bound (ss : block) =
  let rec go = function
    | [] -> ()
    | s :: rest ->
      stmt p depth ~bound:(match rest with r :: _ -> stmt_line r | [] -> bound) s;
      go rest in
  go ss;
  comments_closing p depth ~header_col:(col_of header) ~bound

and stmt p depth ~bound (s : stmt) =
  comments_before p depth (line_of s.at);
  let simple str = line p depth s.at str in
  match s.it with
  | Assign (l, e) -> simple (lvalue l ^ " = " ^ expr e)
  | Local (x, t, e) -> simple (x.it ^ " as " ^ ty t ^ " = " ^ expr e)
  | Do (f, Positional []) -> simple ("do " ^ f.it)
  | Do (f, Positional args) ->
    simple (with_args depth ("do " ^ f.it) (List.map positional_arg args))
  | Do (f, Named args) -> simple (with_args depth ("do " ^ f.it) (List.map named args))
  | Nothing -> simple "do nothing"
  | InvokeS i -> simple (invoke i)
  | Activate (b, []) -> simple ("activate behaviour " ^ b.it)
  | Activate (b, args) ->
    simple (with_args depth ("activate behaviour " ^ b.it) (List.map named args))
  | Deactivate -> simple "deactivate this"
  | Send (perf, c, rs) -> simple ("send " ^ perf.it ^ " " ^ expr c ^ " to " ^ exprs rs)
  | Log e -> simple ("log " ^ expr e)
  | Return None -> simple "return"
  | Return (Some e) -> simple ("return " ^ expr e)
  | Break -> simple "break"
  | Continue -> simple "continue"
  | While (c, b) ->
    line p depth s.at ("while " ^ expr c ^ " do");
    block p (depth + 1) ~header:s.at ~bound b
  | For (x, e, b) ->
    line p depth s.at ("for " ^ x.it ^ " in " ^ expr e ^ " do");
    block p (depth + 1) ~header:s.at ~bound b
  | If (branches, els) ->
    (* Walked with the rest of the chain at hand (not List.nth), so that a
       long else-if chain prints in linear time. *)
    let rec branch first = function
      | [] -> ()
      | (c, b) :: rest ->
        let kw = if first then "if " else "else if " in
        (* An "else if" line is located by its condition; no blank line before it. *)
        (if first then line p depth s.at (kw ^ expr c ^ " do")
         else line ~keep_blank:false p depth c.at (kw ^ expr c ^ " do"));
        let next = match rest, els with
          | (_, b') :: _, _ -> block_start b'
          | [], Some e -> block_start e
          | [], None -> bound in
        block p (depth + 1) ~header:s.at ~bound:next b;
        branch false rest in
    branch true branches;
    (match els with
     | None -> ()
     | Some b ->
       line p depth Source.no_region "else do";
       (* "else do" has no region: count it as the line before its block. *)
       if block_start b <> max_int then p.last_line <- block_start b - 1;
       block p (depth + 1) ~header:s.at ~bound b)

(* ----------------------------------------------------------- features *)

let has_block (f : feature) = match f.it with Property _ -> false | _ -> true

let feature p depth ~bound (f : feature) =
  comments_before p depth (line_of f.at);
  let header s b =
    line p depth f.at s;
    block p (depth + 1) ~header:f.at ~bound b in
  let guard = function None -> "" | Some g -> " when " ^ expr g in
  match f.it with
  | Property { name; ty = t; init } ->
    let t = match t with None -> "" | Some t -> " as " ^ ty t in
    let i = match init with None -> "" | Some e -> " = " ^ expr e in
    line p depth f.at ("property " ^ name.it ^ t ^ i)
  | Function { name; params = ps; ret; body } ->
    header ("function " ^ name.it ^ "(" ^ params ps ^ ") as " ^ ty ret ^ " do") body
  | Procedure { name; params = []; body } -> header ("procedure " ^ name.it ^ " do") body
  | Procedure { name; params = ps; body } ->
    header ("procedure " ^ name.it ^ " with " ^ params ps ^ " do") body
  | OnCreate { params = []; body } -> header "on create do" body
  | OnCreate { params = ps; body } -> header ("on create with " ^ params ps ^ " do") body
  | OnDestroy body -> header "on destroy do" body
  | ActionSection body -> header "do" body
  | OnPercept { guard = g; body } -> header ("on percept" ^ guard g ^ " do") body
  | OnMessage { perf = None; guard = g; body } -> header ("on message" ^ guard g ^ " do") body
  | OnMessage { perf = Some pf; guard = g; body } ->
    header ("on " ^ pf.it ^ guard g ^ " do") body

let features p depth ~header ~bound fs =
  let rec go prev = function
    | [] -> ()
    | f :: rest ->
      (match prev with
       | Some pf when has_block pf || has_block f -> blank p
       | _ -> ());
      feature p depth ~bound:(match rest with r :: _ -> line_of r.at | [] -> bound) f;
      go (Some f) rest in
  go None fs;
  comments_closing p depth ~header_col:(col_of header) ~bound

(* -------------------------------------------------------- declarations *)

let schema_kind = function
  | Concept -> "concept" | Predicate -> "predicate"
  | Proposition -> "proposition" | Action -> "action"

let schema p depth (s : schema) =
  comments_before p depth (line_of s.at);
  let sc = s.it in
  let slots = if sc.slots = [] then "" else
      "(" ^ String.concat ", " (List.map (fun sl -> sl.slot_name.it ^ " as " ^ ty sl.slot_ty) sc.slots) ^ ")" in
  let sup = match sc.super with
    | None -> ""
    | Some n ->
      " extends " ^ n.it
      ^ (if sc.defaults = [] then "" else " with " ^ String.concat ", " (List.map named sc.defaults)) in
  line p depth s.at (schema_kind sc.kind ^ " " ^ sc.sname.it ^ slots ^ sup)

let uses = function
  | [] -> ""
  | [o] -> " uses ontology " ^ o.it
  | os -> " uses ontologies " ^ String.concat ", " (List.map (fun o -> o.it) os)

let decl p ~bound (d : decl) =
  comments_before p 0 (line_of d.at);
  match d.it with
  | DOntology o ->
    line p 0 d.at ("ontology " ^ o.oname.it
                   ^ (match o.oextends with None -> "" | Some e -> " extends " ^ e.it));
    let rec go = function
      | [] -> ()
      | s :: rest -> schema p 1 s; go rest in
    go o.schemas;
    comments_closing p 1 ~header_col:(col_of d.at) ~bound
  | DAgent a ->
    line p 0 d.at ("agent " ^ a.aname.it
                   ^ (match a.aextends with None -> "" | Some e -> " extends " ^ e.it)
                   ^ uses a.aontologies);
    features p 1 ~header:d.at ~bound a.afeatures
  | DBehaviour b ->
    line p 0 d.at ((match b.bkind with Cyclic -> "cyclic" | OneShot -> "one shot")
                   ^ " behaviour " ^ b.bname.it
                   ^ (match b.bextends with None -> "" | Some e -> " extends " ^ e.it)
                   ^ (match b.for_agent with None -> "" | Some a -> " for agent " ^ a.it)
                   ^ uses b.bontologies);
    features p 1 ~header:d.at ~bound b.bfeatures

let program ?(comments = []) (prog : program) =
  let p = { buf = Buffer.create 4096; pending = comments; last_line = 0 } in
  (match prog.module_name with
   | [] -> ()
   | (first :: _) as q ->
     comments_before p 0 (line_of first.at);
     line p 0 first.at ("module " ^ String.concat "." (List.map (fun n -> n.it) q)));
  let rec go = function
    | [] -> ()
    | d :: rest ->
      blank p;
      decl p ~bound:(match rest with r :: _ -> line_of r.at | [] -> max_int) d;
      go rest in
  go prog.decls;
  (* Comments after the last declaration close the file, at column 1. *)
  if p.pending <> [] then blank p;
  List.iter (comment_line p 0) p.pending;
  Buffer.contents p.buf

let expr e = expr e
