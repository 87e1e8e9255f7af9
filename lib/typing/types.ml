module Ast = Syntax.Ast

type t =
  | Boolean
  | Integer
  | Float
  | Double
  | Text
  | Aid
  | Any
  | List of t
  | Map of t * t
  | Schema of string
  | Onto of Ast.schema_kind list
  | Agent of string option
  | Behaviour of string
  | Message of t
  | Var of var
  | Error

and var = {
  id : int;
  mutable link : t option;
  origin : Syntax.Source.region;
  mutable hint : string;
}

let counter = ref 0

let fresh ?(hint = "") origin =
  incr counter;
  Var { id = !counter; link = None; origin; hint }

let rec repr t =
  match t with
  | Var { link = Some t'; _ } -> repr t'
  | _ -> t

let rec zonk t =
  match repr t with
  | List a -> List (zonk a)
  | Map (k, v) -> Map (zonk k, zonk v)
  | Message c -> Message (zonk c)
  | t -> t

let unresolved t =
  let rec go acc t =
    match repr t with
    | Var v -> if List.memq v acc then acc else v :: acc
    | List a | Message a -> go acc a
    | Map (k, v) -> go (go acc k) v
    | _ -> acc in
  List.rev (go [] t)

let percept_root = "percept"

type hierarchy = {
  schema_supers : string -> string list;
  schema_kind : string -> Ast.schema_kind option;
  agent_supers : string -> string list;
  behaviour_supers : string -> string list;
}

let rec occurs v t =
  match repr t with
  | Var v' -> v == v'
  | List a | Message a -> occurs v a
  | Map (k, x) -> occurs v k || occurs v x
  | _ -> false

let rec unify a b =
  match repr a, repr b with
  | Var v, Var w when v == w -> true
  | Var v, t | t, Var v ->
    (* binding to Error too: an empty literal used after an error is not
       reported again as unresolved *)
    if occurs v t then false else (v.link <- Some t; true)
  | Error, _ | _, Error -> true
  | List a, List b -> unify a b
  | Map (k, v), Map (k', v') -> unify k k' && unify v v'
  | Message a, Message b -> unify a b
  | a, b -> a = b

(* Rule Assignable of docs/typing.md. *)
let assignable h actual expected =
  match repr actual, repr expected with
  | (Var _, _ | _, Var _) -> unify actual expected
  | Error, _ | _, Error -> true
  | Integer, (Integer | Float | Double) -> true
  | Schema a, Schema b ->
    a = b || List.mem b (h.schema_supers a)
  | Schema a, Onto ks ->
    if a = percept_root then List.mem Ast.Predicate ks && List.mem Ast.Proposition ks
    else (match h.schema_kind a with Some k -> List.mem k ks | None -> false)
  | Onto ks, Onto ks' -> List.for_all (fun k -> List.mem k ks') ks
  | Agent (Some a), Agent (Some b) -> a = b || List.mem b (h.agent_supers a)
  | Agent _, Agent None -> true
  | Behaviour a, Behaviour b -> a = b || List.mem b (h.behaviour_supers a)
  | (List _ | Map _ | Message _), _ -> unify actual expected
  | a, b -> a = b

let is_numeric t =
  match repr t with Integer | Float | Double -> true | _ -> false

let kind_to_string = function
  | Ast.Concept -> "concept"
  | Ast.Predicate -> "predicate"
  | Ast.Proposition -> "proposition"
  | Ast.Action -> "action"

let rec to_string t =
  match repr t with
  | Boolean -> "boolean"
  | Integer -> "integer"
  | Float -> "float"
  | Double -> "double"
  | Text -> "text"
  | Aid -> "aid"
  | Any -> "any"
  | List a -> "list of " ^ to_string a
  | Map (k, v) ->
    let k' = match repr k with
      | List _ | Map _ -> "(" ^ to_string k ^ ")"
      | _ -> to_string k in
    "map of " ^ k' ^ ":" ^ to_string v
  | Schema s -> s
  | Onto ks ->
    let all = [Ast.Concept; Ast.Action; Ast.Predicate; Ast.Proposition] in
    if List.for_all (fun k -> List.mem k ks) all then "ontology value"
    else String.concat " or " (List.map kind_to_string ks)
  | Agent (Some a) -> a
  | Agent None -> "agent"
  | Behaviour b -> b
  | Message _ -> "message"
  | Var _ -> "?"
  | Error -> "<error>"
