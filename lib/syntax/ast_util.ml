open Ast
open Source

let nr = Source.no_region
let ph x = { Source.it = x; at = nr }
let nm (n : name) = ph n.it

let rec ty (t : Ast.ty) = ph (match t.it with
    | TName x -> TName x
    | TList e -> TList (ty e)
    | TMap (k, v) -> TMap (ty k, ty v))

let rec pattern (p : Ast.pattern) = ph (match p.it with
    | PCons (f, ps) -> PCons (nm f, List.map pattern ps)
    | (PWild | PLit _ | PName _) as x -> x)

let rec expr (e : Ast.expr) = ph (match e.it with
    | (Lit _ | Name _ | This | Agent | Content | Message) as x -> x
    | List es -> List (List.map expr es)
    | Map kvs -> Map (List.map (fun (k, v) -> (expr k, expr v)) kvs)
    | Call (f, es) -> Call (nm f, List.map expr es)
    | Index (m, k) -> Index (expr m, expr k)
    | Of (p, e) -> Of (nm p, expr e)
    | Matches (e, p) -> Matches (expr e, pattern p)
    | Unop (op, e) -> Unop (op, expr e)
    | Binop (op, l, r) -> Binop (op, expr l, expr r)
    | Invoke i -> Invoke (invoke i))

and invoke i = { meth = ph i.meth.it; target = expr i.target; args = List.map expr i.args }

let named (n, e) = (nm n, expr e)

let lvalue (l : Ast.lvalue) = ph (match l.it with
    | LName x -> LName x
    | LOf (p, e) -> LOf (nm p, expr e)
    | LIndex (m, k) -> LIndex (expr m, expr k))

let rec stmt (s : Ast.stmt) = ph (match s.it with
    | Assign (l, e) -> Assign (lvalue l, expr e)
    | Local (x, t, e) -> Local (nm x, ty t, expr e)
    | Do (f, Positional es) -> Do (nm f, Positional (List.map expr es))
    | Do (f, Named a) -> Do (nm f, Named (List.map named a))
    | InvokeS i -> InvokeS (invoke i)
    | Activate (b, a) -> Activate (nm b, List.map named a)
    | Send (p, c, rs) -> Send (nm p, expr c, List.map expr rs)
    | Log e -> Log (expr e)
    | If (bs, els) ->
      If (List.map (fun (c, b) -> (expr c, block b)) bs, Option.map block els)
    | While (c, b) -> While (expr c, block b)
    | For (x, e, b) -> For (nm x, expr e, block b)
    | Return e -> Return (Option.map expr e)
    | (Nothing | Deactivate | Break | Continue) as x -> x)

and block b = List.map stmt b

let param p = { pname = nm p.pname; pty = ty p.pty }

let feature (f : Ast.feature) = ph (match f.it with
    | Property { name; ty = t; init } ->
      Property { name = nm name; ty = Option.map ty t; init = Option.map expr init }
    | Function { name; params; ret; body } ->
      Function { name = nm name; params = List.map param params; ret = ty ret; body = block body }
    | Procedure { name; params; body } ->
      Procedure { name = nm name; params = List.map param params; body = block body }
    | OnCreate { params; body } -> OnCreate { params = List.map param params; body = block body }
    | OnDestroy b -> OnDestroy (block b)
    | ActionSection b -> ActionSection (block b)
    | OnPercept { guard; body } -> OnPercept { guard = Option.map expr guard; body = block body }
    | OnMessage { perf; guard; body } ->
      OnMessage { perf = Option.map nm perf; guard = Option.map expr guard; body = block body })

let schema (s : Ast.schema) =
  let s = s.it in
  ph { kind = s.kind; sname = nm s.sname;
       slots = List.map (fun sl -> { slot_name = nm sl.slot_name; slot_ty = ty sl.slot_ty }) s.slots;
       super = Option.map nm s.super; defaults = List.map named s.defaults }

let decl (d : Ast.decl) = ph (match d.it with
    | DOntology o ->
      DOntology { oname = nm o.oname; oextends = Option.map nm o.oextends;
                  schemas = List.map schema o.schemas }
    | DAgent a ->
      DAgent { aname = nm a.aname; aextends = Option.map nm a.aextends;
               aontologies = List.map nm a.aontologies;
               afeatures = List.map feature a.afeatures }
    | DBehaviour b ->
      DBehaviour { bkind = b.bkind; bname = nm b.bname; bextends = Option.map nm b.bextends;
                   for_agent = Option.map nm b.for_agent;
                   bontologies = List.map nm b.bontologies;
                   bfeatures = List.map feature b.bfeatures })

