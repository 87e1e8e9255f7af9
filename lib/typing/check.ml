(* The typing rules of docs/typing.md, one function per syntactic category, in
   the manner of the WebAssembly reference interpreter's valid/. Each rule is
   named in a comment as it is in docs/typing.md. *)

open Syntax
open Source
module Ast = Syntax.Ast
open Ast
module T = Types

(* ------------------------------------------------------------ state *)

type st = {
  env : Tenv.t;
  h : T.hierarchy;
  mutable diags : Diag.t list;
  mutable vars : T.var list;              (* every unification variable made *)
  bad_for_agent : (string, unit) Hashtbl.t;
      (* behaviours whose for agent is unknown: their agent is not checked *)
}

let error st at fmt =
  Printf.ksprintf (fun m -> st.diags <- Diag.make Diag.Type at m :: st.diags) fmt

let warning st at fmt =
  Printf.ksprintf
    (fun m -> st.diags <- Diag.make ~severity:Diag.Warning Diag.Type at m :: st.diags) fmt

let ts = T.to_string
let pos at = Printf.sprintf "%d:%d" at.left.line at.left.column
(* A position as seen from [here]: LINE:COL in the same file, else FILE:LINE:COL. *)
let where ~here at =
  if at.left.file = here.left.file then pos at
  else Printf.sprintf "%s:%d:%d" at.left.file at.left.line at.left.column

let fresh st ?hint at =
  let t = T.fresh ?hint at in
  (match t with T.Var v -> st.vars <- v :: st.vars | _ -> ());
  t

let assignable st a b = T.assignable st.h a b

(* ---------------------------------------------------------- contexts *)

type owner =
  | OAgent of Tenv.agent
  | OBehaviour of Tenv.behaviour
  | OOntology                   (* the with clauses of schemas *)

type ret =
  | RFunction of string * T.t   (* in the body of function f returning t *)
  | RNone                       (* procedures, handlers, on create, do *)
  | RInit                       (* a property initialiser: no statements *)

type local = { l_type : T.t; l_at : region }

type ctx = {
  owner : owner;
  agent : string option;        (* the agent whose properties are visible *)
  agent_bad : bool;             (* its name is unknown: do not check it *)
  visible : string list;        (* the visible ontologies *)
  locals : (string * local) list;
  content : T.t option;         (* in a handler *)
  message : T.t option;         (* in a message handler: the content type *)
  ret : ret;
  loop : bool;
}

let ctx_of_agent (a : Tenv.agent) ret = {
  owner = OAgent a; agent = Some a.a_name; agent_bad = false; visible = a.a_visible;
  locals = []; content = None; message = None; ret; loop = false;
}

let ctx_of_behaviour st (b : Tenv.behaviour) ret = {
  owner = OBehaviour b; agent = b.b_for_agent;
  agent_bad = Hashtbl.mem st.bad_for_agent b.b_name;
  visible = b.b_visible; locals = []; content = None; message = None; ret; loop = false;
}

(* ------------------------------------------------------ performatives *)

let props = [Predicate; Proposition]
let all_kinds = [Concept; Action; Predicate; Proposition]

(* Rule Performative: the content a performative carries. *)
let performatives = [
  "accept_proposal", props; "agree", props; "cancel", [Action]; "cfp", [Action];
  "confirm", props; "disconfirm", props; "failure", props; "inform", props;
  "inform_if", props; "inform_ref", all_kinds; "not_understood", props;
  "propagate", all_kinds; "propose", props; "proxy", all_kinds; "query_if", props;
  "query_ref", all_kinds; "refuse", props; "reject_proposal", props;
  "request", [Action]; "request_when", [Action]; "request_whenever", [Action];
  "subscribe", all_kinds;
]

let performative st (p : name) =
  match List.assoc_opt p.it performatives with
  | Some ks -> T.Onto ks
  | None ->
    error st p.at "unknown performative %s (the FIPA performatives are %s)" p.it
      (String.concat ", " (List.map fst performatives));
    T.Error

(* ------------------------------------------------------------- types *)

let builtin_types = ["boolean"; "integer"; "float"; "double"; "text"; "string"; "aid"; "any"]

(* Rule Type: a written type, in a place that sees the ontologies [visible]. *)
let rec ty st ?(in_slot = false) visible (t : Ast.ty) : T.t =
  match t.it with
  | TList a -> T.List (ty st ~in_slot visible a)
  | TMap (k, v) -> T.Map (ty st ~in_slot visible k, ty st ~in_slot visible v)
  | TName n ->
    match n with
    | "boolean" -> T.Boolean | "integer" -> T.Integer | "float" -> T.Float
    | "double" -> T.Double | "text" | "string" -> T.Text | "aid" -> T.Aid | "any" -> T.Any
    | _ ->
      match Tenv.schema st.env n with
      | Some s when List.mem s.s_ontology visible -> T.Schema n
      | Some s ->
        error st t.at "schema %s is not visible here: it is declared in ontology %s, \
                       which is not used (add 'uses ontology %s')" n s.s_ontology s.s_ontology;
        T.Error
      | None ->
        let kind, r =
          match Tenv.agent st.env n, Tenv.behaviour st.env n with
          | Some _, _ -> "agent", T.Agent (Some n)
          | None, Some _ -> "behaviour", T.Behaviour n
          | None, None -> "", T.Error in
        if kind = "" then begin
          error st t.at "unknown type %s" n; T.Error
        end else if in_slot then begin
          error st t.at "a slot cannot have the %s type %s: ontology values are data" kind n;
          T.Error
        end else r

(* ----------------------------------------------------- ontology closure *)

(* The ontologies [names] and those they extend. *)
let closure st names =
  let rec go acc n =
    if List.mem n acc then acc
    else match Tenv.ontology st.env n with
      | None -> acc
      | Some o -> match o.o_super with None -> n :: acc | Some s -> go (n :: acc) s in
  List.rev (List.fold_left go [] names)

let union a b = a @ List.filter (fun x -> not (List.mem x a)) b

(* ------------------------------------------------------- declarations *)

let builtin_or_reserved n = List.mem n builtin_types || n = "percept"

(* Rule Decl-Unique: one namespace for the types (schemas, agents, behaviours),
   one for the ontologies; across all the files of the program. *)
