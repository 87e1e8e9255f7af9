(* The interpreter's evaluation rules: the reference. docs/semantics.md
   ("Running programs") states them; the functions follow the syntactic
   categories (expressions, patterns, statements), then the bodies the
   machine runs (Bodies, at the end).

   Plain on purpose: no caches, no comparison of addresses, no slot or hook
   for the fast engine, no state outside the values passed. What a rule
   changes is given back: a body takes the agent and answers the agent
   after it. Only the program's own data changes in place: its properties
   and the lists, maps and schema values they reach, which Jadescript (as
   Java) shares by reference (docs/semantics.md, "Values").

   The fast engine's twin of the percept handlers, compiled to closures,
   is lib/engine/compiled_bodies.ml: it calls the rules below for every
   value it computes, and test/fastpath holds it equal to this file. *)

open Syntax
module Ast = Syntax.Ast
module T = Typing.Tenv
module Ty = Typing.Types
module V = Value
module Names = Syntax.Strtbl

type message = { perf : string; content : V.t; sender : string }

(* A property: its value and its declared type, to which assignments convert
   (integer to float or double). *)
type cell = { mutable v : V.t; ty : Ty.t }

type beh = {
  uid : int;
  btype : T.behaviour;
  bprops : cell Names.t;
  phandlers : T.handler array;
  mhandlers : T.handler array;
  action : Ast.block option;
}

(* ------------------------------------------------------------ errors *)

(* One exception per kind of run-time error, as the WebAssembly reference
   interpreter's util/error.ml makes them; the kind decides the wording of
   a report, never the trace line. *)
type error_kind = Trap_error | Exhaustion_error | Link_error

exception Trap of Source.region * string
exception Exhaustion of Source.region * string
exception Link of Source.region * string

let wording kind msg = match kind with
  | Trap_error -> msg
  | Exhaustion_error -> "exhaustion: " ^ msg
  | Link_error -> "link error: " ^ msg

let error_of_exn = function
  | Trap (at, m) -> Some (Trap_error, at, m)
  | Exhaustion (at, m) -> Some (Exhaustion_error, at, m)
  | Link (at, m) -> Some (Link_error, at, m)
  | _ -> None

let err at fmt = Printf.ksprintf (fun s -> raise (Trap (at, s))) fmt
let exhausted at fmt = Printf.ksprintf (fun s -> raise (Exhaustion (at, s))) fmt
let link at fmt = Printf.ksprintf (fun s -> raise (Link (at, s))) fmt

(* What ends a block early. *)
exception Return of V.t
exception Break
exception Continue

(* ------------------------------------------------------------ config *)

(* The limits of a run, as the WebAssembly reference interpreter's config
   holds its budget. *)
type config = {
  fuel : int;
  max_call_depth : int;
  max_behaviours : int;
  max_memory : int option;
  record_effects : bool;
}

let default_config = {
  fuel = 100_000; max_call_depth = 200; max_behaviours = 10_000;
  max_memory = None; record_effects = true;
}

(* D21: the largest text (bytes, also as printed by log, send, invoke) and
   map (entries) a run may build: part of the conformance contract. *)
let max_text = 1_000_000
let max_map_size = 1_000_000

type event =
  | Log of string
  | Invoke of { meth : string; cls : string; args : V.t list; result : V.t }
  | Sent of { perf : string; content : V.t; receivers : string list }
  | Activated of string
  | Deactivated of int
  | Error of error_kind * Source.region * string
  | Ran of { handler : int; effects : beh Semantics.Machine.effect list }

type agent = {
  env : T.t;
  name : string;
  atype : T.agent;
  props : cell Names.t;
  config : config;
  next_uid : int;
  events : event list;
  outbox : (string * message) list;
}

let property a x = match Names.find_opt a.props x with Some c -> Some c.v | None -> None

let take_events a = match a.events with
  | [] -> (a, [])
  | evs -> ({ a with events = [] }, List.rev evs)

let beh_type b = b.btype.b_name

(* ------------------------------------------------------------ frames *)

(* A body's run: its step budget left, and what it did so far (newest
   first), which the agent gets when the body ends ({!finish}). Made afresh
   for each body, and shared by the calls it makes and the behaviours it
   activates. *)
type run = {
  mutable fuel : int;
  mutable events : event list;
  mutable outbox : (string * message) list;
  mutable effects : beh Semantics.Machine.effect list;
  mutable next_uid : int;
  mutable live : int;
      (* D19: the agent's active instances as the body started, plus the
         activations it made, minus its [deactivate this] *)
}

(* Local variables: few per frame, an association list of cells. *)
type locals = { mutable vars : (string * V.t ref) list }

(* What a running body sees. *)
type frame = {
  ag : agent;
  run : run;
  beh : beh option;          (* the behaviour whose code runs, if any *)
  id : int;                  (* its machine instance id (0 in agent code) *)
  locals : locals;
  content : V.t option;
  message : message option;
  depth : int;               (* nested calls of functions and procedures *)
  in_guard : bool;           (* a when condition, or code it calls (D41) *)
}

let new_run (a : agent) ~active =
  { fuel = a.config.fuel; events = []; outbox = []; effects = []; next_uid = a.next_uid; live = active }

let frame (a : agent) run ?beh ?(id = 0) ?content ?message ?(locals = []) () =
  { ag = a; run; beh; id; locals = { vars = List.map (fun (x, v) -> (x, ref v)) locals };
    content; message; depth = 0; in_guard = false }