let strip p = { module_name = List.map nm p.module_name; decls = List.map decl p.decls }
let strip_expr = expr

(* ----------------------------------------------------------------- dump *)

type sexp = A of string | L of string * Source.region * sexp list

let at_str (r : Source.region) = Printf.sprintf "@%d:%d" r.left.line r.left.column

let rec render b depth = function
  | A s -> Buffer.add_string b s
  | L (head, at, []) -> Printf.bprintf b "(%s %s)" head (at_str at)
  | L (head, at, kids) ->
    Printf.bprintf b "(%s %s" head (at_str at);
    List.iter (fun k ->
        Buffer.add_char b '\n';
        Buffer.add_string b (String.make (2 * (depth + 1)) ' ');
        render b (depth + 1) k) kids;
    Buffer.add_char b ')'

let q s = A (Print.text_literal s)
let sx_name (n : name) = L ("name " ^ n.it, n.at, [])
let opt f = function None -> [] | Some x -> [f x]

let rec sx_ty (t : Ast.ty) = match t.it with
  | TName x -> L ("type " ^ x, t.at, [])
  | TList e -> L ("list-of", t.at, [sx_ty e])
  | TMap (k, v) -> L ("map-of", t.at, [sx_ty k; sx_ty v])

let rec sx_pat (p : Ast.pattern) = match p.it with
  | PWild -> L ("wild", p.at, [])
  | PLit l -> L ("lit " ^ Print.literal l, p.at, [])
  | PName x -> L ("pname " ^ x, p.at, [])
  | PCons (f, ps) -> L ("pcons " ^ f.it, p.at, List.map sx_pat ps)

let binop_name = function
  | Or -> "or" | And -> "and" | Eq -> "=" | Neq -> "!=" | Lt -> "<" | Gt -> ">"
  | Le -> "<=" | Ge -> ">=" | Add -> "+" | Sub -> "-" | Mul -> "*" | Div -> "/" | Mod -> "%"

let rec sx_expr (e : Ast.expr) = match e.it with
  | Lit l -> L ("lit " ^ Print.literal l, e.at, [])
  | Name x -> L ("name " ^ x, e.at, [])
  | This -> L ("this", e.at, []) | Agent -> L ("agent", e.at, [])
  | Content -> L ("content", e.at, []) | Message -> L ("message", e.at, [])
  | List es -> L ("list", e.at, List.map sx_expr es)
  | Map kvs -> L ("map", e.at, List.concat_map (fun (k, v) -> [sx_expr k; sx_expr v]) kvs)
  | Call (f, es) -> L ("call " ^ f.it, e.at, List.map sx_expr es)
  | Index (m, k) -> L ("index", e.at, [sx_expr m; sx_expr k])
  | Of (p, x) -> L ("of " ^ p.it, e.at, [sx_expr x])
  | Matches (x, p) -> L ("matches", e.at, [sx_expr x; sx_pat p])
  | Unop (Not, x) -> L ("not", e.at, [sx_expr x])
  | Unop (Neg, x) -> L ("neg", e.at, [sx_expr x])
  | Binop (op, l, r) -> L (binop_name op, e.at, [sx_expr l; sx_expr r])
  | Invoke i -> sx_invoke e.at i

and sx_invoke at i = L ("invoke", at, q i.meth.it :: sx_expr i.target :: List.map sx_expr i.args)

let sx_named (n, e) = L ("arg " ^ n.it, n.at, [sx_expr e])

