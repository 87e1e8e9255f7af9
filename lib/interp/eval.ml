(* The interpreter's evaluation rules. docs/semantics.md ("Running programs")
   states them; the names of the functions follow the syntactic categories. *)

open Syntax
module Ast = Syntax.Ast
module T = Typing.Tenv
module Ty = Typing.Types
module V = Value

type message = { perf : string; content : V.t; sender : string }

(* The kinds of run-time errors (the exceptions Trap, Exhaustion, Link below). *)
type error_kind = Trap_error | Exhaustion_error | Link_error

(* A property: its value and its declared type, to which assignments convert
   (integer to float or double). *)
type cell = { mutable v : V.t; ty : Ty.t }

module Names = Syntax.Strtbl

(* What the fast engine (lib/engine) keeps with a behaviour instance; the
   evaluation rules never look at it. *)
type engine_slot = ..
type engine_slot += Nothing_kept

type beh = {
  uid : int;
  btype : T.behaviour;
  bprops : cell Names.t;
  mutable bcache : (string * cell option) list;
      (* properties found by name from this behaviour's code, by address *)
  phandlers : T.handler array;
  mhandlers : T.handler array;
  action : Ast.block option;
  mutable kept : engine_slot;
}

type event =
  | Log of string
  | Invoke of { meth : string; cls : string; args : V.t list; result : V.t }
  | Sent of { perf : string; content : V.t; receivers : string list }
  | Activated of string
  | Deactivated of int
  | Error of error_kind * Source.region * string
  | Ran of { handler : int; effects : beh Semantics.Machine.effect list }

(* Local variables: few per frame, so an association list of cells is
   cheaper than a hash table (frames are made for every guard evaluated). *)
type locals = { mutable vars : (string * V.t ref) list }

(* Names are interned by the lexer (Syntax.Lexer): equal names are usually
   the same string. *)
let[@inline] same_name (x : string) y =
  x == y || (String.length x = String.length y && String.equal x y)

let new_locals () = { vars = [] }
(* [no_local]: what [local_cell] answers for a name no local has (compared
   by address; never written), so that a lookup allocates nothing. *)
let no_local : V.t ref = ref V.Unit
let rec local_cell x = function
  | [] -> no_local
  | (y, r) :: rest -> if same_name x y then r else local_cell x rest
let local_set l x v =
  let r = local_cell x l.vars in
  if r != no_local then r := v else l.vars <- (x, ref v) :: l.vars

let beh_type b = b.btype.b_name
let keep b x = b.kept <- x

type agent = {
  env : T.t;
  name : string;
  atype : T.agent;
  props : cell Names.t;
  mutable acache : (string * cell option) list;
      (* properties found by name from the agent's own code, by address *)
  mutable outbox : (string * message) list;
  mutable events : event list;
  mutable effects : beh Semantics.Machine.effect list;
  mutable fuel_limit : int;
  mutable pending : (int * int * frame) option;
  mutable record_ran : bool;   (* record Ran events (for a trace) *)
  mutable live : int;
      (* D19: active instances when the current rule started (set_live),
         plus the activations its bodies made since, minus their
         deactivations *)
}

(* What a running body sees. *)
and frame = {
  ag : agent;
  beh : beh option;          (* the behaviour whose code runs, if any *)
  id : int;                  (* its machine instance id (0 in agent code) *)
  locals : locals;
  content : V.t option;
  message : message option;
  fuel : int ref;
  depth : int;               (* nested calls of functions and procedures *)
}

let property a x = match Names.find_opt a.props x with Some c -> Some c.v | None -> None

let take_events a = match a.events with
  | [] -> []
  | [ _ ] as e -> a.events <- []; e
  | e -> a.events <- []; List.rev e

(* Run-time errors, one exception per kind (as the WebAssembly reference
   interpreter's util/error.ml): the kind decides the wording of a report,
   never the trace line, which is the same [error] event for all three. A
   broken invariant of the implementation is Semantics.Fault.Crash. *)
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

exception Return of V.t
exception Break
exception Continue

let err at fmt = Printf.ksprintf (fun s -> raise (Trap (at, s))) fmt
let link at fmt = Printf.ksprintf (fun s -> raise (Link (at, s))) fmt

(* Nested calls of Jadescript functions and procedures one body may make:
   deeper recursion is an exhaustion error, never an OCaml stack overflow. *)
let max_call_depth = 200

(* D19: active behaviour instances one agent may have. *)
let max_behaviours = 10_000

let set_live a n = a.live <- n

(* D21: the largest text (bytes, also as printed by log, send, invoke) and
   map (entries) a run may build. *)
let max_text = 1_000_000
let max_map_size = 1_000_000

let too_big at what =
  raise (Exhaustion (at, Printf.sprintf "value too large: %s (at most %d bytes in a text, %d entries in a map)"
                       what max_text max_map_size))

(* The text of [v] (log), or its literal (what a trace line carries), when
   it is at most max_text bytes long. *)
let bounded_text ~quote at v =
  if not (V.printed_within ~quote max_text v) then too_big at "its text would be too long";
  v

(* D37: a comparison or a hash past V.max_visits values. *)
let too_large_to_compare at =
  raise (Exhaustion (at, Printf.sprintf "value too large: comparing or hashing it would visit more than %d values"
                       V.max_visits))

let map_set_bounded at (m : V.map_v) k v =
  try
    if m.size >= max_map_size && V.map_find m k = None then too_big at "the map would have too many entries";
    V.map_set m k v
  with V.Too_large -> too_large_to_compare at

let uids = ref 0


(* ------------------------------------------------------------ frames *)


(* D22: the memory a run may take, in megabytes ([None]: no bound). Every
   1,024 statements, and before a text of more than 64 KB is built, the
   major heap's size is compared with it; over it, the heap is compacted
   (garbage may be most of it) and compared again; still over it, the
   statement is an exhaustion error (R7). *)
let max_memory : int option ref = ref None

let set_max_memory mb = max_memory := mb

let check_memory at =
  match !max_memory with
  | None -> ()
  | Some mb ->
    let words = mb * (1024 * 1024 / (Sys.word_size / 8)) in
    if (Gc.quick_stat ()).heap_words > words then begin
      Gc.compact ();
      if (Gc.quick_stat ()).heap_words > words then
        raise (Exhaustion (at, Printf.sprintf "out of memory: the run takes more than %d MB (--max-memory)" mb))
    end

let tick (f : frame) at =
  decr f.fuel;
  if !(f.fuel) < 0 then
    raise (Exhaustion (at, Printf.sprintf "step budget exhausted: more than %d statements in one handler or step (--fuel)" f.ag.fuel_limit));
  if !(f.fuel) land 1023 = 0 then check_memory at

(* ------------------------------------------------------- conversions *)

let rec coerce_param (ty : Ty.t) (v : V.t) : V.t option =
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

and coerce ty v = match coerce_param ty v with Some v -> v | None -> v

(* ------------------------------------------------------- names *)

(* The property a name denotes where no local has it: the running
   behaviour's, else the agent's. *)
let prop_cell_slow (f : frame) x =
  match (match f.beh with
      | Some b when Names.length b.bprops > 0 -> Names.find_opt b.bprops x
      | _ -> None) with
  | Some _ as c -> c
  | None -> Names.find_opt f.ag.props x

(* The same, remembered per behaviour instance (or for the agent's code) by
   the name's address: the lexer interns names, so a name of the program is
   found by one comparison. Only properties found are remembered, at most
   [cache_size] names, after which the tables answer. A table is complete
   once its initialisers have run; what they remembered is forgotten then
   (a later property of the same name may have replaced a cell). *)
let cache_size = 8

let rec cached x = function
  | [] -> None
  | (y, c) :: rest -> if x == y then c else cached x rest

let prop_cell (f : frame) x =
  let cache = match f.beh with Some b -> b.bcache | None -> f.ag.acache in
  match cached x cache with
  | Some _ as c -> c
  | None ->
    let r = prop_cell_slow f x in
    (match r with
     | Some _ when List.length cache < cache_size ->
       (match f.beh with
        | Some b -> b.bcache <- (x, r) :: b.bcache
        | None -> f.ag.acache <- (x, r) :: f.ag.acache)
     | _ -> ());
    r

let lookup (f : frame) at x =
  let r = local_cell x f.locals.vars in
  if r != no_local then !r else
    match prop_cell f x with
    | Some c -> c.v
    | None ->
      match T.schema f.ag.env x with
      | Some s when s.s_slots = [] -> V.Schema { sname = s.s_name; slots = [||] }
      | _ -> err at "unknown name %s" x

let set_cell c v = c.v <- coerce c.ty v

let assign_name (f : frame) x v =
  let r = local_cell x f.locals.vars in
  if r != no_local then r := v else
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
  match Array.find_opt (fun (n, _) -> n = x) s.slots with
  | Some (_, r) -> r
  | None -> err at "%s has no slot %s" s.sname x

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

let rec pattern (f : frame) binds (p : Ast.pattern) (v : V.t) : bool =
  match p.it, v with
  | PWild, _ -> true
  | PLit l, _ -> V.equal (literal l) v
  | PName x, V.Schema s when same_name s.sname x -> true   (* the value's own schema *)
  | PName x, _ ->
    (match T.schema f.ag.env x with
     | Some _ -> (match v with V.Schema s -> T.subschema f.ag.env s.sname x | _ -> false)
     | None -> binds := (x, v) :: !binds; true)
  | PCons (c, ps), V.Schema s when same_name s.sname c.it && List.length ps = Array.length s.slots ->
    (* the value's own schema: its slots are the constructor's, in order *)
    let rec all i = function
      | [] -> true
      | p :: rest -> pattern f binds p !(snd s.slots.(i)) && all (i + 1) rest in
    all 0 ps
  | PCons (c, ps), V.Schema s ->
    T.subschema f.ag.env s.sname c.it
    && (match T.schema f.ag.env c.it with
        | Some sc ->
          List.length ps = List.length sc.s_slots
          && List.for_all2 (fun p (n, _) -> pattern f binds p !(slot p.at s n)) ps sc.s_slots
        | None -> false)
  | PCons _, _ -> false

and literal = function
  | Ast.Int i -> V.Int i
  | Ast.Real r -> V.Double (float_of_string r)
  | Ast.Text s -> V.Text s
  | Ast.Bool b -> V.Bool b

(* [invoke] once its target and arguments are evaluated (in that order):
   each argument's literal within D21's bound, then the host's method. *)
(* A send's receivers: an aid, or a list of aids (R6). *)
let receivers_of at = function
  | V.Aid a -> [ a ]
  | V.List l -> List.map (function V.Aid a -> a | v -> err at "a receiver is an aid, not a %s" (V.type_name v)) (V.list_items l)
  | v -> err at "a receiver is an aid, not a %s" (V.type_name v)

(* The message of a send, in each receiver's outbox entry, and the event. *)
let post_send (a : agent) perf content receivers =
  List.iter (fun r -> a.outbox <- (r, { perf; content; sender = a.name }) :: a.outbox) receivers;
  a.events <- Sent { perf; content; receivers } :: a.events

let invoke_values (a : agent) at (i : Ast.invoke) target vs =
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
       a.events <- Invoke { meth = i.meth.it; cls = n.cls; args; result } :: a.events;
       result)
  | v -> err i.target.at "invoke needs a host object (any), not a %s" (V.type_name v)

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
    if pattern f binds p v then (List.iter (fun (x, v) -> local_set f.locals x v) (List.rev !binds); V.Bool true)
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
  | Binop (Eq, l, r) -> V.Bool (equal_values e.at (expr f l) (expr f r))
  | Binop (Neq, l, r) -> V.Bool (not (equal_values e.at (expr f l) (expr f r)))
  | Binop ((Lt | Gt | Le | Ge) as op, l, r) -> compare_values e.at op (expr f l) (expr f r)
  | Binop (Add, l, r) ->
    let a = expr f l and b = expr f r in
    (match a, b with
     | V.Text _, _ | _, V.Text _ ->
       let a = V.to_text (bounded_text ~quote:false e.at a) and b = V.to_text (bounded_text ~quote:false e.at b) in
       if String.length a + String.length b > max_text then too_big e.at "the text would be too long";
       if String.length a + String.length b > 65536 then check_memory e.at;
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

and run_routine (f : frame) at (r : T.routine) beh args : V.t option =
  tick f at;
  if f.depth >= max_call_depth then
    raise (Exhaustion (at, Printf.sprintf "recursion too deep: more than %d nested calls of functions and procedures"
                         max_call_depth));
  let locals = new_locals () in
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
  invoke_values f.ag at i target (List.map (expr f) i.args)

(* ----------------------------------------------------- statements *)

and block (f : frame) (b : Ast.block) = List.iter (stmt f) b

and stmt (f : frame) (s : Ast.stmt) =
  tick f s.at;
  match s.it with
  | Assign (lv, e) -> let v = expr f e in assign f lv v
  | Local (x, ty, e) ->
    let v = expr f e in
    let v = match ty.it with
      | TName ("float") -> coerce Ty.Float v | TName "double" -> coerce Ty.Double v | _ -> v in
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
  | Deactivate ->
    (match f.beh with
     | Some _ when List.mem Semantics.Machine.Deactivate f.ag.effects ->
       (* R5h: this body already deactivated its behaviour; doing it again does nothing *)
       ()
     | Some _ ->
       f.ag.effects <- Semantics.Machine.Deactivate :: f.ag.effects;
       f.ag.live <- f.ag.live - 1;   (* D19: the instance leaves at the end of the rule *)
       f.ag.events <- Deactivated f.id :: f.ag.events
     | None -> err s.at "deactivate this outside a behaviour")
  | Send (perf, c, rs) ->
    let content = bounded_text ~quote:true c.at (expr f c) in
    let receivers = List.concat_map (fun (r : Ast.expr) -> receivers_of r.at (expr f r)) rs in
    post_send f.ag perf.it content receivers
  | Log e -> let v = bounded_text ~quote:false e.at (expr f e) in f.ag.events <- Log (V.to_text v) :: f.ag.events
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

(* R5g: a new instance; its properties, then its on create, run now; then the
   machine appends it to the active behaviours and the ready list. *)
and activate (f : frame) at name kvs =
  match T.behaviour f.ag.env name with
  | None -> err at "unknown behaviour %s" name
  | Some bt ->
    if f.ag.live >= max_behaviours then
      raise (Exhaustion (at, Printf.sprintf "too many behaviours: an agent has at most %d active behaviour instances"
                           max_behaviours));
    incr uids;
    let handlers = T.behaviour_handlers f.ag.env name in
    let phandlers = Array.of_list (List.filter (fun (h : T.handler) -> h.h_kind = T.On_percept) handlers) in
    let b = { uid = !uids; btype = bt; bprops = Names.create 8; bcache = []; kept = Nothing_kept;
              phandlers;
              mhandlers = Array.of_list (List.filter (fun (h : T.handler) -> h.h_kind <> T.On_percept) handlers);
              action = T.behaviour_action f.ag.env name } in
    let bf = { f with beh = Some b; id = 0; locals = new_locals (); content = None; message = None } in
    List.iter (fun (p : T.property) ->
        let v = match p.p_init with Some e -> coerce p.p_type (expr bf e) | None -> default_value p.p_type in
        Names.replace b.bprops p.p_name { v; ty = p.p_type }) (T.behaviour_properties f.ag.env name);
    b.bcache <- [];
    (match T.behaviour_create f.ag.env name with
     | Some r -> ignore (run_routine bf at r (Some b) (`Named kvs))
     | None -> ());
    f.ag.effects <- Semantics.Machine.Activate b :: f.ag.effects;
    f.ag.live <- f.ag.live + 1;
    f.ag.events <- Activated name :: f.ag.events

and default_value (ty : Ty.t) = match Ty.repr ty with
  | Ty.Integer -> V.Int 0 | Ty.Float -> V.Float 0. | Ty.Double -> V.Double 0.
  | Ty.Boolean -> V.Bool false | Ty.Text -> V.Text ""
  | Ty.List _ -> V.list_of [] | Ty.Map _ -> V.map_empty ()
  | _ -> V.Unit

(* -------------------------------------------------------- running *)

let frame ag ?beh ?(id = 0) ?content ?message () =
  { ag; beh; id; locals = new_locals (); content; message; fuel = ref ag.fuel_limit; depth = 0 }

(* Run a body: a run-time error stops it and is recorded (R7). *)
let record_error (a : agent) x =
  match error_of_exn x with
  | Some (kind, at, msg) -> a.events <- Error (kind, at, msg) :: a.events; true
  | None -> false

let recover (a : agent) = function
  | Return _ | Break | Continue -> ()
  | Stack_overflow ->
    (* what max_call_depth does not bound (an expression nested too deeply;
       a smaller stack, as in a browser) *)
    a.events <- Error (Exhaustion_error, Source.no_region, "recursion too deep") :: a.events
  | x -> if not (record_error a x) then raise x

let protect (a : agent) body = try body () with x -> recover a x

(* The same for a block, without a closure (a handler body, once per percept). *)
let protect_block (a : agent) f b = try block f b with x -> recover a x

(* The effects of the body that just ran, for the machine. *)
let take_effects a =
  match a.effects with
  | [] -> []
  | effs -> a.effects <- []; List.rev effs

(* The same, recorded with the body that ran them (the trace's [effects],
   [action_effects] and [handler]): [handler] is 0 for an action block. *)
let take_ran a handler =
  let effects = take_effects a in
  if a.record_ran then a.events <- Ran { handler; effects } :: a.events;
  effects

(* The value of a when condition [g] (or of its last conjunct). *)
let condition_value (g : Ast.expr) = function
  | V.Bool b -> b
  | v -> err g.at "a when condition is a boolean, not a %s" (V.type_name v)

let condition (f : frame) (g : Ast.expr) = condition_value g (expr f g)

let guard_holds (f : frame) (h : T.handler) =
  match h.h_guard with
  | None -> true
  | Some g -> condition f g

let create_agent env ~name ~atype ~args ~fuel =
  match T.agent env atype with
  | None -> link Source.no_region "unknown agent type %s" atype
  | Some at ->
    let a = { env; name; atype = at; props = Names.create 16; acache = []; outbox = []; events = [];
              effects = []; fuel_limit = fuel; pending = None; record_ran = true; live = 0 } in
    let f = frame a () in
    let params = match T.agent_create env atype with Some r -> r.r_params | None -> [] in
    if List.length params <> List.length args then
      link Source.no_region "agent type %s takes %d creation argument%s, not %d"
        atype (List.length params) (if List.length params = 1 then "" else "s") (List.length args);
    let args = List.map2 (fun (n, ty) v -> match coerce_param ty v with
        | Some v -> v
        | None -> link Source.no_region "creation argument %s of %s is a %s, not a %s" n atype (Ty.to_string ty) (V.type_name v))
        params args in
    protect a (fun () ->
        List.iter (fun (p : T.property) ->
            let v = match p.p_init with Some e -> coerce p.p_type (expr f e) | None -> default_value p.p_type in
            Names.replace a.props p.p_name { v; ty = p.p_type }) (T.agent_properties env atype);
        a.acache <- [];
        match T.agent_create env atype with
        | Some r -> ignore (run_routine f Source.no_region r None (`Positional args))
        | None -> ());
    let behs = List.filter_map (function Semantics.Machine.Activate b -> Some b | _ -> None) (take_effects a) in
    (a, behs)

let destroy_agent a =
  match a.atype.a_destroy with
  | None -> ()
  | Some b -> protect a (fun () -> block (frame a ()) b)

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

let percept_handler b h = b.phandlers.(h - 1)
let percept_handler_count b = Array.length b.phandlers
let guard_frame a ~id b p = frame a ~beh:b ~id ~content:p ()
let bind_local (f : frame) x v = local_set f.locals x v
let condition_part (f : frame) ~(whole : Ast.expr) (part : Ast.expr) = condition_value whole (expr f part)

(* What lib/engine/compiled_bodies.ml reuses of the rules above, unchanged. *)
let reset_fuel (f : frame) = f.fuel := f.ag.fuel_limit
let agent_frame (f : frame) =
  { f with beh = None; id = 0; locals = new_locals (); content = None; message = None }
let activate_at (f : frame) ~depth at name kvs = activate { f with depth } at name kvs

module Bodies = struct
  type percept = V.t
  type nonrec message = message
  type obj = V.t
  type nonrec beh = beh
  type world = agent

  let cyclic b = b.btype.b_kind = Ast.Cyclic
  let has_action b = b.action <> None
  let percept_handlers b = Array.length b.phandlers
  let message_handlers b = Array.length b.mhandlers

  (* R3b: the pattern and the when are evaluated now; an error makes the
     handler not applicable, and is recorded. The bindings are kept for the
     body. *)
  let percept_applicable a ~id b h p =
    let f = frame a ~beh:b ~id ~content:p () in
    let ok = try guard_holds f b.phandlers.(h - 1) with x when record_error a x -> false in
    a.pending <- (if ok then Some (id, h, f) else None);
    (a, ok)

  (* The body runs in the frame its guard was evaluated in (for the
     bindings), with a fresh step budget. *)
  let run_percept_handler a ~id b h p =
    let f = match a.pending with
      | Some (i, j, f) when i = id && j = h && (match f.content with Some q -> q == p | None -> false) ->
        a.pending <- None; f.fuel := a.fuel_limit; f
      | Some _ -> a.pending <- None; frame a ~beh:b ~id ~content:p ()
      | None -> frame a ~beh:b ~id ~content:p () in
    protect_block a f b.phandlers.(h - 1).h_body;
    (a, take_ran a h)

  let run_action a ~id b =
    (match b.action with
     | Some body -> protect a (fun () -> block (frame a ~beh:b ~id ()) body)
     | None -> ());
    (a, take_ran a 0)

  let perf_ok (h : T.handler) (m : message) = match h.h_kind with
    | T.On_message (Some p) -> p = m.perf
    | T.On_message None -> true
    | T.On_percept -> false

  let message_accepted a ~id b h (m : message) =
    let hd = b.mhandlers.(h - 1) in
    perf_ok hd m
    && (let f = frame a ~beh:b ~id ~content:m.content ~message:m () in
        try guard_holds f hd with x when record_error a x -> false)

  let run_message_handler a ~id b h (m : message) =
    let hd = b.mhandlers.(h - 1) in
    let f = frame a ~beh:b ~id ~content:m.content ~message:m () in
    protect a (fun () ->
        (* the guard again, for its pattern variables *)
        ignore (guard_holds f hd);
        block f hd.h_body);
    (a, take_ran a h)

  let take_outbox a = let o = List.rev a.outbox in a.outbox <- []; (a, o)
end