let collect st (files : Parse.result list) =
  let types = Hashtbl.create 32 and onts = Hashtbl.create 8 in
  let declare tbl what (n : name) =
    if builtin_or_reserved n.it then begin
      error st n.at "%s is a builtin type name and cannot name %s" n.it what; false
    end else match Hashtbl.find_opt tbl n.it with
      | Some at -> error st n.at "%s is already declared at %s" n.it (where ~here:n.at at); false
      | None -> Hashtbl.replace tbl n.it n.at; true in
  let param_list ps = List.map (fun p -> (p.pname.it, T.Error)) ps in
  let features owner (fs : feature list) =
    let seen = Hashtbl.create 8 in
    let feature_name (n : name) =
      match Hashtbl.find_opt seen n.it with
      | Some at -> error st n.at "%s is already declared in %s at %s" n.it owner (where ~here:n.at at); false
      | None -> Hashtbl.replace seen n.it n.at; true in
    let props = ref [] and funs = ref [] and procs = ref [] and create = ref None
    and destroy = ref None and action = ref None and handlers = ref [] in
    List.iter (fun (f : feature) ->
        match f.it with
        | Property { name; ty = _; init } ->
          if feature_name name then
            props := { Tenv.p_name = name.it; p_owner = owner; p_type = T.Error; p_init = init;
                       p_decl = f; p_status = Tenv.Pending; p_read = false } :: !props
        | Function { name; params; ret = _; body } ->
          if feature_name name then
            funs := { Tenv.r_name = name.it; r_owner = owner; r_params = param_list params;
                      r_ret = Some T.Error; r_body = body; r_at = f.at; r_decl = f } :: !funs
        | Procedure { name; params; body } ->
          if feature_name name then
            procs := { Tenv.r_name = name.it; r_owner = owner; r_params = param_list params;
                       r_ret = None; r_body = body; r_at = f.at; r_decl = f } :: !procs
        | OnCreate { params; body } ->
          if !create = None then
            create := Some { Tenv.r_name = ""; r_owner = owner; r_params = param_list params;
                             r_ret = None; r_body = body; r_at = f.at; r_decl = f }
        | OnDestroy b -> if !destroy = None then destroy := Some b
        | ActionSection b -> if !action = None then action := Some b
        | OnPercept { guard; body } ->
          handlers := { Tenv.h_kind = Tenv.On_percept; h_guard = guard; h_body = body;
                        h_at = f.at } :: !handlers
        | OnMessage { perf; guard; body } ->
          handlers := { Tenv.h_kind = Tenv.On_message (Option.map (fun (p : name) -> p.it) perf);
                        h_guard = guard; h_body = body; h_at = f.at } :: !handlers) fs;
    (List.rev !props, List.rev !funs, List.rev !procs, !create, !destroy, !action,
     List.rev !handlers) in
  List.iter (fun (r : Parse.result) ->
      List.iter (fun (d : decl) ->
          match d.it with
          | DOntology o ->
            if declare onts "an ontology" o.oname then begin
              let names = List.filter_map (fun (s : schema) ->
                  if declare types "a schema" s.it.sname then begin
                    let s' = s.it in
                    Tenv.add_schema st.env
                      { Tenv.s_name = s'.sname.it; s_kind = s'.kind; s_ontology = o.oname.it;
                        s_super = Option.map (fun (n : name) -> n.it) s'.super;
                        s_supers = []; s_slots = []; s_defaults = s'.defaults;
                        s_percept = false; s_priority = 0; s_decl = s };
                    Some s'.sname.it
                  end else None) o.schemas in
              Tenv.add_ontology st.env
                { Tenv.o_name = o.oname.it; o_super = Option.map (fun (n : name) -> n.it) o.oextends;
                  o_schemas = names; o_decl = { it = o; at = d.at } }
            end
          | DAgent a ->
            if declare types "an agent" a.aname then begin
              let (ps, fs, prs, cr, de, _, _) = features a.aname.it a.afeatures in
              Tenv.add_agent st.env
                { Tenv.a_name = a.aname.it; a_super = Option.map (fun (n : name) -> n.it) a.aextends;
                  a_ontologies = List.map (fun (n : name) -> n.it) a.aontologies; a_visible = [];
                  a_properties = ps; a_functions = fs; a_procedures = prs; a_create = cr;
                  a_destroy = de; a_decl = { it = a; at = d.at } }
            end
          | DBehaviour b ->
            if declare types "a behaviour" b.bname then begin
              let (ps, fs, prs, cr, _, act, hs) = features b.bname.it b.bfeatures in
              Tenv.add_behaviour st.env
                { Tenv.b_name = b.bname.it; b_kind = b.bkind;
                  b_super = Option.map (fun (n : name) -> n.it) b.bextends;
                  b_for_agent = Option.map (fun (n : name) -> n.it) b.for_agent;
                  b_ontologies = List.map (fun (n : name) -> n.it) b.bontologies; b_visible = [];
                  b_properties = ps; b_functions = fs; b_procedures = prs; b_create = cr;
                  b_action = act; b_handlers = hs; b_decl = { it = b; at = d.at } }
            end) r.program.decls) files

(* Rule Extends-Acyclic: follow [super] from [start]; on a cycle, report it at
   [at] and return true. *)
let cyclic find super start =
  let rec go seen n =
    match find n with
    | None -> false
    | Some d ->
      match super d with
      | None -> false
      | Some s -> if s = start then true else if List.mem s seen then false else go (s :: seen) s in
  go [start] start

(* Rule Extends, for every kind of declaration: the chain of [extends] is
   acyclic, and (check_super) the super exists. On an error the link is
   dropped ([drop]), so that every chain below is finite. *)
let check_acyclic st ~what ~find ~super ~drop name (n : Ast.name) s =
  if cyclic find super name then begin
    error st n.at "%s %s extends itself (through %s): extends chains must be acyclic" what name s;
    drop ()
  end

let check_super st ~what ~find ~super ~drop name n s =
  if find s = None then begin error st n.Source.at "unknown %s %s" what s; drop () end
  else check_acyclic st ~what ~find ~super ~drop name n s

(* Rule Ontology. *)
let check_ontologies st =
  List.iter (fun (o : Tenv.ontology) ->
      let ext = o.o_decl.it.oextends in
      match o.o_super, ext with
      | Some s, Some n ->
        check_super st ~what:"ontology" ~find:(Tenv.ontology st.env) ~super:(fun o -> o.Tenv.o_super)
          ~drop:(fun () -> o.o_super <- None) o.o_name n s
      | _ -> ()) (Tenv.ontologies st.env)

(* Rule Schema-Extends: the super of a schema is a visible schema of a
   compatible kind, or [percept] for a predicate or proposition. *)
let check_schema_supers st =
  List.iter (fun (s : Tenv.schema) ->
      match s.s_super, s.s_decl.it.super with
      | Some sup, Some n ->
        let visible = closure st [s.s_ontology] in
        if sup = T.percept_root then begin
          if s.s_kind <> Predicate && s.s_kind <> Proposition then begin
            error st n.at "only predicates and propositions can extend percept, and %s is %s %s"
              s.s_name (if s.s_kind = Action then "an" else "a") (T.kind_to_string s.s_kind);
            s.s_super <- None
          end
        end else begin
          match Tenv.schema st.env sup with
          | None -> error st n.at "unknown schema %s" sup; s.s_super <- None
          | Some p when not (List.mem p.s_ontology visible) ->
            error st n.at "schema %s is not visible in ontology %s: it is declared in %s, \
                           which %s does not extend" sup s.s_ontology p.s_ontology s.s_ontology;
            s.s_super <- None
          | Some p ->
            let ok = match s.s_kind, p.s_kind with
              | Concept, Concept | Action, (Action | Concept) | Predicate, (Predicate | Proposition)
              | Proposition, Proposition -> true
              | _ -> false in
            if not ok then begin
              error st n.at "%s %s cannot extend %s %s" (T.kind_to_string s.s_kind) s.s_name
                (T.kind_to_string p.s_kind) sup;
              s.s_super <- None
            end else
              check_acyclic st ~what:"schema" ~find:(Tenv.schema st.env) ~super:(fun s -> s.Tenv.s_super)
                ~drop:(fun () -> s.s_super <- None) s.s_name n sup
        end
      | _ -> ()) (Tenv.schemas st.env)

(* Rule Schema-Slots: supers, slots (inherited first, overriding slots
   compatible), percept flag and effective default priority (R1a). *)