let add_event (f : frame) e = f.run.events <- e :: f.run.events

let local_cell x l = List.assoc_opt x l.vars

let local_set l x v =
  match local_cell x l with
  | Some r -> r := v
  | None -> l.vars <- (x, ref v) :: l.vars

(* ------------------------------------------------------------ limits *)

let too_big at what =
  exhausted at "value too large: %s (at most %d bytes in a text, %d entries in a map)" what max_text max_map_size

(* The text of [v] (log), or its literal (what a trace line carries), when
   it is at most max_text bytes long (D21). *)
let bounded_text ~quote at v =
  if not (V.printed_within ~quote max_text v) then too_big at "its text would be too long";
  v

(* D37: a comparison or a hash past V.max_visits values. *)
let too_large_to_compare at =
  exhausted at "value too large: comparing or hashing it would visit more than %d values" V.max_visits

let map_set_bounded at (m : V.map_v) k v =
  try
    if m.size >= max_map_size && V.map_find m k = None then too_big at "the map would have too many entries";
    V.map_set m k v
  with V.Too_large -> too_large_to_compare at

(* D22: every 1,024 statements, and before a text of more than 64 KB is
   built, the major heap's size is compared with the run's bound; over it,
   the heap is compacted (garbage may be most of it) and compared again;
   still over it, the statement is an exhaustion error (R7). *)
let check_memory (a : agent) at =
  match a.config.max_memory with
  | None -> ()
  | Some mb ->
    let words = mb * (1024 * 1024 / (Sys.word_size / 8)) in
    if (Gc.quick_stat ()).heap_words > words then begin
      Gc.compact ();
      if (Gc.quick_stat ()).heap_words > words then
        exhausted at "out of memory: the run takes more than %d MB (--max-memory)" mb
    end

