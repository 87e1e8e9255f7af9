(* Percept handlers compiled to OCaml closures (D38): the same rules as
   Eval's, with the names resolved and the dispatch on the syntax done once.
   Every rule that computes something is Eval's own (arith, compare_values,
   equal_values, pattern, map_set_bounded, tick, set_cell...); what is here
   is only the walk over the tree, done once instead of per run.
   docs/semantics.md, "Compiled percept handlers" (D38). *)

module Eval = Interp_eval.Eval
module V = Interp_eval.Value
module T = Typing.Tenv
module Ty = Typing.Types
module Ast = Syntax.Ast
module Names = Syntax.Strtbl

(* ------------------------------------------------------------ runs *)

(* What one handler of one behaviour instance runs on: the slots of its
   locals (pattern variables and locals, by number), the cells of the
   properties it names (by number), the percept, and a frame of Eval's for
   the rules that take one (the step budget, [of], patterns, names not
   resolved). *)
type ctx = {
  ag : Eval.agent;
  beh : Eval.beh;
  mutable slots : V.t array;
      (* the running body's: the handler's, or a called routine's while it
         runs (put back when it ends, however it ends) *)
  cells : Eval.cell array;
  mutable content : V.t;
  sf : Eval.frame;
  mutable id : int;
  yes : Eval.agent * bool;      (* what the bodies answer, made once *)
  no : Eval.agent * bool;
  ran : Eval.agent * Eval.beh Semantics.Machine.effect list;   (* no effects *)
  skipped : (Eval.agent, Eval.beh) Fast.handled;
  handled : (Eval.agent, Eval.beh) Fast.handled;               (* no effects *)
  mutable armed : int;
      (* the guard's bindings wait for the body (R3b) while [armed] is the
         number of the last guard evaluated ({!guards}) *)
  rsf : Eval.frame;
      (* Eval's frame of an agent's function or procedure (no behaviour),
         for the rules that read one there; the same step budget as [sf] *)
  mutable depth : int;          (* nested calls, as Eval's frame's [depth] *)
  mutable ret : V.t;            (* the value of the last [return] *)
}

(* A local that has no value yet (compared by address, never shown). *)
let unset : V.t = V.Text "(unset)"

let vtrue = V.Bool true
let vfalse = V.Bool false
let[@inline] vbool b = if b then vtrue else vfalse

(* What ends a compiled body or loop early, as Eval's Return, Break and
   Continue do there. *)
exception Ret
exception Brk
exception Cont

(* A construct this compiler does not take: the handler falls back. *)
exception Unsupported

(* ------------------------------------------------------ compiling *)

(* What the compiler knows of the names of the code it compiles: the
   handler's, or a function's or procedure's it calls. A local name has a
   slot; a property name (declared by the behaviour or the agent) has a
   cell, found per instance. A name can be both: a local shadows the
   property once it has a value (Eval.lookup, Eval.assign_name).

   The code of an agent's own function or procedure sees the agent's
   properties only (Eval runs it in a frame without behaviour): its
   properties are numbered apart ([agent_only]). The handler and every
   routine it calls share one numbering of the cells, so that one array of
   cells per instance serves them all. *)
