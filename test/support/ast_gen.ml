open Syntax
open Ast
open QCheck.Gen

let ph x = { Source.it = x; at = Source.no_region }

let ident_pool = [|
  "x"; "y"; "qrCode"; "worldMap"; "currentPosition"; "position"; "obstacle";
  "falling"; "count"; "m"; "k"; "v"; "shape"; "myShape"; "area"; "p1"; "p_2";
  "HandlePercepts"; "RoboMe"; "stop"; "moveForward"; "length"; "size"; "sender";
  "priority"; "list"; "map"; "integer"; "text"; "double"; "aid"; "any";
  "_hidden"; "X9"; "agentName"; "doIt"; "ifTrue";
|]

let ident = oneofa ident_pool
let name = map ph ident
let performative = oneofl ["inform"; "request"; "agree"; "query_if"; "not_understood"; "cfp"]

let text_chars = [| 'a'; 'Z'; ' '; '"'; '\\'; '\n'; '\t'; '#'; '('; '\001'; '\127' |]
let text =
  let piece = frequency [
      (6, map (String.make 1) (oneofa text_chars));
      (2, oneofl ["hello"; "A7"; "qr-42"; "é"; "\xe2\x82\xac"]);
    ] in
  map (String.concat "") (list_size (int_bound 5) piece)

let real =
  oneof [
    map2 (fun a b -> Printf.sprintf "%d.%d" a b) nat nat;
    map2 (fun a e -> Printf.sprintf "%de%d" a e) small_nat (int_range (-5) 5);
    map3 (fun a b e -> Printf.sprintf "%d.%dE+%d" a b e) small_nat small_nat small_nat;
  ]

let literal = frequency [
    (3, map (fun i -> Int i) (oneof [small_nat; nat; int_bound max_int]));
    (2, map (fun r -> Real r) real);
    (2, map (fun s -> Text s) text);
    (1, map (fun b -> Bool b) bool);
  ]

let rec ty_sized n =
  if n <= 0 then map (fun x -> ph (TName x)) ident
  else frequency [
      (3, map (fun x -> ph (TName x)) ident);
      (1, map (fun t -> ph (TList t)) (ty_sized (n / 2)));
      (1, map2 (fun k v -> ph (TMap (k, v))) (ty_sized (n / 3)) (ty_sized (n / 2)));
    ]
let ty = sized_size (int_bound 4) ty_sized

let rec pattern_sized n =
  let leaf = frequency [
      (1, return (ph PWild));
      (2, map (fun l -> ph (PLit l)) literal);
      (1, map (fun i -> ph (PLit (Int (- (i + 1))))) small_nat);
      (1, map (fun r -> ph (PLit (Real ("-" ^ r)))) real);
      (3, map (fun x -> ph (PName x)) ident);
    ] in
  if n <= 0 then leaf
  else frequency [
      (2, leaf);
      (2, map2 (fun f ps -> ph (PCons (f, ps))) name
         (list_size (int_bound 3) (pattern_sized (n / 3))));
    ]
let pattern = sized_size (int_bound 6) pattern_sized

let binops = [| Or; And; Eq; Neq; Lt; Gt; Le; Ge; Add; Sub; Mul; Div; Mod |]

let rec expr_sized n =
  let leaf = frequency [
      (4, map (fun l -> ph (Lit l)) literal);
      (4, map (fun x -> ph (Name x)) ident);
      (1, oneofl (List.map ph [This; Agent; Content; Message]));
      (1, return (ph (List [])));
      (1, return (ph (Map [])));
    ] in
  if n <= 0 then leaf
  else
    let sub = expr_sized (n / 2) and small = expr_sized (n / 4) in
    frequency [
      (3, leaf);
      (3, map3 (fun op l r -> ph (Binop (op, l, r))) (oneofa binops) sub sub);
      (1, map2 (fun op e -> ph (Unop (op, e))) (oneofl [Not; Neg]) sub);
      (1, map2 (fun p e -> ph (Of (p, e))) name sub);
      (1, map2 (fun m k -> ph (Index (m, k))) sub small);
      (1, map2 (fun e p -> ph (Matches (e, p))) sub pattern);
      (1, map2 (fun f a -> ph (Call (f, a))) name (list_size (int_bound 3) small));
      (1, map (fun es -> ph (List es)) (list_size (int_range 1 3) small));
      (1, map (fun kvs -> ph (Map kvs)) (list_size (int_range 1 3) (pair small small)));
    ]
let expr = sized_size (int_bound 12) expr_sized
let small_expr = sized_size (int_bound 4) expr_sized

let invoke =
  map3 (fun m t a -> { meth = ph m; target = t; args = a })
    text small_expr (list_size (int_bound 3) small_expr)

let rhs = frequency [ (5, expr); (1, map (fun i -> ph (Invoke i)) invoke) ]

let lvalue = frequency [
    (3, map (fun x -> ph (LName x)) ident);
    (1, map2 (fun p e -> ph (LOf (p, e))) name small_expr);
    (1, map2 (fun m k -> ph (LIndex (m, k))) small_expr small_expr);
  ]

let named_args = list_size (int_range 1 3) (pair name small_expr)