let resolve_schemas st =
  let is_done = Hashtbl.create 16 in
  let rec resolve (s : Tenv.schema) =
    if not (Hashtbl.mem is_done s.s_name) then begin
      Hashtbl.replace is_done s.s_name ();
      let visible = closure st [s.s_ontology] in
      let parent_slots, supers, percept, prio =
        match s.s_super with
        | None -> [], [], false, 0
        | Some p when p = T.percept_root -> [], [T.percept_root], true, 0
        | Some p ->
          match Tenv.schema st.env p with
          | None -> [], [], false, 0
          | Some ps -> resolve ps; ps.s_slots, p :: ps.s_supers, ps.s_percept, ps.s_priority in
      s.s_supers <- supers;
      s.s_percept <- percept;
      s.s_priority <- prio;
      let own = s.s_decl.it.slots in
      if s.s_kind = Proposition && own <> [] then
        error st s.s_decl.it.sname.at "proposition %s cannot have slots (use a predicate)" s.s_name;
      let seen = Hashtbl.create 8 in
      (* the parent's slots by name, the overrides of them, and the new
         slots, last first: linear in the slots (a concept may have many) *)
      let inherited = Hashtbl.create 8 in
      List.iter (fun (m, u) -> Hashtbl.replace inherited m u) parent_slots;
      let overridden = Hashtbl.create 8 in
      let added = List.fold_left (fun acc (sl : slot) ->
          let n = sl.slot_name in
          let t = ty st ~in_slot:true visible sl.slot_ty in
          if Hashtbl.mem seen n.it then begin
            error st n.at "slot %s is declared twice in %s" n.it s.s_name; acc
          end else begin
            Hashtbl.replace seen n.it ();
            if percept && n.it = "priority" then begin
              error st n.at "priority is the priority of every percept (R1a) and cannot be a \
                             slot of the percept type %s" s.s_name; acc
            end else match Hashtbl.find_opt inherited n.it with
              | Some t0 ->
                (* Rule Slot-Override: covariant. *)
                if not (assignable st t t0) then
                  error st sl.slot_ty.at "slot %s overrides the slot of %s with an incompatible \
                                          type: expected %s (or a subtype), found %s"
                    n.it (Option.value s.s_super ~default:"?") (ts t0) (ts t);
                Hashtbl.replace overridden n.it t;
                acc
              | None -> (n.it, t) :: acc
          end) [] own in
      let parent = List.rev_map (fun (m, u) ->
          match Hashtbl.find_opt overridden m with Some t -> (m, t) | None -> (m, u)) parent_slots in
      s.s_slots <- List.rev_append parent (List.rev added)
    end in
  List.iter resolve (Tenv.schemas st.env)

