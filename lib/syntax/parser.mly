(* The grammar of Jadescript (the paper's dialect and Jadescript 1.0 spellings).

   Layout tokens NEWLINE, INDENT and DEDENT come from Layout, which implements the
   indentation rule of docs/syntax.md; this grammar never sees white space.
   Expression precedence, loosest first (Jadescript 1.0, docs/syntax.md):
     or < and < = != < < > <= >= < + - < * / % < matches < not, unary - < of < [ ]
   Each level is a nonterminal below, so the table is readable in the grammar. *)

%{
open Ast

let region (s, e) = Source.region_of_lexing s e
let mk loc x = Source.(x @@ region loc)
let fail loc fmt = Diag.errorf Diag.Syntax (region loc) fmt

let performatives = [
  "accept_proposal"; "agree"; "cancel"; "cfp"; "confirm"; "disconfirm";
  "failure"; "inform"; "inform_if"; "inform_ref"; "not_understood";
  "propagate"; "propose"; "proxy"; "query_if"; "query_ref"; "refuse";
  "reject_proposal"; "request"; "request_when"; "request_whenever"; "subscribe";
]

let check_performative (p : name) =
  if not (List.mem p.it performatives) then
    Diag.errorf Diag.Syntax p.at
      "'%s' is not a performative nor an event (expected percept, message, create, \
       destroy or a FIPA performative such as inform or request)" p.it;
  p

let to_lvalue (e : expr) : lvalue =
  let lv = match e.it with
    | Name x -> LName x
    | Of (p, e') -> LOf (p, e')
    | Index (m, k) -> LIndex (m, k)
    | _ -> Diag.error Diag.Syntax e.at
             "cannot assign to this expression: the left side of '=' must be a name, \
              'x of e' or 'e[k]'" in
  Source.(lv @@ e.at)

type clause =
  | CExtends of name
  | CUses of name list
  | CFor of name

(* Header clauses may come in any order, each at most once. *)
let clauses ~what loc cs =
  let ext = ref None and uses = ref None and for_ = ref None in
  let once r v word =
    match !r with
    | Some _ -> fail loc "this %s has more than one '%s' clause" what word
    | None -> r := Some v in
  List.iter (function
      | CExtends n -> once ext n "extends"
      | CUses ns -> once uses ns "uses ontology"
      | CFor n -> once for_ n "for agent") cs;
  (!ext, Option.value !uses ~default:[], !for_)

let feature_name (f : feature) = match f.it with
  | Property _ -> "a property" | Function _ -> "a function"
  | Procedure _ -> "a procedure" | OnCreate _ -> "an 'on create' handler"
  | OnDestroy _ -> "an 'on destroy' handler" | ActionSection _ -> "an action section ('do')"
  | OnPercept _ -> "an 'on percept' handler" | OnMessage _ -> "a message handler"

let check_features ~agent (fs : feature list) =
  let seen_create = ref false and seen_destroy = ref false and seen_do = ref false in
  let once r (f : feature) =
    if !r then Diag.errorf Diag.Syntax f.at "%s appears twice in this declaration"
        (String.capitalize_ascii (feature_name f));
    r := true in
  List.iter (fun (f : feature) ->
      match f.it with
      | OnCreate _ -> once seen_create f
      | OnDestroy _ when agent -> once seen_destroy f
      | ActionSection _ when not agent -> once seen_do f
      | (OnPercept _ | OnMessage _ | ActionSection _) when agent ->
        Diag.errorf Diag.Syntax f.at
          "an agent cannot have %s: it belongs in a behaviour" (feature_name f)
      | OnDestroy _ ->
        Diag.errorf Diag.Syntax f.at "a behaviour cannot have an 'on destroy' handler"
      | _ -> ()) fs;
  fs
%}

%token <string> IDENT TEXT REAL
%token <int> INT
%token TRUE FALSE
%token MODULE ONTOLOGY ONTOLOGIES EXTENDS CONCEPT PREDICATE PROPOSITION ACTION
%token AGENT USES BEHAVIOUR CYCLIC ONE SHOT ONESHOT FOR
%token PROPERTY FUNCTION PROCEDURE ON CREATE DESTROY PERCEPT MESSAGE WHEN
%token DO AS WITH RETURN BREAK CONTINUE IF ELSE WHILE IN NOTHING
%token INVOKE ACTIVATE DEACTIVATE THIS SEND TO LOG CONTENT
%token MATCHES AND OR NOT OF
%token LPAREN RPAREN LBRACKET RBRACKET LBRACE RBRACE COMMA COLON DOT UNDERSCORE
%token EQ NEQ LT GT LE GE PLUS MINUS STAR SLASH PERCENT
%token NEWLINE INDENT DEDENT EOF

(* One conflict is resolved by precedence: in [do p with x = 1] the arguments
   are named ([x = 1]) rather than the positional equality [x = 1]; write
   [do p with (x = 1)] for the latter. *)
%nonassoc below_EQ
%nonassoc EQ

%start <Ast.program> program
%start <Ast.expr> expr_only

%%

(* ---------------------------------------------------------------- program *)

program:
  | m = loption(module_header) ds = decl* EOF { { module_name = m; decls = ds } }

expr_only:
  | e = expr NEWLINE EOF { e }

module_header:
  | MODULE q = separated_nonempty_list(DOT, name) NEWLINE { q }

name:
  | x = IDENT { mk $loc x }

names:
  | ns = separated_nonempty_list(COMMA, name) { ns }

body(X):
  | NEWLINE { [] }
  | NEWLINE INDENT xs = X+ DEDENT { xs }

(* ----------------------------------------------------------- declarations *)

decl:
  | ONTOLOGY n = name e = preceded(EXTENDS, name)? ss = body(schema)
      { mk ($startpos, $endpos(e)) (DOntology { oname = n; oextends = e; schemas = ss }) }
  | AGENT n = name cs = clause* fs = body(feature)
      { let loc = ($startpos, $endpos(cs)) in
        let (e, uses, for_) = clauses ~what:"agent" loc cs in
        (match for_ with
         | Some f -> Diag.error Diag.Syntax f.at "an agent has no 'for agent' clause (behaviours do)"
         | None -> ());
        mk loc (DAgent { aname = n; aextends = e; aontologies = uses;
                        afeatures = check_features ~agent:true fs }) }
  | k = behaviour_kind BEHAVIOUR n = name cs = clause* fs = body(feature)
      { let loc = ($startpos, $endpos(cs)) in
        let (e, uses, for_) = clauses ~what:"behaviour" loc cs in
        mk loc (DBehaviour { bkind = k; bname = n; bextends = e; for_agent = for_;
                            bontologies = uses;
                            bfeatures = check_features ~agent:false fs }) }

behaviour_kind:
  | CYCLIC { Cyclic }
  | ONE SHOT { OneShot }
  | ONESHOT { OneShot }

clause:
  | EXTENDS n = name { CExtends n }
  | USES ONTOLOGY ns = names { CUses ns }
  | USES ONTOLOGIES ns = names { CUses ns }
  | FOR AGENT n = name { CFor n }

(* ---------------------------------------------------------------- schemas *)

schema:
  | k = schema_kind n = name sl = loption(slots) sup = extends_clause? NEWLINE
      { let (super, defaults) = match sup with
          | None -> (None, [])
          | Some (s, d) -> (Some s, d) in
        if k = Proposition && sl <> [] then
          fail $loc(sl) "a proposition has no slots (use a predicate)";
        mk ($startpos, $endpos(sup))
          { kind = k; sname = n; slots = sl; super; defaults } }

schema_kind:
  | CONCEPT { Concept }
  | PREDICATE { Predicate }
  | PROPOSITION { Proposition }
  | ACTION { Action }

slots:
  | LPAREN ss = separated_list(COMMA, slot) RPAREN { ss }

slot:
  | n = name AS t = ty { { slot_name = n; slot_ty = t } }

extends_clause:
  | EXTENDS s = super_name ds = loption(preceded(WITH, separated_nonempty_list(COMMA, default)))
      { (s, ds) }

super_name:
  | n = name { n }
  | PERCEPT { mk $loc "percept" }

default:
  | x = IDENT EQ e = expr { (mk $loc(x) x, e) }

(* --------------------------------------------------------------- features *)

feature:
  | PROPERTY n = name AS t = ty i = preceded(EQ, rhs)? NEWLINE
      { mk $loc (Property { name = n; ty = Some t; init = i }) }
  | PROPERTY n = name EQ i = rhs NEWLINE
      { mk $loc (Property { name = n; ty = None; init = Some i }) }
  | FUNCTION n = name LPAREN ps = separated_list(COMMA, param) RPAREN AS t = ty DO b = block
      { mk ($startpos, $endpos(t)) (Function { name = n; params = ps; ret = t; body = b }) }
  | PROCEDURE n = name ps = params DO b = block
      { mk ($startpos, $endpos(ps)) (Procedure { name = n; params = ps; body = b }) }
  | ON CREATE ps = params DO b = block
      { mk ($startpos, $endpos(ps)) (OnCreate { params = ps; body = b }) }
  | ON DESTROY DO b = block
      { mk ($startpos, $endpos($2)) (OnDestroy b) }
  | ON PERCEPT g = guard? DO b = block
      { mk ($startpos, $endpos(g)) (OnPercept { guard = g; body = b }) }
  | ON MESSAGE p = name? g = guard? DO b = block
      { let p = Option.map check_performative p in
        mk ($startpos, $endpos(g)) (OnMessage { perf = p; guard = g; body = b }) }
  | ON p = name g = guard? DO b = block
      { let p = check_performative p in
        mk ($startpos, $endpos(g)) (OnMessage { perf = Some p; guard = g; body = b }) }
  | DO b = block
      { mk $loc($1) (ActionSection b) }

params:
  | { [] }
  | WITH ps = separated_nonempty_list(COMMA, param) { ps }

param:
  | n = name AS t = ty { { pname = n; pty = t } }

guard:
  | WHEN e = expr { e }

(* ------------------------------------------------------------------ types *)

(* [list of T], [map of K:V]; a map's key is a name or a parenthesised type. *)
ty:
  | x = IDENT { mk $loc (TName x) }
  | LPAREN t = ty RPAREN { t }
  | c = IDENT OF t = ty
      { match c with
        | "list" -> mk $loc (TList t)
        | "map" -> fail $loc "a map type names its key and value types: map of K:V"
        | _ -> fail $loc(c) "unknown type constructor '%s' (expected list or map)" c }
  | c = IDENT OF k = key_ty COLON v = ty
      { match c with
        | "map" -> mk $loc (TMap (k, v))
        | "list" -> fail $loc "a list type names one element type: list of T"
        | _ -> fail $loc(c) "unknown type constructor '%s' (expected list or map)" c }

key_ty:
  | x = IDENT { mk $loc (TName x) }
  | LPAREN t = ty RPAREN { t }

(* ------------------------------------------------------------- statements *)

block:
  | NEWLINE INDENT ss = stmt+ DEDENT { ss }

stmt:
  | s = simple NEWLINE { s }
  | IF c = expr DO b = block r = if_rest
      { let (elifs, els) = r in mk ($startpos, $endpos(c)) (If ((c, b) :: elifs, els)) }
  | WHILE c = expr DO b = block
      { mk ($startpos, $endpos(c)) (While (c, b)) }
  | FOR x = name IN e = expr DO b = block
      { mk ($startpos, $endpos(e)) (For (x, e, b)) }

if_rest:
  | { ([], None) }
  | ELSE IF c = expr DO b = block r = if_rest { let (l, e) = r in ((c, b) :: l, e) }
  | ELSE DO b = block { ([], Some b) }

simple:
  | l = of_expr EQ r = rhs { mk $loc (Assign (to_lvalue l, r)) }
  | n = name AS t = ty EQ r = rhs { mk $loc (Local (n, t, r)) }
  | DO NOTHING { mk $loc Nothing }
  | DO p = name a = do_args { mk $loc (Do (p, a)) }
  | i = invoke { mk $loc (InvokeS i) }
  | ACTIVATE BEHAVIOUR? b = name a = loption(preceded(WITH, named_args))
      { mk $loc (Activate (b, a)) }
  | DEACTIVATE THIS { mk $loc Deactivate }
  | SEND p = name c = expr TO rs = separated_nonempty_list(COMMA, expr)
      { mk $loc (Send (check_performative p, c, rs)) }
  | LOG e = expr { mk $loc (Log e) }
  | RETURN e = expr? { mk $loc (Return e) }
  | BREAK { mk $loc Break }
  | CONTINUE { mk $loc Continue }

do_args:
  | { Positional [] }
  | WITH a = named_args { Named a }
  | WITH a = separated_nonempty_list(COMMA, expr) { Positional a }

named_args:
  | a = separated_nonempty_list(COMMA, named_arg) { a }

named_arg:
  | x = IDENT EQ e = expr { (mk $loc(x) x, e) }

invoke:
  | INVOKE m = TEXT ON t = expr a = loption(preceded(WITH, separated_nonempty_list(COMMA, expr)))
      { { meth = mk $loc(m) m; target = t; args = a } }

rhs:
  | e = expr { e }
  | i = invoke { mk $loc (Invoke i) }

(* ------------------------------------------------------------ expressions *)

expr:
  | e = or_expr { e }

or_expr:
  | l = or_expr OR r = and_expr { mk $loc (Binop (Or, l, r)) }
  | e = and_expr { e }

and_expr:
  | l = and_expr AND r = eq_expr { mk $loc (Binop (And, l, r)) }
  | e = eq_expr { e }

eq_expr:
  | l = rel_expr op = eq_op r = rel_expr { mk $loc (Binop (op, l, r)) }
  | e = rel_expr { e }

eq_op:
  | EQ { Eq }
  | NEQ { Neq }

rel_expr:
  | l = add_expr op = rel_op r = add_expr { mk $loc (Binop (op, l, r)) }
  | e = add_expr { e }

rel_op:
  | LT { Lt }
  | GT { Gt }
  | LE { Le }
  | GE { Ge }

add_expr:
  | l = add_expr op = add_op r = mul_expr { mk $loc (Binop (op, l, r)) }
  | e = mul_expr { e }

add_op:
  | PLUS { Add }
  | MINUS { Sub }

mul_expr:
  | l = mul_expr op = mul_op r = match_expr { mk $loc (Binop (op, l, r)) }
  | e = match_expr { e }

mul_op:
  | STAR { Mul }
  | SLASH { Div }
  | PERCENT { Mod }

match_expr:
  | e = unary_expr MATCHES p = pattern { mk $loc (Matches (e, p)) }
  | e = unary_expr { e }

unary_expr:
  | NOT e = unary_expr { mk $loc (Unop (Not, e)) }
  | MINUS e = unary_expr { mk $loc (Unop (Neg, e)) }
  | e = of_expr { e }

of_expr:
  | p = IDENT OF e = of_expr { mk $loc (Of (mk $loc(p) p, e)) }
  | e = postfix_expr { e }

postfix_expr:
  | e = postfix_expr LBRACKET i = expr RBRACKET { mk $loc (Index (e, i)) }
  | e = primary { e }

primary:
  | l = literal { mk $loc (Lit l) }
  | x = IDENT %prec below_EQ { mk $loc (Name x) }
  | f = IDENT LPAREN a = separated_list(COMMA, expr) RPAREN { mk $loc (Call (mk $loc(f) f, a)) }
  | THIS { mk $loc This }
  | AGENT { mk $loc Agent }
  | CONTENT { mk $loc Content }
  | MESSAGE { mk $loc Message }
  | LPAREN e = expr RPAREN { e }
  | LBRACKET es = separated_list(COMMA, expr) RBRACKET { mk $loc (List es) }
  | LBRACE es = separated_list(COMMA, entry) RBRACE { mk $loc (Map es) }

entry:
  | k = expr COLON v = expr { (k, v) }

literal:
  | i = INT { Int i }
  | r = REAL { Real r }
  | s = TEXT { Text s }
  | TRUE { Bool true }
  | FALSE { Bool false }

(* --------------------------------------------------------------- patterns *)

pattern:
  | UNDERSCORE { mk $loc PWild }
  | l = literal { mk $loc (PLit l) }
  | MINUS i = INT { mk $loc (PLit (Int (- i))) }
  | MINUS r = REAL { mk $loc (PLit (Real ("-" ^ r))) }
  | x = IDENT { mk $loc (PName x) }
  | f = IDENT LPAREN ps = separated_list(COMMA, pattern) RPAREN
      { mk $loc (PCons (mk $loc(f) f, ps)) }
