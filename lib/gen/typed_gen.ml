(* Well-typed random programs by construction (see typed_gen.mli). The
   generators are written against Random.State directly: a QCheck.Gen.t is a
   function of the random state. *)

open Syntax
open Ast
open Source

let ph x = { Source.it = x; at = Source.no_region }
let int rs n = Random.State.int rs n
let chance rs p = Random.State.float rs 1.0 < p
let pick rs l = List.nth l (int rs (List.length l))

(* The generator's own types: exactly the inferred types of what it emits. *)
type gty =
  | GInt | GDouble | GFloat | GText | GBool | GAid | GAny
  | GList of gty | GMap of gty * gty | GSchema of string

let rec ty_of = function
  | GInt -> ph (TName "integer") | GDouble -> ph (TName "double")
  | GFloat -> ph (TName "float") | GText -> ph (TName "text")
  | GBool -> ph (TName "boolean") | GAid -> ph (TName "aid") | GAny -> ph (TName "any")
  | GList t -> ph (TList (ty_of t))
  | GMap (k, v) -> ph (TMap (ty_of k, ty_of v))
  | GSchema s -> ph (TName s)

type schema_info = {
  sname : string;
  kind : schema_kind;
  slots : (string * gty) list;   (* all, inherited first *)
  percept : bool;
}

type env = {
  schemas : schema_info list;
  sources : (expr * gty) list;      (* readable: locals, properties, content... *)
  vars : (string * gty) list;       (* assignable by name *)
  funcs : (string * gty list * gty) list;
  procs : (string * gty list) list;
  float_ok : bool;                  (* a float value is at hand *)
  in_behaviour : string option;
  can_activate_c : (string * gty) list option;  (* C's on create parameters *)
  message : bool;
  real_props : (string * gty) list; (* double and float properties: an integer widens (R1c) *)
}

let counter = ref 0
let fresh p = incr counter; Printf.sprintf "%s%d" p !counter

let lit l = ph (Lit l)
let ilit n = lit (Int n)
let name x = ph (Name x)
let bin op a b = ph (Binop (op, a, b))

let texts = ["A7"; "qr-42"; "left"; "right"; "hello world"; ""]
let reals = ["0.5"; "1.5"; "2.25"; "10.0"; "3e-1"]

let sources_of env t = List.filter (fun (_, t') -> t' = t) env.sources

let schema env s = List.find (fun sc -> sc.sname = s) env.schemas

(* An expression whose inferred type is exactly [t]. *)
let rec expr rs env t d : expr =
  let leafy = d <= 0 || chance rs 0.3 in
  let srcs = sources_of env t in
  let from_source () = fst (pick rs srcs) in
  let slot_reads =
    List.concat_map (fun (e, st) -> match st with
        | GSchema s ->
          (try List.filter_map (fun (sl, slt) -> if slt = t then Some (ph (Of (ph sl, e))) else None)
                 (schema env s).slots with Not_found -> [])
        | _ -> []) env.sources in
  let calls = List.filter (fun (_, _, r) -> r = t) env.funcs in
  let options = ref [] in
  let add w f = options := (w, f) :: !options in
  if srcs <> [] then add 4 from_source;
  if slot_reads <> [] && not leafy then add 2 (fun () -> pick rs slot_reads);
  if calls <> [] && not leafy then
    add 1 (fun () -> let (f, ps, _) = pick rs calls in
            ph (Call (ph f, List.map (fun p -> arg rs env p (d / 2)) ps)));
  (match t with
   | GInt ->
     (* now and then an integer near the 32-bit bound, so that + - * wrap (D8) *)
     add 3 (fun () -> ilit (if chance rs 0.1 then pick rs [2147483647; 65536; 1000000007] else int rs 100));
     if not leafy then begin
       add 2 (fun () -> bin (pick rs [Add; Sub; Mul]) (expr rs env GInt (d - 1)) (expr rs env GInt (d - 1)));
       add 1 (fun () -> bin (pick rs [Div; Mod]) (expr rs env GInt (d - 1)) (ilit (1 + int rs 9)));
       add 1 (fun () -> ph (Of (ph "length", expr rs env GText (d - 1))));
       add 1 (fun () -> ph (Unop (Neg, expr rs env GInt (d - 1))));
       let lists = List.filter (fun (_, t) -> match t with GList _ | GMap _ -> true | _ -> false)
           env.sources in
       if lists <> [] then add 1 (fun () -> ph (Of (ph "size", fst (pick rs lists))))
     end
   | GDouble ->
     add 3 (fun () -> lit (Real (pick rs reals)));
     if not leafy then
       add 2 (fun () ->
           let a = expr rs env GDouble (d - 1) in
           let b = expr rs env (pick rs [GInt; GDouble]) (d - 1) in
           if chance rs 0.5 then bin (pick rs [Add; Sub; Mul]) a b else bin (pick rs [Add; Mul]) b a)
   | GFloat ->
     add 1 (fun () -> bin Mul (expr rs env GFloat (d - 1)) (expr rs env GInt (d - 1)));
     add 1 (fun () -> bin Add (expr rs env GFloat (d - 1)) (lit (Real (pick rs reals))))
   | GText ->
     add 3 (fun () -> lit (Text (pick rs texts)));
     if not leafy then
       add 2 (fun () -> bin Add (expr rs env GText (d - 1))
                 (expr rs env (pick rs [GText; GInt; GDouble; GBool]) (d - 1)))
   | GBool ->
     add 2 (fun () -> lit (Bool (chance rs 0.5)));
     if not leafy then begin
       add 2 (fun () -> bin (pick rs [Lt; Gt; Le; Ge; Eq; Neq])
                 (expr rs env GInt (d - 1)) (expr rs env GInt (d - 1)));
       add 1 (fun () -> bin (pick rs [Eq; Neq]) (expr rs env GText (d - 1)) (expr rs env GText (d - 1)));
       (* an integer compared with a real (R1c: 1 = 1.0 holds) *)
       add 1 (fun () ->
           let i = expr rs env GInt (d - 1) and r = expr rs env GDouble (d - 1) in
           let op = pick rs [Lt; Gt; Le; Ge; Eq; Neq] in
           if chance rs 0.5 then bin op i r else bin op r i);
       add 1 (fun () -> int_real_equal rs env);
       add 1 (fun () -> bin (pick rs [And; Or]) (expr rs env GBool (d - 1)) (expr rs env GBool (d - 1)));
       add 1 (fun () -> ph (Unop (Not, expr rs env GBool (d - 1))));
       let schema_srcs = List.filter (fun (_, t) -> match t with GSchema _ -> true | _ -> false)
           env.sources in
       if schema_srcs <> [] then
         add 1 (fun () ->
             let (e, st) = pick rs schema_srcs in
             let s = match st with GSchema s -> s | _ -> assert false in
             let sc = schema env s in
             ph (Matches (e, ph (PCons (ph s, List.map (fun _ -> ph PWild) sc.slots)))));
       if schema_srcs <> [] then add 1 (fun () -> schema_equal rs env (d - 1))
     end
   | GAid -> add 2 (fun () -> ph (Call (ph "aid", [lit (Text (pick rs ["Bob"; "provider"]))])))
   | GAny -> ()
   | GList a ->
     add 3 (fun () -> ph (List (List.init (1 + int rs 3) (fun _ -> expr rs env a (d - 1)))))
   | GMap (k, v) ->
     add 3 (fun () -> ph (Map (List.init (1 + int rs 2)
                                (fun _ -> (expr rs env k (d - 1), expr rs env v (d - 1))))))
   | GSchema s ->
     let sc = schema env s in
     add 3 (fun () -> if sc.slots = [] && chance rs 0.5 then name s
             else ph (Call (ph s, List.map (fun (_, t) -> arg rs env t (d - 1)) sc.slots))));
  let total = List.fold_left (fun a (w, _) -> a + w) 0 !options in
  let rec choose n = function
    | (w, f) :: rest -> if n < w then f () else choose (n - w) rest
    | [] -> assert false in
  choose (int rs total) !options

(* An argument for a slot, parameter or property of type [t]: for a double
   or a float, now and then an integer, which widens (R1c). *)
and arg rs env t d =
  match t with
  | (GDouble | GFloat) when chance rs 0.3 -> expr rs env GInt d
  | _ -> expr rs env t d

(* [e = e * 1.0] (or [<>]), [e] an integer: true by R1c (an integer equals
   the real of the same value). *)
and int_real_equal rs env =
  let e = expr rs env GInt 0 in
  let r = bin Mul e (lit (Real "1.0")) in
  let op = pick rs [Eq; Eq; Neq] in
  if chance rs 0.5 then bin op e r else bin op r e

(* A schema value compared with a copy of it made by its constructor from
   its own slots (R1c: equal by structure, not identity), or with another
   value of its type; [d]: the depth of that other value. *)
and schema_equal rs env d =
  let schema_srcs = List.filter (fun (_, t) -> match t with GSchema _ -> true | _ -> false)
      env.sources in
  let (e, st) = pick rs schema_srcs in
  let s = match st with GSchema s -> s | _ -> assert false in
  let sc = schema env s in
  let other =
    if chance rs 0.3 then expr rs env st d
    else if sc.slots = [] then name s
    else ph (Call (ph s, List.map (fun (sl, _) -> ph (Of (ph sl, e))) sc.slots)) in
  let op = pick rs [Eq; Eq; Neq] in
  if chance rs 0.5 then bin op e other else bin op other e

let data_types env =
  let base = [GInt; GDouble; GText; GBool; GAid; GList GInt; GList GText; GMap (GText, GInt)] in
  let schemas = List.filter_map (fun sc -> if sc.kind = Concept then Some (GSchema sc.sname) else None)
      env.schemas in
  base @ schemas @ (if env.float_ok then [GFloat] else [])

let add_local env x t =
  { env with sources = (name x, t) :: env.sources; vars = (x, t) :: env.vars }

(* A block of statements; [loop]: inside a for (break and continue allowed). *)
let rec block rs env ~loop d n : block =
  let rec go env k acc =
    if k = 0 then List.rev acc
    else
      let (s, env') = stmt rs env ~loop d in
      go env' (k - 1) (s :: acc) in
  go env (max 1 n) []

and stmt rs env ~loop d : stmt * env =
  let t = pick rs (data_types env) in
  let options = ref [] in
  let add w f = options := (w, f) :: !options in
  add 3 (fun () -> let x = fresh "v" in
          (ph (Assign (ph (LName x), expr rs env t 2)), add_local env x t));
  add 1 (fun () -> let x = fresh "v" in
          (ph (Local (ph x, ty_of t, arg rs env t 2)), add_local env x t));
  let assignable = List.filter (fun (_, t) -> t <> GAny) env.vars in
  if assignable <> [] then
    add 2 (fun () -> let (x, t) = pick rs assignable in
            (ph (Assign (ph (LName x), expr rs env t 2)), env));
  add 2 (fun () -> (ph (Log (expr rs env (pick rs [GText; GInt; GDouble]) 2)), env));
  if env.procs <> [] then
    add 2 (fun () ->
        let (p, ps) = pick rs env.procs in
        let args = List.map (fun t -> arg rs env t 1) ps in
        let a = if ps <> [] && chance rs 0.3 then
            Named (List.mapi (fun i e -> (ph (Printf.sprintf "a%d" (i + 1)), e)) args)
          else Positional args in
        (ph (Do (ph p, a)), env));
  let maps = List.filter (fun (_, t) -> match t with GMap _ -> true | _ -> false) env.sources in
  if maps <> [] then
    add 1 (fun () -> match pick rs maps with
        | (m, GMap (k, v)) -> (ph (Assign (ph (LIndex (m, expr rs env k 1)), expr rs env v 1)), env)
        | _ -> assert false);
  add 1 (fun () ->
      let q = pick rs (List.filter (fun sc -> sc.kind = Predicate || sc.kind = Proposition) env.schemas) in
      let c = expr rs env (GSchema q.sname) 1 in
      let r = if chance rs 0.5 then [expr rs env GAid 0]
        else [ph (List [expr rs env GAid 0; expr rs env GAid 0])] in
      (ph (Send (ph "inform", c, r)), env));
  if List.exists (fun (_, t) -> t = GAny) env.sources && chance rs 0.3 then
    add 1 (fun () ->
        let (target, _) = List.find (fun (_, t) -> t = GAny) env.sources in
        (ph (InvokeS { meth = ph "ping"; target; args = [expr rs env GInt 0] }), env));
  (match env.can_activate_c with
   | Some ps -> add 1 (fun () ->
       (ph (Activate (ph "C", List.map (fun (x, t) -> (ph x, arg rs env t 1)) ps)), env))
   | None -> ());
  (* R1c, shown in the trace: an integer widened into a double or float
     property, then the property logged; a schema value constructed with an
     integer for a double slot, logged; an integer compared with a real, and
     a schema value with a copy of it, the outcome logged *)
  if env.real_props <> [] then
    add 1 (fun () ->
        let (x, _) = pick rs env.real_props in
        (ph (If ([(lit (Bool true),
                   [ph (Assign (ph (LName x), expr rs env GInt 1));
                    ph (Log (bin Add (lit (Text (x ^ " "))) (name x)))])], None)), env));
  let with_real_slot = List.filter (fun sc -> List.exists (fun (_, t) -> t = GDouble) sc.slots)
      env.schemas in
  if with_real_slot <> [] then
    add 1 (fun () ->
        let sc = pick rs with_real_slot in
        let widened = ref false in
        let args = List.map (fun (_, t) ->
            if t = GDouble && not !widened then (widened := true; expr rs env GInt 1)
            else arg rs env t 1) sc.slots in
        (ph (Log (ph (Call (ph sc.sname, args)))), env));
  add 1 (fun () -> (ph (Log (bin Add (lit (Text "equal ")) (int_real_equal rs env))), env));
  if List.exists (fun (_, t) -> match t with GSchema _ -> true | _ -> false) env.sources then
    add 1 (fun () -> (ph (Log (bin Add (lit (Text "same ")) (schema_equal rs env 1))), env));
  if loop then add 1 (fun () ->
      (ph (If ([(expr rs env GBool 1, [ph (pick rs [Break; Continue])])], None)), env));
  if d > 0 then begin
    add 2 (fun () ->
        (* if, with a matches on a schema value binding variables in the then branch *)
        let schema_srcs = List.filter (fun (_, t) -> match t with GSchema _ -> true | _ -> false)
            env.sources in
        let (c, then_env) =
          if schema_srcs <> [] && chance rs 0.5 then
            let (e, st) = pick rs schema_srcs in
            let s = match st with GSchema s -> s | _ -> assert false in
            let sc = schema env s in
            let binds = List.map (fun (_, t) -> if chance rs 0.6 then Some (fresh "pv", t) else None)
                sc.slots in
            let pat = if sc.slots = [] then ph (PName s) else
                ph (PCons (ph s, List.map (function
                    | Some (x, _) -> ph (PName x) | None -> ph PWild) binds)) in
            let env' = List.fold_left (fun env -> function
                | Some (x, t) -> add_local env x t | None -> env) env binds in
            (ph (Matches (e, pat)), env')
          else (expr rs env GBool 2, env) in
        let b1 = block rs then_env ~loop (d - 1) (1 + int rs 2) in
        let elifs = if chance rs 0.3 then [(expr rs env GBool 1, block rs env ~loop (d - 1) 1)] else [] in
        let els = if chance rs 0.5 then Some (block rs env ~loop (d - 1) (1 + int rs 2)) else None in
        (ph (If ((c, b1) :: elifs, els)), env));
    let colls = List.filter (fun (_, t) -> match t with GList _ | GMap _ -> true | _ -> false)
        env.sources in
    add 1 (fun () ->
        let x = fresh "it" in
        let (coll, elt) =
          if colls <> [] && chance rs 0.7 then
            (match pick rs colls with
             | (e, GList a) -> (e, a) | (e, GMap (k, _)) -> (e, k) | _ -> assert false)
          else let a = pick rs [GInt; GText] in (expr rs env (GList a) 1, a) in
        (ph (For (ph x, coll, block rs (add_local env x elt) ~loop:true (d - 1) (1 + int rs 2))), env));
    add 1 (fun () ->
        (* a counting loop: terminates, whatever the body does (no continue) *)
        let i = fresh "i" in
        let env_i = add_local env i GInt in
        let body = block rs { env_i with vars = List.remove_assoc i env_i.vars } ~loop:false (d - 1)
            (1 + int rs 2) in
        let incr = ph (Assign (ph (LName i), bin Add (name i) (ilit 1))) in
        (ph (If ([(lit (Bool true),
                   [ph (Assign (ph (LName i), ilit 0));
                    ph (While (bin Lt (name i) (ilit (1 + int rs 3)), body @ [incr]))])], None)),
         env))
  end;
  let total = List.fold_left (fun a (w, _) -> a + w) 0 !options in
  let rec choose n = function
    | (w, f) :: rest -> if n < w then f () else choose (n - w) rest
    | [] -> assert false in
  choose (int rs total) !options

(* ------------------------------------------------------------ the program *)

let prim rs = pick rs [GInt; GDouble; GText; GBool]

let ontology rs =
  let concepts = List.init (1 + int rs 2) (fun i ->
      { sname = Printf.sprintf "c%d" (i + 1); kind = Concept; percept = false;
        slots = List.init (1 + int rs 2) (fun j -> (Printf.sprintf "f%d" (j + 1), prim rs)) }) in
  let q1 = { sname = "q1"; kind = Predicate; percept = true;
             slots = ("x", GDouble) :: List.init (int rs 3) (fun j -> (Printf.sprintf "s%d" (j + 1), prim rs)) } in
  let q2 = { sname = "q2"; kind = Predicate; percept = true;
             slots = q1.slots @ [("extra", prim rs)] } in
  let r1 = { sname = "r1"; kind = Proposition; percept = true; slots = [] } in
  let act1 = { sname = "act1"; kind = Action; percept = false;
               slots = ("n", GInt) :: (if chance rs 0.5 then [("what", GText)] else []) } in
  (* sometimes q3 extends q2 extends q1: a q1 pattern matches it through two
     extends (R1a) *)
  let q3 = if chance rs 0.5 then [{ sname = "q3"; kind = Predicate; percept = true; slots = q2.slots }] else [] in
  let infos = concepts @ [q1; q2] @ q3 @ [r1; act1] in
  let own sc super = match super with
    | Some p -> List.filter (fun (x, _) -> not (List.mem_assoc x p.slots)) sc.slots
    | None -> sc.slots in
  let mk sc super defaults =
    ph { kind = sc.kind; sname = ph sc.sname;
         slots = List.map (fun (x, t) -> { slot_name = ph x; slot_ty = ty_of t }) (own sc super);
         super = (match super, sc.percept with
             | Some p, _ -> Some (ph p.sname) | None, true -> Some (ph "percept") | _ -> None);
         defaults } in
  let prio () = [(ph "priority", ilit (int rs 11))] in
  let schemas =
    List.map (fun c -> mk c None []) concepts
    @ [mk q1 None (prio ()); mk q2 (Some q1) (if chance rs 0.5 then prio () else [])]
    @ List.map (fun q -> mk q (Some q2) []) q3
    @ [
       mk r1 None (prio ()); mk act1 None []] in
  (infos, ph (DOntology { oname = ph "Onto"; oextends = None; schemas }))

let param (x, t) = { pname = ph x; pty = ty_of t }

let program_rs rs =
  counter := 0;
  let (infos, onto) = ontology rs in
  let base = { schemas = infos; sources = []; vars = []; funcs = []; procs = [];
               float_ok = false; in_behaviour = None; can_activate_c = None; message = false;
               real_props = [] } in
  (* Agent properties. *)
  let fixed = [("count", GInt, Some (ilit (int rs 10)), true);
               ("ratio", GFloat, Some (lit (Real "1.5")), true);
               ("dist", GDouble, Some (lit (Real "0.0")), true);
               ("label", GText, Some (lit (Text "robot")), false);
               ("names", GList GText, Some (ph (List [lit (Text "a"); lit (Text "b")])), false);
               ("seen", GMap (GText, GInt), Some (ph (Map [])), false);
               ("iface", GAny, None, true)] in
  let extra = List.init (int rs 3) (fun _ ->
      let t = prim rs and typed = chance rs 0.5 in
      (* a typed property's initialiser may widen (R1c); an untyped one's
         type is its initialiser's *)
      (fresh "pr", t, Some ((if typed then arg else expr) rs base t 1), typed)) in
  let props = fixed @ extra in
  let prop_features = List.map (fun (x, t, init, typed) ->
      ph (Property { name = ph x; ty = (if typed then Some (ty_of t) else None); init })) props in
  let agent_env = List.fold_left (fun env (x, t, _, _) -> add_local env x t) base props in
  let agent_env = { agent_env with float_ok = true;
                                   real_props = List.filter_map (fun (x, t, _, typed) ->
                                       if typed && (t = GDouble || t = GFloat) then Some (x, t) else None) props } in
  (* Functions and procedures: each may call only the earlier ones. *)
  let env = ref agent_env and routines = ref [] in
  for _ = 1 to 1 + int rs 2 do
    let f = fresh "fn" in
    let ps = List.init (int rs 3) (fun i -> (Printf.sprintf "a%d" (i + 1), prim rs)) in
    let ret = prim rs in
    let fenv = List.fold_left (fun e (x, t) -> add_local e x t) !env ps in
    let body = block rs fenv ~loop:false 2 (int rs 3) in
    let body = (if body = [] then [] else body) @ [ph (Return (Some (expr rs fenv ret 2)))] in
    let body = List.filter (fun (s : stmt) -> s.it <> Nothing) body in
    routines := ph (Function { name = ph f; params = List.map param ps; ret = ty_of ret; body })
                :: !routines;
    env := { !env with funcs = (f, List.map snd ps, ret) :: !env.funcs }
  done;
  for k = 1 to 1 + int rs 2 do
    let p = fresh "proc" in
    let ps = (if k = 1 then [("a1", GInt)] else [])
             @ List.init (int rs 2) (fun i -> (Printf.sprintf "a%d" (i + (if k = 1 then 2 else 1))), prim rs) in
    let penv = List.fold_left (fun e (x, t) -> add_local e x t) !env ps in
    let body = block rs penv ~loop:false 2 (1 + int rs 3) in
    routines := ph (Procedure { name = ph p; params = List.map param ps; body }) :: !routines;
    env := { !env with procs = (p, List.map snd ps) :: !env.procs }
  done;
  let agent_env = !env in
  (* Behaviour C: one shot, no for agent, uses the ontology; its single step
     runs its action block, or (no action block) takes a cfp if one is
     queued, which B never takes (D1: either way, the step ends it). *)
  let c_params = [("c1p", prim rs)] in
  let c_action = chance rs 0.7 in
  let c_env0 = { base with sources = []; vars = [] } in
  let c_env = List.fold_left (fun e (x, t) -> add_local e x t) c_env0 [("note", GText)] in
  let c_decl = ph (DBehaviour {
      bkind = OneShot; bname = ph "C"; bextends = None; for_agent = None;
      bontologies = [ph "Onto"];
      bfeatures = [
        ph (Property { name = ph "note"; ty = None; init = Some (lit (Text "c")) });
        ph (OnCreate { params = List.map param c_params;
                       body = [ph (Log (bin Add (name "note") (name "c1p")))] });
        (if c_action then
           ph (ActionSection (block rs c_env ~loop:false 1 (1 + int rs 2)
                              @ [ph (Send (ph "request", expr rs c_env (GSchema "act1") 1,
                                           [expr rs c_env GAid 0]))]))
         else
           ph (OnMessage { perf = Some (ph "cfp"); guard = None;
                           body = [ph (Log (bin Add (name "note") (lit (Text " took a cfp"))))] }));
      ] }) in
  (* Behaviour B: cyclic, for agent Ag. *)
  let b_params = [("b1", GInt)] @ (if chance rs 0.5 then [("b2", prim rs)] else []) in
  let b_env = { agent_env with can_activate_c = Some c_params; in_behaviour = Some "B" } in
  let b_env = { b_env with sources = (ph (Of (ph "count", ph Agent)), GInt)
                                     :: (ph (Of (ph "hits", ph This)), GInt) :: b_env.sources } in
  let b_env = add_local b_env "hits" GInt in
  let handler_env binds content msg =
    let e = List.fold_left (fun e (x, t) -> add_local e x t) b_env binds in
    let e = match content with Some t -> { e with sources = (ph Content, t) :: e.sources } | None -> e in
    if msg then { e with message = true;
                         sources = (ph (Of (ph "sender", ph Message)), GAid) :: e.sources }
    else e in
  let q1 = List.find (fun s -> s.sname = "q1") infos in
  let pat_binds sc =
    List.map (fun (_, t) -> if chance rs 0.7 then Some (fresh "px", t) else None) sc.slots in
  let pat sc binds = ph (PCons (ph sc.sname, List.map (function
      | Some (x, _) -> ph (PName x) | None -> ph PWild) binds)) in
  let some = List.filter_map (fun x -> x) in
  let on_q sc =
    let binds = pat_binds sc in
    let m = ph (Matches (ph Content, pat sc binds)) in
    let env = handler_env (some binds) (Some (GSchema sc.sname)) false in
    let guard = if chance rs 0.5 then bin And m (expr rs env GBool 1) else m in
    ph (OnPercept { guard = Some guard;
                    body = block rs env ~loop:false 2 (1 + int rs 3)
                           @ [ph (Log (ph (Of (ph "priority", ph Content))))] }) in
  (* r1's handler changes the behaviours: it may activate another B (with
     one hit more than its own) or C, and it may deactivate its own instance (R5g,
     R5h), so that runs create and remove instances as percepts arrive *)
  let r1_env = handler_env [] None false in
  let r1_effects =
    (* bounded: each new B starts with more hits than its parent, and only
       an instance with fewer than 3 hits activates one (else the
       instances would double with every r1) *)
    (if chance rs 0.3 then
       [ph (If ([(bin Lt (name "hits") (ilit 3),
                  [ph (Activate (ph "B", List.map (fun (x, t) ->
                       (ph x, if x = "b1" then bin Add (name "hits") (ilit 1) else expr rs r1_env t 0))
                       b_params))])], None))]
     else [])
    @ (if chance rs 0.3 then [ph (If ([(bin Gt (name "hits") (ilit (int rs 4)), [ph Deactivate])], None))]
       else []) in
  let on_r1 = ph (OnPercept { guard = Some (ph (Matches (ph Content, ph (PName "r1"))));
                              body = [ph (Assign (ph (LName "hits"), bin Add (name "hits") (ilit 1)))]
                                     @ block rs r1_env ~loop:false 1 1 @ r1_effects }) in
  let on_any = ph (OnPercept { guard = None;
                               body = [ph (Log (bin Add (lit (Text "percept ")) (ph (Of (ph "priority", ph Content)))))] }) in
  let on_inform =
    let binds = pat_binds q1 in
    let env = handler_env (some binds) (Some (GSchema "q1")) true in
    ph (OnMessage { perf = Some (ph "inform");
                    guard = Some (ph (Matches (ph Content, pat q1 binds)));
                    body = block rs env ~loop:false 2 (1 + int rs 2)
                           @ [ph (Send (ph "inform", expr rs env (GSchema "q1") 1,
                                        [ph (Of (ph "sender", ph Message))]))] }) in
  let on_request =
    let act1 = List.find (fun s -> s.sname = "act1") infos in
    let binds = pat_binds act1 in
    let env = handler_env (some binds) (Some (GSchema "act1")) true in
    ph (OnMessage { perf = Some (ph "request");
                    guard = Some (ph (Matches (ph Content, pat act1 binds)));
                    body = block rs env ~loop:false 1 (1 + int rs 2) }) in
  let handlers = [on_q q1; on_q (List.find (fun s -> s.sname = "q2") infos); on_r1; on_inform;
                  on_request] @ (if chance rs 0.5 then [on_any] else []) in
  let b_create_env = List.fold_left (fun e (x, t) -> add_local e x t) b_env b_params in
  (* Half the time B extends a cyclic behaviour BP for agent Ag, whose
     percept handlers (for q1, r1, or any percept) B inherits: for a percept
     that both take, the inherited handlers run before B's own (R4a). *)
  let parent =
    if not (chance rs 0.5) then None
    else
      let p_env = { agent_env with in_behaviour = Some "BP" } in
      let tag = lit (Text "inherited ") in
      let on_q1 () =
        let binds = pat_binds q1 in
        let env = List.fold_left (fun e (x, t) -> add_local e x t) p_env (some binds) in
        let env = { env with sources = (ph Content, GSchema "q1") :: env.sources } in
        ph (OnPercept { guard = Some (ph (Matches (ph Content, pat q1 binds)));
                        body = ph (Log (bin Add tag (ph (Of (ph "x", ph Content)))))
                               :: block rs env ~loop:false 1 (int rs 2) }) in
      let on_r1 () =
        ph (OnPercept { guard = Some (ph (Matches (ph Content, ph (PName "r1"))));
                        body = ph (Log (bin Add tag (lit (Text "r1"))))
                               :: block rs p_env ~loop:false 1 (int rs 2) }) in
      let on_any () =
        ph (OnPercept { guard = None;
                        body = [ph (Log (bin Add tag (ph (Of (ph "priority", ph Content)))))] }) in
      let handlers = List.filter_map (fun (p, h) -> if chance rs p then Some (h ()) else None)
          [(0.7, on_q1); (0.4, on_r1); (0.3, on_any)] in
      let handlers = if handlers = [] then [on_q1 ()] else handlers in
      Some (ph (DBehaviour {
          bkind = Cyclic; bname = ph "BP"; bextends = None; for_agent = Some (ph "Ag");
          bontologies = []; bfeatures = handlers })) in
  let b_decl = ph (DBehaviour {
      bkind = Cyclic; bname = ph "B"; bextends = Option.map (fun _ -> ph "BP") parent;
      for_agent = Some (ph "Ag");
      bontologies = [];
      bfeatures =
        ph (Property { name = ph "hits"; ty = Some (ty_of GInt); init = Some (ilit 0) })
        :: ph (OnCreate { params = List.map param b_params;
                          body = [ph (Assign (ph (LName "hits"), name "b1"))]
                                 @ block rs b_create_env ~loop:false 1 (int rs 2) })
        :: handlers }) in
  (* The agent's on create. *)
  let create_params = [("iface0", GAny)] @ (if chance rs 0.5 then [("start", GInt)] else []) in
  let cenv = List.fold_left (fun e (x, t) -> add_local e x t) agent_env create_params in
  let create_body =
    [ph (Assign (ph (LName "iface"), name "iface0"));
     ph (Assign (ph (LIndex (name "seen", lit (Text "start"))), ilit 0))]
    @ block rs cenv ~loop:false 2 (1 + int rs 3)
    @ [ph (Activate (ph "B", List.map (fun (x, t) -> (ph x, arg rs cenv t 1)) b_params))]
    (* sometimes an error after the activation: the agent keeps B (R7) *)
    @ (if chance rs 0.2 then [ph (Log (ph (Index (name "seen", lit (Text "absent")))))] else []) in
  (* on destroy (D14): the agent's count as the run left it *)
  let destroy = if chance rs 0.7 then [ph (OnDestroy [ph (Log (bin Add (lit (Text "destroyed with ")) (name "count")))])]
    else [] in
  let agent = ph (DAgent {
      aname = ph "Ag"; aextends = None; aontologies = [ph "Onto"];
      afeatures = prop_features
                  @ [ph (OnCreate { params = List.map param create_params; body = create_body })]
                  @ destroy
                  @ List.rev !routines }) in
  { module_name = []; decls = [onto; agent] @ Option.to_list parent @ [b_decl; c_decl] }

let program : program QCheck.Gen.t = program_rs
let arb_program = QCheck.make ~print:(fun p -> Print.program p) program

(* ------------------------------------------------------------- mutations *)

type mutation = { name : string; fragment : string; program : program }

let map_decls f p = { p with decls = List.map f p.decls }

let map_agent f = map_decls (fun d -> match d.it with
    | DAgent a -> { d with it = DAgent (f a) } | _ -> d)

let map_behaviour b f = map_decls (fun d -> match d.it with
    | DBehaviour x when x.bname.it = b -> { d with it = DBehaviour (f x) } | _ -> d)

let map_ontology f = map_decls (fun d -> match d.it with
    | DOntology o -> { d with it = DOntology (f o) } | _ -> d)

(* Prepend a statement to the agent's on create. *)
let in_create s = map_agent (fun a ->
    { a with afeatures = List.map (fun f -> match f.it with
          | OnCreate c -> { f with it = OnCreate { c with body = s :: c.body } }
          | _ -> f) a.afeatures })

let in_first_procedure s = map_agent (fun a ->
    let first = ref true in
    { a with afeatures = List.map (fun f -> match f.it with
          | Procedure p when !first -> first := false;
            { f with it = Procedure { p with body = s :: p.body } }
          | _ -> f) a.afeatures })

let mutations : (string * string * (program -> program)) list = [
  "wrong initialiser", "initial value of property count: expected integer, found text",
  map_agent (fun a -> { a with afeatures = List.map (fun f -> match f.it with
      | Property ({ name = { it = "count"; _ }; _ } as p) ->
        { f with it = Property { p with init = Some (lit (Text "ten")) } }
      | _ -> f) a.afeatures });
  "negative priority", "natural number",
  map_ontology (fun o -> { o with schemas = List.map (fun (s : schema) ->
      if s.it.sname.it = "q1" then
        { s with it = { s.it with defaults = [(ph "priority", ph (Unop (Neg, ilit 1)))] } }
      else s) o.schemas });
  "extra argument", "has no parameter zz",
  map_agent (fun a -> { a with afeatures = List.map (fun f -> match f.it with
      | OnCreate c -> { f with it = OnCreate { c with body = List.map (fun s -> match s.it with
          | Activate (b, args) -> { s with it = Activate (b, args @ [(ph "zz", ilit 1)]) }
          | _ -> s) c.body } }
      | _ -> f) a.afeatures });
  "missing argument", "missing argument b1",
  map_agent (fun a -> { a with afeatures = List.map (fun f -> match f.it with
      | OnCreate c -> { f with it = OnCreate { c with body = List.map (fun s -> match s.it with
          | Activate (b, args) -> { s with it = Activate (b, List.tl args) }
          | _ -> s) c.body } }
      | _ -> f) a.afeatures });
  "break outside a loop", "only allowed inside a loop", in_first_procedure (ph Break);
  "missing return", "does not return a value on every path",
  map_agent (fun a -> let first = ref true in
              { a with afeatures = List.map (fun f -> match f.it with
                    | Function fn when !first -> first := false;
                      let body = List.filter (fun s -> match s.it with Return _ -> false | _ -> true)
                          fn.body in
                      let body = if body = [] then [ph Nothing] else body in
                      { f with it = Function { fn with body } }
                    | _ -> f) a.afeatures });
  "invoke on a non-any", "invoke needs a host value of type any",
  in_create (ph (InvokeS { meth = ph "m"; target = ilit 1; args = [] }));
  "unknown name", "unknown name undefinedThing", in_create (ph (Log (name "undefinedThing")));
  "content of the wrong kind", "the content of a inform message: expected predicate or proposition, found act1",
  in_create (ph (Send (ph "inform", ph (Call (ph "act1", [ilit 1])), [name "iface0"])));
  "pattern arity", "sub-pattern",
  (let rec widen (e : expr) = match e.it with
      | Matches (c, { it = PCons (q, ps); at }) ->
        { e with it = Matches (c, { it = PCons (q, ps @ [ph PWild]); at }) }
      | Binop (And, l, r) -> { e with it = Binop (And, widen l, r) }
      | _ -> e in
   map_behaviour "B" (fun b -> { b with bfeatures = List.map (fun f -> match f.it with
       | OnPercept { guard = Some g; body } -> { f with it = OnPercept { guard = Some (widen g); body } }
       | _ -> f) b.bfeatures }));
  "float op double", "float does not widen to double",
  in_create (ph (Log (bin Mul (name "ratio") (name "dist"))));
  "wrong constructor argument", "argument x of predicate q1: expected double, found text",
  (fun p ->
     let arity = List.fold_left (fun n d -> match d.it with
         | DOntology o -> List.fold_left (fun n (s : schema) ->
             if s.it.sname.it = "q1" then List.length s.it.slots else n) n o.schemas
         | _ -> n) 1 p.decls in
     let wrong = function
       | 0 -> lit (Text "no") | _ -> ilit 0 in
     in_create (ph (Log (ph (Of (ph "x", ph (Call (ph "q1", List.init arity wrong))))))) p);
  "wrong assignment", "the value assigned to property count: expected integer, found text",
  in_create (ph (Assign (ph (LName "count"), lit (Text "x"))));
  "deactivate in an agent", "only allowed in a behaviour", in_first_procedure (ph Deactivate);
  "content outside a handler", "'content' is only available", in_first_procedure (ph (Log (ph Content)));
  "unresolved empty list", "cannot infer the type of this empty collection",
  map_agent (fun a -> { a with afeatures = ph (Property { name = ph "emptyOne"; ty = None;
                                                          init = Some (ph (List [])) }) :: a.afeatures });
  "duplicate schema", "c1 is already declared",
  map_ontology (fun o -> { o with schemas = o.schemas @ [
      ph { kind = Concept; sname = ph "c1"; slots = []; super = None; defaults = [] }] });
  "integer out of range", "out of range", in_create (ph (Log (ilit 3000000000)));
]

let mutation_names = List.map (fun (n, _, _) -> n) mutations

let mutate p rs =
  let (name, fragment, f) = pick rs mutations in
  { name; fragment; program = f p }

let arb_mutated =
  QCheck.make
    ~print:(fun (_, m) -> Printf.sprintf "mutation %s (expecting %S):\n%s" m.name m.fragment
               (Print.program m.program))
    (fun rs -> let p = program rs in (p, mutate p rs))

(* ------------------------------------------------------------ the limits *)

type limit = { kind : string; size : int; text : string }

(* A program that hits a limit of the interpreter when it handles the
   percept [tick(n)]: the handler of a cyclic behaviour does the costly
   thing [size] times (or [n] times, n from the events file). *)
let limit_kinds = [
  "recursion"; "mutual recursion"; "long loop"; "growing text"; "deep parentheses"; "growing map"; "growing map of texts";
  "activations"; "deep expression"; "nested loops"; "many percepts"; "raw bytes"; "shared parts"
]

let limit_body kind size =
  let i = "\t\t" in
  match kind with
  | "recursion" ->
    ("\tfunction f(n as integer) as integer do\n\t\treturn f(n + 1) + 1\n",
     i ^ "log \"r \" + f(0)\n")
  | "mutual recursion" ->
    ("\tprocedure p with n as integer do\n\t\tif n > " ^ string_of_int size ^ " do\n\t\t\treturn\n\t\tdo q with n = n + 1\n"
     ^ "\tprocedure q with n as integer do\n\t\tdo p with n = n + 1\n",
     i ^ "do p with n = 0\n")
  | "long loop" ->
    ("", i ^ "k = 0\n" ^ i ^ "while k < " ^ string_of_int size ^ " do\n" ^ i ^ "\tk = k + 1\n" ^ i ^ "log \"k \" + k\n")
  | "growing text" ->
    ("", i ^ "s = \"ab\"\n" ^ i ^ "k = 0\n" ^ i ^ "while k < " ^ string_of_int size ^ " do\n"
         ^ i ^ "\ts = s + s\n" ^ i ^ "\tk = k + 1\n" ^ i ^ "log \"len \" + length of s\n")
  | "growing map" ->
    ("", i ^ "m = {0: \"zero\"}\n" ^ i ^ "k = 0\n" ^ i ^ "while k < " ^ string_of_int size ^ " do\n"
         ^ i ^ "\tm[k] = \"v\" + k\n" ^ i ^ "\tk = k + 1\n" ^ i ^ "log \"size \" + size of m\n")
  | "growing map of texts" ->
    (* every entry a longer text: memory grows as the square of the size *)
    ("", i ^ "m = {0: \"\"}\n" ^ i ^ "s = \"\"\n" ^ i ^ "k = 0\n" ^ i ^ "while k < " ^ string_of_int size ^ " do\n"
         ^ i ^ "\ts = s + \"xy\"\n" ^ i ^ "\tm[k] = s\n" ^ i ^ "\tk = k + 1\n" ^ i ^ "log \"size \" + size of m\n")
  | "activations" ->
    ("", i ^ "k = 0\n" ^ i ^ "while k < " ^ string_of_int size ^ " do\n"
         ^ i ^ "\tactivate behaviour Idle\n" ^ i ^ "\tk = k + 1\n")
  | "deep expression" ->
    ("", i ^ "log " ^ String.concat " + " (List.init size (fun _ -> "n")) ^ "\n")
  | "deep parentheses" ->
    (* within the parser's bound of 200 nested brackets *)
    ("", i ^ "log " ^ String.concat "" (List.init size (fun _ -> "(1 + ")) ^ "n" ^ String.make size ')' ^ "\n")
  | "nested loops" ->
    ("", i ^ "a = 0\n" ^ i ^ "for x in [1, 2, 3, 4, 5, 6, 7, 8, 9, 10] do\n" ^ i ^ "\tfor y in [1, 2, 3, 4, 5, 6, 7, 8, 9, 10] do\n"
         ^ i ^ "\t\tk = 0\n" ^ i ^ "\t\twhile k < " ^ string_of_int size ^ " do\n" ^ i ^ "\t\t\tk = k + 1\n"
         ^ i ^ "\t\t\ta = a + x * y\n" ^ i ^ "log \"a \" + a\n")
  | "shared parts" ->
    (* D37: two lists of two copies of ... [size] levels deep, 3 * 2^size - 1
       parts each, compared, hashed as a map key, printed *)
    let chain x = i ^ x ^ "0 = [n]\n"
                  ^ String.concat "" (List.init size (fun k ->
                      Printf.sprintf "%s%s%d = [%s%d, %s%d]\n" i x (k + 1) x k x k)) in
    let top x = Printf.sprintf "%s%d" x size in
    ("", chain "a" ^ chain "b" ^ i ^ "log \"same \" + (" ^ top "a" ^ " = " ^ top "b" ^ ")\n"
         ^ i ^ "m = {" ^ top "b" ^ ": 1}\n" ^ i ^ "log \"found \" + m[" ^ top "a" ^ "]\n"
         ^ i ^ "log " ^ top "a" ^ "\n")
  | "raw bytes" ->
    (* invalid UTF-8 and control bytes inside a text literal *)
    ("", i ^ "log \"caf\xff \x01\xc3 \xed\xa0\x80 end\" + n\n")
  | _ (* many percepts *) ->
    ("", i ^ "log \"tick \" + n\n")

let limit rs =
  let kind = pick rs limit_kinds in
  let size = match kind with
    | "recursion" -> 0
    | "mutual recursion" -> pick rs [ 50; 150; 250; 100_000 ]
    | "long loop" -> pick rs [ 1_000; 100_000; 10_000_000 ]
    | "growing text" -> pick rs [ 5; 20; 26; 40; 64 ]
    | "growing map" -> pick rs [ 100; 10_000; 1_000_000 ]
    | "growing map of texts" -> pick rs [ 100; 10_000; 100_000 ]
    | "activations" -> if chance rs 0.05 then 8_000 else pick rs [ 10; 100; 500 ]
    | "deep expression" -> pick rs [ 10; 500; 5_000; 50_000 ]
    | "deep parentheses" -> pick rs [ 10; 100; 190 ]
    | "nested loops" -> pick rs [ 10; 1_000; 100_000 ]
    | "shared parts" -> pick rs [ 3; 12; 21; 22; 40; 62 ]
    | _ -> 0 in
  let (routines, body) = limit_body kind size in
  let text =
    "ontology Lim\n\tpredicate tick(n as integer) extends percept with priority = 3\n\n"
    ^ "agent Ag uses ontology Lim\n" ^ routines
    ^ "\ton create do\n\t\tactivate behaviour Work\n\n"
    ^ "cyclic behaviour Work for agent Ag\n"
    ^ "\ton percept when content matches tick(n) do\n" ^ body ^ "\n"
    ^ "cyclic behaviour Idle uses ontology Lim\n\ton percept when content matches tick(n) do\n\t\tlog \"idle\"\n" in
  { kind; size; text }
