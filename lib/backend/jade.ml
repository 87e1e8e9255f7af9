(* The JADE back end: Java 17 source for a checked program, to run on the
   runtime of runtime/jade (CONTRACT.md). The semantics are the interpreter's
   (lib/interp/eval.ml): every value is a Java Object, operators go through
   jsref.values.Ops with the source position the interpreter reports errors
   at, fuel is ticked where eval.ml ticks, operands are evaluated in the order
   eval.ml evaluates them. *)

open Syntax
module Ast = Syntax.Ast
module T = Typing.Tenv
module Ty = Typing.Types

exception Unsupported of Source.region * string

let unsupported at fmt = Printf.ksprintf (fun s -> raise (Unsupported (at, s))) fmt

(* ------------------------------------------------------------ Java text *)

(* Decode UTF-8 (invalid bytes become U+FFFD) into code points. *)
let code_points s =
  let n = String.length s in
  let rec go i acc =
    if i >= n then List.rev acc
    else
      let c = Char.code s.[i] in
      let cont k = if i + k < n then Char.code s.[i + k] land 0x3F else 0 in
      let ok k = let rec chk j = j > k || (i + j < n && Char.code s.[i + j] land 0xC0 = 0x80 && chk (j + 1)) in chk 1 in
      if c < 0x80 then go (i + 1) (c :: acc)
      else if c land 0xE0 = 0xC0 && ok 1 then go (i + 2) ((((c land 0x1F) lsl 6) lor cont 1) :: acc)
      else if c land 0xF0 = 0xE0 && ok 2 then
        go (i + 3) ((((c land 0x0F) lsl 12) lor (cont 1 lsl 6) lor cont 2) :: acc)
      else if c land 0xF8 = 0xF0 && ok 3 then
        go (i + 4) ((((c land 0x07) lsl 18) lor (cont 1 lsl 12) lor (cont 2 lsl 6) lor cont 3) :: acc)
      else go (i + 1) (0xFFFD :: acc) in
  go 0 []

(* A code point outside ASCII as Java \uXXXX escapes (a surrogate pair above
   the BMP); safe in literals and comments since it is never a line end. *)
let add_unicode b cp =
  if cp < 0x10000 then Printf.bprintf b "\\u%04X" cp
  else
    let c = cp - 0x10000 in
    Printf.bprintf b "\\u%04X\\u%04X" (0xD800 lor (c lsr 10)) (0xDC00 lor (c land 0x3FF))

let java_string s =
  let b = Buffer.create (String.length s + 2) in
  Buffer.add_char b '"';
  List.iter (fun cp ->
      match cp with
      | 0x22 -> Buffer.add_string b "\\\""
      | 0x5C -> Buffer.add_string b "\\\\"
      | 0x0A -> Buffer.add_string b "\\n"
      | 0x0D -> Buffer.add_string b "\\r"
      | 0x09 -> Buffer.add_string b "\\t"
      | c when c < 0x20 || c = 0x7F -> Printf.bprintf b "\\%03o" c
      | c when c < 0x80 -> Buffer.add_char b (Char.chr c)
      | c -> add_unicode b c) (code_points s);
  Buffer.add_char b '"';
  Buffer.contents b

(* Source text made safe for a // comment: every backslash doubled (so that
   none starts a Java unicode escape), non-ASCII as escapes. *)
let comment_text s =
  let b = Buffer.create (String.length s) in
  List.iter (fun cp ->
      match cp with
      | 0x5C -> Buffer.add_string b "\\\\"
      | c when c < 0x20 || c = 0x7F -> Buffer.add_char b ' '
      | c when c < 0x80 -> Buffer.add_char b (Char.chr c)
      | c -> add_unicode b c) (code_points s);
  (* and never the end of a block comment *)
  let t = Buffer.contents b in
  let r = Buffer.create (String.length t) in
  String.iteri (fun i c ->
      Buffer.add_char r c;
      if c = '*' && i + 1 < String.length t && t.[i + 1] = '/' then Buffer.add_char r ' ') t;
  Buffer.contents r

let java_keywords = [
  "abstract"; "assert"; "boolean"; "break"; "byte"; "case"; "catch"; "char"; "class"; "const";
  "continue"; "default"; "do"; "double"; "else"; "enum"; "extends"; "final"; "finally"; "float";
  "for"; "goto"; "if"; "implements"; "import"; "instanceof"; "int"; "interface"; "long"; "native";
  "new"; "package"; "private"; "protected"; "public"; "return"; "short"; "static"; "strictfp";
  "super"; "switch"; "synchronized"; "this"; "throw"; "throws"; "transient"; "try"; "void";
  "volatile"; "while"; "true"; "false"; "null"; "_"; "var"; "yield"; "record"; "sealed";
  "permits"; "non-sealed" ]

(* Simple names the generated code uses unqualified: a class, field or local
   of the program with one of these names would hide them. *)
let used_names = [
  "Object"; "String"; "Integer"; "Float"; "Double"; "Boolean"; "Number"; "Override";
  "SuppressWarnings"; "StackOverflowError"; "RuntimeException"; "Class"; "Math"; "System";
  "Ops"; "Text"; "Schema"; "JList"; "JMap"; "Aid"; "AgentRef"; "BehaviourRef"; "Nothing"; "Type";
  "JadescriptError"; "Literals"; "LiteralError"; "Scope"; "MessageValue"; "Program";
  "JadescriptAgent"; "JadescriptBehaviour"; "Message"; "ProgramInfo"; "BehaviourInfo";
  "java"; "jsgen"; "jsref"; "jade"; "myAgent"; "parent"; "serialVersionUID"; "List"; "ArrayList";
  "LinkedHashMap"; "Map" ]

let reserved x = List.mem x java_keywords || List.mem x used_names

(* ------------------------------------------------------------ the program *)

type gen = {
  env : T.t;
  files : string list;
  sources : (string, string array) Hashtbl.t;   (* file -> lines *)
  classes : (string, string) Hashtbl.t;          (* "S:name" | "A:name" | "B:name" -> Java class *)
  class_names : (string, unit) Hashtbl.t;        (* every Java class name given *)
}

(* A class of the program by its simple name: for its declaration and its
   file. *)
let simple_cls g kind name =
  match Hashtbl.find_opt g.classes (kind ^ ":" ^ name) with
  | Some c -> c
  | None -> "Schema"

(* A class of the program where the generated code refers to it: qualified
   by its package, since inside an agent or a behaviour a simple name would
   first find what JADE's classes declare and the class inherits (the
   nested classes Agent.Interrupted and Behaviour.RunnableChangedEvent, the
   fields Agent.AP_ACTIVE and Behaviour.STATE_READY), not the program's
   schema of that name (docs/jade.md, "Names"). *)
let cls g kind name =
  match Hashtbl.find_opt g.classes (kind ^ ":" ^ name) with
  | Some c -> "jsgen." ^ c
  | None -> "Schema"

let source_line g (r : Source.region) =
  match Hashtbl.find_opt g.sources r.left.file with
  | Some lines when r.left.line >= 1 && r.left.line <= Array.length lines ->
    String.trim lines.(r.left.line - 1)
  | _ -> ""

let at_string (r : Source.region) = java_string (Source.string_of_region r)

(* A position inside a comment. *)
let region_doc (r : Source.region) = comment_text (Source.string_of_region r)