(* One statement or loop iteration of the body's step budget (R7). *)
let tick (f : frame) at =
  f.run.fuel <- f.run.fuel - 1;
  if f.run.fuel < 0 then
    exhausted at "step budget exhausted: more than %d statements in one handler or step (--fuel)" f.ag.config.fuel;
  if f.run.fuel land 1023 = 0 then check_memory f.ag at

(* ------------------------------------------------------- conversions *)

let coerce_param (ty : Ty.t) (v : V.t) : V.t option =
  match Ty.repr ty, v with
  | Ty.Integer, V.Int _ -> Some v
  | Ty.Double, V.Int i -> Some (V.Double (float_of_int i))
  | Ty.Double, V.Double _ -> Some v
  | Ty.Float, V.Int i -> Some (V.Float (V.float32 (float_of_int i)))
  | Ty.Float, (V.Float f | V.Double f) -> Some (V.Float (V.float32 f))
  | Ty.Text, V.Text _ | Ty.Boolean, V.Bool _ | Ty.Aid, V.Aid _ | Ty.Any, _ -> Some v
  | Ty.List _, V.List _ | Ty.Map _, V.Map _ -> Some v
  | Ty.Schema _, V.Schema _ | Ty.Onto _, V.Schema _ -> Some v
  | (Ty.Agent _ | Ty.Behaviour _ | Ty.Message _), _ -> Some v
  | (Ty.Var _ | Ty.Error), _ -> Some v
  | _ -> None

(* ------------------------------------------------------ arithmetic *)

let num_kind a b = match a, b with
  | V.Int _, V.Int _ -> `Int
  | (V.Float _, _) | (_, V.Float _) -> `Float
  | _ -> `Double

let to_f = function V.Int i -> float_of_int i | V.Float f | V.Double f -> f | _ -> nan

(* A double next to a float can only be a decimal literal (the type checker
   rejects float op double): it counts as a float, rounded to binary32. *)
let as_float_pair a b = match a, b with
  | V.Float _, V.Double d -> (a, V.Float (V.float32 d))
  | V.Double d, V.Float _ -> (V.Float (V.float32 d), b)
  | _ -> (a, b)

(* = and != (D37: past V.max_visits, an exhaustion error at the operator) *)
let equal_values at a b =
  let (a, b) = as_float_pair a b in
  try V.equal a b with V.Too_large -> too_large_to_compare at

let arith at (op : Ast.binop) a b =
  let (a, b) = as_float_pair a b in
  let numeric v = match v with V.Int _ | V.Float _ | V.Double _ -> true | _ -> false in
  if not (numeric a && numeric b) then
    err at "cannot apply an arithmetic operator to %s and %s" (V.type_name a) (V.type_name b);
  match num_kind a b, a, b with
  | `Int, V.Int x, V.Int y ->
    (match op with
     | Add -> V.int32 (x + y) | Sub -> V.int32 (x - y) | Mul -> V.int32 (x * y)
     | Div -> if y = 0 then err at "division by zero" else V.int32 (x / y)
     | Mod -> if y = 0 then err at "division by zero (%%)" else V.int32 (x mod y)
     | _ -> Semantics.Fault.crash "Eval.arith: the operator is not arithmetic")
  | kind, _, _ ->
    let x = to_f a and y = to_f b in
    let r = match op with
      | Add -> x +. y | Sub -> x -. y | Mul -> x *. y | Div -> x /. y
      | Mod -> Float.rem x y | _ -> Semantics.Fault.crash "Eval.arith: the operator is not arithmetic" in
    if kind = `Float then V.Float (V.float32 r) else V.Double r

let compare_values at (op : Ast.binop) a b =
  let (a, b) = as_float_pair a b in
  let c = match a, b with
    | (V.Int _ | V.Float _ | V.Double _), (V.Int _ | V.Float _ | V.Double _) -> compare (to_f a) (to_f b)
    | V.Text x, V.Text y -> compare x y
    | _ -> err at "cannot compare %s with %s" (V.type_name a) (V.type_name b) in
  V.Bool (match op with
      | Lt -> c < 0 | Gt -> c > 0 | Le -> c <= 0 | Ge -> c >= 0
      | _ -> Semantics.Fault.crash "Eval.compare_values: the operator is not a comparison")

(* ------------------------------------------------------- patterns *)

let literal = function
  | Ast.Int i -> V.Int i
  | Ast.Real r -> V.Double (float_of_string r)
  | Ast.Text s -> V.Text s
  | Ast.Bool b -> V.Bool b

(* ------------------------------------------------------------ names *)

(* The property a name denotes where no local has it: the running
   behaviour's, else the agent's. *)
let prop_cell (f : frame) x =
  match (match f.beh with Some b -> Names.find_opt b.bprops x | None -> None) with
  | Some _ as c -> c
  | None -> Names.find_opt f.ag.props x

let lookup (f : frame) at x =
  match local_cell x f.locals with
  | Some r -> !r
  | None ->
    match prop_cell f x with
    | Some c -> c.v
    | None ->
      match T.schema f.ag.env x with
      | Some s when s.s_slots = [] -> V.Schema { sname = s.s_name; slots = [||] }
      | _ -> err at "unknown name %s" x

(* ------------------------------------------------ sends and invokes *)

(* A send's receivers: an aid, or a list of aids. *)
let receivers_of at = function
  | V.Aid a -> [ a ]
  | V.List l -> List.map (function V.Aid a -> a | v -> err at "a receiver is an aid, not a %s" (V.type_name v)) (V.list_items l)
  | v -> err at "a receiver is an aid, not a %s" (V.type_name v)

(* The message of a send in each receiver's outbox entry, and the event
   (R5e), once its content and receivers are evaluated. *)
let post_send (f : frame) perf content receivers =
  List.iter (fun r -> f.run.outbox <- (r, { perf; content; sender = f.ag.name }) :: f.run.outbox) receivers;
  add_event f (Sent { perf; content; receivers })

(* [invoke] once its target and arguments are evaluated (in that order):
   each argument's literal within D21's bound, then the host's method. *)
let invoke_values (f : frame) at (i : Ast.invoke) target vs =
  let args = List.map2 (fun (e : Ast.expr) v -> bounded_text ~quote:true e.at v) i.args vs in
  match target with
  | V.Native n ->
    (match List.assoc_opt i.meth.it n.methods with
     | None -> link i.meth.at "%s has no method %S" n.cls i.meth.it
     | Some m ->
       let result = try m args with
         | (Trap _ | Exhaustion _ | Link _) as x -> raise x
         | Invalid_argument msg -> link at "%s.%s failed: %s" n.cls i.meth.it msg
         | Failure msg -> err at "%s.%s failed: %s" n.cls i.meth.it msg in
       add_event f (Invoke { meth = i.meth.it; cls = n.cls; args; result });
       result)
  | v -> err i.target.at "invoke needs a host object (any), not a %s" (V.type_name v)

(* ------------------------------------------------------ primitives *)

(* The evaluator's primitives: what it does with numbers, texts and schema
   types, the one seam between the rules below and what a value means. The
   rules are a functor over them ({!Make}), applied once, at the end of this
   file, to these, the reference's; the bug catalogue (lib/defects) applies
   it to altered ones. *)
module type PRIMITIVES = sig
  val arith : Source.region -> Ast.binop -> V.t -> V.t -> V.t
  val compare_values : Source.region -> Ast.binop -> V.t -> V.t -> V.t
  val equal_values : Source.region -> V.t -> V.t -> bool
  val coerce_param : Ty.t -> V.t -> V.t option
  val text : V.t -> string
  val subschema : T.t -> string -> string -> bool
end

module Primitives = struct
  let arith = arith
  let compare_values = compare_values
  let equal_values = equal_values
  let coerce_param = coerce_param
  let text = V.to_text
  let subschema = T.subschema
end

(* The rules of evaluation, over the primitives. *)
module Make (P : PRIMITIVES) = struct

let arith = P.arith
let compare_values = P.compare_values
let equal_values = P.equal_values
let coerce_param = P.coerce_param

let coerce ty v = match coerce_param ty v with Some v -> v | None -> v

let set_cell c v = c.v <- coerce c.ty v

let assign_name (f : frame) x v =
  match local_cell x f.locals with
  | Some r -> r := v
  | None ->
    match prop_cell f x with
    | Some c -> set_cell c v
    | None -> local_set f.locals x v

(* ------------------------------------------------------- schemas *)

let construct (env : T.t) at name (args : V.t list) =
  match T.schema env name with
  | None -> err at "unknown schema %s" name
  | Some s ->
    if List.length args <> List.length s.s_slots then
      err at "%s takes %d argument%s, not %d" name (List.length s.s_slots)
        (if List.length s.s_slots = 1 then "" else "s") (List.length args);
    let slots = List.map2 (fun (n, ty) v ->
        match coerce_param ty v with
        | Some v -> (n, ref v)
        | None -> err at "slot %s of %s is a %s, not a %s" n name (Ty.to_string ty) (V.type_name v))
        s.s_slots args in
    V.Schema { sname = s.s_name; slots = Array.of_list slots }

let slot at (s : V.schema_v) x =
  match Array.find_opt (fun (n, _) -> String.equal n x) s.slots with
  | Some (_, r) -> r
  | None -> err at "%s has no slot %s" s.sname x

(* Does [v] match [p]? A name that is a schema tests the value's schema
   (itself or a subschema); any other name is a variable and binds; a
   constructor pattern tests the schema, then matches the slots it names,
   in its order. The bindings go into [binds], newest first. *)
let rec pattern (env : T.t) binds (p : Ast.pattern) (v : V.t) : bool =
  match p.it, v with
  | PWild, _ -> true
  | PLit l, _ -> V.equal (literal l) v
  | PName x, _ ->
    (match T.schema env x with
     | Some _ -> (match v with V.Schema s -> P.subschema env s.sname x | _ -> false)
     | None -> binds := (x, v) :: !binds; true)
  | PCons (c, ps), V.Schema s ->
    P.subschema env s.sname c.it
    && (match T.schema env c.it with
        | Some sc ->
          List.length ps = List.length sc.s_slots
          && List.for_all2 (fun (q : Ast.pattern) (n, _) -> pattern env binds q !(slot q.at s n)) ps sc.s_slots
        | None -> false)
  | PCons _, _ -> false

(* ---------------------------------------------------- expressions *)

let rec expr (f : frame) (e : Ast.expr) : V.t =
  match e.it with
  | Lit l -> literal l
  | Name x -> lookup f e.at x
  | This -> (match f.beh with Some b -> V.Behaviour_ref b.uid | None -> V.Agent_ref f.ag.name)
  | Agent -> V.Agent_ref f.ag.name
  | Content -> (match f.content with Some c -> c | None -> err e.at "no content here")
  | Message -> (match f.message with
      | Some m -> V.Schema { sname = "message"; slots = [| ("performative", ref (V.Text m.perf));
                                                          ("content", ref m.content);
                                                          ("sender", ref (V.Aid m.sender)) |] }
      | None -> err e.at "no message here")
  | List es -> V.list_of (List.map (expr f) es)
  | Map kvs ->
    let m = V.map_empty () in
    (match m with
     | V.Map mv ->
       List.iter (fun (k, v) ->
           let v = expr f v in            (* the value before its key *)
           let k = expr f k in
           try V.map_set mv k v with V.Too_large -> too_large_to_compare e.at) kvs
     | _ -> ());
    m
  | Call (g, args) -> call f e.at g.it (List.map (expr f) args)
  | Index (m, k) ->
    let mv = expr f m and kv = expr f k in
    (match mv, kv with
     | V.List l, V.Int i ->
       if i < 0 || i >= l.len then err e.at "index %d is out of bounds (the list has %d elements)" i l.len;
       l.items.(i)
     | V.Map m, _ ->
       (match (try V.map_find m kv with V.Too_large -> too_large_to_compare e.at) with
        | Some v -> v
        | None -> err e.at "the map has no key %s" (V.to_literal kv))
     | _ -> err e.at "cannot index a %s" (V.type_name mv))
  | Of (p, x) -> of_ f e.at p.it (expr f x)
  | Matches (x, p) ->
    let v = expr f x in
    let binds = ref [] in
    if pattern f.ag.env binds p v then (List.iter (fun (x, v) -> local_set f.locals x v) (List.rev !binds); V.Bool true)
    else V.Bool false
  | Unop (Not, x) -> (match expr f x with V.Bool b -> V.Bool (not b) | v -> err e.at "not needs a boolean, not a %s" (V.type_name v))
  | Unop (Neg, x) ->
    (match expr f x with
     | V.Int i -> V.int32 (- i) | V.Float x -> V.Float (-. x) | V.Double x -> V.Double (-. x)
     | v -> err e.at "cannot negate a %s" (V.type_name v))
  | Binop (And, l, r) -> (match expr f l with V.Bool false -> V.Bool false | V.Bool true -> expr f r
                                            | v -> err e.at "and needs booleans, not a %s" (V.type_name v))
  | Binop (Or, l, r) -> (match expr f l with V.Bool true -> V.Bool true | V.Bool false -> expr f r
                                           | v -> err e.at "or needs booleans, not a %s" (V.type_name v))
  (* the right operand first, then the left, for = != < > <= >= *)
  | Binop (Eq, l, r) -> let b = expr f r in let a = expr f l in V.Bool (equal_values e.at a b)
  | Binop (Neq, l, r) -> let b = expr f r in let a = expr f l in V.Bool (not (equal_values e.at a b))
  | Binop ((Lt | Gt | Le | Ge) as op, l, r) -> let b = expr f r in let a = expr f l in compare_values e.at op a b
  | Binop (Add, l, r) ->
    let a = expr f l in
    let b = expr f r in
    (match a, b with
     | V.Text _, _ | _, V.Text _ ->
       let a = P.text (bounded_text ~quote:false e.at a) and b = P.text (bounded_text ~quote:false e.at b) in
       if String.length a + String.length b > max_text then too_big e.at "the text would be too long";
       if String.length a + String.length b > 65536 then check_memory f.ag e.at;
       V.Text (a ^ b)
     | _ -> arith e.at Add a b)
  | Binop (op, l, r) -> let a = expr f l in let b = expr f r in arith e.at op a b
  | Invoke i -> invoke f e.at i

and of_ (f : frame) at p v =
  match p, v with
  | "length", V.Text s -> V.Int (String.length s)
  | ("length" | "size"), V.List l -> V.Int l.len
  | "size", V.Map m -> V.Int m.size
  | "keys", V.Map m -> V.list_of (List.map fst (V.map_bindings m))
  | "values", V.Map m -> V.list_of (List.map snd (V.map_bindings m))
  | "priority", V.Schema s when Array.for_all (fun (n, _) -> n <> "priority") s.slots ->
    (match T.schema f.ag.env s.sname with
     | Some sc when sc.s_percept -> V.Int sc.s_priority
     | _ -> err at "%s has no priority" s.sname)
  | _, V.Schema s -> !(slot at s p)
  | _, V.Agent_ref _ ->
    (match Names.find_opt f.ag.props p with Some c -> c.v | None -> err at "the agent has no property %s" p)
  | _, V.Behaviour_ref u ->
    (match f.beh with
     | Some b when b.uid = u -> (match Names.find_opt b.bprops p with
         | Some c -> c.v | None -> err at "the behaviour has no property %s" p)
     | _ -> err at "no such behaviour property %s" p)
  | _ -> err at "a %s has no property %s" (V.type_name v) p

and call (f : frame) at g args =
  let routine = match f.beh with
    | Some b -> (match T.behaviour_function f.ag.env b.btype.b_name g with
        | Some r -> Some (r, f.beh)
        | None -> Option.map (fun r -> (r, None)) (T.agent_function f.ag.env f.ag.atype.a_name g))
    | None -> Option.map (fun r -> (r, None)) (T.agent_function f.ag.env f.ag.atype.a_name g) in
  match routine with
  | Some (r, beh) -> (match run_routine f at r beh (`Positional args) with Some v -> v | None -> V.Unit)
  | None ->
    match g, args with
    | "aid", [ V.Text n ] -> V.Aid n
    | "aid", [ V.Aid n ] -> V.Aid n
    | _ -> construct f.ag.env at g args