(* Rule Agent-Header and Behaviour-Header. *)
let check_headers st =
  let check_onts at_list names =
    List.iter2 (fun (n : name) _ ->
        if Tenv.ontology st.env n.it = None then error st n.at "unknown ontology %s" n.it)
      at_list names in
  let agents = Tenv.agents st.env in
  List.iter (fun (a : Tenv.agent) ->
      let d = a.a_decl.it in
      check_onts d.aontologies a.a_ontologies;
      match a.a_super, d.aextends with
      | Some s, Some n ->
        check_super st ~what:"agent" ~find:(Tenv.agent st.env) ~super:(fun a -> a.Tenv.a_super)
          ~drop:(fun () -> a.a_super <- None) a.a_name n s
      | _ -> ()) agents;
  List.iter (fun (a : Tenv.agent) ->
      let chain = Tenv.agent_chain st.env a.a_name in
      a.a_visible <- closure st (List.concat_map (fun a -> a.Tenv.a_ontologies) chain)) agents;
  let behaviours = Tenv.behaviours st.env in
  List.iter (fun (b : Tenv.behaviour) ->
      let d = b.b_decl.it in
      check_onts d.bontologies b.b_ontologies;
      (match b.b_super, d.bextends with
       | Some s, Some n ->
         check_super st ~what:"behaviour" ~find:(Tenv.behaviour st.env) ~super:(fun b -> b.Tenv.b_super)
           ~drop:(fun () -> b.b_super <- None) b.b_name n s
       | _ -> ());
      match b.b_for_agent, d.for_agent with
      | Some a, Some n when Tenv.agent st.env a = None ->
        error st n.at "unknown agent %s in 'for agent %s' of behaviour %s" a a b.b_name;
        Hashtbl.replace st.bad_for_agent b.b_name ()
      | _ -> ()) behaviours;
  (* for agent: inherited from the super behaviour when absent; a subtype's
     agent must be a subtype of its super's (nearest first, so supers first). *)
  let is_done = Hashtbl.create 16 in
  let rec settle (b : Tenv.behaviour) =
    if not (Hashtbl.mem is_done b.b_name) then begin
      Hashtbl.replace is_done b.b_name ();
      (match b.b_super with
       | None -> ()
       | Some s ->
         match Tenv.behaviour st.env s with
         | None -> ()
         | Some p ->
           settle p;
           if Hashtbl.mem st.bad_for_agent p.b_name && b.b_for_agent = None then
             Hashtbl.replace st.bad_for_agent b.b_name ();
           match b.b_for_agent, p.b_for_agent with
           | None, inherited -> b.b_for_agent <- inherited
           | Some a, Some pa when not (Hashtbl.mem st.bad_for_agent b.b_name) ->
             if not (assignable st (T.Agent (Some a)) (T.Agent (Some pa))) then
               error st (Option.get b.b_decl.it.for_agent).at
                 "behaviour %s is for agent %s, but it extends %s, which is for agent %s: \
                  %s must be %s or extend it" b.b_name a p.b_name pa a pa
           | _ -> ());
      let own = List.concat_map (fun b -> b.Tenv.b_ontologies)
          (Tenv.behaviour_chain st.env b.b_name) in
      let agent_onts = match b.b_for_agent with
        | Some a -> (match Tenv.agent st.env a with Some a -> a.a_visible | None -> [])
        | None -> [] in
      b.b_visible <- closure st (union own agent_onts)
    end in
  List.iter settle behaviours

(* Rule Signature: parameter and return types of routines, explicit property
   types; overriding a routine keeps its signature; a subtype does not redeclare
   a property. *)
let resolve_signatures st =
  let sig_of visible (ps : param list) (r : Tenv.routine) ret =
    let seen = Hashtbl.create 4 in
    r.r_params <- List.map (fun (p : param) ->
        if Hashtbl.mem seen p.pname.it then
          error st p.pname.at "parameter %s is declared twice" p.pname.it;
        Hashtbl.replace seen p.pname.it ();
        (p.pname.it, ty st visible p.pty)) ps;
    r.r_ret <- Option.map (ty st visible) ret in
  let features visible (fs : feature list) routines create props =
    List.iter (fun (f : feature) ->
        match f.it with
        | Function { name; params; ret; _ } ->
          (match List.find_opt (fun (r : Tenv.routine) -> r.r_name = name.it && r.r_decl == f) routines with
           | Some r -> sig_of visible params r (Some ret) | None -> ())
        | Procedure { name; params; _ } ->
          (match List.find_opt (fun (r : Tenv.routine) -> r.r_name = name.it && r.r_decl == f) routines with
           | Some r -> sig_of visible params r None | None -> ())
        | OnCreate { params; _ } ->
          (match create with
           | Some (r : Tenv.routine) when r.r_decl == f -> sig_of visible params r None
           | _ -> ())
        | Property { name; ty = Some t; _ } ->
          (match List.find_opt (fun (p : Tenv.property) -> p.p_decl == f) props with
           | Some p -> p.p_type <- ty st visible t; p.p_status <- Tenv.Resolved
           | None -> ignore name)
        | _ -> ()) fs in
  List.iter (fun (a : Tenv.agent) ->
      features a.a_visible a.a_decl.it.afeatures (a.a_functions @ a.a_procedures) a.a_create
        a.a_properties) (Tenv.agents st.env);
  List.iter (fun (b : Tenv.behaviour) ->
      features b.b_visible b.b_decl.it.bfeatures (b.b_functions @ b.b_procedures) b.b_create
        b.b_properties) (Tenv.behaviours st.env);
  (* Overriding. *)
  let name_at (f : feature) = match f.it with
    | Property { name; _ } | Function { name; _ } | Procedure { name; _ } -> name.at
    | _ -> f.at in
  let check_overrides owner supers_props supers_routine (props : Tenv.property list) routines =
    List.iter (fun (p : Tenv.property) ->
        match supers_props p.p_name with
        | Some (q : Tenv.property) ->
          error st (name_at p.p_decl) "property %s is already declared in %s (a subtype cannot \
                                        redeclare a property)" p.p_name q.p_owner
        | None -> ()) props;
    List.iter (fun (r : Tenv.routine) ->
        match supers_routine r.r_name with
        | Some (q : Tenv.routine) ->
          let same = List.length q.r_params = List.length r.r_params
                     && List.for_all2 (fun (_, a) (_, b) -> T.zonk a = T.zonk b) q.r_params r.r_params
                     && (match q.r_ret, r.r_ret with
                         | None, None -> true | Some a, Some b -> T.zonk a = T.zonk b | _ -> false) in
          if not same then
            error st r.r_at "%s overrides the %s of %s with a different signature"
              r.r_name r.r_name q.r_owner
        | None -> ()) routines;
    ignore owner in
  List.iter (fun (a : Tenv.agent) ->
      match a.a_super with
      | None -> ()
      | Some s ->
        check_overrides a.a_name (Tenv.agent_property st.env s)
          (fun n -> match Tenv.agent_function st.env s n with
             | Some r -> Some r | None -> Tenv.agent_procedure st.env s n)
          a.a_properties (a.a_functions @ a.a_procedures)) (Tenv.agents st.env);
  List.iter (fun (b : Tenv.behaviour) ->
      match b.b_super with
      | None -> ()
      | Some s ->
        check_overrides b.b_name (Tenv.behaviour_property st.env s)
          (fun n -> match Tenv.behaviour_function st.env s n with
             | Some r -> Some r | None -> Tenv.behaviour_procedure st.env s n)
          b.b_properties (b.b_functions @ b.b_procedures)) (Tenv.behaviours st.env)

(* --------------------------------------------------------- expressions *)

let int_max = 2147483647

let is_real_lit (e : expr) =
  match e.it with
  | Lit (Real _) | Unop (Neg, { it = Lit (Real _); _ }) -> true
  | _ -> false

(* Rule Known: operations that look inside a value need its type. *)
let known st at t =
  match T.repr t with
  | T.Var _ ->
    error st at "the type of this expression is not known here: it comes from an empty \
                 collection whose type only later uses decide; write its type where it is declared";
    T.Error
  | t -> t

let mismatch st at what expected actual =
  error st at "%s: expected %s, found %s" what (ts expected) (ts actual)

(* Rule Literal. *)
let literal st at = function
  | Int n ->
    if n > int_max || n < - int_max - 1 then
      error st at "integer literal %d is out of range: integer is 32-bit \
                   (-2147483648..2147483647)" n;
    T.Integer
  | Real _ -> T.Double
  | Text _ -> T.Text
  | Bool _ -> T.Boolean

(* Find a property by name as code of [ctx] sees it (rule Name). *)
let find_property st ctx x =
  let from_behaviour = match ctx.owner with
    | OBehaviour b -> Tenv.behaviour_property st.env b.b_name x
    | _ -> None in
  match from_behaviour with
  | Some p -> Some p
  | None ->
    match ctx.agent with
    | Some a when not ctx.agent_bad -> Tenv.agent_property st.env a x
    | _ -> None

let find_routine st ctx kind x =
  let pick_b, pick_a = match kind with
    | `Function -> Tenv.behaviour_function, Tenv.agent_function
    | `Procedure -> Tenv.behaviour_procedure, Tenv.agent_procedure in
  let from_behaviour = match ctx.owner with
    | OBehaviour b -> pick_b st.env b.b_name x
    | _ -> None in
  match from_behaviour with
  | Some r -> Some r
  | None ->
    match ctx.agent with
    | Some a when not ctx.agent_bad -> pick_a st.env a x
    | _ -> None

let schema_visible st ctx s =
  match Tenv.schema st.env s with
  | Some sc when List.mem sc.s_ontology ctx.visible -> `Visible sc
  | Some sc -> `Hidden sc
  | None -> `Unknown

let not_visible st at (sc : Tenv.schema) =
  error st at "schema %s is not visible here: it is declared in ontology %s, which is not used \
               (add 'uses ontology %s')" sc.s_name sc.s_ontology sc.s_ontology

let rec prop_type st (p : Tenv.property) =
  match p.p_status with
  | Tenv.Resolved -> p.p_type
  | Tenv.Resolving ->
    error st (match p.p_decl.it with Property { name; _ } -> name.at | _ -> p.p_decl.at)
      "the type of property %s depends on itself: write its type (property %s as T = ...)"
      p.p_name p.p_name;
    p.p_type <- T.Error; p.p_status <- Tenv.Resolved; T.Error
  | Tenv.Pending ->
    p.p_status <- Tenv.Resolving;
    let t = match p.p_init, init_ctx st p with
      | Some e, Some ctx -> infer_rhs st ctx e
      | _ -> T.Error in
    if p.p_status = Tenv.Resolving then begin
      List.iter (fun (v : T.var) ->
          v.hint <- Printf.sprintf "write the type of property %s (property %s as %s = ...)"
              p.p_name p.p_name
              (match T.repr t with T.Map _ -> "map of K:V" | T.List _ -> "list of T" | _ -> "T"))
        (T.unresolved t);
      p.p_type <- t; p.p_status <- Tenv.Resolved
    end;
    p.p_type

and init_ctx st (p : Tenv.property) =
  match Tenv.agent st.env p.p_owner, Tenv.behaviour st.env p.p_owner with
  | Some a, _ -> Some (ctx_of_agent a RInit)
  | None, Some b -> Some (ctx_of_behaviour st b RInit)
  | None, None -> None

and read_property st (p : Tenv.property) =
  p.p_read <- true;
  prop_type st p

(* Rule Check: [e] where a [expected] is required. Decimal literals check as
   float where a float is expected; list and map literals check element-wise. *)
and check st ctx ~what (e : expr) expected =
  match e.it, T.repr expected with
  | (Lit (Real _) | Unop (Neg, { it = Lit (Real _); _ })), T.Float -> ()
  | List (_ :: _ as es), T.List t ->
    List.iter (fun e -> check st ctx ~what:"this list element" e t) es
  | Map (_ :: _ as kvs), T.Map (k, v) ->
    List.iter (fun (ke, ve) ->
        check st ctx ~what:"this map key" ke k;
        check st ctx ~what:"this map value" ve v) kvs
  | _ ->
    let t = infer_rhs st ctx e in
    if not (assignable st t expected) then mismatch st e.at what expected t

(* A right-hand side: an expression or an invoke (rule Invoke). *)
and infer_rhs st ctx (e : expr) =
  match e.it with
  | Invoke i -> invoke st ctx i; T.Any
  | _ -> infer st ctx e

(* Rule Invoke: the target is an [any]; arguments are any values. *)
and invoke st ctx (i : invoke) =
  let t = infer st ctx i.target in
  (match T.repr t with
   | T.Any | T.Error -> ()
   | _ -> error st i.target.at "invoke needs a host value of type any on the right of 'on', \
                                found %s" (ts t));
  List.iter (fun a -> ignore (infer st ctx a)) i.args

(* Rule Expr: the type of an expression. *)
and infer st ctx (e : expr) : T.t =
  match e.it with
  | Lit l -> literal st e.at l
  | Name x -> name st ctx e.at x
  | This ->
    (match ctx.owner with
     | OBehaviour b -> T.Behaviour b.b_name
     | OAgent a -> T.Agent (Some a.a_name)
     | OOntology -> error st e.at "'this' is not available in an ontology"; T.Error)
  | Agent ->
    (match ctx.owner with
     | OOntology -> error st e.at "'agent' is not available in an ontology"; T.Error
     | _ -> if ctx.agent_bad then T.Error else T.Agent ctx.agent)
  | Content ->
    (match ctx.content with
     | Some t -> t
     | None -> error st e.at "'content' is only available in an 'on percept' or message handler";
       T.Error)
  | Message ->
    (match ctx.message with
     | Some t -> T.Message t
     | None -> error st e.at "'message' is only available in a message handler"; T.Error)
  | List [] -> T.List (fresh st e.at ~hint:"write its type where it is declared \
                                            (for example 'xs as list of integer = []')")
  | List (first :: rest) ->
    let t = infer st ctx first in
    List.fold_left (fun t (x : expr) ->
        let u = infer st ctx x in
        if assignable st u t then t
        else if assignable st t u then u
        else (error st x.at "the elements of a list have one type: expected %s, found %s"
                (ts t) (ts u); t)) t rest
    |> fun t -> T.List t
  | Map [] ->
    let hint = "write its type where it is declared (for example 'm as map of text:integer = {}')" in
    T.Map (fresh st e.at ~hint, fresh st e.at ~hint)
  | Map ((k0, v0) :: rest) ->
    let join what t (x : expr) =
      let u = infer st ctx x in
      if assignable st u t then t
      else if assignable st t u then u
      else (error st x.at "the %s of a map have one type: expected %s, found %s" what (ts t) (ts u); t) in
    let k = infer st ctx k0 and v = infer st ctx v0 in
    let k, v = List.fold_left (fun (k, v) (ke, ve) -> (join "keys" k ke, join "values" v ve))
        (k, v) rest in
    T.Map (k, v)
  | Call (f, args) -> call st ctx e.at f args
  | Index (m, i) ->
    let t = known st m.at (infer st ctx m) in
    (match t with
     | T.List a -> check st ctx ~what:"a list index" i T.Integer; a
     | T.Map (k, v) -> check st ctx ~what:"a map key" i k; v
     | T.Error -> ignore (infer st ctx i); T.Error
     | t -> error st m.at "only lists and maps can be indexed, and this is a %s" (ts t);
       ignore (infer st ctx i); T.Error)
  | Of (p, x) -> of_ st ctx p x
  | Matches (x, p) ->
    let t = infer st ctx x in
    ignore (pattern st ctx t [] p);
    T.Boolean
  | Unop (Not, x) -> check st ctx ~what:"the operand of 'not'" x T.Boolean; T.Boolean
  | Unop (Neg, { it = Lit (Int 2147483648); _ }) -> T.Integer
  | Unop (Neg, x) ->
    let t = known st x.at (infer st ctx x) in
    if T.is_numeric t || t = T.Error then t
    else (error st x.at "'-' needs a number (integer, float or double), found %s" (ts t); T.Error)
  | Binop ((And | Or), _, _) -> ignore (cond st ctx e); T.Boolean
  | Binop (op, l, r) -> binop st ctx e.at op l r
  | Invoke _ ->
    error st e.at "invoke is a statement, or the right side of an assignment or property";
    T.Error

(* Rule Name: a local, a property of the behaviour, a property of the agent
   (for a behaviour: of its 'for agent'), a proposition or slotless schema. *)
and name st ctx at x =
  match List.assoc_opt x ctx.locals with
  | Some l -> l.l_type
  | None ->
    match find_property st ctx x with
    | Some p -> read_property st p
    | None ->
      match schema_visible st ctx x with
      | `Visible sc when sc.s_slots = [] -> T.Schema x
      | `Visible sc ->
        error st at "%s has %d slot%s: construct it with %s(...)" x (List.length sc.s_slots)
          (if List.length sc.s_slots = 1 then "" else "s") x; T.Error
      | `Hidden sc -> not_visible st at sc; T.Error
      | `Unknown ->
        if ctx.agent_bad then T.Error
        else begin
          let hint = match ctx.owner, ctx.agent with
            | OBehaviour _, None ->
              " (a behaviour sees the properties of an agent only with 'for agent A')"
            | _ -> "" in
          error st at "unknown name %s%s" x hint; T.Error
        end

(* Rule Call: functions, schema constructors, aid(text). *)
and call st ctx at (f : name) args =
  match find_routine st ctx `Function f.it with
  | Some r ->
    positional st ctx at ("function " ^ f.it) r.r_params args;
    Option.value r.r_ret ~default:T.Error
  | None ->
    match schema_visible st ctx f.it with
    | `Visible sc ->
      positional st ctx at (T.kind_to_string sc.s_kind ^ " " ^ f.it) sc.s_slots args;
      T.Schema f.it
    | `Hidden sc -> not_visible st f.at sc; List.iter (fun a -> ignore (infer st ctx a)) args; T.Error
    | `Unknown ->
      if f.it = "aid" then begin
        (match args with
         | [a] -> check st ctx ~what:"the argument of aid" a T.Text
         | _ -> error st at "aid expects 1 argument (the agent's name, a text), found %d"
                  (List.length args));
        T.Aid
      end else begin
        List.iter (fun a -> ignore (infer st ctx a)) args;
        (match find_routine st ctx `Procedure f.it with
         | Some _ -> error st f.at "%s is a procedure: call it with 'do %s'" f.it f.it
         | None -> if not ctx.agent_bad then error st f.at "unknown function or schema %s" f.it);
        T.Error
      end

