(** The types of Jadescript (Section 3 of the paper): five categories.

    - primitive: [boolean integer float double text] ([string] is [text], R1b);
    - collection: [list of T], [map of K:V];
    - ontology: the schemas of ontologies (concepts, actions, predicates,
      propositions), with subtyping through [extends]; percept types are the
      schemas that extend [percept] (R1a);
    - agent and behaviour types;
    - plus [aid] (agent identifiers) and [any] (opaque host values, usable only
      with [invoke] and equality).

    Two internal types never written by programs: [Onto ks] (some ontology value
    of one of the kinds [ks]: the content of a message whose content has not been
    narrowed) and [Message] (the message being handled). Unification variables
    ([Var]) stand for the element types of empty collection literals until a
    later use fixes them; [Error] is the type of an expression that already
    produced an error, and is compatible with everything, so that one mistake
    is reported once. *)

type t =
  | Boolean
  | Integer   (** Java's 32-bit [int] *)
  | Float     (** IEEE binary32 *)
  | Double    (** IEEE binary64 *)
  | Text
  | Aid
  | Any
  | List of t
  | Map of t * t
  | Schema of string
      (** a schema by name; [Schema "percept"] is the root of percept types *)
  | Onto of Syntax.Ast.schema_kind list
      (** any ontology value of one of these kinds *)
  | Agent of string option
      (** an agent type; [None]: some agent, of a type not known statically
          (the [agent] of a behaviour without [for agent]) *)
  | Behaviour of string
  | Message of t   (** the message being handled, with its content type *)
  | Var of var     (** not known yet: an empty collection's element type *)
  | Error          (** after an error: compatible with everything *)

and var = {
  id : int;
  mutable link : t option;        (** [Some t] once unified with [t] *)
  origin : Syntax.Source.region;  (** the empty literal it comes from *)
  mutable hint : string;          (** where to write a type, for the error *)
}

val fresh : ?hint:string -> Syntax.Source.region -> t
(** A new unresolved variable. *)

val repr : t -> t
(** Follows the links of resolved variables (at the top only). *)

val zonk : t -> t
(** Follows every link, deeply: the type as far as it is known. *)

val unresolved : t -> var list
(** The unresolved variables of a type. *)

val percept_root : string
(** ["percept"]. *)

(** What subtyping needs to know about declarations. *)
type hierarchy = {
  schema_supers : string -> string list;
      (** the proper supertypes of a schema, nearest first; a percept type's
          chain ends with [percept] *)
  schema_kind : string -> Syntax.Ast.schema_kind option;
  agent_supers : string -> string list;
  behaviour_supers : string -> string list;
}

val unify : t -> t -> bool
(** Structural equality, binding unresolved variables (invariance: the element
    types of collections). [Error] unifies with everything. *)

val assignable : hierarchy -> t -> t -> bool
(** [assignable h actual expected]: a value of type [actual] may be used where
    [expected] is required (rule [Assignable] of docs/typing.md):
    the same type; [integer] to [float] or [double] (the only implicit
    conversion); a schema to its supertypes and to [Onto ks] when its kind is
    in [ks]; an agent or behaviour type to its supertypes; collections are
    invariant (their element types unify). May bind variables. *)

val is_numeric : t -> bool
(** [integer], [float] or [double]. *)

val to_string : t -> string
(** As Jadescript writes it: [map of (list of integer):text], [position]. *)

val kind_to_string : Syntax.Ast.schema_kind -> string