let rec sx_stmt (s : Ast.stmt) = match s.it with
  | Assign (l, e) ->
    let lv = match l.it with
      | LName x -> L ("name " ^ x, l.at, [])
      | LOf (p, x) -> L ("of " ^ p.it, l.at, [sx_expr x])
      | LIndex (m, k) -> L ("index", l.at, [sx_expr m; sx_expr k]) in
    L ("assign", s.at, [lv; sx_expr e])
  | Local (x, t, e) -> L ("local " ^ x.it, s.at, [sx_ty t; sx_expr e])
  | Do (f, Positional es) -> L ("do " ^ f.it, s.at, List.map sx_expr es)
  | Do (f, Named a) -> L ("do " ^ f.it, s.at, List.map sx_named a)
  | Nothing -> L ("nothing", s.at, [])
  | InvokeS i -> sx_invoke s.at i
  | Activate (b, a) -> L ("activate " ^ b.it, s.at, List.map sx_named a)
  | Deactivate -> L ("deactivate", s.at, [])
  | Send (p, c, rs) -> L ("send " ^ p.it, s.at, sx_expr c :: List.map sx_expr rs)
  | Log e -> L ("log", s.at, [sx_expr e])
  | If (bs, els) ->
    L ("if", s.at,
       List.map (fun (c, b) -> L ("branch", c.at, sx_expr c :: List.map sx_stmt b)) bs
       @ opt (fun b -> L ("else", s.at, List.map sx_stmt b)) els)
  | While (c, b) -> L ("while", s.at, sx_expr c :: List.map sx_stmt b)
  | For (x, e, b) -> L ("for " ^ x.it, s.at, sx_expr e :: List.map sx_stmt b)
  | Return e -> L ("return", s.at, opt sx_expr e)
  | Break -> L ("break", s.at, []) | Continue -> L ("continue", s.at, [])

let sx_params ps = List.map (fun p -> L ("param " ^ p.pname.it, p.pname.at, [sx_ty p.pty])) ps
let sx_body b = List.map sx_stmt b

let sx_feature (f : Ast.feature) = match f.it with
  | Property { name; ty; init } ->
    L ("property " ^ name.it, f.at, opt sx_ty ty @ opt sx_expr init)
  | Function { name; params; ret; body } ->
    L ("function " ^ name.it, f.at, sx_params params @ [L ("returns", ret.at, [sx_ty ret])] @ sx_body body)
  | Procedure { name; params; body } -> L ("procedure " ^ name.it, f.at, sx_params params @ sx_body body)
  | OnCreate { params; body } -> L ("on-create", f.at, sx_params params @ sx_body body)
  | OnDestroy b -> L ("on-destroy", f.at, sx_body b)
  | ActionSection b -> L ("action", f.at, sx_body b)
  | OnPercept { guard; body } ->
    L ("on-percept", f.at, opt (fun g -> L ("when", g.at, [sx_expr g])) guard @ sx_body body)
  | OnMessage { perf; guard; body } ->
    L ("on-message" ^ (match perf with None -> "" | Some p -> " " ^ p.it), f.at,
       opt (fun g -> L ("when", g.at, [sx_expr g])) guard @ sx_body body)

let sx_decl (d : Ast.decl) = match d.it with
  | DOntology o ->
    L ("ontology " ^ o.oname.it, d.at,
       opt (fun e -> L ("extends", e.at, [sx_name e])) o.oextends
       @ List.map (fun (s : Ast.schema) ->
           let sc = s.it in
           let kind = match sc.kind with
             | Concept -> "concept" | Predicate -> "predicate"
             | Proposition -> "proposition" | Action -> "action" in
           L (kind ^ " " ^ sc.sname.it, s.at,
              List.map (fun sl -> L ("slot " ^ sl.slot_name.it, sl.slot_name.at, [sx_ty sl.slot_ty])) sc.slots
              @ opt (fun n -> L ("extends", n.at, [sx_name n])) sc.super
              @ List.map sx_named sc.defaults)) o.schemas)
  | DAgent a ->
    L ("agent " ^ a.aname.it, d.at,
       opt (fun e -> L ("extends", e.at, [sx_name e])) a.aextends
       @ List.map (fun o -> L ("uses", o.at, [sx_name o])) a.aontologies
       @ List.map sx_feature a.afeatures)
  | DBehaviour b ->
    L ((match b.bkind with Cyclic -> "cyclic-behaviour " | OneShot -> "one-shot-behaviour ") ^ b.bname.it, d.at,
       opt (fun e -> L ("extends", e.at, [sx_name e])) b.bextends
       @ opt (fun a -> L ("for-agent", a.at, [sx_name a])) b.for_agent
       @ List.map (fun o -> L ("uses", o.at, [sx_name o])) b.bontologies
       @ List.map sx_feature b.bfeatures)

let dump (p : program) =
  let b = Buffer.create 4096 in
  let top = L ("program" ^ (match p.module_name with
      | [] -> "" | q -> " " ^ String.concat "." (List.map (fun n -> n.it) q)),
               Source.no_region, List.map sx_decl p.decls) in
  render b 0 top;
  Buffer.add_char b '\n';
  Buffer.contents b
