(** The typed environment: every declaration of a checked program, with the
    types the checker gave it. This is what the interpreter runs from.

    {!Typing.check} builds it. Fields marked mutable are filled in by the
    checker (slot lists, inferred property types, visibility); once [check] has
    returned they do not change. Types are zonked: an unresolved [Types.Var] is
    left only where an error was reported. When a declaration is erroneous
    (unknown super type, cyclic [extends]) the link is dropped ([None]), so that
    every chain below is finite. *)

module Ast = Syntax.Ast

type ontology = {
  o_name : string;
  mutable o_super : string option;
  o_schemas : string list;          (** own schemas, in declaration order *)
  o_decl : Ast.ontology Ast.phrase;
}

type schema = {
  s_name : string;
  s_kind : Ast.schema_kind;
  s_ontology : string;
  mutable s_super : string option;  (** [extends]; ["percept"] for the root *)
  mutable s_supers : string list;
      (** every proper supertype, nearest first; a percept type's chain ends
          with ["percept"] *)
  mutable s_slots : (string * Types.t) list;
      (** every slot, inherited ones first, in declaration order; a slot that a
          subtype overrides keeps its inherited position with the new type. The
          positional arguments of the constructor and of a constructor pattern *)
  s_defaults : (Ast.name * Ast.expr) list;  (** the [with slot = e] clause *)
  mutable s_percept : bool;         (** extends [percept], maybe indirectly *)
  mutable s_priority : int;
      (** the effective default priority of a percept type (R1a: its own
          [with priority = N], else its parent's, else 0); 0 for the others *)
  s_decl : Ast.schema;
}

type status = Pending | Resolving | Resolved
(** Checker bookkeeping for inferred property types. *)

type property = {
  p_name : string;
  p_owner : string;                 (** the agent or behaviour declaring it *)
  mutable p_type : Types.t;
  p_init : Ast.expr option;
  p_decl : Ast.feature;
  mutable p_status : status;
  mutable p_read : bool;            (** read somewhere in the program *)
}

type routine = {
  r_name : string;                  (** [""] for [on create] *)
  r_owner : string;
  mutable r_params : (string * Types.t) list;
  mutable r_ret : Types.t option;   (** [Some t] for a function *)
  r_body : Ast.block;
  r_at : Syntax.Source.region;
  r_decl : Ast.feature;             (** the declaration *)
}

type handler_kind =
  | On_percept
  | On_message of string option     (** the performative, if any *)

type handler = {
  h_kind : handler_kind;
  h_guard : Ast.expr option;
  h_body : Ast.block;
  h_at : Syntax.Source.region;
}

type agent = {
  a_name : string;
  mutable a_super : string option;
  a_ontologies : string list;       (** the [uses ontology] clause *)
  mutable a_visible : string list;
      (** every ontology whose schemas are visible: own, inherited from the
          super agent, and the ontologies those extend *)
  a_properties : property list;     (** own, in declaration order *)
  a_functions : routine list;
  a_procedures : routine list;
  a_create : routine option;        (** own [on create] *)
  a_destroy : Ast.block option;
  a_decl : Ast.agent Ast.phrase;
}

type behaviour = {
  b_name : string;
  b_kind : Ast.behaviour_kind;
  mutable b_super : string option;
  mutable b_for_agent : string option;
      (** [for agent A], or the super behaviour's when absent *)
  b_ontologies : string list;
  mutable b_visible : string list;
      (** own ontologies, the super behaviour's, those of the [for agent]
          agent, and the ontologies they extend *)
  b_properties : property list;
  b_functions : routine list;
  b_procedures : routine list;
  b_create : routine option;
  b_action : Ast.block option;
  b_handlers : handler list;        (** own, in declaration order *)
  b_decl : Ast.behaviour Ast.phrase;
}

type t

val create : unit -> t

val add_ontology : t -> ontology -> unit
val add_schema : t -> schema -> unit
val add_agent : t -> agent -> unit
val add_behaviour : t -> behaviour -> unit
(** The first declaration of a name wins; the checker reports duplicates. *)

val ontology : t -> string -> ontology option
val schema : t -> string -> schema option
val agent : t -> string -> agent option
val behaviour : t -> string -> behaviour option

val ontologies : t -> ontology list
val schemas : t -> schema list
val agents : t -> agent list
val behaviours : t -> behaviour list
(** In program order (files in the order given, declarations in file order). *)

val agent_chain : t -> string -> agent list
val behaviour_chain : t -> string -> behaviour list
(** The declaration and its supers, nearest first (finite even on a cycle). *)

val agent_properties : t -> string -> property list
val behaviour_properties : t -> string -> property list
(** Every property, inherited ones first, in declaration order. *)

val agent_property : t -> string -> string -> property option
val behaviour_property : t -> string -> string -> property option
val agent_function : t -> string -> string -> routine option
val agent_procedure : t -> string -> string -> routine option
val behaviour_function : t -> string -> string -> routine option
val behaviour_procedure : t -> string -> string -> routine option
(** By name, the nearest declaration up the [extends] chain. *)

val agent_create : t -> string -> routine option
val behaviour_create : t -> string -> routine option
(** The [on create] that runs: the nearest up the chain. Its parameters are
    the arguments of [activate behaviour B with ...] (and, for an agent, of the
    host's creation of the agent). *)

val behaviour_handlers : t -> string -> handler list
(** Every handler, inherited ones first, in declaration order (R4a). *)

val behaviour_action : t -> string -> Ast.block option
(** The nearest action section up the chain. *)

val hierarchy : t -> Types.hierarchy
(** Subtyping for {!Types.assignable}. *)

val visible_schema : t -> string list -> string -> bool
(** [visible_schema env ontologies s]: schema [s] is declared in one of
    [ontologies]. *)

val subschema : t -> string -> string -> bool
(** [subschema env a b]: [a] is [b] or a subtype of it. *)