(* A call of a function or procedure (D18: at most max_call_depth nested):
   a tick at the call, the depth, the arguments against the parameters,
   then the body in fresh locals. An agent's routine ([beh = None]) sees the
   agent's properties only. *)
and run_routine (f : frame) at (r : T.routine) beh args : V.t option =
  tick f at;
  if f.depth >= f.ag.config.max_call_depth then
    exhausted at "recursion too deep: more than %d nested calls of functions and procedures" f.ag.config.max_call_depth;
  let locals = { vars = [] } in
  (match args with
   | `Positional vs ->
     if List.length vs <> List.length r.r_params then
       err at "%s takes %d arguments, not %d" r.r_name (List.length r.r_params) (List.length vs);
     List.iter2 (fun (n, ty) v -> local_set locals n (coerce ty v)) r.r_params vs
   | `Named kvs ->
     List.iter (fun (n, ty) ->
         match List.assoc_opt n kvs with
         | Some v -> local_set locals n (coerce ty v)
         | None -> err at "missing argument %s" n) r.r_params);
  let f' = { f with beh; locals; content = None; message = None; depth = f.depth + 1;
                    id = (match beh with Some _ -> f.id | None -> 0) } in
  match block f' r.r_body with
  | () -> None
  | exception Return v -> Some v