let simple_stmt = frequency [
    (4, map2 (fun l e -> ph (Assign (l, e))) lvalue rhs);
    (1, map3 (fun x t e -> ph (Local (x, t, e))) name ty rhs);
    (1, map (fun f -> ph (Do (f, Positional []))) name);
    (1, map2 (fun f a -> ph (Do (f, Positional a))) name (list_size (int_range 1 3) small_expr));
    (1, map2 (fun f a -> ph (Do (f, Named a))) name named_args);
    (1, return (ph Nothing));
    (1, map (fun i -> ph (InvokeS i)) invoke);
    (1, map2 (fun b a -> ph (Activate (b, a))) name (list_size (int_bound 2) (pair name small_expr)));
    (1, return (ph Deactivate));
    (1, map3 (fun p c r -> ph (Send (ph p, c, r))) performative small_expr
       (list_size (int_range 1 2) small_expr));
    (2, map (fun e -> ph (Log e)) expr);
    (1, map (fun e -> ph (Return e)) (opt small_expr));
    (1, oneofl [ph Break; ph Continue]);
  ]

let rec block_sized n =
  list_size (int_range 1 (if n <= 0 then 2 else 4)) (stmt_sized n)
and stmt_sized n =
  if n <= 0 then simple_stmt
  else
    let b = block_sized (n / 3) in
    frequency [
      (6, simple_stmt);
      (1, map3 (fun c b1 rest ->
           let (elifs, els) = rest in ph (If ((c, b1) :: elifs, els)))
           small_expr b
           (pair (list_size (int_bound 2) (pair small_expr b)) (opt b)));
      (1, map2 (fun c b -> ph (While (c, b))) small_expr b);
      (1, map3 (fun x e b -> ph (For (x, e, b))) name small_expr b);
    ]
let block = sized_size (int_bound 9) block_sized

let param = map2 (fun n t -> { pname = n; pty = t }) name ty
let params = list_size (int_bound 3) param

let property =
  oneof [
    map3 (fun n t i -> ph (Property { name = n; ty = Some t; init = i })) name ty (opt rhs);
    map2 (fun n i -> ph (Property { name = n; ty = None; init = Some i })) name rhs;
  ]

let common_feature = frequency [
    (3, property);
    (1, map3 (fun n (ps, r) b -> ph (Function { name = n; params = ps; ret = r; body = b }))
       name (pair params ty) block);
    (1, map3 (fun n ps b -> ph (Procedure { name = n; params = ps; body = b })) name params block);
  ]

let once_each fs =
  (* At most one feature of each "once" kind, as the parser requires. *)
  let seen = Hashtbl.create 4 in
  List.filter (fun (f : feature) ->
      let key = match f.it with
        | OnCreate _ -> Some 0 | OnDestroy _ -> Some 1 | ActionSection _ -> Some 2 | _ -> None in
      match key with
      | None -> true
      | Some k -> if Hashtbl.mem seen k then false else (Hashtbl.add seen k (); true)) fs

let agent_feature = frequency [
    (4, common_feature);
    (1, map2 (fun ps b -> ph (OnCreate { params = ps; body = b })) params block);
    (1, map (fun b -> ph (OnDestroy b)) block);
  ]

let behaviour_feature = frequency [
    (3, common_feature);
    (1, map2 (fun ps b -> ph (OnCreate { params = ps; body = b })) params block);
    (1, map (fun b -> ph (ActionSection b)) block);
    (2, map2 (fun g b -> ph (OnPercept { guard = g; body = b })) (opt expr) block);
    (2, map3 (fun p g b -> ph (OnMessage { perf = Option.map ph p; guard = g; body = b }))
       (opt performative) (opt expr) block);
  ]

let schema =
  let kind = oneofl [Concept; Predicate; Proposition; Action] in
  kind >>= fun k ->
  let slots = if k = Proposition then return []
    else list_size (int_bound 3) (map2 (fun n t -> { slot_name = n; slot_ty = t }) name ty) in
  let super = opt (oneof [name; return (ph "percept")]) in
  map3 (fun n sl sup ->
      let defaults = match sup with
        | None -> return []
        | Some _ -> list_size (int_bound 2) (pair name small_expr) in
      (n, sl, sup, defaults)) name slots super >>= fun (n, sl, sup, defaults) ->
  map (fun ds -> ph { kind = k; sname = n; slots = sl; super = sup; defaults = ds }) defaults

let names_list = list_size (int_bound 2) name

let decl = frequency [
    (1, map3 (fun n e ss -> ph (DOntology { oname = n; oextends = e; schemas = ss }))
       name (opt name) (list_size (int_bound 4) schema));
    (2, map3 (fun (n, e) os fs ->
         ph (DAgent { aname = n; aextends = e; aontologies = os; afeatures = once_each fs }))
        (pair name (opt name)) names_list (list_size (int_bound 4) agent_feature));
    (2, map3 (fun (k, n, e) (fa, os) fs ->
         ph (DBehaviour { bkind = k; bname = n; bextends = e; for_agent = fa;
                          bontologies = os; bfeatures = once_each fs }))
        (triple (oneofl [Cyclic; OneShot]) name (opt name)) (pair (opt name) names_list)
        (list_size (int_bound 4) behaviour_feature));
  ]

let program =
  map2 (fun m ds -> { module_name = m; decls = ds })
    (list_size (int_bound 3) name) (list_size (int_bound 4) decl)

let arb_program = QCheck.make ~print:(fun p -> Print.program p) program
