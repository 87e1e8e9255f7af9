module Ast = Syntax.Ast

type ontology = {
  o_name : string;
  mutable o_super : string option;
  o_schemas : string list;
  o_decl : Ast.ontology Ast.phrase;
}

type schema = {
  s_name : string;
  s_kind : Ast.schema_kind;
  s_ontology : string;
  mutable s_super : string option;
  mutable s_supers : string list;
  mutable s_slots : (string * Types.t) list;
  s_defaults : (Ast.name * Ast.expr) list;
  mutable s_percept : bool;
  mutable s_priority : int;
  s_decl : Ast.schema;
}

type status = Pending | Resolving | Resolved

type property = {
  p_name : string;
  p_owner : string;
  mutable p_type : Types.t;
  p_init : Ast.expr option;
  p_decl : Ast.feature;
  mutable p_status : status;
  mutable p_read : bool;
}

type routine = {
  r_name : string;
  r_owner : string;
  mutable r_params : (string * Types.t) list;
  mutable r_ret : Types.t option;
  r_body : Ast.block;
  r_at : Syntax.Source.region;
  r_decl : Ast.feature;
}

type handler_kind =
  | On_percept
  | On_message of string option

type handler = {
  h_kind : handler_kind;
  h_guard : Ast.expr option;
  h_body : Ast.block;
  h_at : Syntax.Source.region;
}

type agent = {
  a_name : string;
  mutable a_super : string option;
  a_ontologies : string list;
  mutable a_visible : string list;
  a_properties : property list;
  a_functions : routine list;
  a_procedures : routine list;
  a_create : routine option;
  a_destroy : Ast.block option;
  a_decl : Ast.agent Ast.phrase;
}

type behaviour = {
  b_name : string;
  b_kind : Ast.behaviour_kind;
  mutable b_super : string option;
  mutable b_for_agent : string option;
  b_ontologies : string list;
  mutable b_visible : string list;
  b_properties : property list;
  b_functions : routine list;
  b_procedures : routine list;
  b_create : routine option;
  b_action : Ast.block option;
  b_handlers : handler list;
  b_decl : Ast.behaviour Ast.phrase;
}

(* A table that remembers insertion order. *)
type 'a table = { tbl : 'a Syntax.Strtbl.t; mutable order : 'a list }

let table () = { tbl = Syntax.Strtbl.create 16; order = [] }
let add t k v =
  if not (Syntax.Strtbl.mem t.tbl k) then begin
    Syntax.Strtbl.replace t.tbl k v; t.order <- v :: t.order
  end
let find t k = Syntax.Strtbl.find_opt t.tbl k
let items t = List.rev t.order

type t = {
  onts : ontology table;
  schs : schema table;
  ags : agent table;
  behs : behaviour table;
}

let create () = { onts = table (); schs = table (); ags = table (); behs = table () }

let add_ontology e o = add e.onts o.o_name o
let add_schema e s = add e.schs s.s_name s
let add_agent e a = add e.ags a.a_name a
let add_behaviour e b = add e.behs b.b_name b

let ontology e = find e.onts
let schema e = find e.schs
let agent e = find e.ags
let behaviour e = find e.behs
let ontologies e = items e.onts
let schemas e = items e.schs
let agents e = items e.ags
let behaviours e = items e.behs

(* Follow [super] links from [start], stopping at a repetition. *)
let chain find super start =
  let rec go seen acc = function
    | None -> List.rev acc
    | Some n when List.mem n seen -> List.rev acc
    | Some n ->
      match find n with
      | None -> List.rev acc
      | Some d -> go (n :: seen) (d :: acc) (super d) in
  go [] [] (Some start)

let agent_chain e = chain (agent e) (fun a -> a.a_super)
let behaviour_chain e = chain (behaviour e) (fun b -> b.b_super)

let inherited chain field = List.concat_map field (List.rev chain)

let agent_properties e a = inherited (agent_chain e a) (fun a -> a.a_properties)
let behaviour_properties e b = inherited (behaviour_chain e b) (fun b -> b.b_properties)

let nearest chain field name =
  List.find_map (fun d -> List.find_opt (fun x -> name x) (field d)) chain

let agent_property e a x = nearest (agent_chain e a) (fun a -> a.a_properties) (fun p -> p.p_name = x)
let behaviour_property e b x =
  nearest (behaviour_chain e b) (fun b -> b.b_properties) (fun p -> p.p_name = x)
let agent_function e a x = nearest (agent_chain e a) (fun a -> a.a_functions) (fun r -> r.r_name = x)
let agent_procedure e a x = nearest (agent_chain e a) (fun a -> a.a_procedures) (fun r -> r.r_name = x)
let behaviour_function e b x =
  nearest (behaviour_chain e b) (fun b -> b.b_functions) (fun r -> r.r_name = x)
let behaviour_procedure e b x =
  nearest (behaviour_chain e b) (fun b -> b.b_procedures) (fun r -> r.r_name = x)

let agent_create e a = List.find_map (fun a -> a.a_create) (agent_chain e a)
let behaviour_create e b = List.find_map (fun b -> b.b_create) (behaviour_chain e b)
let behaviour_action e b = List.find_map (fun b -> b.b_action) (behaviour_chain e b)
let behaviour_handlers e b = inherited (behaviour_chain e b) (fun b -> b.b_handlers)

let hierarchy e =
  let tail_names name chain = match chain with [] -> [] | _ :: tl -> List.map name tl in
  {
    Types.schema_supers = (fun s -> match schema e s with Some s -> s.s_supers | None -> []);
    schema_kind = (fun s -> Option.map (fun s -> s.s_kind) (schema e s));
    agent_supers = (fun a -> tail_names (fun a -> a.a_name) (agent_chain e a));
    behaviour_supers = (fun b -> tail_names (fun b -> b.b_name) (behaviour_chain e b));
  }
let visible_schema e onts s =
  match schema e s with
  | Some s -> List.mem s.s_ontology onts
  | None -> false

let subschema e a b =
  a = b || (match schema e a with Some s -> List.mem b s.s_supers | None -> false)