and invoke (f : frame) at (i : Ast.invoke) =
  let target = expr f i.target in
  invoke_values f at i target (List.map (expr f) i.args)

(* ----------------------------------------------------- statements *)

and block (f : frame) (b : Ast.block) = List.iter (stmt f) b

and stmt (f : frame) (s : Ast.stmt) =
  tick f s.at;
  match s.it with
  | Assign (lv, e) -> let v = expr f e in assign f lv v
  | Local (x, ty, e) ->
    let v = expr f e in
    let v = match ty.it with
      | TName "float" -> coerce Ty.Float v | TName "double" -> coerce Ty.Double v | _ -> v in
    local_set f.locals x.it v
  | Do (p, args) ->
    let r = match f.beh with
      | Some b -> (match T.behaviour_procedure f.ag.env b.btype.b_name p.it with
          | Some r -> Some (r, f.beh)
          | None -> Option.map (fun r -> (r, None)) (T.agent_procedure f.ag.env f.ag.atype.a_name p.it))
      | None -> Option.map (fun r -> (r, None)) (T.agent_procedure f.ag.env f.ag.atype.a_name p.it) in
    (match r with
     | None -> err p.at "unknown procedure %s" p.it
     | Some (r, beh) ->
       let args = match args with
         | Positional es -> `Positional (List.map (expr f) es)
         | Named kvs -> `Named (List.map (fun ((n : Ast.name), e) -> (n.it, expr f e)) kvs) in
       ignore (run_routine f s.at r beh args))
  | Nothing -> ()
  | InvokeS i -> ignore (invoke f s.at i)
  | Activate (b, args) ->
    let kvs = List.map (fun ((n : Ast.name), e) -> (n.it, expr f e)) args in
    activate f s.at b.it kvs
  | Deactivate -> deactivate f s.at
  | Send (perf, c, rs) ->
    let content = bounded_text ~quote:true c.at (expr f c) in
    let receivers = List.concat_map (fun (r : Ast.expr) -> receivers_of r.at (expr f r)) rs in
    post_send f perf.it content receivers
  | Log e -> let v = bounded_text ~quote:false e.at (expr f e) in add_event f (Log (P.text v))
  | If (branches, els) ->
    let rec go = function
      | [] -> (match els with Some b -> block f b | None -> ())
      | (c, b) :: rest ->
        (match expr f c with
         | V.Bool true -> block f b
         | V.Bool false -> go rest
         | v -> err c.at "a condition is a boolean, not a %s" (V.type_name v)) in
    go branches
  | While (c, b) ->
    let rec loop () =
      match expr f c with
      | V.Bool true ->
        (match block f b with () -> () | exception Continue -> ());
        tick f s.at; loop ()
      | V.Bool false -> ()
      | v -> err c.at "a condition is a boolean, not a %s" (V.type_name v) in
    (try loop () with Break -> ())
  | For (x, e, b) ->
    let items = match expr f e with
      | V.List l -> V.list_items l
      | V.Map m -> List.map fst (V.map_bindings m)
      | v -> err e.at "cannot iterate over a %s" (V.type_name v) in
    (try List.iter (fun v ->
         local_set f.locals x.it v;
         tick f s.at;
         match block f b with () -> () | exception Continue -> ()) items
     with Break -> ())
  | Return e -> raise (Return (match e with Some e -> expr f e | None -> V.Unit))
  | Break -> raise Break
  | Continue -> raise Continue

