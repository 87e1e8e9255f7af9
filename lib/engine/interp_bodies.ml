(* The interpreter's bodies, with resolved guards, a memo and a pre-test:
   the fast path of the percept guards. Eval.Bodies is the reference. *)

module Eval = Interp_eval.Eval
module V = Interp_eval.Value
module T = Typing.Tenv
module Ast = Syntax.Ast

(* A guard [content matches S(x1, ..., xn)], possibly followed by [and rest],
   resolved: S's name as the type environment spells it, and per slot the
   variable it binds ([None] for [_]). *)
type resolved_guard = { fschema : string; fvars : string option array; frest : Ast.expr option }

(* What is known of one percept handler. *)
type info = {
  fast : resolved_guard option;
  required : (string * (string * bool) list ref) option;
      (* the schema the guard requires of content, and per percept type
         (by name) whether it is that schema or extends it *)
}

(* Names are interned by the lexer: equal names are usually the same string. *)
let same_name (x : string) y = x == y || String.equal x y

(* The schema a guard requires of content, when its leftmost conjunct is
   [content matches S] or [content matches S(...)]. *)
let rec required_schema (e : Ast.expr) = match e.it with
  | Matches ({ it = Content; _ }, { it = PCons (c, _); _ }) -> Some c.it
  | Matches ({ it = Content; _ }, { it = PName x; _ }) -> Some x
  | Binop (And, l, _) -> required_schema l
  | _ -> None

let resolve_guard env (g : Ast.expr) =
  let form (m : Ast.expr) rest = match m.it with
    | Matches ({ it = Content; _ }, { it = PCons (c, ps); _ }) ->
      (match T.schema env c.it with
       | Some sc when List.length sc.s_slots = List.length ps ->
         let var (p : Ast.pattern) = match p.it with
           | PWild -> Some None
           | PName x when T.schema env x = None -> Some (Some x)
           | _ -> None in
         let vars = List.map var ps in
         if List.mem None vars then None
         else Some { fschema = sc.s_name; fvars = Array.of_list (List.map Option.get vars); frest = rest }
       | _ -> None)
    | _ -> None in
  match g.it with
  | Binop (And, l, r) -> form l (Some r)
  | _ -> form g None

let info_of env (h : T.handler) =
  match h.h_guard with
  | None -> { fast = None; required = None }
  | Some g ->
    { fast = resolve_guard env g;
      required = (match required_schema g with
          | Some x when T.schema env x <> None -> Some (x, ref [])
          | _ -> None) }

(* What is known of each percept handler of a behaviour instance, kept with
   the instance (Eval.keep) once first asked for. *)
type Eval.engine_slot += Resolved of info array

let resolve (a : Eval.agent) (b : Eval.beh) =
  let r = Array.map (info_of a.env) b.phandlers in
  Eval.keep b (Resolved r);
  r

(* The memo's answer for the type named by the very string [n]: 1 (yes),
   0 (no), -1 (not there). *)
let rec memo_by_address n = function
  | (m, r) :: rest -> if m == n then (if r then 1 else 0) else memo_by_address n rest
  | [] -> -1

let may_apply (a : Eval.agent) (i : info) (p : V.t) =
  match i.required, p with
  | Some (x, memo), V.Schema s ->
    let n = s.sname in
    x == n
    || (match memo_by_address n !memo with
        | 1 -> true
        | 0 -> false
        | _ ->
          match List.find_opt (fun (m, _) -> String.equal m n) !memo with
          | Some (_, r) -> r
          | None ->
            let r = same_name x n || T.subschema a.env n x in
            memo := (n, r) :: !memo; r)
  | _ -> true

include (Eval.Bodies : Semantics.Machine.BODIES
         with type percept = V.t and type message = Eval.message and type obj = V.t
          and type beh = Eval.beh and type world = Eval.agent)

let percept_may_apply a (b : Eval.beh) h p =
  match b.kept with
  | Resolved r -> may_apply a r.(h - 1) p
  | _ -> may_apply a (resolve a b).(h - 1) p

(* Kinds (Fast.BODIES.percept_kind): a number per schema name, the same
   for every agent (the pre-test's answer depends on the name, the
   behaviour and the handler only). The names are usually the type
   environment's own strings: found by address first. *)
let kind_numbers : (string, int) Hashtbl.t = Hashtbl.create 16
let kinds_by_address : (string * int) list ref = ref []

let rec kind_by_address n = function
  | (m, k) :: rest -> if m == n then k else kind_by_address n rest
  | [] -> -1

let kind_of_name n =
  let k = kind_by_address n !kinds_by_address in
  if k >= 0 then k
  else begin
    let k = match Hashtbl.find_opt kind_numbers n with
      | Some k -> k
      | None -> let k = Hashtbl.length kind_numbers in Hashtbl.add kind_numbers n k; k in
    if List.length !kinds_by_address < 16 then kinds_by_address := (n, k) :: !kinds_by_address;
    k
  end

(* The last name asked and its kind: a dispatch takes the percepts of one
   priority, so mostly of one type, in a row. *)
let last_name = ref ""
let last_kind = ref (-1)

let percept_kind = function
  | V.Schema { sname; _ } ->
    if sname == !last_name then !last_kind
    else begin let k = kind_of_name sname in last_name := sname; last_kind := k; k end
  | _ -> -1

let percept_applicable (a : Eval.agent) ~id b h p =
  let hd = b.Eval.phandlers.(h - 1) in
  let i = match b.kept with Resolved r -> r.(h - 1) | _ -> (resolve a b).(h - 1) in
  if not (may_apply a i p) then begin
    (match a.pending with None -> () | Some _ -> a.pending <- None);
    (a, false)
  end else
    match i.fast, p, hd.h_guard with
    | Some { fschema; fvars; frest }, V.Schema s, Some g
      when same_name s.sname fschema && Array.length s.slots = Array.length fvars ->
      let f = Eval.guard_frame a ~id b p in
      for k = 0 to Array.length fvars - 1 do
        match fvars.(k) with
        | Some x -> Eval.bind_local f x !(snd s.slots.(k))
        | None -> ()
      done;
      let ok = match frest with
        | None -> true
        | Some r ->
          (try Eval.condition_part f ~whole:g r with x when Eval.record_error a x -> false) in
      a.pending <- (if ok then Some (id, h, f) else None);
      (a, ok)
    | _ -> Eval.Bodies.percept_applicable a ~id b h p

(* The guard, then the body when it holds: the pending frame carries the
   bindings from one to the other. *)
let percept_handle a ~id b h p = Fast.handle_in_two percept_applicable run_percept_handler a ~id b h p