(* Rule Args: positional arguments against parameters (arity, then types). *)
and positional st ctx at what params args =
  let n = List.length params and m = List.length args in
  if n <> m then begin
    error st at "%s expects %d argument%s (%s), found %d" what n (if n = 1 then "" else "s")
      (String.concat ", " (List.map (fun (x, t) -> x ^ " as " ^ ts t) params)) m;
    List.iter (fun a -> ignore (infer_rhs st ctx a)) args
  end else
    List.iter2 (fun (x, t) a ->
        check st ctx ~what:(Printf.sprintf "argument %s of %s" x what) a t) params args

(* Rule Named-Args: every parameter exactly once, by name. *)
and named st ctx at what params (args : (name * expr) list) =
  let seen = Hashtbl.create 4 in
  List.iter (fun ((x : name), a) ->
      if Hashtbl.mem seen x.it then error st x.at "argument %s is given twice" x.it;
      Hashtbl.replace seen x.it ();
      match List.assoc_opt x.it params with
      | Some t -> check st ctx ~what:(Printf.sprintf "argument %s of %s" x.it what) a t
      | None ->
        error st x.at "%s has no parameter %s (its parameters: %s)" what x.it
          (if params = [] then "none"
           else String.concat ", " (List.map (fun (x, t) -> x ^ " as " ^ ts t) params));
        ignore (infer_rhs st ctx a)) args;
  List.iter (fun (x, t) ->
      if not (Hashtbl.mem seen x) then
        error st at "missing argument %s (as %s) of %s" x (ts t) what) params

(* Rule Of: p of e. *)
and of_ st ctx (p : name) (x : expr) =
  let t = infer st ctx x in
  of_type st p x t

and of_type st (p : name) (x : expr) t =
  let none () =
    error st p.at "%s has no '%s' (a value of type %s)" (ts t) p.it (ts t); T.Error in
  match known st x.at t, p.it with
  | T.Error, _ -> T.Error
  | T.Text, "length" -> T.Integer
  | T.List _, ("length" | "size") -> T.Integer
  | T.Map _, "size" -> T.Integer
  | T.Map (k, _), "keys" -> T.List k
  | T.Map (_, v), "values" -> T.List v
  | T.Message _, "sender" -> T.Aid
  | T.Message _, "performative" -> T.Text
  | T.Message c, "content" -> c
  | T.Schema s, "priority" when s = T.percept_root -> T.Integer
  | T.Schema s, f ->
    (match Tenv.schema st.env s with
     | Some sc ->
       (match List.assoc_opt f sc.s_slots with
        | Some t -> t
        | None ->
          if f = "priority" && sc.s_percept then T.Integer
          else (error st p.at "%s %s has no slot %s" (T.kind_to_string sc.s_kind) s f; T.Error))
     | None -> none ())
  | T.Agent None, f ->
    error st x.at "'%s of agent' needs to know the agent: add 'for agent A' to this behaviour" f;
    T.Error
  | T.Agent (Some a), f ->
    (match Tenv.agent_property st.env a f with
     | Some prop -> read_property st prop
     | None -> error st p.at "agent %s has no property %s" a f; T.Error)
  | T.Behaviour b, f ->
    (match Tenv.behaviour_property st.env b f with
     | Some prop -> read_property st prop
     | None -> error st p.at "behaviour %s has no property %s" b f; T.Error)
  | _ -> none ()