and assign (f : frame) (lv : Ast.lvalue) v =
  match lv.it with
  | LName x -> assign_name f x v
  | LIndex (m, k) ->
    let mv = expr f m and kv = expr f k in
    (match mv, kv with
     | V.List l, V.Int i ->
       if i < 0 || i >= l.len then err lv.at "index %d is out of bounds (the list has %d elements)" i l.len;
       l.items.(i) <- v
     | V.Map m, _ -> map_set_bounded lv.at m kv v
     | _ -> err lv.at "cannot index a %s" (V.type_name mv))
  | LOf (p, e) ->
    (match expr f e with
     | V.Schema s -> (slot lv.at s p.it) := v
     | V.Agent_ref _ as o ->
       (match Names.find_opt f.ag.props p.it with
        | Some c -> set_cell c v
        | None -> err lv.at "cannot set %s of a %s" p.it (V.type_name o))
     | V.Behaviour_ref u ->
       (match f.beh with
        | Some b when b.uid = u ->
          (match Names.find_opt b.bprops p.it with
           | Some c -> set_cell c v
           | None -> err lv.at "no such behaviour property %s" p.it)
        | _ -> err lv.at "no such behaviour property %s" p.it)
     | o -> err lv.at "cannot set %s of a %s" p.it (V.type_name o))

(* D41: a when condition changes no behaviour (R3b, R4b): an activate or a
   deactivate reached from one, through a call, is an error there. *)
and no_effect_in_guard at =
  err at "a when condition cannot activate or deactivate a behaviour"

