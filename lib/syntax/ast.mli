(** Abstract syntax of Jadescript, the dialect of the 2020 paper (Sections 3-5,
    Figures 1-7) plus the spellings of Jadescript 1.0.

    Every node is a {!Source.phrase}: the node and the region it was parsed from.
    Spelling variants that mean the same thing ([behaviour]/[behavior],
    [one shot]/[oneshot], [activate B]/[activate behaviour B], [uses ontology]/
    [uses ontologies]) are not distinguished here: the printer writes the
    canonical spelling. Comments are not part of the tree; the parser returns them
    beside it ({!Parse.result}). *)

type 'a phrase = 'a Source.phrase

type name = string phrase
(** An identifier. Builtin type names ([integer], [text], ...) and performatives
    are ordinary identifiers, resolved by the type checker. *)

(** {1 Types} *)

type ty = ty' phrase
and ty' =
  | TName of string  (** [boolean], [integer], [text], [string], [aid], [any],
                         or a schema, agent or behaviour name *)
  | TList of ty      (** [list of T] *)
  | TMap of ty * ty  (** [map of K:V] *)

(** {1 Expressions} *)

type literal =
  | Int of int       (** a decimal integer; negative only inside patterns
                         (elsewhere [-3] is [Unop (Neg, 3)]) *)
  | Real of string   (** a decimal literal, kept as written ([1.50], [2e-3]) so
                         that [float] and [double] can each round it once *)
  | Text of string   (** the text after escapes are resolved *)
  | Bool of bool

type unop = Not | Neg

type binop =
  | Or | And
  | Eq | Neq
  | Lt | Gt | Le | Ge
  | Add | Sub
  | Mul | Div | Mod

type pattern = pattern' phrase
and pattern' =
  | PWild                          (** [_] *)
  | PLit of literal
  | PName of string                (** a schema name ([obstacle]) or a fresh
                                       variable ([qrCode]): the type checker
                                       decides, by whether a schema of that name
                                       is visible *)
  | PCons of name * pattern list   (** [position(x, _)] *)

type expr = expr' phrase
and expr' =
  | Lit of literal
  | Name of string
  | This                           (** [this]: the running behaviour *)
  | Agent                          (** [agent]: the agent the code runs in *)
  | Content                        (** [content]: the event being handled *)
  | Message                        (** [message]: the message being handled *)
  | List of expr list              (** [[a, b]]; [[]] is the empty list *)
  | Map of (expr * expr) list      (** [{k: v}]; [{}] is the empty map *)
  | Call of name * expr list       (** [f(a, b)], [position(x, y)], [aid(e)] *)
  | Index of expr * expr           (** [e[i]] *)
  | Of of name * expr              (** [p of e] *)
  | Matches of expr * pattern      (** [e matches pattern] *)
  | Unop of unop * expr
  | Binop of binop * expr * expr
  | Invoke of invoke               (** only as a statement or as the right side
                                       of an assignment or property *)

and invoke = {
  meth : string phrase;  (** the method name, a text literal *)
  target : expr;         (** [on e] *)
  args : expr list;      (** [with e1, e2] *)
}

(** {1 Statements} *)

type lvalue = lvalue' phrase
and lvalue' =
  | LName of string          (** [x = e]: a local (declared by its first
                                 assignment), a property or an agent property *)
  | LOf of name * expr       (** [x of e = v] *)
  | LIndex of expr * expr    (** [m[k] = v] *)

type args =
  | Positional of expr list           (** [do p with a, b] *)
  | Named of (name * expr) list       (** [do p with x = a, y = b] *)

type stmt = stmt' phrase
and stmt' =
  | Assign of lvalue * expr
  | Local of name * ty * expr              (** [x as T = e] *)
  | Do of name * args                      (** [do p], [do p with ...] *)
  | Nothing                                (** [do nothing] *)
  | InvokeS of invoke                      (** [invoke "m" on e with ...] *)
  | Activate of name * (name * expr) list  (** [activate behaviour B with x = e] *)
  | Deactivate                             (** [deactivate this] *)
  | Send of name * expr * expr list        (** [send perf content to r1, r2] *)
  | Log of expr
  | If of (expr * block) list * block option
      (** [if c do ... else if c do ... else do ...] *)
  | While of expr * block
  | For of name * expr * block             (** [for x in e do] *)
  | Return of expr option
  | Break
  | Continue

and block = stmt list

(** {1 Declarations} *)

type schema_kind = Concept | Predicate | Proposition | Action

type slot = { slot_name : name; slot_ty : ty }

type schema = schema' phrase
and schema' = {
  kind : schema_kind;
  sname : name;
  slots : slot list;                (** empty for propositions *)
  super : name option;              (** [extends S]; [percept] is the root of
                                        percept types (R1a) *)
  defaults : (name * expr) list;    (** [with slot = e, ...], e.g. [priority] *)
}

type param = { pname : name; pty : ty }

type feature = feature' phrase
and feature' =
  | Property of { name : name; ty : ty option; init : expr option }
      (** [property x as T [= e]] or [property x = e]; not both absent *)
  | Function of { name : name; params : param list; ret : ty; body : block }
  | Procedure of { name : name; params : param list; body : block }
  | OnCreate of { params : param list; body : block }
  | OnDestroy of block
  | ActionSection of block                 (** a behaviour's [do] block *)
  | OnPercept of { guard : expr option; body : block }
  | OnMessage of { perf : name option; guard : expr option; body : block }
      (** [on message [perf] [when e] do], and the short form [on inform ...] *)

type ontology = {
  oname : name;
  oextends : name option;
  schemas : schema list;
}

type agent = {
  aname : name;
  aextends : name option;
  aontologies : name list;
  afeatures : feature list;
}

type behaviour_kind = Cyclic | OneShot

type behaviour = {
  bkind : behaviour_kind;
  bname : name;
  bextends : name option;
  for_agent : name option;
  bontologies : name list;
  bfeatures : feature list;
}

type decl = decl' phrase
and decl' =
  | DOntology of ontology
  | DAgent of agent
  | DBehaviour of behaviour

type program = {
  module_name : name list;   (** [module a.b.c]; empty when absent *)
  decls : decl list;
}