(* A member's Java name: a prefix keeps it apart from everything else. *)
let prop_field x = "p_" ^ x
let fn_method x = "fn_" ^ x
let proc_method x = "do_" ^ x

(* A name that begins as the fields and methods of members do. *)
let member_prefixed x =
  List.exists (fun p -> String.length x > String.length p && String.sub x 0 (String.length p) = p)
    [ "p_"; "fn_"; "do_" ]

(* A slot's field: the slot's own name unless Java or the generated code
   reserves it. *)
let slot_field x = if reserved x then x ^ "$" else x

let assign_classes g =
  let take kind name =
    let base =
      if reserved name || Hashtbl.mem g.class_names name
         || member_prefixed name
      then name ^ "$" ^ kind else name in
    let rec fresh c k = if Hashtbl.mem g.class_names c then fresh (base ^ string_of_int k) (k + 1) else c in
    let c = fresh base 2 in
    Hashtbl.replace g.class_names c ();
    Hashtbl.replace g.classes (kind ^ ":" ^ name) c in
  List.iter (fun (s : T.schema) -> take "S" s.s_name) (T.schemas g.env);
  List.iter (fun (a : T.agent) -> take "A" a.a_name) (T.agents g.env);
  List.iter (fun (b : T.behaviour) -> take "B" b.b_name) (T.behaviours g.env)

(* ----------------------------------------------------------------- types *)

let rec type_expr (t : Ty.t) = match Ty.repr t with
  | Ty.Integer -> "Type.INTEGER" | Ty.Float -> "Type.FLOAT" | Ty.Double -> "Type.DOUBLE"
  | Ty.Boolean -> "Type.BOOLEAN" | Ty.Text -> "Type.TEXT" | Ty.Aid -> "Type.AID" | Ty.Any -> "Type.ANY"
  | Ty.List e -> "Type.list(" ^ type_expr e ^ ")"
  | Ty.Map (k, v) -> "Type.map(" ^ type_expr k ^ ", " ^ type_expr v ^ ")"
  | Ty.Schema s -> "Type.schema(" ^ java_string s ^ ")"
  | Ty.Onto _ as o -> "Type.onto(" ^ java_string (Ty.to_string o) ^ ")"
  | Ty.Agent (Some a) -> "Type.agent(" ^ java_string a ^ ")"
  | Ty.Agent None -> "Type.agent(null)"
  | Ty.Behaviour b -> "Type.behaviour(" ^ java_string b ^ ")"
  | Ty.Message _ -> "Type.MESSAGE"
  | Ty.Var _ | Ty.Error -> "Type.OTHER"

(* The Java type of a slot's field. *)
let field_type g (t : Ty.t) = match Ty.repr t with
  | Ty.Integer -> "Integer" | Ty.Float | Ty.Double -> "Number" | Ty.Boolean -> "Boolean"
  | Ty.Text -> "String" | Ty.Aid -> "Aid" | Ty.List _ -> "JList" | Ty.Map _ -> "JMap"
  | Ty.Schema s when T.schema g.env s <> None -> cls g "S" s
  | Ty.Schema _ | Ty.Onto _ -> "Schema"
  | _ -> "Object"

(* The conversion an assignment to a declared type makes (Eval.coerce): only
   numbers change. *)
let coerce_to (t : Ty.t) v = match Ty.repr t with
  | Ty.Float -> "Ops.coerce(Type.FLOAT, " ^ v ^ ")"
  | Ty.Double -> "Ops.coerce(Type.DOUBLE, " ^ v ^ ")"
  | _ -> v

(* ------------------------------------------------------------ an output *)

type out = { b : Buffer.t; mutable ind : int }

let line o fmt =
  Printf.ksprintf (fun s ->
      if s = "" then Buffer.add_char o.b '\n'
      else begin
        Buffer.add_string o.b (String.make (2 * o.ind) ' ');
        Buffer.add_string o.b s;
        Buffer.add_char o.b '\n'
      end) fmt

let indent o f = o.ind <- o.ind + 1; f (); o.ind <- o.ind - 1

let new_out () = { b = Buffer.create 4096; ind = 0 }

(* ------------------------------------------------- code of one method *)

type owner = OAgent of T.agent | OBehaviour of T.behaviour

type ret = RValue | RVoid | RTrue

type ctx = {
  g : gen;
  owner : owner;
  cls_name : string;                     (* the Java class being written *)
  locals : (string, string) Hashtbl.t;   (* Jadescript local -> Java local *)
  content : string option;               (* Java expression of content *)
  message : string option;               (* Java variable holding the Message *)
  ret : ret;
  mutable loops : string list;           (* labels of the enclosing loop bodies *)
  counter : int ref;                     (* fresh names, per class *)
  matchers : out;                        (* static pattern methods, per class *)
  mutable max_binds : int;
}

let fresh ctx p = incr ctx.counter; p ^ "$" ^ string_of_int !(ctx.counter)

(* How code reaches the agent: itself, or the behaviour's agent cast to the
   for-agent class. *)
let agent_ref ctx = match ctx.owner with
  | OAgent _ -> "this"
  | OBehaviour b -> (match b.b_for_agent with Some _ -> "jsAgent$()" | None -> "agent()")

let svc ctx = match ctx.owner with OAgent _ -> "" | OBehaviour _ -> "agent()."

type prop_home = Own | Of_agent

let find_prop ctx x : (T.property * prop_home) option =
  match ctx.owner with
  | OAgent a -> Option.map (fun p -> (p, Own)) (T.agent_property ctx.g.env a.a_name x)
  | OBehaviour b ->
    (match T.behaviour_property ctx.g.env b.b_name x with
     | Some p -> Some (p, Own)
     | None ->
       match b.b_for_agent with
       | Some a -> Option.map (fun p -> (p, Of_agent)) (T.agent_property ctx.g.env a x)
       | None -> None)

(* The interpreter resolves names and routines at run time, against the
   running agent's and behaviour's own types; the back end resolves them
   against the types of the code. They differ only when a subtype declares a
   property or routine under a name that the code of its super type resolves
   otherwise: such programs are refused. *)
let subtypes chain all name self =
  List.filter (fun x -> let c = chain x in List.length c > 1 && List.exists (fun y -> name y = self) (List.tl c)) all

let sub_behaviours ctx (b : T.behaviour) =
  subtypes (fun (x : T.behaviour) -> T.behaviour_chain ctx.g.env x.b_name) (T.behaviours ctx.g.env)
    (fun (x : T.behaviour) -> x.b_name) b.b_name

let sub_agents ctx a =
  subtypes (fun (x : T.agent) -> T.agent_chain ctx.g.env x.a_name) (T.agents ctx.g.env) (fun (x : T.agent) -> x.a_name) a

let refuse_shadow ctx at x ~found =
  let agents a = List.filter (fun (s : T.agent) -> List.exists (fun (p : T.property) -> p.p_name = x) s.a_properties)
      (sub_agents ctx a) in
  let behs b = List.filter (fun (s : T.behaviour) -> List.exists (fun (p : T.property) -> p.p_name = x) s.b_properties)
      (sub_behaviours ctx b) in
  let clash = match ctx.owner, found with
    | OAgent a, `Local -> List.map (fun (s : T.agent) -> s.a_name) (agents a.a_name)
    | OAgent _, _ -> []
    | OBehaviour b, `Local ->
      List.map (fun (s : T.behaviour) -> s.b_name) (behs b)
      @ (match b.b_for_agent with Some a -> List.map (fun (s : T.agent) -> s.a_name) (agents a) | None -> [])
    | OBehaviour b, `Agent_prop -> List.map (fun (s : T.behaviour) -> s.b_name) (behs b)
    | OBehaviour _, `Own_prop -> [] in
  match clash with
  | [] -> ()
  | t :: _ ->
    unsupported at "%s is %s here, but %s, which extends this code's type, declares a property %s: \
                    the interpreter resolves the name at run time (rename one of them)"
      x (match found with `Local -> "a local" | _ -> "an agent property") t x

let refuse_routine_shadow ctx at x kind =
  match ctx.owner with
  | OAgent _ -> ()
  | OBehaviour b ->
    let has (s : T.behaviour) = List.exists (fun (r : T.routine) -> r.r_name = x)
        (match kind with `Function -> s.b_functions | `Procedure -> s.b_procedures) in
    match List.filter has (sub_behaviours ctx b) with
    | [] -> ()
    | s :: _ ->
      unsupported at "%s is the agent's %s here, but behaviour %s, which extends %s, declares its own: \
                      the interpreter resolves it at run time (rename one of them)"
        x (match kind with `Function -> "function" | `Procedure -> "procedure") s.b_name b.b_name

let prop_lvalue ctx x home = match home with
  | Own -> prop_field x
  | Of_agent -> agent_ref ctx ^ "." ^ prop_field x

(* A local's Java name: its own, unless Java reserves it, a class of the
   program has it (a local would hide the class in [C.make(...)]), or it
   begins as the fields and methods of members do ([p_count] would hide the
   property [count]'s field [p_count]). *)
let local_name ctx x =
  if reserved x || Hashtbl.mem ctx.g.class_names x || member_prefixed x then x ^ "$" else x

(* Every local a body may create: parameters, [x as T = e], [for x in],
   pattern variables, and assignments to names that are not properties. *)
let rec collect_expr ctx acc (e : Ast.expr) = match e.it with
  | Lit _ | Name _ | This | Agent | Content | Message -> ()
  | List es -> List.iter (collect_expr ctx acc) es
  | Map kvs -> List.iter (fun (k, v) -> collect_expr ctx acc k; collect_expr ctx acc v) kvs
  | Call (_, es) -> List.iter (collect_expr ctx acc) es
  | Index (a, b) -> collect_expr ctx acc a; collect_expr ctx acc b
  | Of (_, x) | Unop (_, x) -> collect_expr ctx acc x
  | Matches (x, p) -> collect_expr ctx acc x; collect_pattern ctx acc p
  | Binop (_, a, b) -> collect_expr ctx acc a; collect_expr ctx acc b
  | Invoke i -> collect_expr ctx acc i.target; List.iter (collect_expr ctx acc) i.args

and collect_pattern ctx acc (p : Ast.pattern) = match p.it with
  | PWild | PLit _ -> ()
  | PName x -> if T.schema ctx.g.env x = None then acc := x :: !acc
  | PCons (_, ps) -> List.iter (collect_pattern ctx acc) ps

and collect_stmt ctx acc (s : Ast.stmt) = match s.it with
  | Assign (lv, e) ->
    collect_expr ctx acc e;
    (match lv.it with
     | LName x -> if find_prop ctx x = None then acc := x :: !acc
     | LOf (_, t) -> collect_expr ctx acc t
     | LIndex (m, k) -> collect_expr ctx acc m; collect_expr ctx acc k)
  | Local (x, _, e) -> collect_expr ctx acc e; acc := x.it :: !acc
  | Do (_, Positional es) -> List.iter (collect_expr ctx acc) es
  | Do (_, Named kvs) | Activate (_, kvs) -> List.iter (fun (_, e) -> collect_expr ctx acc e) kvs
  | Nothing | Deactivate | Break | Continue | Return None -> ()
  | InvokeS i -> collect_expr ctx acc i.target; List.iter (collect_expr ctx acc) i.args
  | Send (_, c, rs) -> collect_expr ctx acc c; List.iter (collect_expr ctx acc) rs
  | Log e | Return (Some e) -> collect_expr ctx acc e
  | If (bs, els) ->
    List.iter (fun (c, b) -> collect_expr ctx acc c; List.iter (collect_stmt ctx acc) b) bs;
    Option.iter (List.iter (collect_stmt ctx acc)) els
  | While (c, b) -> collect_expr ctx acc c; List.iter (collect_stmt ctx acc) b
  | For (x, e, b) -> collect_expr ctx acc e; acc := x.it :: !acc; List.iter (collect_stmt ctx acc) b

(* Declare the locals (params excluded) at the top of a method. *)
let declare_locals ctx o ~params names =
  let seen = Hashtbl.create 8 in
  List.iter (fun x -> Hashtbl.replace seen x ()) params;
  List.iter (fun x ->
      if not (Hashtbl.mem seen x) then begin
        Hashtbl.replace seen x ();
        let j = local_name ctx x in
        Hashtbl.replace ctx.locals x j;
        line o "Object %s = null;" j
      end) (List.rev names)

(* ------------------------------------------------------------- patterns *)

let java_double f =
  if Float.is_nan f then "Double.NaN"
  else if f = Float.infinity then "Double.POSITIVE_INFINITY"
  else if f = Float.neg_infinity then "Double.NEGATIVE_INFINITY"
  else if Float.is_integer f && Float.abs f < 1e15 then Printf.sprintf "%.1f" f
  else Printf.sprintf "%h" f

(* A static method testing pattern [p] on a value, recording the variables'
   values in [b] (committed by the caller only if the whole pattern matches). *)
let matcher ctx (p : Ast.pattern) =
  let name = fresh ctx "match" in
  let vars = ref [] in
  let o = ctx.matchers in
  let v_count = ref 0 in
  line o "/** The pattern %s at %s, in %s. */" (comment_text (Print.pattern p)) (region_doc p.at) ctx.cls_name;
  line o "private static boolean %s(Object v$, Object[] b$) {" name;
  indent o (fun () ->
      let rec test v (p : Ast.pattern) = match p.it with
        | PWild -> ()
        | PLit l ->
          let lit = match l with
            | Ast.Int i when i >= -2147483648 && i <= 2147483647 -> Printf.sprintf "Integer.valueOf(%d)" i
            | Ast.Int _ -> unsupported p.at "an integer literal outside Java's int range"
            | Ast.Real r -> Printf.sprintf "Double.valueOf(%s)" (java_double (float_of_string r))
            | Ast.Text s -> java_string s
            | Ast.Bool b -> if b then "Boolean.TRUE" else "Boolean.FALSE" in
          line o "if (!Ops.same(%s, %s)) return false;" lit v
        | PName x ->
          (match T.schema ctx.g.env x with
           | Some _ -> line o "if (!(%s instanceof %s)) return false;" v (cls ctx.g "S" x)
           | None ->
             let i = List.length !vars in
             vars := x :: !vars;
             line o "b$[%d] = %s;   // %s" i v x)
        | PCons (c, ps) ->
          (match T.schema ctx.g.env c.it with
           | Some sc when List.length sc.s_slots = List.length ps ->
             let k = cls ctx.g "S" c.it in
             line o "if (!(%s instanceof %s)) return false;" v k;
             List.iter2 (fun (p : Ast.pattern) (n, _) ->
                 match p.it with
                 | PWild -> ()
                 | _ ->
                   incr v_count;
                   let w = Printf.sprintf "v%d$" !v_count in
                   line o "Object %s = ((%s) %s).%s;" w k v (slot_field n);
                   test w p) ps sc.s_slots
           | _ -> unsupported p.at "a constructor pattern %s with %d arguments, which no schema has" c.it (List.length ps)) in
      test "v$" p;
      line o "return true;");
  line o "}";
  line o "";
  (name, List.rev !vars)

(* ---------------------------------------------------------- expressions *)

let rec expr ctx (e : Ast.expr) : string =
  let at = at_string e.at in
  match e.it with
  | Lit l -> literal e.at l
  | Name x -> name ctx e.at x
  | This -> (match ctx.owner with
      | OBehaviour _ -> "new BehaviourRef(uid())"
      | OAgent _ -> "new AgentRef(name())")
  | Agent -> (match ctx.owner with
      | OBehaviour _ -> "new AgentRef(agent().name())"
      | OAgent _ -> "new AgentRef(name())")
  | Content -> (match ctx.content with Some c -> c | None -> Printf.sprintf "Ops.noContent(%s)" at)
  | Message -> (match ctx.message with
      | Some m -> Printf.sprintf "new MessageValue(%s.performative(), %s.content(), %s.sender())" m m m
      | None -> Printf.sprintf "Ops.noMessage(%s)" at)
  | List [] -> "new JList()"
  | List es -> "JList.of(" ^ String.concat ", " (List.map (expr ctx) es) ^ ")"
  | Map [] -> "new JMap()"
  | Map kvs ->
    (* the interpreter evaluates each value before its key *)
    "JMap.ofValueKeyAt(" ^ String.concat ", " (at :: List.concat_map (fun (k, v) -> [ expr ctx v; expr ctx k ]) kvs) ^ ")"
  | Call (g, args) -> call ctx e.at g args
  | Index (m, k) -> Printf.sprintf "Ops.index(%s, %s, %s)" at (expr ctx m) (expr ctx k)
  | Of (p, x) -> Printf.sprintf "Ops.of(%s, %s, %s, this)" at (java_string p.it) (expr ctx x)
  | Matches (x, p) ->
    let subject = expr ctx x in
    let (m, vars) = matcher ctx p in
    if vars = [] then Printf.sprintf "(%s(%s, null) ? Boolean.TRUE : Boolean.FALSE)" m subject
    else begin
      ctx.max_binds <- max ctx.max_binds (List.length vars);
      let binds = List.mapi (fun i x ->
          Printf.sprintf "%s = b$[%d]" (Hashtbl.find ctx.locals x) i) vars in
      Printf.sprintf "(%s(%s, b$) ? Ops.yes(%s) : Boolean.FALSE)" m subject (String.concat ", " binds)
    end
  | Unop (Not, x) -> Printf.sprintf "Ops.not(%s, %s)" at (expr ctx x)
  | Unop (Neg, { it = Lit (Int n); at = lat }) ->
    let v = Int32.to_int (Int32.of_int (- n)) in
    if n > 2147483648 then unsupported lat "an integer literal outside Java's int range";
    Printf.sprintf "Integer.valueOf(%d)" v
  | Unop (Neg, x) -> Printf.sprintf "Ops.neg(%s, %s)" at (expr ctx x)
  | Binop (And, l, r) ->
    Printf.sprintf "(Ops.truth(%s, \"and\", %s) ? %s : Boolean.FALSE)" at (expr ctx l) (expr ctx r)
  | Binop (Or, l, r) ->
    Printf.sprintf "(Ops.truth(%s, \"or\", %s) ? Boolean.TRUE : %s)" at (expr ctx l) (expr ctx r)
  (* the interpreter evaluates the right operand of a comparison first *)
  | Binop (Eq, l, r) -> Printf.sprintf "Ops.eqRL(%s, %s, %s)" at (expr ctx r) (expr ctx l)
  | Binop (Neq, l, r) -> Printf.sprintf "Ops.neqRL(%s, %s, %s)" at (expr ctx r) (expr ctx l)
  | Binop ((Lt | Gt | Le | Ge) as op, l, r) ->
    let f = match op with Lt -> "ltRL" | Gt -> "gtRL" | Le -> "leRL" | _ -> "geRL" in
    Printf.sprintf "Ops.%s(%s, %s, %s)" f at (expr ctx r) (expr ctx l)
  | Binop ((Add | Sub | Mul | Div | Mod) as op, l, r) ->
    let f = match op with Add -> "add" | Sub -> "sub" | Mul -> "mul" | Div -> "div" | _ -> "mod" in
    Printf.sprintf "Ops.%s(%s, %s, %s)" f at (expr ctx l) (expr ctx r)
  | Invoke i -> invoke ctx e.at i

and literal at (l : Ast.literal) = match l with
  | Int i when i >= -2147483648 && i <= 2147483647 -> Printf.sprintf "Integer.valueOf(%d)" i
  | Int _ -> unsupported at "an integer literal outside Java's int range"
  | Real r -> Printf.sprintf "Double.valueOf(%s)" (java_double (float_of_string r))
  | Text s -> java_string s
  | Bool b -> if b then "Boolean.TRUE" else "Boolean.FALSE"

and prop_read ctx at x ((_ : T.property), home) =
  Printf.sprintf "Ops.prop(%s, %s, %s)" (at_string at) (java_string x) (prop_lvalue ctx x home)

and name ctx at x =
  let fallback () =
    match find_prop ctx x with
    | Some ((_, home) as ph) ->
      if home = Of_agent then refuse_shadow ctx at x ~found:`Agent_prop;
      Some (prop_read ctx at x ph)
    | None ->
      match T.schema ctx.g.env x with
      | Some s when s.s_slots = [] -> Some ("new " ^ cls ctx.g "S" x ^ "()")
      | _ -> None in
  match Hashtbl.find_opt ctx.locals x with
  | Some j ->
    (match fallback () with
     | Some f -> Printf.sprintf "(%s != null ? %s : %s)" j j f
     | None -> refuse_shadow ctx at x ~found:`Local; Printf.sprintf "Ops.local(%s, %s, %s)" (at_string at) (java_string x) j)
  | None ->
    match fallback () with
    | Some f -> f
    | None -> Printf.sprintf "Ops.local(%s, %s, null)" (at_string at) (java_string x)

and routine ctx at kind x =
  let pick_b, pick_a = match kind with
    | `Function -> T.behaviour_function, T.agent_function
    | `Procedure -> T.behaviour_procedure, T.agent_procedure in
  match ctx.owner with
  | OBehaviour b ->
    (match pick_b ctx.g.env b.b_name x with
     | Some r -> Some (r, "")
     | None -> match b.b_for_agent with
       | Some a -> Option.map (fun r -> refuse_routine_shadow ctx at x kind; (r, agent_ref ctx ^ ".")) (pick_a ctx.g.env a x)
       | None -> None)
  | OAgent a -> Option.map (fun r -> (r, "")) (pick_a ctx.g.env a.a_name x)

and call ctx at (g : Ast.name) args =
  let a = at_string at in
  match routine ctx at `Function g.it with
  | Some (r, recv) ->
    if List.length args <> List.length r.r_params then
      unsupported at "%s takes %d arguments, not %d" r.r_name (List.length r.r_params) (List.length args);
    Printf.sprintf "%s%s(%s)" recv (fn_method g.it) (String.concat ", " (a :: List.map (expr ctx) args))
  | None ->
    match g.it, args with
    | "aid", [ x ] -> Printf.sprintf "Ops.aid(%s, %s)" a (expr ctx x)
    | _ ->
      match T.schema ctx.g.env g.it with
      | Some sc when List.length sc.s_slots = List.length args ->
        Printf.sprintf "%s.make(%s)" (cls ctx.g "S" g.it) (String.concat ", " (a :: List.map (expr ctx) args))
      | Some _ -> unsupported at "%s takes %d arguments" g.it (List.length args)
      | None -> unsupported at "unknown function or schema %s" g.it

and invoke ctx at (i : Ast.invoke) =
  Printf.sprintf "%sinvoke(%s, %s, %s, %s, %s, new Object[] { %s })" (svc ctx) (at_string at)
    (at_string i.meth.at) (at_string i.target.at) (expr ctx i.target) (java_string i.meth.it)
    (String.concat ", " (List.map (expr ctx) i.args))

(* ----------------------------------------------------------- statements *)

let rec block ctx o (b : Ast.block) = List.iter (stmt ctx o) b

and stmt ctx o (s : Ast.stmt) =
  let at = at_string s.at in
  line o "// %s:%d: %s" (comment_text s.at.left.file) s.at.left.line (comment_text (source_line ctx.g s.at));
  line o "%stick(%s);" (svc ctx) at;
  match s.it with
  | Assign (lv, e) -> assign ctx o lv e
  | Local (x, ty, e) ->
    let v = expr ctx e in
    let v = match ty.it with
      | TName "float" -> "Ops.coerce(Type.FLOAT, " ^ v ^ ")"
      | TName "double" -> "Ops.coerce(Type.DOUBLE, " ^ v ^ ")"
      | _ -> v in
    line o "%s = %s;" (Hashtbl.find ctx.locals x.it) v
  | Do (p, args) ->
    (match routine ctx p.at `Procedure p.it with
     | None -> unsupported p.at "unknown procedure %s" p.it
     | Some (r, recv) ->
       (match args with
        | Positional es ->
          if List.length es <> List.length r.r_params then
            unsupported s.at "%s takes %d arguments, not %d" r.r_name (List.length r.r_params) (List.length es);
          line o "%s%s(%s);" recv (proc_method p.it) (String.concat ", " (at :: List.map (expr ctx) es))
        | Named kvs ->
          let arr = fresh ctx "a" in
          line o "Object[] %s = { %s };" arr (String.concat ", " (List.map (fun (_, e) -> expr ctx e) kvs));
          let names = List.map (fun ((n : Ast.name), _) -> n.it) kvs in
          let pos n =
            let rec go i = function
              | [] -> unsupported s.at "missing argument %s" n
              | m :: rest -> if m = n then i else go (i + 1) rest in
            go 0 names in
          line o "%s%s(%s);" recv (proc_method p.it)
            (String.concat ", " (at :: List.map (fun (n, _) -> Printf.sprintf "%s[%d]" arr (pos n)) r.r_params))))
  | Nothing -> line o "// do nothing"
  | InvokeS i -> line o "%s;" (invoke ctx s.at i)
  | Activate (b, args) ->
    if T.behaviour ctx.g.env b.it = None then unsupported b.at "unknown behaviour %s" b.it;
    let k = cls ctx.g "B" b.it in
    let arr = fresh ctx "a" and nb = fresh ctx "b" in
    line o "Object[] %s = { %s };" arr (String.concat ", " (List.map (fun (_, e) -> expr ctx e) args));
    line o "%s %s = new %s();" k nb k;
    line o "%s.jsCreateAt$ = %s;" nb at;
    line o "%sactivate(%s, %s, new String[] { %s }, %s);" (svc ctx) at nb
      (String.concat ", " (List.map (fun ((n : Ast.name), _) -> java_string n.it) args)) arr
  | Deactivate ->
    (match ctx.owner with
     | OBehaviour _ -> line o "agent().deactivate(this);"
     | OAgent _ -> line o "Ops.fail(%s, \"deactivate this outside a behaviour\");" at)
  | Send (perf, c, rs) ->
    let cv = fresh ctx "c" and rv = fresh ctx "r" in
    line o "Object %s = %s;" cv (expr ctx c);
    line o "java.util.List<String> %s = Ops.names();" rv;
    List.iter (fun (r : Ast.expr) -> line o "Ops.addReceivers(%s, %s, %s);" (at_string r.at) (expr ctx r) rv) rs;
    line o "%ssend(%s, %s, %s);" (svc ctx) (java_string perf.it) cv rv
  | Log e -> line o "%slog(%s);" (svc ctx) (expr ctx e)
  | If (branches, els) ->
    List.iteri (fun i ((c : Ast.expr), b) ->
        line o "%sif (Ops.cond(%s, %s)) {" (if i = 0 then "" else "} else ") (at_string c.at) (expr ctx c);
        indent o (fun () -> block ctx o b)) branches;
    (match els with
     | Some b -> line o "} else {"; indent o (fun () -> block ctx o b)
     | None -> ());
    line o "}"
  | While (c, b) ->
    let lbl = fresh ctx "body" in
    line o "while (true) {";
    indent o (fun () ->
        line o "if (!Ops.cond(%s, %s)) break;" (at_string c.at) (expr ctx c);
        line o "%s: {" lbl;
        ctx.loops <- lbl :: ctx.loops;
        indent o (fun () -> block ctx o b);
        ctx.loops <- List.tl ctx.loops;
        line o "}";
        line o "%stick(%s);   // the loop's round" (svc ctx) at);
    line o "}"
  | For (x, e, b) ->
    let lbl = fresh ctx "body" and it = fresh ctx "item" in
    line o "for (Object %s : Ops.iter(%s, %s)) {" it (at_string e.at) (expr ctx e);
    indent o (fun () ->
        line o "%s = %s;" (Hashtbl.find ctx.locals x.it) it;
        line o "%stick(%s);   // the loop's item" (svc ctx) at;
        line o "%s: {" lbl;
        ctx.loops <- lbl :: ctx.loops;
        indent o (fun () -> block ctx o b);
        ctx.loops <- List.tl ctx.loops;
        line o "}");
    line o "}"
  | Return e ->
    (match ctx.ret, e with
     | RValue, Some e -> line o "if (true) return %s;" (expr ctx e)
     | RValue, None -> line o "if (true) return Nothing.NOTHING;"
     | RVoid, Some e -> line o "Ops.ignore(%s);" (expr ctx e); line o "if (true) return;"
     | RVoid, None -> line o "if (true) return;"
     | RTrue, Some e -> line o "Ops.ignore(%s);" (expr ctx e); line o "if (true) return true;"
     | RTrue, None -> line o "if (true) return true;")
  | Break ->
    if ctx.loops = [] then unsupported s.at "'break' outside a loop";
    line o "if (true) break;"
  | Continue ->
    (match ctx.loops with
     | [] -> unsupported s.at "'continue' outside a loop"
     | l :: _ -> line o "if (true) break %s;   // continue" l)

and assign ctx o (lv : Ast.lvalue) e =
  let v = expr ctx e in
  match lv.it with
  | LName x ->
    (match Hashtbl.find_opt ctx.locals x, find_prop ctx x with
     | Some j, None -> refuse_shadow ctx lv.at x ~found:`Local; line o "%s = %s;" j v
     | None, Some (p, home) ->
       if home = Of_agent then refuse_shadow ctx lv.at x ~found:`Agent_prop;
       line o "%s = %s;" (prop_lvalue ctx x home) (coerce_to p.p_type v)
     | Some j, Some (p, home) ->
       let t = fresh ctx "v" in
       line o "Object %s = %s;" t v;
       line o "if (%s != null) %s = %s; else %s = %s;" j j t (prop_lvalue ctx x home) (coerce_to p.p_type t)
     | None, None -> unsupported lv.at "unknown name %s" x)
  | LIndex (m, k) ->
    let t = fresh ctx "v" in
    line o "Object %s = %s;" t v;
    line o "Ops.setIndex(%s, %s, %s, %s);" (at_string lv.at) (expr ctx m) (expr ctx k) t
  | LOf (p, target) ->
    let t = fresh ctx "v" in
    line o "Object %s = %s;" t v;
    line o "Ops.setOf(%s, %s, %s, %s, this);" (at_string lv.at) (java_string p.it) (expr ctx target) t

(* ---------------------------------------------------------- method bodies *)

let new_ctx g owner cls_name ~counter ~matchers ~content ~message ~ret = {
  g; owner; cls_name; locals = Hashtbl.create 8; content; message; ret; loops = [];
  counter; matchers; max_binds = 0 }

(* Generate a body into a separate buffer (so that the locals and the binds
   array can be declared before it), then copy. *)
let with_body ctx o ~params ~(exprs : Ast.expr list) ~(stmts : Ast.block) f =
  let acc = ref [] in
  List.iter (collect_expr ctx acc) exprs;
  List.iter (collect_stmt ctx acc) stmts;
  List.iter (fun p -> Hashtbl.replace ctx.locals p (local_name ctx p)) params;
  let body = { b = Buffer.create 1024; ind = o.ind } in
  let decls = { b = Buffer.create 256; ind = o.ind } in
  declare_locals ctx decls ~params !acc;
  f body;
  if ctx.max_binds > 0 then line decls "Object[] b$ = new Object[%d];" ctx.max_binds;
  Buffer.add_buffer o.b decls.b;
  Buffer.add_buffer o.b body.b

let catches ctx o ~recover =
  let a = match ctx.owner with OAgent _ -> "" | OBehaviour _ -> "agent()." in
  line o "} catch (JadescriptError e$) {";
  indent o (fun () -> line o "%srecordError(e$);" a; if recover <> "" then line o "%s" recover);
  line o "} catch (StackOverflowError e$) {";
  indent o (fun () -> line o "%srecordTooDeep();" a; if recover <> "" then line o "%s" recover);
  line o "}"

(* The Java parameters of a routine, renamed where needed. *)
let routine_params ctx (r : T.routine) = List.map (fun (n, _) -> (n, local_name ctx n)) r.r_params

let routine_method g owner cls_name ~counter ~matchers o kind (r : T.routine) =
  let ctx = new_ctx g owner cls_name ~counter ~matchers ~content:None ~message:None
      ~ret:(if kind = `Function then RValue else RVoid) in
  let ps = routine_params ctx r in
  line o "/** %s %s (%s). */" (if kind = `Function then "Function" else "Procedure") r.r_name
    (region_doc r.r_at);
  line o "public %s %s(%s) {" (if kind = `Function then "Object" else "void")
    ((if kind = `Function then fn_method else proc_method) r.r_name)
    (String.concat ", " ("String at$" :: List.map (fun (_, j) -> "Object " ^ j) ps));
  indent o (fun () ->
      line o "%stick(at$);" (svc ctx);
      (* Eval.run_routine: more than max_call_depth nested calls is an
         exhaustion error at the call, never a JVM stack overflow *)
      line o "%senterCall(at$);" (svc ctx);
      line o "try {";
      indent o (fun () ->
          List.iter2 (fun (_, j) (_, ty) ->
              let c = coerce_to ty j in
              if c <> j then line o "%s = %s;" j c) ps r.r_params;
          with_body ctx o ~params:(List.map fst ps) ~exprs:[] ~stmts:r.r_body (fun body ->
              block ctx body r.r_body);
          if kind = `Function then line o "return Nothing.NOTHING;");
      line o "} finally {";
      indent o (fun () -> line o "%sexitCall();" (svc ctx));
      line o "}");
  line o "}";
  line o ""

(* ------------------------------------------------------------- schemas *)

let kind_name = function
  | Ast.Concept -> "concept" | Ast.Predicate -> "predicate" | Ast.Proposition -> "proposition" | Ast.Action -> "action"

let schema_class g (s : T.schema) =
  let o = new_out () in
  let c = simple_cls g "S" s.s_name in
  let super_schema = match s.s_super with
    | Some p when p <> Ty.percept_root -> T.schema g.env p
    | _ -> None in
  let sup = match super_schema with Some p -> cls g "S" p.s_name | None -> "Schema" in
  let inherited = match super_schema with Some p -> p.s_slots | None -> [] in
  let own = List.filter (fun (n, _) -> not (List.mem_assoc n inherited)) s.s_slots in
  (* the Java type of each slot's field: where it was first declared *)
  let rec decl_type n (sc : T.schema) =
    match (match sc.s_super with Some p when p <> Ty.percept_root -> T.schema g.env p | _ -> None) with
    | Some p when List.mem_assoc n p.s_slots -> decl_type n p
    | _ -> field_type g (List.assoc n sc.s_slots) in
  line o "package jsgen;";
  line o "";
  line o "import jsref.values.Ops;";
  line o "import jsref.values.Schema;";
  line o "import jsref.values.Type;";
  line o "";
  line o "/** %s %s%s (%s)%s. */" (kind_name s.s_kind) s.s_name
    (match s.s_super with Some p -> " extends " ^ p | None -> "")
    (region_doc s.s_decl.at)
    (if s.s_percept then Printf.sprintf ": a percept type, default priority %d" s.s_priority else "");
  line o "public class %s extends %s {" c sup;
  indent o (fun () ->
      line o "private static final long serialVersionUID = 1L;";
      line o "private static final String[] SLOTS$ = { %s };"
        (String.concat ", " (List.map (fun (n, _) -> java_string n) s.s_slots));
      List.iteri (fun i (_, t) -> line o "private static final Type TYPE$%d = %s;" i (type_expr t)) s.s_slots;
      List.iter (fun (n, t) ->
          line o "/** Slot %s: %s. */" n (Ty.to_string t);
          line o "public %s %s;" (field_type g t) (slot_field n)) own;
      line o "";
      (* the constructor, slots in order *)
      line o "/** The value with these slots (no conversion: see {@link #make}). */";
      line o "public %s(%s) {" c
        (String.concat ", " (List.map (fun (n, _) -> decl_type n s ^ " " ^ slot_field n) s.s_slots));
      indent o (fun () ->
          (match super_schema with
           | Some p -> line o "super(%s);" (String.concat ", " (List.map (fun (n, _) -> slot_field n) p.s_slots))
           | None -> ());
          List.iter (fun (n, _) -> line o "this.%s = %s;" (slot_field n) (slot_field n)) own);
      line o "}";
      line o "";
      line o "/** A construction %s(...) (Eval.construct): each argument converted to its slot's type. */" s.s_name;
      line o "public static %s make(%s) {" c
        (String.concat ", " ("String at$" :: List.map (fun (n, _) -> "Object " ^ slot_field n) s.s_slots));
      indent o (fun () ->
          let args = List.mapi (fun i (n, _) ->
              let ft = decl_type n s in
              let v = Printf.sprintf "Ops.slot(at$, %s, %s, TYPE$%d, %s)" (java_string s.s_name) (java_string n) i (slot_field n) in
              if ft = "Object" then v else Printf.sprintf "(%s) %s" ft v) s.s_slots in
          line o "return new %s(%s);" c (String.concat ", " args));
      line o "}";
      line o "";
      line o "@Override public String schemaName() { return %s; }" (java_string s.s_name);
      line o "@Override public String[] slotNames() { return SLOTS$.clone(); }";
      line o "@Override public Object[] slotValues() { return new Object[] { %s }; }"
        (String.concat ", " (List.map (fun (n, _) -> slot_field n) s.s_slots));
      line o "@Override public boolean isPercept() { return %b; }" s.s_percept;
      line o "@Override public int defaultPriority() { return %d; }" s.s_priority;
      line o "@Override public Object get(String slot$) {";
      indent o (fun () ->
          line o "switch (slot$) {";
          indent o (fun () ->
              List.iter (fun (n, _) -> line o "case %s: return %s;" (java_string n) (slot_field n)) s.s_slots;
              line o "default: return null;");
          line o "}");
      line o "}";
      line o "@Override public boolean set(String slot$, Object v$) {";
      indent o (fun () ->
          line o "switch (slot$) {";
          indent o (fun () ->
              List.iter (fun (n, _) ->
                  let ft = decl_type n s in
                  if ft = "Object" then line o "case %s: %s = v$; return true;" (java_string n) (slot_field n)
                  else line o "case %s: %s = (%s) v$; return true;" (java_string n) (slot_field n) ft) s.s_slots;
              line o "default: return false;");
          line o "}");
      line o "}");
  line o "}";
  (c ^ ".java", Buffer.contents o.b)

(* ---------------------------------------------------------- properties *)

let prop_decls o (props : T.property list) =
  List.iter (fun (p : T.property) ->
      line o "/** Property %s: %s. */" p.p_name (Ty.to_string p.p_type);
      line o "public Object %s;" (prop_field p.p_name)) props

(* Property initialisers (inherited first: the super class's method runs first). *)
let init_method g owner cls_name ~counter ~matchers o ~meth ~super_call (props : T.property list) =
  let ctx = new_ctx g owner cls_name ~counter ~matchers ~content:None ~message:None ~ret:RVoid in
  line o "%sprotected void %s() {" (if meth = "jsInit$" && not super_call then "" else "@Override ") meth;
  indent o (fun () ->
      if super_call then line o "super.%s();" meth;
      let inits = List.filter_map (fun (p : T.property) -> p.p_init) props in
      with_body ctx o ~params:[] ~exprs:inits ~stmts:[] (fun body ->
          List.iter (fun (p : T.property) ->
              match p.p_init with
              | Some e ->
                line body "// %s:%d: %s" (comment_text e.at.left.file) e.at.left.line (comment_text (source_line g e.at));
                line body "%s = %s;" (prop_field p.p_name) (coerce_to p.p_type (expr ctx e))
              | None ->
                let d = match Ty.repr p.p_type with
                  | Ty.Integer -> "Integer.valueOf(0)" | Ty.Float -> "Float.valueOf(0f)"
                  | Ty.Double -> "Double.valueOf(0.0)" | Ty.Boolean -> "Boolean.FALSE" | Ty.Text -> "\"\""
                  | Ty.List _ -> "new JList()" | Ty.Map _ -> "new JMap()" | _ -> "Nothing.NOTHING" in
                line body "%s = %s;" (prop_field p.p_name) d) props));
  line o "}";
  line o ""

let scope_methods o ~agent_side ~(props : T.property list) ~super_generated ~for_agent_cast =
  (* properties by name, for x of agent / x of this *)
  let getter name = 
    line o "@Override public Object %s(String n$) {" name;
    indent o (fun () ->
        line o "switch (n$) {";
        indent o (fun () ->
            List.iter (fun (p : T.property) -> line o "case %s: return %s;" (java_string p.p_name) (prop_field p.p_name)) props;
            line o "default: return %s;" (if super_generated then "super." ^ name ^ "(n$)" else "null"));
        line o "}");
    line o "}" in
  let setter name =
    line o "@Override public boolean %s(String n$, Object v$) {" name;
    indent o (fun () ->
        line o "switch (n$) {";
        indent o (fun () ->
            List.iter (fun (p : T.property) ->
                line o "case %s: %s = %s; return true;" (java_string p.p_name) (prop_field p.p_name) (coerce_to p.p_type "v$")) props;
            line o "default: return %s;" (if super_generated then "super." ^ name ^ "(n$, v$)" else "false"));
        line o "}");
    line o "}" in
  if agent_side then begin
    getter "jsAgentProperty";
    setter "jsSetAgentProperty";
    if not super_generated then begin
      line o "@Override public int jsBehaviourUid() { return -1; }";
      line o "@Override public Object jsBehaviourProperty(String n$) { return null; }";
      line o "@Override public boolean jsSetBehaviourProperty(String n$, Object v$) { return false; }"
    end
  end else begin
    getter "jsBehaviourProperty";
    setter "jsSetBehaviourProperty";
    if not super_generated then begin
      line o "@Override public int jsBehaviourUid() { return uid(); }";
      line o "@Override public Object jsAgentProperty(String n$) { return %s.jsAgentProperty(n$); }" for_agent_cast;
      line o "@Override public boolean jsSetAgentProperty(String n$, Object v$) { return %s.jsSetAgentProperty(n$, v$); }" for_agent_cast
    end
  end;
  line o ""

let header o imports =
  line o "package jsgen;";
  line o "";
  List.iter (fun i -> line o "import %s;" i) imports;
  line o ""

let value_imports = [
  "jsref.values.AgentRef"; "jsref.values.Aid"; "jsref.values.BehaviourRef"; "jsref.values.JList";
  "jsref.values.JMap"; "jsref.values.JadescriptError"; "jsref.values.MessageValue";
  "jsref.values.Nothing"; "jsref.values.Ops"; "jsref.values.Schema"; "jsref.values.Scope";
  "jsref.values.Type" ]

(* Imports actually used, so that javac -Xlint does not see unused ones
   (it does not warn, but readers do). *)
let used_imports text imports =
  List.filter (fun i ->
      let simple = match String.rindex_opt i '.' with Some k -> String.sub i (k + 1) (String.length i - k - 1) | None -> i in
      let re = simple in
      let n = String.length text and m = String.length re in
      let rec find k =
        if k + m > n then false
        else if String.sub text k m = re
             && (k = 0 || not (match text.[k - 1] with 'a'..'z' | 'A'..'Z' | '0'..'9' | '_' | '$' | '.' -> true | _ -> false))
             && (k + m = n || not (match text.[k + m] with 'a'..'z' | 'A'..'Z' | '0'..'9' | '_' | '$' -> true | _ -> false))
        then true else find (k + 1) in
      find 0) imports

let finish o_head imports body =
  let imports = used_imports body imports in
  header o_head imports;
  Buffer.contents o_head.b ^ body

(* -------------------------------------------------------------- agents *)

let agent_class g (a : T.agent) =
  let o = new_out () in
  let c = simple_cls g "A" a.a_name in
  let super = match a.a_super with Some s when T.agent g.env s <> None -> Some s | _ -> None in
  let sup = match super with Some s -> cls g "A" s | None -> "JadescriptAgent" in
  let counter = ref 0 and matchers = new_out () in
  matchers.ind <- 1;
  let owner = OAgent a in
  line o "/** agent %s%s (%s). */" a.a_name (match a.a_super with Some s -> " extends " ^ s | None -> "")
    (region_doc a.a_decl.at);
  line o "public class %s extends %s%s {" c sup (if super = None then " implements Scope" else "");
  indent o (fun () ->
      line o "private static final long serialVersionUID = 1L;";
      prop_decls o a.a_properties;
      if super = None then line o "private boolean jsFailed$;";
      line o "";
      line o "@Override public String typeName() { return %s; }" (java_string a.a_name);
      line o "";
      (* property initialisers and on create: one protected run (R7) *)
      init_method g owner c ~counter ~matchers o ~meth:"jsInit$" ~super_call:(super <> None) a.a_properties;
      if super = None then begin
        line o "@Override protected void initProperties() {";
        indent o (fun () ->
            line o "try {";
            indent o (fun () -> line o "jsInit$();");
            catches (new_ctx g owner c ~counter ~matchers ~content:None ~message:None ~ret:RVoid) o
              ~recover:"jsFailed$ = true;");
        line o "}";
        line o "";
        line o "@Override protected void onCreate(Object[] args$) {";
        indent o (fun () ->
            line o "if (jsFailed$) return;";
            line o "try {";
            indent o (fun () -> line o "jsCreate$(args$);");
            catches (new_ctx g owner c ~counter ~matchers ~content:None ~message:None ~ret:RVoid) o ~recover:"");
        line o "}";
        line o "";
        if a.a_create = None then begin
          line o "/** The on create that runs (the nearest up the chain): none. */";
          line o "protected void jsCreate$(Object[] args$) {}";
          line o ""
        end
      end;
      (match a.a_create with
       | Some r ->
         let ctx = new_ctx g owner c ~counter ~matchers ~content:None ~message:None ~ret:RVoid in
         let ps = routine_params ctx r in
         line o "@Override public String[] createParamNames() { return new String[] { %s }; }"
           (String.concat ", " (List.map (fun (n, _) -> java_string n) r.r_params));
         line o "@Override public Type[] createParamTypes() { return new Type[] { %s }; }"
           (String.concat ", " (List.map (fun (_, t) -> type_expr t) r.r_params));
         line o "";
         line o "/** on create (%s). */" (region_doc r.r_at);
         line o "%sprotected void jsCreate$(Object[] args$) {" (if super = None then "" else "@Override ");
         indent o (fun () ->
             line o "tick(\":0:0\");";
             line o "enterCall(\":0:0\");   // on create is a call (Eval.run_routine)";
             line o "try {";
             indent o (fun () ->
                 List.iteri (fun i ((_, j), (_, ty)) ->
                     line o "Object %s = %s;" j (coerce_to ty (Printf.sprintf "args$[%d]" i))) (List.combine ps r.r_params);
                 with_body ctx o ~params:(List.map fst ps) ~exprs:[] ~stmts:r.r_body (fun body -> block ctx body r.r_body));
             line o "} finally {";
             indent o (fun () -> line o "exitCall();");
             line o "}");
         line o "}";
         line o ""
       | None -> ());
      (* on destroy: the agent type's own only (Eval.destroy_agent) *)
      (match a.a_destroy with
       | Some b ->
         let ctx = new_ctx g owner c ~counter ~matchers ~content:None ~message:None ~ret:RVoid in
         line o "@Override protected void onDestroy() {";
         indent o (fun () ->
             with_body ctx o ~params:[] ~exprs:[] ~stmts:b (fun body ->
                 line body "try {";
                 indent body (fun () -> block ctx body b);
                 catches ctx body ~recover:""));
         line o "}";
         line o ""
       | None -> if super <> None then begin
           line o "@Override protected void onDestroy() {}   // on destroy is not inherited";
           line o ""
         end);
      List.iter (routine_method g owner c ~counter ~matchers o `Function) a.a_functions;
      List.iter (routine_method g owner c ~counter ~matchers o `Procedure) a.a_procedures;
      scope_methods o ~agent_side:true ~props:a.a_properties ~super_generated:(super <> None) ~for_agent_cast:"";
      Buffer.add_buffer o.b matchers.b);
  line o "}";
  let imports = "jsref.runtime.JadescriptAgent" :: value_imports in
  (c ^ ".java", finish (new_out ()) imports (Buffer.contents o.b))

(* ---------------------------------------------------------- behaviours *)

let behaviour_class g (b : T.behaviour) =
  let o = new_out () in
  let c = simple_cls g "B" b.b_name in
  let super = match b.b_super with Some s when T.behaviour g.env s <> None -> Some s | _ -> None in
  let sup = match super with Some s -> cls g "B" s | None -> "JadescriptBehaviour" in
  let counter = ref 0 and matchers = new_out () in
  matchers.ind <- 1;
  let owner = OBehaviour b in
  let all_handlers = T.behaviour_handlers g.env b.b_name in
  let percepts hs = List.filter (fun (h : T.handler) -> h.h_kind = T.On_percept) hs in
  let messages hs = List.filter (fun (h : T.handler) -> h.h_kind <> T.On_percept) hs in
  let inherited = match super with Some s -> T.behaviour_handlers g.env s | None -> [] in
  let p_base = List.length (percepts inherited) and m_base = List.length (messages inherited) in
  let for_agent_cast = match b.b_for_agent with
    | Some a when T.agent g.env a <> None -> "jsAgent$()"
    | _ -> "((Scope) agent())" in
  line o "/** %s behaviour %s%s%s (%s). */" (match b.b_kind with Ast.Cyclic -> "cyclic" | Ast.OneShot -> "one shot")
    b.b_name (match b.b_super with Some s -> " extends " ^ s | None -> "")
    (match b.b_for_agent with Some a -> " for agent " ^ a | None -> "")
    (region_doc b.b_decl.at);
  line o "public class %s extends %s%s {" c sup (if super = None then " implements Scope" else "");
  indent o (fun () ->
      line o "private static final long serialVersionUID = 1L;";
      prop_decls o b.b_properties;
      if super = None then begin
        line o "/** Where the activation that runs on create is (for its fuel tick). */";
        line o "protected String jsCreateAt$ = \":0:0\";"
      end;
      line o "";
      line o "@Override public String typeName() { return %s; }" (java_string b.b_name);
      line o "@Override public boolean isCyclic() { return %b; }" (b.b_kind = Ast.Cyclic);
      line o "@Override public boolean hasAction() { return %b; }" (T.behaviour_action g.env b.b_name <> None);
      line o "@Override public int perceptHandlerCount() { return %d; }" (List.length (percepts all_handlers));
      line o "@Override public int messageHandlerCount() { return %d; }" (List.length (messages all_handlers));
      (match b.b_for_agent with
       | Some a when T.agent g.env a <> None ->
         line o "/** The agent, as its for-agent type. */";
         let inherited = match super with
           | Some s -> (match T.behaviour g.env s with
               | Some sb -> (match sb.b_for_agent with Some a -> T.agent g.env a <> None | None -> false)
               | None -> false)
           | None -> false in
         line o "%sprotected %s jsAgent$() { return (%s) agent(); }" (if inherited then "@Override " else "")
           (cls g "A" a) (cls g "A" a)
       | _ -> ());
      line o "";
      init_method g owner c ~counter ~matchers o ~meth:"initProperties" ~super_call:(super <> None) b.b_properties;
      (match b.b_create with
       | Some r ->
         let ctx = new_ctx g owner c ~counter ~matchers ~content:None ~message:None ~ret:RVoid in
         let ps = routine_params ctx r in
         line o "/** on create (%s): the arguments by name. */" (region_doc r.r_at);
         line o "@Override protected void onCreate(String[] names$, Object[] values$) {";
         indent o (fun () ->
             line o "agent().tick(jsCreateAt$);";
             line o "agent().enterCall(jsCreateAt$);";
             line o "try {";
             indent o (fun () ->
                 List.iter2 (fun (n, j) (_, ty) ->
                     line o "Object %s = %s;" j (coerce_to ty (Printf.sprintf "Ops.named(jsCreateAt$, %s, names$, values$)" (java_string n))))
                   ps r.r_params;
                 with_body ctx o ~params:(List.map fst ps) ~exprs:[] ~stmts:r.r_body (fun body -> block ctx body r.r_body));
             line o "} finally {";
             indent o (fun () -> line o "agent().exitCall();");
             line o "}");
         line o "}";
         line o ""
       | None -> ());
      (match b.b_action with
       | Some body_ ->
         let ctx = new_ctx g owner c ~counter ~matchers ~content:None ~message:None ~ret:RVoid in
         line o "/** The do block. */";
         line o "@Override protected void actionBlock() {";
         indent o (fun () ->
             with_body ctx o ~params:[] ~exprs:[] ~stmts:body_ (fun body ->
                 line body "try {";
                 indent body (fun () -> block ctx body body_);
                 catches ctx body ~recover:""));
         line o "}";
         line o ""
       | None -> ());
      (* percept handlers *)
      let own_p = percepts b.b_handlers and own_m = messages b.b_handlers in
      if own_p <> [] then begin
        line o "@Override public boolean perceptHandler(int h$, Object content$) {";
        indent o (fun () ->
            line o "switch (h$) {";
            indent o (fun () ->
                List.iteri (fun i _ -> line o "case %d: return percept%d$(content$);" (p_base + i + 1) (p_base + i + 1)) own_p;
                line o "default: return %s;" (if super <> None then "super.perceptHandler(h$, content$)" else "false"));
            line o "}");
        line o "}";
        line o "";
        List.iteri (fun i (h : T.handler) ->
            let k = p_base + i + 1 in
            let ctx = new_ctx g owner c ~counter ~matchers ~content:(Some "content$") ~message:None ~ret:RTrue in
            line o "/** on percept (%s). */" (region_doc h.h_at);
            line o "private boolean percept%d$(Object content$) {" k;
            indent o (fun () ->
                with_body ctx o ~params:[] ~exprs:(Option.to_list h.h_guard) ~stmts:h.h_body (fun body ->
                    (match h.h_guard with
                     | Some gd ->
                       line body "boolean ok$;";
                       line body "try {";
                       indent body (fun () ->
                           line body "// %s:%d: when %s" (comment_text gd.at.left.file) gd.at.left.line (comment_text (Print.expr gd));
                           line body "ok$ = Ops.whenCond(%s, %s);" (at_string gd.at) (expr ctx gd));
                       catches ctx body ~recover:"return false;";
                       line body "if (!ok$) return false;"
                     | None -> ());
                    line body "agent().freshFuel();";
                    line body "try {";
                    indent body (fun () -> block ctx body h.h_body);
                    catches ctx body ~recover:"";
                    line body "return true;"));
            line o "}";
            line o "") own_p
      end;
      if own_m <> [] then begin
        let perf (h : T.handler) = match h.h_kind with T.On_message (Some p) -> Some p | _ -> None in
        line o "@Override public String messagePerformative(int h$) {";
        indent o (fun () ->
            line o "switch (h$) {";
            indent o (fun () ->
                List.iteri (fun i h -> line o "case %d: return %s;" (m_base + i + 1)
                               (match perf h with Some p -> java_string p | None -> "null")) own_m;
                line o "default: return %s;" (if super <> None then "super.messagePerformative(h$)" else "null"));
            line o "}");
        line o "}";
        line o "";
        line o "@Override public boolean messageAccepts(int h$, Message m$) {";
        indent o (fun () ->
            line o "switch (h$) {";
            indent o (fun () ->
                List.iteri (fun i _ -> line o "case %d: return accepts%d$(m$);" (m_base + i + 1) (m_base + i + 1)) own_m;
                line o "default: return %s;" (if super <> None then "super.messageAccepts(h$, m$)" else "true"));
            line o "}");
        line o "}";
        line o "";
        line o "@Override public void messageHandler(int h$, Message m$) {";
        indent o (fun () ->
            line o "switch (h$) {";
            indent o (fun () ->
                List.iteri (fun i _ -> line o "case %d: message%d$(m$); return;" (m_base + i + 1) (m_base + i + 1)) own_m;
                line o "default: %s" (if super <> None then "super.messageHandler(h$, m$);" else "return;"));
            line o "}");
        line o "}";
        line o "";
        List.iteri (fun i (h : T.handler) ->
            let k = m_base + i + 1 in
            let perf_test o = match perf h with
              | Some p -> line o "if (!%s.equals(m$.performative())) return false;" (java_string p)
              | None -> () in
            (* the guard alone *)
            let ctx = new_ctx g owner c ~counter ~matchers ~content:(Some "m$.content()") ~message:(Some "m$") ~ret:RVoid in
            line o "/** on message (%s): does it accept the message? */" (region_doc h.h_at);
            line o "private boolean accepts%d$(Message m$) {" k;
            indent o (fun () ->
                perf_test o;
                match h.h_guard with
                | None -> line o "return true;"
                | Some gd ->
                  with_body ctx o ~params:[] ~exprs:[ gd ] ~stmts:[] (fun body ->
                      line body "try {";
                      indent body (fun () ->
                          line body "// %s:%d: when %s" (comment_text gd.at.left.file) gd.at.left.line (comment_text (Print.expr gd));
                          line body "return Ops.whenCond(%s, %s);" (at_string gd.at) (expr ctx gd));
                      catches ctx body ~recover:"return false;"));
            line o "}";
            line o "";
            (* the guard again, for its bindings, then the body *)
            let ctx = new_ctx g owner c ~counter ~matchers ~content:(Some "m$.content()") ~message:(Some "m$") ~ret:RVoid in
            line o "/** on message (%s): the body. */" (region_doc h.h_at);
            line o "private void message%d$(Message m$) {" k;
            indent o (fun () ->
                with_body ctx o ~params:[] ~exprs:(Option.to_list h.h_guard) ~stmts:h.h_body (fun body ->
                    line body "try {";
                    indent body (fun () ->
                        (match h.h_guard with
                         | Some gd ->
                           line body "// %s:%d: when %s (again, for its bindings)" (comment_text gd.at.left.file) gd.at.left.line
                             (comment_text (Print.expr gd));
                           line body "Ops.whenCond(%s, %s);" (at_string gd.at) (expr ctx gd)
                         | None -> ());
                        block ctx body h.h_body);
                    catches ctx body ~recover:""));
            line o "}";
            line o "") own_m
      end;
      List.iter (routine_method g owner c ~counter ~matchers o `Function) b.b_functions;
      List.iter (routine_method g owner c ~counter ~matchers o `Procedure) b.b_procedures;
      scope_methods o ~agent_side:false ~props:b.b_properties ~super_generated:(super <> None) ~for_agent_cast;
      Buffer.add_buffer o.b matchers.b);
  line o "}";
  let imports = "jsref.runtime.JadescriptBehaviour" :: "jsref.runtime.Message" :: value_imports in
  (c ^ ".java", finish (new_out ()) imports (Buffer.contents o.b))

(* ------------------------------------------------------------- Program *)

let program_class g =
  let o = new_out () in
  let schemas = T.schemas g.env in
  line o "/** The compiled program: what the runtime and the host need to know of it. */";
  line o "public final class Program implements ProgramInfo {";
  indent o (fun () ->
      line o "/** The program. */";
      line o "public Program() {}";
      line o "";
      line o "@Override public String[] files() { return new String[] { %s }; }"
        (String.concat ", " (List.map java_string g.files));
      line o "";
      line o "@Override public Class<? extends JadescriptAgent> agentClass(String type$) {";
      indent o (fun () ->
          line o "switch (type$) {";
          indent o (fun () ->
              List.iter (fun (a : T.agent) -> line o "case %s: return %s.class;" (java_string a.a_name) (cls g "A" a.a_name)) (T.agents g.env);
              line o "default: return null;");
          line o "}");
      line o "}";
      line o "";
      line o "@Override public List<BehaviourInfo> behaviours() {";
      indent o (fun () ->
          line o "List<BehaviourInfo> r$ = new ArrayList<>();";
          List.iter (fun (b : T.behaviour) ->
              let hs = T.behaviour_handlers g.env b.b_name in
              let np = List.length (List.filter (fun (h : T.handler) -> h.h_kind = T.On_percept) hs) in
              line o "r$.add(new BehaviourInfo(%s, %s, %b, %d, %d));" (java_string b.b_name)
                (java_string (match b.b_kind with Ast.Cyclic -> "cyclic" | Ast.OneShot -> "oneshot"))
                (T.behaviour_action g.env b.b_name <> None) np (List.length hs - np)) (T.behaviours g.env);
          line o "return r$;");
      line o "}";
      line o "";
      line o "@Override public LinkedHashMap<String, Integer> percepts() {";
      indent o (fun () ->
          line o "LinkedHashMap<String, Integer> r$ = new LinkedHashMap<>();";
          List.iter (fun (s : T.schema) ->
              if s.s_percept then line o "r$.put(%s, %d);" (java_string s.s_name) s.s_priority) schemas;
          line o "return r$;");
      line o "}";
      line o "";
      line o "@Override public Object construct(String at$, String schema$, List<Object> a$) {";
      indent o (fun () ->
          line o "switch (schema$) {";
          indent o (fun () ->
              List.iter (fun (s : T.schema) ->
                  let n = List.length s.s_slots in
                  line o "case %s:" (java_string s.s_name);
                  indent o (fun () ->
                      line o "Ops.arity(at$, %s, %d, a$.size());" (java_string s.s_name) n;
                      line o "return %s.make(%s);" (cls g "S" s.s_name)
                        (String.concat ", " ("at$" :: List.init n (fun i -> Printf.sprintf "a$.get(%d)" i))))) schemas;
              line o "default: throw JadescriptError.at(at$, \"unknown schema \" + schema$);");
          line o "}");
      line o "}";
      line o "";
      let by_schema f default =
        line o "switch (s$) {";
        indent o (fun () ->
            List.iter (fun (s : T.schema) -> line o "case %s: return %s;" (java_string s.s_name) (f s)) schemas;
            line o "default: return %s;" default);
        line o "}" in
      line o "@Override public boolean isSchema(String s$) {";
      indent o (fun () -> by_schema (fun _ -> "true") "false");
      line o "}";
      line o "";
      line o "@Override public int slotCount(String s$) {";
      indent o (fun () -> by_schema (fun s -> string_of_int (List.length s.s_slots)) "0");
      line o "}";
      line o "";
      line o "@Override public boolean isPercept(String s$) {";
      indent o (fun () -> by_schema (fun s -> string_of_bool s.s_percept) "false");
      line o "}";
      line o "";
      line o "@Override public int defaultPriority(String s$) {";
      indent o (fun () -> by_schema (fun s -> string_of_int s.s_priority) "0");
      line o "}";
      line o "";
      line o "@Override public boolean visibleTo(String agentType$, String s$) {";
      if schemas = [] then indent o (fun () -> line o "return false;") else
      indent o (fun () ->
          line o "String o$;";
          line o "switch (s$) {";
          indent o (fun () ->
              List.iter (fun (s : T.schema) -> line o "case %s: o$ = %s; break;" (java_string s.s_name) (java_string s.s_ontology)) schemas;
              line o "default: return false;");
          line o "}";
          line o "switch (agentType$) {";
          indent o (fun () ->
              List.iter (fun (a : T.agent) ->
                  line o "case %s: return List.of(%s).contains(o$);" (java_string a.a_name)
                    (String.concat ", " (List.map java_string a.a_visible))) (T.agents g.env);
              line o "default: return false;");
          line o "}");
      line o "}");
  line o "}";
  let imports = [ "java.util.ArrayList"; "java.util.LinkedHashMap"; "java.util.List";
                  "jsref.runtime.BehaviourInfo"; "jsref.runtime.JadescriptAgent"; "jsref.runtime.ProgramInfo";
                  "jsref.values.JadescriptError"; "jsref.values.Ops" ] in
  ("Program.java", finish (new_out ()) imports (Buffer.contents o.b))

(* -------------------------------------------------------------- checks *)

(* What javac and the JVM can take (docs/jade.md, "What Java can hold").
   A program past one of these limits is refused at the place that passes
   it, before any Java is written, rather than given as Java that javac
   refuses. The limits are set below what was measured to fail, with a
   margin for constructs heavier than those measured. *)

(* A text literal is one constant of the class file: at most 65,535 bytes
   of Java's modified UTF-8, in which a NUL takes 2 bytes and a character
   beyond U+FFFF 6 (a pair of surrogates of 3 bytes each), and javac takes
   fewer than 65,535 chars: at most 65,534 bytes (which is at least as many
   chars) is both. *)
let max_constant_bytes = 65534

let modified_utf8_length t =
  let n = ref 0 in
  String.iter (fun c ->
      n := !n + (match c with
          | '\000' -> 2
          | '\xf0' .. '\xf7' -> 3   (* a 4-byte character: 4 + 2 *)
          | _ -> 1)) t;
  !n

(* The names of the program's classes become file names ([NAME.class],
   [NAME$1.class]), at most 255 bytes on common file systems; a member's
   name becomes a field or a method. *)
let max_name_bytes = 200

(* A method has at most 255 parameters, [this] and the generated ones
   included: a routine's parameters and a schema's slots (its constructor
   takes one per slot). *)
let max_params = 250

(* javac walks an expression recursively: a chain of 250 [+] overflowed
   its stack (200 did not); the generated Java nests about one call per
   level of the source. *)
let max_expr_depth = 100

(* A method's code is at most 65,535 bytes. The size of a body is counted
   in units (an expression or pattern node 2, a statement 4, a statement
   that opens a block or calls out 16), which measured 2.4 to 3 bytes of
   bytecode each; a method may have 8,000 units. A class holds at most
   65,535 constants (a node's position is one): 40,000 units a class. *)
let max_method_units = 8_000
let max_class_units = 40_000

(* [Program.java] has a case for each agent type, behaviour type and
   schema in one method. *)
let max_types = 1_000

let check_java_limits g =
  let class_units = ref 0 and class_at = ref None in
  let rec expr_units depth (e : Ast.expr) =
    if depth > max_expr_depth then
      unsupported e.at "an expression nested more than %d deep (javac cannot take it): \
                        give a part of it a name with a local" max_expr_depth;
    let sub = List.fold_left (fun acc e -> acc + expr_units (depth + 1) e) 0 in
    2 + match e.it with
      | Lit (Text t) ->
        if modified_utf8_length t > max_constant_bytes then
          unsupported e.at "a text literal of more than %d bytes (a Java constant cannot hold it): \
                            build it from shorter ones with +" max_constant_bytes;
        0
      | Lit _ | Name _ | This | Agent | Content | Message -> 0
      | List l -> sub l
      | Map kvs -> sub (List.concat_map (fun (k, v) -> [ k; v ]) kvs)
      | Call (_, args) -> sub args
      | Index (a, b) -> sub [ a; b ]
      | Of (_, a) | Unop (_, a) -> sub [ a ]
      | Matches (a, p) -> sub [ a ] + pattern_units p
      | Binop (_, a, b) -> sub [ a; b ]
      | Invoke i -> sub (i.target :: i.args)
  and pattern_units (p : Ast.pattern) = match p.it with
    | PCons (_, ps) -> 2 + List.fold_left (fun acc p -> acc + pattern_units p) 0 ps
    | PLit (Text t) when modified_utf8_length t > max_constant_bytes ->
      unsupported p.at "a text literal of more than %d bytes (a Java constant cannot hold it)" max_constant_bytes
    | _ -> 2 in
  let e = expr_units 0 in
  let es = List.fold_left (fun acc x -> acc + e x) 0 in
  let rec stmt (st : Ast.stmt) = match st.it with
    | Assign (lv, v) ->
      4 + e v + (match lv.it with LName _ -> 0 | LOf (_, a) -> e a | LIndex (a, b) -> e a + e b)
    | Local (_, _, v) -> 4 + e v
    | Do (_, Positional args) -> 16 + es args
    | Do (_, Named args) -> 16 + es (List.map snd args)
    | Nothing | Deactivate | Break | Continue -> 4
    | InvokeS i -> 16 + es (i.target :: i.args)
    | Activate (_, args) -> 16 + es (List.map snd args)
    | Send (_, c, rs) -> 16 + es (c :: rs)
    | Log x -> 4 + e x
    | If (arms, els) ->
      List.fold_left (fun acc (c, b) -> acc + 16 + e c + block b) 0 arms
      + (match els with Some b -> block b | None -> 0)
    | While (c, b) -> 16 + e c + block b
    | For (_, x, b) -> 16 + e x + block b
    | Return x -> 4 + (match x with Some x -> e x | None -> 0)
  and block b = List.fold_left (fun acc s -> acc + stmt s) 0 b in
  let meth (at : Source.region) units =
    if units > max_method_units then
      unsupported at "this body is too large for one Java method (%d units, at most %d: \
                      docs/jade.md, \"What Java can hold\"): move a part of it into a procedure"
        units max_method_units;
    class_units := !class_units + units;
    if !class_units > max_class_units then
      unsupported (Option.value !class_at ~default:at)
        "this type's code is too large for one Java class (more than %d units: docs/jade.md, \
         \"What Java can hold\"): split it into types that extend one another" max_class_units in
  let name (n : Ast.name) =
    if String.length n.it > max_name_bytes then
      unsupported n.at "a name longer than %d bytes (Java's class files and their file names cannot hold it)"
        max_name_bytes in
  let params at (ps : Ast.param list) =
    List.iter (fun (p : Ast.param) -> name p.pname) ps;
    if List.length ps > max_params then
      unsupported at "more than %d parameters (a Java method cannot take them)" max_params in
  let features (owner : Ast.name) (fs : Ast.feature list) =
    class_units := 0; class_at := Some owner.at;
    name owner;
    let inits = List.fold_left (fun acc (f : Ast.feature) -> match f.it with
        | Property { name = n; init = Some x; _ } -> name n; acc + 4 + e x
        | Property { name = n; _ } -> name n; acc
        | _ -> acc) 0 fs in
    meth owner.at inits;
    List.iter (fun (f : Ast.feature) -> match f.it with
        | Property _ -> ()
        | Function { name = n; params = ps; body; _ } | Procedure { name = n; params = ps; body } ->
          name n; params f.at ps; meth f.at (block body)
        | OnCreate { params = ps; body } -> params f.at ps; meth f.at (block body)
        | OnDestroy body | ActionSection body -> meth f.at (block body)
        | OnPercept { guard; body } | OnMessage { guard; body; _ } ->
          Option.iter (fun x -> meth f.at (e x)) guard; meth f.at (block body)) fs in
  let count = ref 0 in
  let one_more (at : Source.region) =
    incr count;
    if !count > max_types then
      unsupported at "more than %d schemas, agent types and behaviour types in one program \
                      (Program.java cannot list them in one method)" max_types in
  List.iter (fun (sc : T.schema) ->
      let d = sc.s_decl in
      one_more d.it.sname.at;
      name d.it.sname;
      List.iter (fun (sl : Ast.slot) -> name sl.slot_name) d.it.slots;
      List.iter (fun (_, x) -> ignore (e x)) d.it.defaults;
      if List.length sc.s_slots > max_params then
        unsupported d.it.sname.at "%s has %d slots (with those it inherits), more than %d \
                                   (its Java constructor cannot take them)"
          sc.s_name (List.length sc.s_slots) max_params) (T.schemas g.env);
  List.iter (fun (a : T.agent) -> one_more a.a_decl.it.aname.at; features a.a_decl.it.aname a.a_decl.it.afeatures)
    (T.agents g.env);
  List.iter (fun (b : T.behaviour) -> one_more b.b_decl.it.bname.at; features b.b_decl.it.bname b.b_decl.it.bfeatures)
    (T.behaviours g.env)

(* Constructs the back end refuses, found before any Java is written. *)
let check_supported g =
  List.iter (fun (b : T.behaviour) ->
      match b.b_for_agent with
      | Some a when T.agent g.env a = None -> unsupported b.b_decl.at "unknown agent type %s" a
      | _ -> ()) (T.behaviours g.env);
  check_java_limits g

(* ---------------------------------------------------------------- entry *)

let read_lines file =
  match Parse.read_all file with
  | Ok t -> Array.of_list (String.split_on_char '\n' t)
  | Error _ -> [||]

let generate env ~files =
  let g = { env; files; sources = Hashtbl.create 4; classes = Hashtbl.create 32;
            class_names = Hashtbl.create 32 } in
  List.iter (fun f -> Hashtbl.replace g.sources f (read_lines f)) files;
  Hashtbl.replace g.class_names "Program" ();
  assign_classes g;
  match
    check_supported g;
    let schemas = List.map (schema_class g) (T.schemas env) in
    let agents = List.map (agent_class g) (T.agents env) in
    let behs = List.map (behaviour_class g) (T.behaviours env) in
    schemas @ agents @ behs @ [ program_class g ]
  with
  | units -> Ok units
  | exception Unsupported (at, msg) -> Error (at, msg)

let write ~out units =
  let dir = Filename.concat out "jsgen" in
  let mkdir d = if not (Sys.file_exists d) then Sys.mkdir d 0o755 in
  mkdir out;
  mkdir dir;
  (* stale classes of an earlier compilation would be compiled too *)
  Array.iter (fun f -> if Filename.check_suffix f ".java" then Sys.remove (Filename.concat dir f)) (Sys.readdir dir);
  List.iter (fun (name, text) ->
      let oc = open_out_bin (Filename.concat dir name) in
      output_string oc text;
      close_out oc) units