(* Rule Binop. *)
and binop st ctx at op l r =
  let lt = infer st ctx l and rt = infer st ctx r in
  let adapt (e : expr) t other = if is_real_lit e && T.repr other = T.Float then T.Float else t in
  let lt' = adapt l lt rt and rt' = adapt r rt lt in
  let sym = match op with
    | Add -> "+" | Sub -> "-" | Mul -> "*" | Div -> "/" | Mod -> "%"
    | Lt -> "<" | Gt -> ">" | Le -> "<=" | Ge -> ">=" | Eq -> "=" | Neq -> "!="
    | And -> "and" | Or -> "or" in
  let numeric () =
    match known st l.at lt', known st r.at rt' with
    | T.Error, _ | _, T.Error -> T.Error
    | T.Integer, T.Integer -> T.Integer
    | (T.Integer | T.Float), (T.Integer | T.Float) -> T.Float
    | (T.Integer | T.Double), (T.Integer | T.Double) -> T.Double
    | (T.Float, T.Double | T.Double, T.Float) ->
      error st at "'%s' on float and double: float does not widen to double \
                   (expected two numbers of one type, found %s and %s)" sym (ts lt') (ts rt');
      T.Error
    | a, b ->
      error st at "'%s' needs numbers (integer, float or double), found %s and %s"
        sym (ts a) (ts b); T.Error in
  match op with
  | Add ->
    (match T.repr lt, T.repr rt with
     | T.Text, _ | _, T.Text ->
       let other, oe = if T.repr lt = T.Text then rt, r else lt, l in
       (match T.repr other with
        | T.Any -> error st oe.at "a value of type any cannot be converted to text \
                                   (any is usable only with invoke and equality)"
        | T.Var _ -> ignore (known st oe.at other)
        | _ -> ());
       T.Text
     | _ -> numeric ())
  | Sub | Mul | Div | Mod -> numeric ()
  | Lt | Gt | Le | Ge ->
    (match T.repr lt, T.repr rt with
     | T.Text, T.Text -> T.Boolean
     | _ -> ignore (numeric ()); T.Boolean)
  | Eq | Neq ->
    if not (assignable st lt' rt' || assignable st rt' lt') then
      error st at "'%s' compares values of one type (one assignable to the other), found %s \
                   and %s" sym (ts lt) (ts rt);
    T.Boolean
  | And | Or -> T.Boolean

(* Rule Pattern: [p] matched against a value of type [t]; returns the
   variables it binds, added to [acc]. *)