type cenv = {
  env : T.t;
  bname : string;
  aname : string;
  locals : (string, int) Hashtbl.t;  (* this code's own *)
  props : (string * bool, int) Hashtbl.t;  (* by name and [agent_only] *)
  declared : string list;          (* the properties the code may name *)
  agent_declared : string list;    (* the agent's *)
  all_declared : string list;      (* the behaviour's, then the agent's *)
  prop_names : (string * bool) list ref;  (* by number, newest first *)
  agent_only : bool;               (* an agent's function or procedure *)
  in_guard : bool;
  routines : (T.routine * bool * routine) list ref;
      (* the functions and procedures compiled for this handler, each once *)
}

(* A function or procedure compiled (filled in once its body is: a
   recursive call finds it unfinished at compile time, finished when it
   runs). *)
and routine = {
  mutable run : ctx -> unit;
  mutable nslots : int;
  mutable params : int array;      (* the parameters' slots, in order *)
}

let slot_of ce x =
  match Hashtbl.find_opt ce.locals x with
  | Some i -> i
  | None -> let i = Hashtbl.length ce.locals in Hashtbl.replace ce.locals x i; i

let prop_of ce x =
  if not (List.mem x ce.declared) then None
  else
    let key = (x, ce.agent_only) in
    match Hashtbl.find_opt ce.props key with
    | Some j -> Some j
    | None ->
      let j = Hashtbl.length ce.props in
      Hashtbl.replace ce.props key j; ce.prop_names := key :: !(ce.prop_names); Some j

let is_var ce x = T.schema ce.env x = None

(* The schema name [x] as the type environment spells it, when that is the
   same text: the string percept values are usually built with
   (Eval.percept_value), so that most comparisons are one of addresses. *)
let interned env x = match T.schema env x with
  | Some s when String.equal s.s_name x -> s.s_name
  | _ -> x

(* The names that may become locals: pattern variables, [x as T = e],
   [for x in], and [x = e] where x is no property. *)
let rec scan_pattern ce (p : Ast.pattern) = match p.it with
  | PName x when is_var ce x -> ignore (slot_of ce x)
  | PCons (_, ps) -> List.iter (scan_pattern ce) ps
  | _ -> ()

let rec scan_expr ce (e : Ast.expr) = match e.it with
  | Matches (x, p) -> scan_expr ce x; scan_pattern ce p
  | List es | Call (_, es) -> List.iter (scan_expr ce) es
  | Map kvs -> List.iter (fun (k, v) -> scan_expr ce k; scan_expr ce v) kvs
  | Index (a, b) | Binop (_, a, b) -> scan_expr ce a; scan_expr ce b
  | Of (_, x) | Unop (_, x) -> scan_expr ce x
  | Invoke i -> scan_expr ce i.target; List.iter (scan_expr ce) i.args
  | Lit _ | Name _ | This | Agent | Content | Message -> ()

let rec scan_block ce b = List.iter (scan_stmt ce) b
and scan_stmt ce (s : Ast.stmt) = match s.it with
  | Assign (lv, e) ->
    scan_expr ce e;
    (match lv.it with
     | LName x -> if not (List.mem x ce.declared) then ignore (slot_of ce x)
     | LOf (_, e) -> scan_expr ce e
     | LIndex (a, b) -> scan_expr ce a; scan_expr ce b)
  | Local (x, _, e) -> scan_expr ce e; ignore (slot_of ce x.it)
  | For (x, e, b) -> scan_expr ce e; ignore (slot_of ce x.it); scan_block ce b
  | If (bs, els) ->
    List.iter (fun (c, b) -> scan_expr ce c; scan_block ce b) bs;
    Option.iter (scan_block ce) els
  | While (c, b) -> scan_expr ce c; scan_block ce b
  | Log e -> scan_expr ce e
  | Return (Some e) -> scan_expr ce e
  | _ -> ()

(* Reading a name: Eval.lookup, resolved. *)
let name ce at x : ctx -> V.t =
  match Hashtbl.find_opt ce.locals x, prop_of ce x with
  | Some i, Some j -> fun c -> let v = Array.unsafe_get c.slots i in if v != unset then v else c.cells.(j).Eval.v
  | Some i, None when ce.agent_only ->
    fun c -> let v = Array.unsafe_get c.slots i in if v != unset then v else Eval.lookup c.rsf at x
  | Some i, None -> fun c -> let v = Array.unsafe_get c.slots i in if v != unset then v else Eval.lookup c.sf at x
  | None, Some j -> fun c -> c.cells.(j).Eval.v
  | None, None ->
    match T.schema ce.env x with
    | Some s when s.s_slots = [] ->
      let v = V.Schema { sname = s.s_name; slots = [||] } in fun _ -> v
    | _ -> raise Unsupported

(* Binding a pattern variable (Eval's local_set). *)
let bind ce x = match Hashtbl.find_opt ce.locals x with
  | Some i -> i
  | None -> raise Unsupported

(* The messages of the rules written inline in Eval.expr and Eval.stmt
   (eval.ml), word for word. *)
let not_boolean at what v = Eval.err at "%s needs booleans, not a %s" what (V.type_name v)
let condition_not_boolean at v = Eval.err at "a condition is a boolean, not a %s" (V.type_name v)
let too_deep at =
  raise (Eval.Exhaustion (at, Printf.sprintf "recursion too deep: more than %d nested calls of functions and procedures"
                            Eval.max_call_depth))

(* The function or procedure a name calls from this code (Eval.call,
   Eval.stmt's Do): the behaviour's, then the agent's; from an agent's
   routine, the agent's only. *)
let resolve ce ~beh ~agent name =
  if ce.agent_only then Option.map (fun r -> (r, true)) (agent ce.env ce.aname name)
  else match beh ce.env ce.bname name with
    | Some r -> Some (r, false)
    | None -> Option.map (fun r -> (r, true)) (agent ce.env ce.aname name)

let empty_slots : V.t array = [||]

let[@inline] tick c at = Eval.tick c.sf at

(* The arguments of a call, as Eval.run_routine takes them. *)
type args = Pos of (ctx -> V.t) list | Named of (string * (ctx -> V.t)) list

let rec expr ce (e : Ast.expr) : ctx -> V.t =
  let at = e.at in
  match e.it with
  | Lit l -> let v = Eval.literal l in fun _ -> v
  | Name x -> name ce at x
  | This when ce.agent_only -> fun c -> V.Agent_ref c.ag.Eval.name
  | This -> fun c -> V.Behaviour_ref c.beh.Eval.uid
  | Agent -> fun c -> V.Agent_ref c.ag.Eval.name
  | Content when ce.agent_only -> raise Unsupported   (* the checker rejects it *)
  | Content -> fun c -> c.content
  | Message -> raise Unsupported
  | List es ->
    let es = List.map (expr ce) es in
    fun c -> V.list_of (List.map (fun e -> e c) es)
  | Map kvs ->
    let kvs = List.map (fun (k, v) -> (expr ce k, expr ce v)) kvs in
    fun c ->
      let m = V.map_empty () in
      (match m with
       | V.Map mv ->
         List.iter (fun (k, v) ->
             let v = v c in            (* the value before its key *)
             let k = k c in
             try V.map_set mv k v with V.Too_large -> Eval.too_large_to_compare at) kvs
       | _ -> ());
      m
  | Call (g, args) when resolve ce ~beh:T.behaviour_function ~agent:T.agent_function g.it <> None ->
    (* a guard's budget is not reset by the entry points: calls, which
       tick, are compiled in bodies only *)
    if ce.in_guard then raise Unsupported;
    let (r, agent_only) = Option.get (resolve ce ~beh:T.behaviour_function ~agent:T.agent_function g.it) in
    call ce at r ~agent_only (Pos (List.map (expr ce) args))
  | Call (g, args) when g.it <> "aid" && (match T.schema ce.env g.it with
      | Some s -> List.length s.s_slots = List.length args | None -> false) ->
    (* Eval.construct with the schema found now: the arguments in order,
       then each slot converted (R1c), the first that does not fit an
       error *)
    let s = Option.get (T.schema ce.env g.it) and name = g.it in
    let spec = Array.of_list s.s_slots and sname = s.s_name in
    (* a value already of the slot's type is the one coerce_param keeps *)
    let same = Array.map (fun (_, ty) -> match Ty.repr ty with
        | Ty.Double -> 1 | Ty.Text -> 2 | Ty.Integer -> 3 | Ty.Boolean -> 4 | _ -> 0) spec in
    let slot i v =
      let (n, ty) = Array.unsafe_get spec i in
      match Array.unsafe_get same i, v with
      | 1, V.Double _ | 2, V.Text _ | 3, V.Int _ | 4, V.Bool _ -> (n, ref v)
      | _ ->
        match Eval.coerce_param ty v with
        | Some v -> (n, ref v)
        | None -> Eval.err at "slot %s of %s is a %s, not a %s" n name (Ty.to_string ty) (V.type_name v) in
    (match List.map (expr ce) args with
     | [ a ] -> fun c -> let v = a c in V.Schema { sname; slots = [| slot 0 v |] }
     | [ a; b ] ->
       fun c -> let v = a c in let w = b c in
         let s0 = slot 0 v in let s1 = slot 1 w in V.Schema { sname; slots = [| s0; s1 |] }
     | args ->
       let args = Array.of_list args in
       fun c ->
         let vs = Array.map (fun a -> a c) args in
         V.Schema { sname; slots = Array.mapi slot vs })
  | Call (g, args) ->
    let g = g.it and env = ce.env in
    let args = List.map (expr ce) args in
    fun c ->
      (match g, List.map (fun a -> a c) args with
       | "aid", [ V.Text n ] -> V.Aid n
       | "aid", [ V.Aid n ] -> V.Aid n
       | _, args -> Eval.construct env at g args)
  | Index (m, k) ->
    let m = expr ce m and k = expr ce k in
    fun c ->
      let mv = m c in
      let kv = k c in
      (match mv, kv with
       | V.List l, V.Int i ->
         if i < 0 || i >= l.len then Eval.err at "index %d is out of bounds (the list has %d elements)" i l.len;
         l.items.(i)
       | V.Map m, _ ->
         (match (try V.map_find m kv with V.Too_large -> Eval.too_large_to_compare at) with
          | Some v -> v
          | None -> Eval.err at "the map has no key %s" (V.to_literal kv))
       | _ -> Eval.err at "cannot index a %s" (V.type_name mv))
  | Of (p, x) when ce.agent_only -> let p = p.it and x = expr ce x in fun c -> Eval.of_ c.rsf at p (x c)
  | Of (p, x) -> let p = p.it and x = expr ce x in fun c -> Eval.of_ c.sf at p (x c)
  | Matches (x, p) -> matches ce x p
  | Unop (Not, x) ->
    let x = expr ce x in
    fun c -> (match x c with V.Bool b -> vbool (not b) | v -> Eval.err at "not needs a boolean, not a %s" (V.type_name v))
  | Unop (Neg, x) ->
    let x = expr ce x in
    fun c -> (match x c with
        | V.Int i -> V.int32 (- i) | V.Float x -> V.Float (-. x) | V.Double x -> V.Double (-. x)
        | v -> Eval.err at "cannot negate a %s" (V.type_name v))
  | Binop (And, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c -> (match l c with V.Bool false -> vfalse | V.Bool true -> r c | v -> not_boolean at "and" v)
  | Binop (Or, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c -> (match l c with V.Bool true -> vtrue | V.Bool false -> r c | v -> not_boolean at "or" v)
  (* Eval applies equal_values and compare_values to (expr f l) (expr f r):
     OCaml evaluates those arguments right to left, and so does this. *)
  | Binop (Eq, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c -> let b = r c in let a = l c in vbool (Eval.equal_values at a b)
  | Binop (Neq, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c -> let b = r c in let a = l c in vbool (not (Eval.equal_values at a b))
  | Binop ((Lt | Gt | Le | Ge) as op, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c -> let b = r c in let a = l c in Eval.compare_values at op a b
  | Binop (Add, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c ->
      let a = l c in
      let b = r c in
      (match a, b with
       | V.Int x, V.Int y -> V.int32 (x + y)   (* Eval.arith's integer case *)
       | V.Text _, _ | _, V.Text _ ->
         let a = V.to_text (Eval.bounded_text ~quote:false at a)
         and b = V.to_text (Eval.bounded_text ~quote:false at b) in
         if String.length a + String.length b > Eval.max_text then Eval.too_big at "the text would be too long";
         if String.length a + String.length b > 65536 then Eval.check_memory at;
         V.Text (a ^ b)
       | _ -> Eval.arith at Add a b)
  | Binop (op, l, r) ->
    let l = expr ce l and r = expr ce r in
    fun c -> let a = l c in let b = r c in Eval.arith at op a b
  | Invoke _ when ce.in_guard -> raise Unsupported
  | Invoke i -> invoke ce at i

(* Eval.invoke: the target, the arguments in order, then the rest. *)
and invoke ce at (i : Ast.invoke) =
  let target = expr ce i.target and args = List.map (expr ce) i.args in
  fun c ->
    let t = target c in
    let vs = List.map (fun a -> a c) args in
    Eval.invoke_values c.ag at i t vs

(* A call of a function or procedure, as Eval.run_routine: the arguments
   (evaluated by the caller, in order), a tick at the call, the depth, the
   arguments against the parameters, then the body in fresh slots with the
   parameters converted to their types; what it returns ([V.Unit] when it
   ends without a value). The caller's slots and depth are put back however
   it ends. *)
and call ce at (r : T.routine) ~agent_only (args : args) : ctx -> V.t =
  let k = routine_code ce r ~agent_only in
  let params = Array.of_list r.r_params in
  let np = Array.length params in
  (* which argument each parameter takes, or the error *)
  let (eval_args, pick, mismatch) = match args with
    | Pos es ->
      let es = Array.of_list es in
      let n = Array.length es in
      ((fun c -> Array.map (fun e -> e c) es), Array.init np Fun.id,
       if n <> np then Some (fun () -> Eval.err at "%s takes %d arguments, not %d" r.r_name np n) else None)
    | Named kvs ->
      let names = Array.of_list (List.map fst kvs) and es = Array.of_list (List.map snd kvs) in
      let first n =
        let rec go i = if i >= Array.length names then -1 else if String.equal names.(i) n then i else go (i + 1) in
        go 0 in
      let pick = Array.map (fun (n, _) -> first n) params in
      let missing = List.find_opt (fun (n, _) -> first n < 0) r.r_params in
      ((fun c -> Array.map (fun e -> e c) es), pick,
       Option.map (fun (n, _) -> fun () -> Eval.err at "missing argument %s" n) missing) in
  let tys = Array.map snd params in
  fun c ->
    let vs = eval_args c in
    tick c at;
    if c.depth >= Eval.max_call_depth then too_deep at;
    (match mismatch with Some e -> e () | None -> ());
    let slots = if k.nslots = 0 then empty_slots else Array.make k.nslots unset in
    let ps = k.params in
    for i = 0 to np - 1 do
      Array.unsafe_set slots (Array.unsafe_get ps i)
        (Eval.coerce (Array.unsafe_get tys i) (Array.unsafe_get vs (Array.unsafe_get pick i)))
    done;
    let saved = c.slots in
    c.slots <- slots;
    c.depth <- c.depth + 1;
    match k.run c with
    | () -> c.slots <- saved; c.depth <- c.depth - 1; V.Unit
    | exception Ret -> c.slots <- saved; c.depth <- c.depth - 1; c.ret
    | exception x -> c.slots <- saved; c.depth <- c.depth - 1; raise x

(* A routine's code, compiled once per handler (memoised; a recursive call
   finds the entry made before its body is compiled). *)
and routine_code ce (r : T.routine) ~agent_only =
  match List.find_opt (fun (r', a, _) -> r' == r && a = agent_only) !(ce.routines) with
  | Some (_, _, k) -> k
  | None ->
    let k = { run = (fun _ -> ()); nslots = 0; params = [||] } in
    ce.routines := (r, agent_only, k) :: !(ce.routines);
    let ce' = { ce with locals = Hashtbl.create 8; agent_only; in_guard = false;
                        declared = (if agent_only then ce.agent_declared else ce.all_declared) } in
    let params = Array.of_list (List.map (fun (n, _) -> slot_of ce' n) r.r_params) in
    scan_block ce' r.r_body;
    let run = block ce' r.r_body in
    k.run <- run; k.params <- params; k.nslots <- Hashtbl.length ce'.locals;
    k

(* [x matches p]: Eval.pattern, the bindings made only when it matches, in
   order. A constructor pattern of variables and [_] on a value of that
   very schema binds by position, which is what Eval.pattern does there. *)
and matches ce x (p : Ast.pattern) =
  let x = expr ce x in
  let test = pattern_test ce p in
  fun c -> vbool (test c (x c))

(* Whether a value matches [p] (Eval.pattern), the bindings made only
   when it does, in order. *)
and pattern_test ce (p : Ast.pattern) : ctx -> V.t -> bool =
  let general c v =
    let binds = ref [] in
    if Eval.pattern c.sf binds p v then begin
      List.iter (fun (y, v) -> c.slots.(bind ce y) <- v) (List.rev !binds); true
    end else false in
  (* the slots the variables bind, checked now (bind raises Unsupported) *)
  let rec check (p : Ast.pattern) = match p.it with
    | PName y when is_var ce y -> ignore (bind ce y)
    | PCons (_, ps) -> List.iter check ps
    | _ -> () in
  check p;
  let var (q : Ast.pattern) = match q.it with
    | PWild -> Some (-1)
    | PName y when is_var ce y -> Some (bind ce y)
    | _ -> None in
  match p.it with
  | PCons (k, ps) when List.for_all (fun q -> var q <> None) ps ->
    let k = interned ce.env k.it and vars = Array.of_list (List.map (fun q -> Option.get (var q)) ps) in
    let n = Array.length vars in
    if n = 1 && vars.(0) >= 0 then begin
      (* one variable, the common [content matches S(x)] *)
      let j = vars.(0) in
      fun c v ->
        (match v with
         | V.Schema { sname; slots = [| (_, r) |] } when sname == k || String.equal sname k ->
           Array.unsafe_set c.slots j !r; true
         | v -> general c v)
    end else
    fun c v ->
      (match v with
       | V.Schema s ->
         if (s.sname == k || String.equal s.sname k) && Array.length s.slots = n then begin
           for i = 0 to n - 1 do
             let j = Array.unsafe_get vars i in
             if j >= 0 then c.slots.(j) <- !(snd (Array.unsafe_get s.slots i))
           done;
           true
         end else general c v
       | v -> general c v)
  | PName k when not (is_var ce k) ->
    (* a schema: the value's own is Eval.pattern's first case *)
    let k = interned ce.env k in
    fun c v ->
      (match v with
       | V.Schema s -> if s.sname == k || String.equal s.sname k then true else general c v
       | v -> general c v)
  | _ -> general

and block ce (b : Ast.block) : ctx -> unit =
  match List.map (stmt ce) b with
  | [] -> fun _ -> ()
  | [ s ] -> s
  | [ s1; s2 ] -> fun c -> s1 c; s2 c
  | ss -> let ss = Array.of_list ss in fun c -> Array.iter (fun s -> s c) ss

and stmt ce (s : Ast.stmt) : ctx -> unit =
  let at = s.at in
  match s.it with
  | Assign (({ it = LName x; _ } as lv), e) ->
    (* the common places, each one closure *)
    let e = expr ce e in
    (match Hashtbl.find_opt ce.locals x, prop_of ce x with
     | Some i, None -> fun c -> tick c at; let v = e c in Array.unsafe_set c.slots i v
     | None, Some j -> fun c -> tick c at; let v = e c in Eval.set_cell (Array.unsafe_get c.cells j) v
     | _ -> let a = assign ce lv in fun c -> tick c at; a c (e c))
  | Assign ({ it = LIndex (m, k); at = lat }, e) ->
    let e = expr ce e and m = expr ce m and k = expr ce k in
    fun c ->
      tick c at;
      let v = e c in
      let mv = m c in
      let kv = k c in
      (match mv, kv with
       | V.Map mm, _ -> Eval.map_set_bounded lat mm kv v
       | V.List l, V.Int i ->
         if i < 0 || i >= l.len then Eval.err lat "index %d is out of bounds (the list has %d elements)" i l.len;
         l.items.(i) <- v
       | _ -> Eval.err lat "cannot index a %s" (V.type_name mv))
  | Assign (lv, e) -> let e = expr ce e in let a = assign ce lv in fun c -> tick c at; a c (e c)
  | Local (x, ty, e) ->
    let e = expr ce e and i = slot_of ce x.it in
    (match ty.it with
     | TName "float" -> fun c -> tick c at; c.slots.(i) <- Eval.coerce Ty.Float (e c)
     | TName "double" -> fun c -> tick c at; c.slots.(i) <- Eval.coerce Ty.Double (e c)
     | _ -> fun c -> tick c at; c.slots.(i) <- e c)
  | Nothing -> fun c -> tick c at
  | Deactivate when ce.agent_only -> raise Unsupported   (* the checker rejects it *)
  | Deactivate ->
    fun c ->
      tick c at;
      let a = c.ag in
      if List.mem Semantics.Machine.Deactivate a.effects then ()   (* R5h: once *)
      else begin
        a.effects <- Semantics.Machine.Deactivate :: a.effects;
        a.live <- a.live - 1;   (* D19 *)
        a.events <- Eval.Deactivated c.id :: a.events
      end
  | Log e ->
    let e = expr ce e and at_e = e.at in
    fun c ->
      tick c at;
      let v = Eval.bounded_text ~quote:false at_e (e c) in
      c.ag.events <- Eval.Log (V.to_text v) :: c.ag.events
  | If (branches, els) ->
    let branches = List.map (fun ((k : Ast.expr), b) -> (expr ce k, k.at, block ce b)) branches in
    let els = match els with Some b -> block ce b | None -> fun _ -> () in
    let rec go c = function
      | [] -> els c
      | (k, kat, b) :: rest ->
        (match k c with
         | V.Bool true -> b c
         | V.Bool false -> go c rest
         | v -> condition_not_boolean kat v) in
    fun c -> tick c at; go c branches
  | While (k, b) ->
    let k = expr ce k and kat = k.at and b = block ce b in
    let rec loop c =
      match k c with
      | V.Bool true ->
        (match b c with () -> () | exception Cont -> ());
        tick c at; loop c
      | V.Bool false -> ()
      | v -> condition_not_boolean kat v in
    fun c -> tick c at; (try loop c with Brk -> ())
  | For (x, e, b) ->
    let i = slot_of ce x.it and e = expr ce e and eat = e.at and b = block ce b in
    fun c ->
      tick c at;
      let items = match e c with
        | V.List l -> V.list_items l
        | V.Map m -> List.map fst (V.map_bindings m)
        | v -> Eval.err eat "cannot iterate over a %s" (V.type_name v) in
      (try List.iter (fun v ->
           c.slots.(i) <- v;
           tick c at;
           match b c with () -> () | exception Cont -> ()) items
       with Brk -> ())
  | Return None -> fun c -> tick c at; c.ret <- V.Unit; raise Ret
  | Return (Some e) -> let e = expr ce e in fun c -> tick c at; c.ret <- e c; raise Ret
  | Break -> fun c -> tick c at; raise Brk
  | Continue -> fun c -> tick c at; raise Cont
  | Do (p, args) ->
    (match resolve ce ~beh:T.behaviour_procedure ~agent:T.agent_procedure p.it with
     | None -> raise Unsupported   (* the checker rejects it *)
     | Some (r, agent_only) ->
       let args = match args with
         | Positional es -> Pos (List.map (expr ce) es)
         | Named kvs -> Named (List.map (fun ((n : Ast.name), e) -> (n.it, expr ce e)) kvs) in
       let k = call ce at r ~agent_only args in
       fun c -> tick c at; ignore (k c))
  | InvokeS i -> let k = invoke ce at i in fun c -> tick c at; ignore (k c)
  | Activate (b, args) ->
    let b = b.it and args = List.map (fun ((n : Ast.name), e) -> (n.it, expr ce e)) args in
    fun c ->
      tick c at;
      let kvs = List.map (fun (n, e) -> (n, e c)) args in
      Eval.activate_at c.sf ~depth:c.depth at b kvs
  | Send (perf, k, rs) ->
    (* Eval.stmt's Send: the content, then each receiver in order *)
    let perf = perf.it and kat = k.at and k = expr ce k
    and rs = List.map (fun (r : Ast.expr) -> (expr ce r, r.at)) rs in
    fun c ->
      tick c at;
      let content = Eval.bounded_text ~quote:true kat (k c) in
      let receivers = List.concat_map (fun (r, rat) -> Eval.receivers_of rat (r c)) rs in
      Eval.post_send c.ag perf content receivers

(* Eval.assign: the value is computed first, then the place. *)
and assign ce (lv : Ast.lvalue) : ctx -> V.t -> unit =
  let at = lv.at in
  match lv.it with
  | LName x ->
    (match Hashtbl.find_opt ce.locals x, prop_of ce x with
     | Some i, Some j ->
       fun c v -> if c.slots.(i) != unset then c.slots.(i) <- v else Eval.set_cell c.cells.(j) v
     | Some i, None -> fun c v -> c.slots.(i) <- v
     | None, Some j -> fun c v -> Eval.set_cell c.cells.(j) v
     | None, None -> raise Unsupported)
  | LIndex (m, k) ->
    let m = expr ce m and k = expr ce k in
    fun c v ->
      let mv = m c in
      let kv = k c in
      (match mv, kv with
       | V.List l, V.Int i ->
         if i < 0 || i >= l.len then Eval.err at "index %d is out of bounds (the list has %d elements)" i l.len;
         l.items.(i) <- v
       | V.Map m, _ -> Eval.map_set_bounded at m kv v
       | _ -> Eval.err at "cannot index a %s" (V.type_name mv))
  | LOf (p, e) ->
    let p = p.it and e = expr ce e in
    fun c v ->
      (match e c with
       | V.Schema s -> (Eval.slot at s p) := v
       | V.Agent_ref _ as o ->
         (match Names.find_opt c.ag.props p with
          | Some cell -> Eval.set_cell cell v
          | None -> Eval.err at "cannot set %s of a %s" p (V.type_name o))
       | V.Behaviour_ref _ when ce.agent_only -> Eval.err at "no such behaviour property %s" p
       | V.Behaviour_ref u ->
         (match Names.find_opt c.beh.bprops p with
          | Some cell when c.beh.uid = u -> Eval.set_cell cell v
          | _ -> Eval.err at "no such behaviour property %s" p)
       | o -> Eval.err at "cannot set %s of a %s" p (V.type_name o))

(* ------------------------------------------------------- handlers *)

(* A handler compiled for a behaviour type and an agent type. *)
type code = {
  nslots : int;
  reset : int array;
      (* the slots a guard must find without a value: all but those its
         leftmost [content matches S(x, ...)] binds whenever it holds *)
  prop_names : (string * bool) array;
      (* the cells a run needs, by number: the name, and whether an agent's
         routine names it (the agent's property, not the behaviour's) *)
  guard : (ctx -> bool) option;
  body : ctx -> unit;
  required : string option;
      (* the pre-test, as Interp_bodies': the schema the guard's leftmost
         conjunct requires of content *)
}

let rec required_schema (e : Ast.expr) = match e.it with
  | Matches ({ it = Content; _ }, { it = PCons (c, _); _ }) -> Some c.it
  | Matches ({ it = Content; _ }, { it = PName x; _ }) -> Some x
  | Binop (And, l, _) -> required_schema l
  | _ -> None

let compile env (bt : T.behaviour) (at : T.agent) (h : T.handler) : code option =
  let agent_declared = List.map (fun (p : T.property) -> p.p_name) (T.agent_properties env at.a_name) in
  let declared =
    List.map (fun (p : T.property) -> p.p_name) (T.behaviour_properties env bt.b_name) @ agent_declared in
  let ce = { env; bname = bt.b_name; aname = at.a_name; locals = Hashtbl.create 8;
             props = Hashtbl.create 8; declared; agent_declared; all_declared = declared; prop_names = ref [];
             agent_only = false; in_guard = false; routines = ref [] } in
  match
    Option.iter (scan_expr ce) h.h_guard;
    scan_block ce h.h_body;
    let guard = match h.h_guard with
      | None -> None
      | Some { it = Matches ({ it = Content; _ }, p); _ } ->
        (* the common guard: the percept matched as it is, a boolean at once *)
        let test = pattern_test { ce with in_guard = true } p in
        Some (fun c -> test c c.content)
      | Some g ->
        let x = expr { ce with in_guard = true } g and gat = g.at in
        Some (fun c -> match x c with
            | V.Bool b -> b
            | v -> Eval.err gat "a when condition is a boolean, not a %s" (V.type_name v)) in
    let body = block ce h.h_body in
    (guard, body)
  with
  | exception Unsupported -> None
  | (guard, body) ->
    let required = match h.h_guard with
      | None -> None
      | Some g -> (match required_schema g with
          | Some x when T.schema env x <> None -> Some (interned env x)
          | _ -> None) in
    (* the variables of the guard's leftmost conjunct, when that is
       [content matches S(x1, ...)]: bound by any percept it holds for *)
    let rec head (e : Ast.expr) = match e.it with
      | Matches ({ it = Content; _ }, { it = PCons (_, ps); _ }) ->
        List.filter_map (fun (q : Ast.pattern) -> match q.it with
            | PName y when is_var ce y -> Some (bind ce y) | _ -> None) ps
        @ (if List.for_all (fun (q : Ast.pattern) -> match q.it with
            | PWild -> true | PName y -> is_var ce y | _ -> false) ps then [] else [ -1 ])
      | Binop (And, l, _) -> head l
      | _ -> [ -1 ] in
    let bound = match h.h_guard with Some g -> head g | None -> [] in
    let n = Hashtbl.length ce.locals in
    let reset = if List.mem (-1) bound then Array.init n Fun.id
      else Array.of_list (List.filter (fun i -> not (List.mem i bound)) (List.init n Fun.id)) in
    Some { nslots = n; reset; prop_names = Array.of_list (List.rev !(ce.prop_names));
           guard; body; required }

(* Handlers compiled, by the handler, the behaviour type and the agent type
   (all by address: a handler inherited by a behaviour type is the very one
   of its super type, and means something else where the subtype declares
   more properties): a behaviour activated many times is compiled once. The
   newest few are kept. *)
let compiled : (T.handler * T.behaviour * T.agent * code option) list ref = ref []
let cache_size = 64

let code_for env bt at h =
  let rec find = function
    | [] -> None
    | (h', b', a', c) :: rest -> if h' == h && b' == bt && a' == at then Some c else find rest in
  match find !compiled with
  | Some c -> c
  | None ->
    let c = compile env bt at h in
    compiled := (h, bt, at, c) :: List.filteri (fun i _ -> i < cache_size - 1) !compiled;
    c

(* What one handler of an instance runs: compiled, or Interp_bodies'. *)
type handler = Compiled of code * ctx | Fallback

(* Kept with the instance (Eval.keep): its handlers, and what
   Interp_bodies keeps there for the handlers that fall back, which is put
   back in place while they run. *)
type kept = {
  handlers : handler array;
  req : string array;
      (* per handler, the schema its pre-test requires of content, or
         {!no_pretest}, or {!falls_back} *)
  memo : (string * bool) list array;
      (* per handler, the pre-test's answer per percept type, by the type
         name's address (the lexer and the type environment intern names) *)
  mutable inner : Eval.engine_slot;
  mutable self : Eval.engine_slot;
}
type Eval.engine_slot += Kept of kept

(* The cell of property x for the instance: Eval.prop_cell's answer. *)
let cell_of (a : Eval.agent) (b : Eval.beh) x =
  match Names.find_opt b.bprops x with
  | Some _ as c -> c
  | None -> Names.find_opt a.props x

let make_ctx (a : Eval.agent) (b : Eval.beh) ~id (code : code) =
  let cells = Array.map (fun (x, agent_only) ->
      if agent_only then Names.find_opt a.props x else cell_of a b x) code.prop_names in
  if Array.exists Option.is_none cells then None   (* an initialiser failed: fall back *)
  else
    let sf = Eval.guard_frame a ~id b V.Unit in
    Some { ag = a; beh = b; slots = Array.make code.nslots unset; cells = Array.map Option.get cells;
           content = V.Unit; sf; id; armed = -1;
           yes = (a, true); no = (a, false); ran = (a, []);
           skipped = Fast.Not_applicable a; handled = Fast.Handled (a, []);
           rsf = Eval.agent_frame sf; depth = 0; ret = V.Unit }

(* Interp_bodies on the instance, its own slot in place. *)
let with_inner (b : Eval.beh) k f =
  Eval.keep b k.inner;
  match f () with
  | r -> k.inner <- b.kept; Eval.keep b k.self; r
  | exception x -> k.inner <- b.kept; Eval.keep b k.self; raise x

(* Marks in [req] (compared by address). *)
let no_pretest = String.make 1 '-'
let falls_back = String.make 1 '*'

let install (a : Eval.agent) ~id (b : Eval.beh) =
  let handlers = Array.map (fun h ->
      match code_for a.env b.btype a.atype h with
      | None -> Fallback
      | Some code -> (match make_ctx a b ~id code with Some c -> Compiled (code, c) | None -> Fallback))
      b.phandlers in
  let req = Array.map (function
      | Compiled ({ required = Some x; _ }, _) -> x
      | Compiled ({ required = None; _ }, _) -> no_pretest
      | Fallback -> falls_back) handlers in
  let k = { handlers; req; memo = Array.map (fun _ -> []) handlers; inner = b.kept; self = Eval.Nothing_kept } in
  k.self <- Kept k;
  Eval.keep b k.self;
  k

let[@inline] kept a ~id (b : Eval.beh) = match b.kept with Kept k -> k | _ -> install a ~id b

(* ----------------------------------------------------- the bodies *)

include (Interp_bodies : Semantics.Machine.BODIES
         with type percept = V.t and type message = Eval.message and type obj = V.t
          and type beh = Eval.beh and type world = Eval.agent)

(* Interp_bodies' pre-test, on this instance's own memo: [false] only
   where the guard's leftmost [content matches S...] is surely false, with
   no effect. *)
let may_apply_slow (a : Eval.agent) b k h p =
  let x = k.req.(h - 1) in
  if x == falls_back then with_inner b k (fun () -> Interp_bodies.percept_may_apply a b h p)
  else if x == no_pretest then true
  else match p with
    | V.Schema { sname = n; _ } ->
      let memo = k.memo.(h - 1) in
      (match List.find_opt (fun (m, _) -> String.equal m n) memo with
       | Some (_, r) -> r
       | None ->
         let r = String.equal x n || T.subschema a.env n x in
         k.memo.(h - 1) <- (n, r) :: memo; r)
    | _ -> true

let rec memo_by_address n = function
  | (m, r) :: rest -> if m == n then (if r then 1 else 0) else memo_by_address n rest
  | [] -> -1

let percept_may_apply a (b : Eval.beh) h p =
  match b.kept, p with
  | Kept k, V.Schema { sname = n; _ } ->
    n == k.req.(h - 1)
    || (match memo_by_address n (Array.unsafe_get k.memo (h - 1)) with   (* as long as [req] *)
        | 1 -> true
        | 0 -> false
        | _ -> may_apply_slow a b k h p)
  | Kept k, _ -> may_apply_slow a b k h p
  | _, _ -> may_apply_slow a b (kept a ~id:0 b) h p

(* Its answer depends on the schema's name, the behaviour and the handler
   only: the kinds are the interpreter's (Fast.BODIES.percept_kind). *)
let percept_kind = Interp_bodies.percept_kind

(* Guards evaluated so far, compiled or not. A compiled guard that holds
   records the number of its own evaluation; its bindings are still waiting
   for the body when no guard was evaluated since (what [a.pending] says in
   the reference: the machine runs a body right after its guard, in the same
   rule, on the same agent). D38. *)
let guards = ref 0

(* A compiled guard on percept [p]: what the reference leaves in
   [a.pending] for a body of another handler is nothing it can use (the
   bindings wait here), the slots its head does not bind start empty; an
   error makes it false and is recorded. *)
let[@inline] guard_holds (a : Eval.agent) ~id code c p =
  (match a.pending with None -> () | Some _ -> a.pending <- None);
  let reset = code.reset in
  for i = 0 to Array.length reset - 1 do
    Array.unsafe_set c.slots (Array.unsafe_get reset i) unset
  done;
  c.content <- p;
  c.id <- id;
  match code.guard with
  | None -> true
  | Some g -> (try g c with x when Eval.record_error a x -> false)

(* A compiled body, on a fresh step budget; an error ends it, recorded. *)
let[@inline] run_body (a : Eval.agent) code c =
  Eval.reset_fuel c.sf;
  try code.body c with
  | Ret | Brk | Cont -> ()
  | x -> Eval.recover a x

(* R3b, as Eval.Bodies.percept_applicable: the guard in fresh locals; an
   error makes the handler not applicable and is recorded. No pre-test
   here: a guard whose leftmost [content matches S...] is false is false at
   once, with no effect, as the pre-test would answer. *)
let percept_applicable (a : Eval.agent) ~id (b : Eval.beh) h p =
  let k = kept a ~id b in
  incr guards;
  match k.handlers.(h - 1) with
  | Fallback -> with_inner b k (fun () -> Interp_bodies.percept_applicable a ~id b h p)
  | Compiled (code, c) ->
    let ok = guard_holds a ~id code c p in
    c.armed <- (if ok then !guards else -1);
    if c.ag != a then (a, ok) else if ok then c.yes else c.no

(* The body in the guard's bindings when they wait for it, else in fresh
   locals (Eval.Bodies.run_percept_handler); a fresh step budget. *)
let run_percept_handler (a : Eval.agent) ~id (b : Eval.beh) h p =
  let k = kept a ~id b in
  match k.handlers.(h - 1) with
  | Fallback -> incr guards; with_inner b k (fun () -> Interp_bodies.run_percept_handler a ~id b h p)
  | Compiled (code, c) ->
    if c.armed = !guards && c.id = id && c.content == p then c.armed <- -1
    else begin
      (match a.pending with None -> () | Some _ -> a.pending <- None);
      Array.fill c.slots 0 (Array.length c.slots) unset;
      c.content <- p; c.id <- id
    end;
    incr guards;   (* the bindings are used once *)
    run_body a code c;
    match Eval.take_ran a h with
    | [] when c.ag == a -> c.ran
    | effs -> (a, effs)

(* The guard and, when it holds, the body at once (Fast.BODIES.percept_handle):
   what [percept_applicable] then [run_percept_handler] do, the bindings
   going straight from one to the other (the count of guards ends as
   theirs would: one for the guard, one for the bindings used). *)
let percept_handle (a : Eval.agent) ~id (b : Eval.beh) h p : (Eval.agent, Eval.beh) Fast.handled =
  let k = kept a ~id b in
  match k.handlers.(h - 1) with
  | Fallback -> Fast.handle_in_two percept_applicable run_percept_handler a ~id b h p
  | Compiled (code, c) ->
    incr guards;
    c.armed <- -1;
    if not (guard_holds a ~id code c p) then (if c.ag != a then Not_applicable a else c.skipped)
    else begin
      incr guards;
      run_body a code c;
      (* Eval.take_ran, which has nothing to do when the body had no
         effect and no Ran event is kept *)
      if a.effects == [] && not a.record_ran && c.ag == a then c.handled
      else match Eval.take_ran a h with
        | [] when c.ag == a -> c.handled
        | effs -> Handled (a, effs)
    end

let compiled_handlers a ~id b =
  let k = kept a ~id b in
  Array.fold_left (fun n -> function Compiled _ -> n + 1 | Fallback -> n) 0 k.handlers
