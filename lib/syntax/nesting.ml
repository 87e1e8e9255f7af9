open Ast

(* D27: the deepest expression, pattern or type accepted. *)
let max_depth = 1000

let too_deep (at : Source.region) what =
  Diag.errorf Diag.Syntax at "this %s is nested too deeply: more than %d levels (D27)%s"
    what max_depth
    (if what = "expression" then "; split it with local variables" else "")

(* Each walk takes the depth of the node it is given and stops as soon as it
   passes max_depth, so its own recursion is bounded. *)
let rec ty d (t : Ast.ty) =
  if d > max_depth then too_deep t.at "type";
  match t.it with
  | TName _ -> ()
  | TList e -> ty (d + 1) e
  | TMap (k, v) -> ty (d + 1) k; ty (d + 1) v

let rec pattern d (p : Ast.pattern) =
  if d > max_depth then too_deep p.at "pattern";
  match p.it with
  | PWild | PLit _ | PName _ -> ()
  | PCons (_, ps) -> List.iter (pattern (d + 1)) ps

let rec expr d (e : Ast.expr) =
  if d > max_depth then too_deep e.at "expression";
  let sub = expr (d + 1) in
  match e.it with
  | Lit _ | Name _ | This | Agent | Content | Message -> ()
  | List es | Call (_, es) -> List.iter sub es
  | Map kvs -> List.iter (fun (k, v) -> sub k; sub v) kvs
  | Index (a, b) | Binop (_, a, b) -> sub a; sub b
  | Of (_, a) | Unop (_, a) -> sub a
  | Matches (a, p) -> sub a; pattern (d + 1) p
  | Invoke i -> invoke d i

and invoke d i = expr (d + 1) i.target; List.iter (expr (d + 1)) i.args

let lvalue (l : Ast.lvalue) = match l.it with
  | LName _ -> ()
  | LOf (_, e) -> expr 1 e
  | LIndex (a, b) -> expr 1 a; expr 1 b

(* Blocks are at most 200 deep (Layout), so walking statements by recursion
   is safe; each statement's expressions count from 0 again. *)
let rec stmt (s : Ast.stmt) = match s.it with
  | Assign (l, e) -> lvalue l; expr 0 e
  | Local (_, t, e) -> ty 0 t; expr 0 e
  | Do (_, Positional es) -> List.iter (expr 0) es
  | Do (_, Named nes) | Activate (_, nes) -> List.iter (fun (_, e) -> expr 0 e) nes
  | Nothing | Deactivate | Break | Continue | Return None -> ()
  | InvokeS i -> invoke 0 i
  | Send (_, c, rs) -> expr 0 c; List.iter (expr 0) rs
  | Log e | Return (Some e) -> expr 0 e
  | If (branches, els) ->
    List.iter (fun (c, b) -> expr 0 c; block b) branches;
    Option.iter block els
  | While (c, b) | For (_, c, b) -> expr 0 c; block b

and block b = List.iter stmt b

let param p = ty 0 p.pty

let feature (f : Ast.feature) = match f.it with
  | Property { ty = t; init; _ } -> Option.iter (ty 0) t; Option.iter (expr 0) init
  | Function { params; ret; body; _ } -> List.iter param params; ty 0 ret; block body
  | Procedure { params; body; _ } | OnCreate { params; body } ->
    List.iter param params; block body
  | OnDestroy body | ActionSection body -> block body
  | OnPercept { guard; body } | OnMessage { guard; body; _ } ->
    Option.iter (expr 0) guard; block body

let schema (s : Ast.schema) =
  List.iter (fun sl -> ty 0 sl.slot_ty) s.it.slots;
  List.iter (fun (_, e) -> expr 0 e) s.it.defaults

let decl (d : Ast.decl) = match d.it with
  | DOntology o -> List.iter schema o.schemas
  | DAgent a -> List.iter feature a.afeatures
  | DBehaviour b -> List.iter feature b.bfeatures

let check_program (p : Ast.program) = List.iter decl p.decls
let check_expr e = expr 0 e