and pattern st ctx t acc (p : pattern) =
  let compatible sc_name at =
    (* the value may be an sc_name: a subtype test, or an upcast *)
    match T.repr t with
    | T.Error -> ()
    | T.Var _ -> ignore (known st at t)
    | _ ->
      if not (assignable st (T.Schema sc_name) t || assignable st t (T.Schema sc_name)) then
        error st at "this pattern can never match: a value of type %s is never a %s"
          (ts t) sc_name in
  match p.it with
  | PWild -> acc
  | PLit l ->
    let lt = match l with Real _ when T.repr t = T.Float -> T.Float | _ -> literal st p.at l in
    if not (assignable st lt t || assignable st t lt) then
      error st p.at "this pattern can never match: expected a pattern for %s, found a %s literal"
        (ts t) (ts lt);
    acc
  | PName x ->
    (match schema_visible st ctx x with
     | `Visible _ -> compatible x p.at; acc
     | `Hidden sc ->
       error st p.at "%s is a schema of ontology %s, which is not visible here (add 'uses \
                      ontology %s'); a pattern variable cannot have the name of a schema"
         x sc.s_ontology sc.s_ontology; acc
     | `Unknown ->
       if List.mem_assoc x acc then begin
         error st p.at "pattern variable %s is bound twice in this pattern" x; acc
       end else begin
         (match List.assoc_opt x ctx.locals with
          | Some l -> error st p.at "pattern variable %s would shadow the local %s declared at %s: \
                                     rename it" x x (where ~here:p.at l.l_at)
          | None -> ());
         (x, { l_type = t; l_at = p.at }) :: acc
       end)
  | PCons (f, ps) ->
    let slots = match schema_visible st ctx f.it with
      | `Visible sc ->
        compatible f.it f.at;
        let n = List.length sc.s_slots and m = List.length ps in
        if n <> m then begin
          error st p.at "pattern %s(...) needs %d sub-pattern%s, one per slot (%s), found %d"
            f.it n (if n = 1 then "" else "s") (String.concat ", " (List.map fst sc.s_slots)) m;
          None
        end else Some (List.map snd sc.s_slots)
      | `Hidden sc -> not_visible st f.at sc; None
      | `Unknown -> error st f.at "unknown schema %s" f.it; None in
    match slots with
    | Some ts -> List.fold_left2 (fun acc t p -> pattern st ctx t acc p) acc ts ps
    | None -> List.fold_left (fun acc p -> pattern st ctx T.Error acc p) acc ps

(* Rule Cond: a boolean condition; returns [ctx] extended with what holds when
   it is true: the variables of the matches that are top-level conjuncts, and
   the narrowed type of 'content'. *)
and cond st ctx (e : expr) : ctx =
  match e.it with
  | Binop (And, a, b) ->
    let ctx1 = cond st ctx a in
    cond st ctx1 b
  | Binop (Or, a, b) ->
    ignore (cond st ctx a); ignore (cond st ctx b); ctx
  | Matches (x, p) ->
    let t = infer st ctx x in
    let binds = pattern st ctx t [] p in
    let ctx = { ctx with locals = List.rev_append binds ctx.locals } in
    (match x.it, p.it with
     | Content, (PName s | PCons ({ it = s; _ }, _)) ->
       (match schema_visible st ctx s, ctx.content with
        | `Visible _, Some c when assignable st (T.Schema s) c -> { ctx with content = Some (T.Schema s) }
        | _ -> ctx)
     | _ -> ctx)
  | _ -> check st ctx ~what:"a condition" e T.Boolean; ctx

(* ----------------------------------------------------------- statements *)

(* Declare a local; pattern variables and loop variables may not shadow one. *)
let add_local ctx x t at = { ctx with locals = (x, { l_type = t; l_at = at }) :: ctx.locals }

let set_local_hint x t =
  List.iter (fun (v : T.var) ->
      v.hint <- Printf.sprintf "write the type of %s (%s as %s = ...)" x x
          (match T.repr t with T.Map _ -> "map of K:V" | T.List _ -> "list of T" | _ -> "T"))
    (T.unresolved t)

(* Rule Stmt: returns the context for the statements that follow. *)
let rec stmt st ctx (s : stmt) : ctx =
  match s.it with
  | Assign (lv, e) -> assign st ctx lv e
  | Local (x, t, e) ->
    let t' = ty st ctx.visible t in
    (match List.assoc_opt x.it ctx.locals with
     | Some l -> error st x.at "local %s is already declared at %s" x.it (where ~here:x.at l.l_at)
     | None -> ());
    check st ctx ~what:(Printf.sprintf "the value of %s" x.it) e t';
    add_local ctx x.it t' x.at
  | Do (p, args) ->
    (match find_routine st ctx `Procedure p.it with
     | Some r ->
       let what = "procedure " ^ p.it in
       (match args with
        | Positional es -> positional st ctx s.at what r.r_params es
        | Named nas -> named st ctx s.at what r.r_params nas)
     | None ->
       (match args with
        | Positional es -> List.iter (fun a -> ignore (infer_rhs st ctx a)) es
        | Named nas -> List.iter (fun (_, a) -> ignore (infer_rhs st ctx a)) nas);
       match find_routine st ctx `Function p.it with
       | Some _ -> error st p.at "%s is a function: call it as %s(...) in an expression" p.it p.it
       | None ->
         if not ctx.agent_bad then
           error st p.at "unknown procedure %s%s" p.it
             (match ctx.owner, ctx.agent with
              | OBehaviour _, None ->
                " (a behaviour calls the procedures of an agent only with 'for agent A')"
              | _ -> ""));
    ctx
  | Nothing -> ctx
  | InvokeS i -> invoke st ctx i; ctx
  | Activate (b, args) -> activate st ctx s.at b args; ctx
  | Deactivate ->
    (match ctx.owner with
     | OBehaviour _ -> ()
     | _ -> error st s.at "'deactivate this' is only allowed in a behaviour");
    ctx
  | Send (perf, c, rs) ->
    let kinds = performative st perf in
    let t = infer st ctx c in
    if not (assignable st t kinds) then
      error st c.at "the content of a %s message: expected %s, found %s" perf.it (ts kinds) (ts t);
    List.iter (fun (r : expr) ->
        let t = infer st ctx r in
        match T.repr t with
        | T.Aid | T.Error -> ()
        | T.List _ when assignable st t (T.List T.Aid) -> ()
        | _ -> error st r.at "a receiver of send: expected aid or list of aid, found %s" (ts t)) rs;
    ctx
  | Log e -> ignore (infer st ctx e); ctx
  | If (branches, els) ->
    List.iter (fun (c, b) ->
        let ctx' = cond st ctx c in
        block st ctx' b) branches;
    Option.iter (block st ctx) els;
    ctx
  | While (c, b) ->
    check st ctx ~what:"the condition of while" c T.Boolean;
    block st { ctx with loop = true } b;
    ctx
  | For (x, e, b) ->
    let t = known st e.at (infer st ctx e) in
    let elt = match t with
      | T.List a -> a
      | T.Map (k, _) -> k
      | T.Error -> T.Error
      | t -> error st e.at "'for' iterates over a list or a map, found %s" (ts t); T.Error in
    (match List.assoc_opt x.it ctx.locals with
     | Some l -> error st x.at "loop variable %s would shadow the local %s declared at %s: rename it"
                   x.it x.it (where ~here:x.at l.l_at)
     | None -> ());
    block st { (add_local ctx x.it elt x.at) with loop = true } b;
    ctx
  | Return e ->
    (match ctx.ret, e with
     | RFunction (_, t), Some e -> check st ctx ~what:"the value returned" e t
     | RFunction (f, t), None ->
       error st s.at "function %s must return a value of type %s" f (ts t)
     | (RNone | RInit), Some e ->
       ignore (infer_rhs st ctx e);
       error st s.at "only a function returns a value; here write 'return' alone"
     | (RNone | RInit), None -> ());
    ctx
  | Break | Continue ->
    if not ctx.loop then
      error st s.at "'%s' is only allowed inside a loop ('while' or 'for')"
        (if s.it = Break then "break" else "continue");
    ctx

(* Rule Assign. *)
and assign st ctx (lv : lvalue) e =
  match lv.it with
  | LName x ->
    (match List.assoc_opt x ctx.locals with
     | Some l -> check st ctx ~what:(Printf.sprintf "the value assigned to %s" x) e l.l_type; ctx
     | None ->
       match find_property st ctx x with
       | Some p ->
         let t = prop_type st p in
         check st ctx ~what:(Printf.sprintf "the value assigned to property %s" x) e t; ctx
       | None ->
         (* Rule Local-Infer: the first assignment declares the local. *)
         let t = infer_rhs st ctx e in
         set_local_hint x t;
         add_local ctx x t lv.at)
  | LOf (p, target) ->
    let t = infer st ctx target in
    let what = Printf.sprintf "the value assigned to %s of %s" p.it
        (match target.it with Agent -> "agent" | This -> "this" | _ -> "this value") in
    (match known st target.at t with
     | T.Schema s when Tenv.schema st.env s <> None
                     && List.mem_assoc p.it (Option.get (Tenv.schema st.env s)).s_slots ->
       check st ctx ~what e (List.assoc p.it (Option.get (Tenv.schema st.env s)).s_slots)
     | T.Agent (Some a) when Tenv.agent_property st.env a p.it <> None ->
       check st ctx ~what e (prop_type st (Option.get (Tenv.agent_property st.env a p.it)))
     | T.Behaviour b when Tenv.behaviour_property st.env b p.it <> None ->
       check st ctx ~what e (prop_type st (Option.get (Tenv.behaviour_property st.env b p.it)))
     | T.Error -> ignore (infer_rhs st ctx e)
     | _ ->
       let t' = of_type st p target t in
       if t' <> T.Error then
         error st lv.at "%s of %s cannot be assigned: it is read-only" p.it (ts t);
       ignore (infer_rhs st ctx e));
    ctx
  | LIndex (m, i) ->
    let t = known st m.at (infer st ctx m) in
    (match t with
     | T.List a -> check st ctx ~what:"a list index" i T.Integer;
       check st ctx ~what:"the value stored in the list" e a
     | T.Map (k, v) -> check st ctx ~what:"a map key" i k;
       check st ctx ~what:"the value stored in the map" e v
     | T.Error -> ignore (infer st ctx i); ignore (infer_rhs st ctx e)
     | t -> error st m.at "only lists and maps can be indexed, and this is a %s" (ts t);
       ignore (infer st ctx i); ignore (infer_rhs st ctx e));
    ctx

(* Rule Activate: B's on create parameters, by name; B's for agent. *)
and activate st ctx at (b : name) args =
  match Tenv.behaviour st.env b.it with
  | None ->
    error st b.at "unknown behaviour %s" b.it;
    List.iter (fun (_, a) -> ignore (infer_rhs st ctx a)) args
  | Some bd ->
    let params = match Tenv.behaviour_create st.env b.it with
      | Some r -> r.r_params | None -> [] in
    named st ctx at ("the on create of behaviour " ^ b.it) params args;
    match bd.b_for_agent with
    | Some a when not (Hashtbl.mem st.bad_for_agent bd.b_name) && not ctx.agent_bad ->
      (match ctx.agent with
       | None ->
         error st b.at "behaviour %s is for agent %s and can be activated only by %s agents, \
                        but this behaviour does not say which agent runs it (add 'for agent %s')"
           b.it a a a
       | Some cur ->
         if not (assignable st (T.Agent (Some cur)) (T.Agent (Some a))) then
           error st b.at "behaviour %s is for agent %s and can be activated only by %s agents, \
                          not by %s" b.it a a cur)
    | _ -> ()

and block st ctx (b : block) =
  ignore (List.fold_left (stmt st) ctx b)

(* Rule Returns: a block returns on every path. *)
let rec returns (b : block) = List.exists stmt_returns b
and stmt_returns (s : stmt) =
  match s.it with
  | Return _ -> true
  | If (branches, Some els) -> List.for_all (fun (_, b) -> returns b) branches && returns els
  | While ({ it = Lit (Bool true); _ }, body) -> not (breaks body)
  | _ -> false
and breaks (b : block) =
  List.exists (fun (s : stmt) -> match s.it with
      | Break -> true
      | If (branches, els) ->
        List.exists (fun (_, b) -> breaks b) branches || (match els with Some b -> breaks b | None -> false)
      | _ -> false) b

(* --------------------------------------------------------- features *)

let params_ctx ctx (r : Tenv.routine) (ps : param list) =
  List.fold_left2 (fun ctx (p : param) (x, t) -> add_local ctx x t p.pname.at)
    ctx ps r.r_params
  |> fun c -> c

let safe_params (r : Tenv.routine) (ps : param list) =
  (* r_params drops nothing, but be defensive about lengths *)
  if List.length ps = List.length r.r_params then Some ps else None

let routine st ctx (r : Tenv.routine) (ps : param list) ret =
  let ctx = { ctx with ret } in
  let ctx = match safe_params r ps with Some ps -> params_ctx ctx r ps | None -> ctx in
  block st ctx r.r_body

(* Rule Feature: properties, functions, procedures, lifecycle handlers. *)
let feature st base (routines : Tenv.routine list) create (props : Tenv.property list)
    (f : feature) =
  let find_r f = List.find_opt (fun (r : Tenv.routine) -> r.r_decl == f) routines in
  match f.it with
  | Property { name; ty = Some _; init = Some e } ->
    (match List.find_opt (fun (p : Tenv.property) -> p.p_decl == f) props with
     | Some p -> check st { base with ret = RInit }
                   ~what:(Printf.sprintf "the initial value of property %s" name.it) e p.p_type
     | None -> ())
  | Property _ ->
    (match List.find_opt (fun (p : Tenv.property) -> p.p_decl == f) props with
     | Some p -> ignore (prop_type st p)
     | None -> ())
  | Function { name; params; body; _ } ->
    (match find_r f with
     | Some r ->
       let ret = Option.value r.r_ret ~default:T.Error in
       routine st base r params (RFunction (name.it, ret));
       if not (returns body) then
         error st name.at "function %s does not return a value on every path \
                           (expected a 'return' of %s at the end)" name.it (ts ret)
     | None -> ())
  | Procedure { params; _ } ->
    (match find_r f with Some r -> routine st base r params RNone | None -> ())
  | OnCreate { params; _ } ->
    (match create with
     | Some (r : Tenv.routine) when r.r_decl == f -> routine st base r params RNone
     | _ -> ())
  | OnDestroy b | ActionSection b -> block st { base with ret = RNone } b
  | OnPercept { guard; body } ->
    let ctx = { base with ret = RNone; content = Some (T.Schema T.percept_root) } in
    let ctx = match guard with Some g -> cond st ctx g | None -> ctx in
    block st ctx body
  | OnMessage { perf; guard; body } ->
    let c = match perf with Some p -> performative st p | None -> T.Onto all_kinds in
    let ctx = { base with ret = RNone; content = Some c; message = Some c } in
    let ctx = match guard with Some g -> cond st ctx g | None -> ctx in
    block st { ctx with message = Some (Option.value ctx.content ~default:c) } body

(* Rule Handler-Reachable (warning): a message handler after an unguarded one
   for the same performative (or after an unguarded one for every message)
   never runs (R5b). *)
let unreachable st (fs : feature list) =
  ignore (List.fold_left (fun catchers (f : feature) ->
      match f.it with
      | OnMessage { perf; guard; _ } ->
        let p = Option.map (fun (n : name) -> n.it) perf in
        (match List.find_opt (fun (q, _) -> q = None || q = p) catchers with
         | Some (q, at) ->
           warning st f.at "this handler is unreachable: the handler at %s takes every %s \
                            message first (R5b)" (pos at)
             (match q with Some q -> q | None -> "")
         | None -> ());
        if guard = None then (p, f.at) :: catchers else catchers
      | _ -> catchers) [] fs)

let check_agent st (a : Tenv.agent) =
  let base = ctx_of_agent a RNone in
  List.iter (feature st base (a.a_functions @ a.a_procedures) a.a_create a.a_properties)
    a.a_decl.it.afeatures

let check_behaviour st (b : Tenv.behaviour) =
  let base = ctx_of_behaviour st b RNone in
  List.iter (feature st base (b.b_functions @ b.b_procedures) b.b_create b.b_properties)
    b.b_decl.it.bfeatures;
  unreachable st b.b_decl.it.bfeatures

(* Rule Schema-Defaults: with priority = N on percept types only, N natural;
   with slot = e against the slot's type. *)
let check_defaults st =
  List.iter (fun (s : Tenv.schema) ->
      let ctx = { owner = OOntology; agent = None; agent_bad = false;
                  visible = closure st [s.s_ontology]; locals = []; content = None;
                  message = None; ret = RInit; loop = false } in
      let seen = Hashtbl.create 4 in
      List.iter (fun ((n : name), (e : expr)) ->
          if Hashtbl.mem seen n.it then error st n.at "%s is given twice in the with clause" n.it;
          Hashtbl.replace seen n.it ();
          if n.it = "priority" && not (List.mem_assoc "priority" s.s_slots) then begin
            if not s.s_percept then
              error st n.at "'with priority' is only for percept types, and %s does not extend \
                             percept" s.s_name
            else match e.it with
              | Lit (Int k) when k <= int_max -> s.s_priority <- k
              | _ ->
                let t = infer st ctx e in
                error st e.at "the priority of a percept type must be a natural number \
                               (0 or more) written as a literal, found %s"
                  (match e.it with
                   | Unop (Neg, { it = Lit (Int k); _ }) -> string_of_int (-k)
                   | _ -> "an expression of type " ^ ts t)
          end else
            match List.assoc_opt n.it s.s_slots with
            | Some t -> check st ctx ~what:(Printf.sprintf "the default of slot %s" n.it) e t
            | None ->
              error st n.at "%s %s has no slot %s to give a value to" (T.kind_to_string s.s_kind)
                s.s_name n.it) s.s_defaults) (Tenv.schemas st.env);
  (* R1a: priorities inherited, so recompute along chains after own values. *)
  let own s = List.exists (fun ((n : name), _) -> n.it = "priority") s.Tenv.s_defaults in
  let rec effective (s : Tenv.schema) =
    if own s then s.s_priority
    else match s.s_super with
      | Some p when p <> T.percept_root ->
        (match Tenv.schema st.env p with Some ps -> effective ps | None -> 0)
      | _ -> 0 in
  List.iter (fun (s : Tenv.schema) -> if s.s_percept then s.s_priority <- effective s)
    (Tenv.schemas st.env)

(* Rule Unused (warning). *)
let unused st =
  let props = List.concat_map (fun (a : Tenv.agent) -> a.a_properties) (Tenv.agents st.env)
              @ List.concat_map (fun (b : Tenv.behaviour) -> b.b_properties) (Tenv.behaviours st.env) in
  List.iter (fun (p : Tenv.property) ->
      if not p.p_read then
        let at = match p.p_decl.it with Property { name; _ } -> name.at | _ -> p.p_decl.at in
        warning st at "property %s of %s is never read" p.p_name p.p_owner) props

(* Rule Resolved: every empty collection's type is known at the end. *)
let unresolved st =
  let reported = Hashtbl.create 8 in
  List.iter (fun (v : T.var) ->
      match T.repr (T.Var v) with
      | T.Var v' when v' == v && not (Hashtbl.mem reported v.origin) ->
        Hashtbl.replace reported v.origin ();
        error st v.origin "cannot infer the type of this empty collection: nothing in the \
                           program decides its element type; %s" v.hint
      | _ -> ()) (List.rev st.vars)

let zonk_env st =
  List.iter (fun (s : Tenv.schema) -> s.s_slots <- List.map (fun (x, t) -> (x, T.zonk t)) s.s_slots)
    (Tenv.schemas st.env);
  let zr (r : Tenv.routine) =
    r.r_params <- List.map (fun (x, t) -> (x, T.zonk t)) r.r_params;
    r.r_ret <- Option.map T.zonk r.r_ret in
  let zp (p : Tenv.property) = p.p_type <- T.zonk p.p_type in
  List.iter (fun (a : Tenv.agent) ->
      List.iter zp a.a_properties; List.iter zr (a.a_functions @ a.a_procedures);
      Option.iter zr a.a_create) (Tenv.agents st.env);
  List.iter (fun (b : Tenv.behaviour) ->
      List.iter zp b.b_properties; List.iter zr (b.b_functions @ b.b_procedures);
      Option.iter zr b.b_create) (Tenv.behaviours st.env)

let program (files : Parse.result list) =
  let env = Tenv.create () in
  let st = { env; h = Tenv.hierarchy env; diags = []; vars = [];
             bad_for_agent = Hashtbl.create 4 } in
  collect st files;
  check_ontologies st;
  check_schema_supers st;
  resolve_schemas st;
  check_headers st;
  resolve_signatures st;
  check_defaults st;
  List.iter (check_agent st) (Tenv.agents env);
  List.iter (check_behaviour st) (Tenv.behaviours env);
  unresolved st;
  unused st;
  zonk_env st;
  (env, List.sort_uniq Diag.compare st.diags)

let performative_names = List.map fst performatives