(* R5g: a new instance; its properties, then its on create, run now; then
   the machine appends it to the active behaviours and the ready list
   (the [Activate] effect). D19: not past max_behaviours active instances.
   D40: instance numbers ([this]) come from the agent's own supply. *)
and activate (f : frame) at name kvs =
  if f.in_guard then no_effect_in_guard at;
  match T.behaviour f.ag.env name with
  | None -> err at "unknown behaviour %s" name
  | Some bt ->
    if f.run.live >= f.ag.config.max_behaviours then
      exhausted at "too many behaviours: an agent has at most %d active behaviour instances" f.ag.config.max_behaviours;
    let uid = f.run.next_uid in
    f.run.next_uid <- uid + 1;
    let handlers = T.behaviour_handlers f.ag.env name in
    let b = { uid; btype = bt; bprops = Names.create 8;
              phandlers = Array.of_list (List.filter (fun (h : T.handler) -> h.h_kind = T.On_percept) handlers);
              mhandlers = Array.of_list (List.filter (fun (h : T.handler) -> h.h_kind <> T.On_percept) handlers);
              action = T.behaviour_action f.ag.env name } in
    let bf = { f with beh = Some b; id = 0; locals = { vars = [] }; content = None; message = None } in
    List.iter (fun (p : T.property) ->
        let v = match p.p_init with Some e -> coerce p.p_type (expr bf e) | None -> default_value p.p_type in
        Names.replace b.bprops p.p_name { v; ty = p.p_type }) (T.behaviour_properties f.ag.env name);
    (match T.behaviour_create f.ag.env name with
     | Some r -> ignore (run_routine bf at r (Some b) (`Named kvs))
     | None -> ());
    f.run.effects <- Semantics.Machine.Activate b :: f.run.effects;
    f.run.live <- f.run.live + 1;
    add_event f (Activated name)

(* R5h: [deactivate this] takes effect once (D16: a second one in the same
   body does nothing and is not traced). *)
and deactivate (f : frame) at =
  if f.in_guard then no_effect_in_guard at;
  match f.beh with
  | Some _ when List.mem Semantics.Machine.Deactivate f.run.effects -> ()
  | Some _ ->
    f.run.effects <- Semantics.Machine.Deactivate :: f.run.effects;
    f.run.live <- f.run.live - 1;
    add_event f (Deactivated f.id)
  | None -> err at "deactivate this outside a behaviour"

and default_value (ty : Ty.t) = match Ty.repr ty with
  | Ty.Integer -> V.Int 0 | Ty.Float -> V.Float 0. | Ty.Double -> V.Double 0.
  | Ty.Boolean -> V.Bool false | Ty.Text -> V.Text ""
  | Ty.List _ -> V.list_of [] | Ty.Map _ -> V.map_empty ()
  | _ -> V.Unit

(* -------------------------------------------------------- running *)

(* A run-time error recorded as an [Error] event (R7): [true]; any other
   exception: [false]. *)
let record_error (f : frame) x =
  match error_of_exn x with
  | Some (kind, at, msg) -> add_event f (Error (kind, at, msg)); true
  | None -> false

(* What ends a body: [return], [break] and [continue] nothing, a run-time
   error recorded, any other exception raised again. *)
let recover (f : frame) = function
  | Return _ | Break | Continue -> ()
  | Stack_overflow ->
    (* what max_call_depth does not bound (an expression nested too deeply;
       a smaller stack, as in a browser) *)
    add_event f (Error (Exhaustion_error, Source.no_region, "recursion too deep"))
  | x -> if not (record_error f x) then raise x

let protect (f : frame) body = try body () with x -> recover f x

(* The agent after a run: what the body did added to what it had. *)
let finish_run (a : agent) (r : run) =
  match r.events, r.outbox with
  | [], [] when r.next_uid = a.next_uid -> a
  | _ -> { a with events = r.events @ a.events; outbox = r.outbox @ a.outbox; next_uid = r.next_uid }

(* The end of a handler ([handler], from 1) or an action block ([0]): its
   effects on the behaviours, in order, recorded with it as a [Ran] event
   when the trace needs them ([record_effects]). *)
let finish_body (f : frame) handler =
  let effects = List.rev f.run.effects in
  if f.ag.config.record_effects then add_event f (Ran { handler; effects });
  (finish_run f.ag f.run, effects)

(* The value of a when condition [g] (or of its last conjunct). *)
let condition_value (g : Ast.expr) = function
  | V.Bool b -> b
  | v -> err g.at "a when condition is a boolean, not a %s" (V.type_name v)

(* R3b: a guard is evaluated now, in fresh locals and on a fresh step
   budget; an error makes it false, and is recorded. When it holds, the
   locals it bound go to the body. *)
let guard (a : agent) ~id b (h : T.handler) ?content ?message () =
  let run = new_run a ~active:0 in
  let f = { (frame a run ~beh:b ~id ?content ?message ()) with in_guard = true } in
  let holds = match h.h_guard with
    | None -> true
    | Some g -> (try condition_value g (expr f g) with x when record_error f x -> false) in
  (finish_run a run, if holds then Some (List.rev_map (fun (x, r) -> (x, !r)) f.locals.vars) else None)

(* A handler's body, in its guard's bindings, on a fresh step budget. *)
let body (a : agent) ~id ~active b (h : T.handler) hi ?content ?message bindings =
  let f = frame a (new_run a ~active) ~beh:b ~id ?content ?message ~locals:bindings () in
  protect f (fun () -> block f h.h_body);
  finish_body f hi

let create_agent ?(config = default_config) env ~name ~atype ~args =
  match T.agent env atype with
  | None -> link Source.no_region "unknown agent type %s" atype
  | Some at ->
    let a = { env; name; atype = at; props = Names.create 16; config; next_uid = 1; events = []; outbox = [] } in
    let params = match T.agent_create env atype with Some r -> r.r_params | None -> [] in
    if List.length params <> List.length args then
      link Source.no_region "agent type %s takes %d creation argument%s, not %d"
        atype (List.length params) (if List.length params = 1 then "" else "s") (List.length args);
    let args = List.map2 (fun (n, ty) v -> match coerce_param ty v with
        | Some v -> v
        | None -> link Source.no_region "creation argument %s of %s is a %s, not a %s" n atype (Ty.to_string ty) (V.type_name v))
        params args in
    let run = new_run a ~active:0 in
    let f = frame a run () in
    protect f (fun () ->
        List.iter (fun (p : T.property) ->
            let v = match p.p_init with Some e -> coerce p.p_type (expr f e) | None -> default_value p.p_type in
            Names.replace a.props p.p_name { v; ty = p.p_type }) (T.agent_properties env atype);
        match T.agent_create env atype with
        | Some r -> ignore (run_routine f Source.no_region r None (`Positional args))
        | None -> ());
    let behs = List.filter_map (function Semantics.Machine.Activate b -> Some b | _ -> None) (List.rev run.effects) in
    (finish_run a run, behs)

let destroy_agent a =
  match a.atype.a_destroy with
  | None -> a
  | Some b ->
    let run = new_run a ~active:0 in
    let f = frame a run () in
    protect f (fun () -> block f b);
    finish_run a run

let rec literal_value env (e : Ast.expr) : V.t =
  match e.it with
  | Unop (Neg, { it = Lit (Ast.Int 2147483648); _ }) -> V.Int (-2147483648)   (* as the checker: the least int *)
  | Lit (Ast.Int n) when n > 2147483647 || n < -2147483648 ->
    (* D8: integers are 32-bit; the type checker says the same of a program *)
    err e.at "integer literal %d is out of range: integer is 32-bit (-2147483648..2147483647)" n
  | Lit l -> literal l
  | Unop (Neg, x) -> (match literal_value env x with
      | V.Int i -> V.int32 (- i) | V.Double d -> V.Double (-. d) | V.Float d -> V.Float (-. d)
      | _ -> err e.at "only numbers can be negated")
  | List es -> V.list_of (List.map (literal_value env) es)
  | Map kvs ->
    let m = V.map_empty () in
    (match m with
     | V.Map mv ->
       List.iter (fun (k, v) ->
           try V.map_set mv (literal_value env k) (literal_value env v)
           with V.Too_large ->
             err e.at "value too large: comparing or hashing it would visit more than %d values" V.max_visits) kvs
     | _ -> ());
    m
  | Call ({ it = "aid"; _ }, [ a ]) -> (match literal_value env a with V.Text n -> V.Aid n | _ -> err e.at "aid takes a text")
  | Call (g, args) -> construct env e.at g.it (List.map (literal_value env) args)
  | Name x -> (match T.schema env x with
      | Some s when s.s_slots = [] -> V.Schema { sname = s.s_name; slots = [||] }
      | _ -> err e.at "%s is not a value the host can give (a literal, aid(\"name\") or a schema construction)" x)
  | _ -> err e.at "only literal values can be given here"

let percept_value env ~agent_type (e : Ast.expr) =
  let v = literal_value env e in
  match v with
  | V.Schema s ->
    (match T.schema env s.sname with
     | Some sc when sc.s_percept ->
       let visible = match T.agent env agent_type with Some a -> a.a_visible | None -> [] in
       if not (T.visible_schema env visible s.sname) then
         err e.at "percept type %s is not in an ontology that agent type %s uses" s.sname agent_type;
       (v, sc.s_priority)
     | _ -> err e.at "%s is not a percept type (it does not extend percept)" s.sname)
  | _ -> err e.at "a percept is a construction of a percept type, such as qrCodeRead(\"A7\")"

(* ------------------------------------------- for the fast engine *)

let reset_run (r : run) (a : agent) ~active =
  r.fuel <- a.config.fuel;
  (match r.events with [] -> () | _ -> r.events <- []);
  (match r.outbox with [] -> () | _ -> r.outbox <- []);
  (match r.effects with [] -> () | _ -> r.effects <- []);
  r.next_uid <- a.next_uid;
  r.live <- active
let refuel (r : run) (a : agent) = r.fuel <- a.config.fuel
let quiet (r : run) (a : agent) =
  (match r.events, r.outbox, r.effects with [], [], [] -> true | _ -> false) && r.next_uid = a.next_uid
let body_frame (a : agent) run ~id b = frame a run ~beh:b ~id ()
let agent_frame (f : frame) =
  { f with beh = None; id = 0; locals = { vars = [] }; content = None; message = None }
let activate_at (f : frame) ~depth at name kvs = activate { f with depth } at name kvs
let deactivate_at (f : frame) at = deactivate f at
let log_value (f : frame) at v = add_event f (Log (P.text (bounded_text ~quote:false at v)))
let run_effects (r : run) = List.rev r.effects

(* The end of handler [h] (0: an action block) that ran in [r], on the
   agent [a] as it was when the body started. *)
let finish (a : agent) (r : run) ~handler =
  let effects = List.rev r.effects in
  if a.config.record_effects then r.events <- Ran { handler; effects } :: r.events;
  (finish_run a r, effects)

(* ------------------------------------------------------- the bodies *)

module Bodies = struct
  type percept = V.t
  type nonrec message = message
  type obj = V.t
  type nonrec beh = beh
  type world = agent
  type bindings = (string * V.t) list

  let cyclic b = b.btype.b_kind = Ast.Cyclic
  let has_action b = b.action <> None
  let percept_handlers b = Array.length b.phandlers
  let message_handlers b = Array.length b.mhandlers

  let percept_applicable a ~id b h p = guard a ~id b b.phandlers.(h - 1) ~content:p ()

  let run_percept_handler a ~id ~active b h p bindings =
    body a ~id ~active b b.phandlers.(h - 1) h ~content:p bindings

  let run_action a ~id ~active b =
    let f = frame a (new_run a ~active) ~beh:b ~id () in
    (match b.action with Some code -> protect f (fun () -> block f code) | None -> ());
    finish_body f 0

  let perf_ok (h : T.handler) (m : message) = match h.h_kind with
    | T.On_message (Some p) -> p = m.perf
    | T.On_message None -> true
    | T.On_percept -> false

  let message_accepted a ~id b h (m : message) =
    let hd = b.mhandlers.(h - 1) in
    if not (perf_ok hd m) then (a, None)
    else guard a ~id b hd ~content:m.content ~message:m ()

  let run_message_handler a ~id ~active b h (m : message) bindings =
    body a ~id ~active b b.mhandlers.(h - 1) h ~content:m.content ~message:m bindings

  let take_outbox (a : agent) = match a.outbox with
    | [] -> (a, [])
    | o -> ({ a with outbox = [] }, List.rev o)
end
end

module type S = sig
  val create_agent :
    ?config:config -> T.t -> name:string -> atype:string -> args:V.t list -> agent * beh list
  val destroy_agent : agent -> agent
  module Bodies : Semantics.Machine.BODIES
    with type percept = V.t and type message = message and type obj = V.t
     and type beh = beh and type world = agent and type bindings = (string * V.t) list
end

include Make (Primitives)
