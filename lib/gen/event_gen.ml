(* Random host scenarios (see event_gen.mli). *)

module T = Typing.Types
module Tenv = Typing.Tenv
module Mc = Semantics.Machine
module Ev = Interp.Events

type scenario = {
  agents : (string * string * string list) list;
  events : Ev.source list;
  variant : Mc.variant;
  tie : Mc.tie_policy;
  budget : int;
  capacity : int option;
  seed : int option;
  fuel : int;
  max_steps : int;
}

let int rs n = Random.State.int rs n
let chance rs p = Random.State.float rs 1.0 < p
let pick rs l = List.nth l (int rs (List.length l))

(* The performatives of Jadescript (lib/syntax/parser.mly), each with the
   kinds of content it carries (the rule Performative of lib/typing/check.ml). *)
let actions = [ "cancel"; "cfp"; "request"; "request_when"; "request_whenever" ]
let any_kind = [ "inform_ref"; "propagate"; "proxy"; "query_ref"; "subscribe" ]
let performatives =
  [ "accept_proposal"; "agree"; "cancel"; "cfp"; "confirm"; "disconfirm"; "failure"; "inform";
    "inform_if"; "inform_ref"; "not_understood"; "propagate"; "propose"; "proxy"; "query_if";
    "query_ref"; "refuse"; "reject_proposal"; "request"; "request_when"; "request_whenever";
    "subscribe" ]

let carries perf (sc : Tenv.schema) =
  if List.mem perf actions then sc.s_kind = Syntax.Ast.Action
  else if List.mem perf any_kind then true
  else sc.s_kind = Syntax.Ast.Predicate || sc.s_kind = Syntax.Ast.Proposition

(* Texts with quotes, escapes, non-ASCII (valid UTF-8) and the empty one. *)
let texts = [ "A7"; ""; "left"; "with \\\"quotes\\\""; "tab\\there"; "caf\xc3\xa9"; "\xe2\x86\x92 east";
              "line\\nbreak"; "back\\\\slash"; "x" ]

let rec literal rs env (t : T.t) =
  match T.repr t with
  | T.Integer ->
    pick rs [ string_of_int (int rs 10); string_of_int (int rs 1000); "0"; "2147483647"; "-2147483648";
              "-" ^ string_of_int (int rs 50) ]
  | T.Double | T.Float ->
    pick rs [ Printf.sprintf "%d.%d" (int rs 100) (int rs 10); string_of_int (int rs 10); "0.0";
              "1e10"; "-3.5"; "2.5e-3" ]
  | T.Text -> "\"" ^ pick rs texts ^ "\""
  | T.Boolean -> if chance rs 0.5 then "true" else "false"
  | T.Aid -> Printf.sprintf "aid(\"%s\")" (pick rs [ "g"; "Bob"; "provider"; "nobody" ])
  | T.List a -> "[" ^ String.concat ", " (List.init (int rs 3) (fun _ -> literal rs env a)) ^ "]"
  | T.Map (k, v) ->
    (* an empty map literal needs its type from elsewhere: give one entry *)
    "{" ^ String.concat ", " (List.init (1 + int rs 2) (fun _ -> literal rs env k ^ ": " ^ literal rs env v)) ^ "}"
  | T.Schema s ->
    (match List.find_opt (fun (sc : Tenv.schema) -> sc.s_name = s) (Tenv.schemas env) with
     | Some sc -> constructor rs env sc
     | None -> "0")
  | _ -> "0"

and constructor rs env (sc : Tenv.schema) =
  if sc.s_slots = [] then sc.s_name
  else sc.s_name ^ "(" ^ String.concat ", " (List.map (fun (_, t) -> literal rs env t) sc.s_slots) ^ ")"

let schemas_where env p = List.filter p (Tenv.schemas env)

let scenario env ~agent_type rs =
  let names = [ "g"; "Bob"; "provider" ] in
  let n_agents = 1 + (if chance rs 0.5 then 0 else int rs 3) in
  let params = match Tenv.agent_create env agent_type with Some r -> r.Tenv.r_params | None -> [] in
  let agents = List.init n_agents (fun i ->
      let args = List.map (fun (_, t) -> match T.repr t with
          | T.Any -> if chance rs 0.7 then "@robome" else literal rs env T.Integer
          | t -> literal rs env t) params in
      (List.nth names i, agent_type, args)) in
  let agent () = let (n, _, _) = pick rs agents in n in
  let percepts = schemas_where env (fun sc -> sc.s_percept) in
  let contents = schemas_where env (fun sc -> sc.s_kind <> Syntax.Ast.Concept) in
  let concepts = schemas_where env (fun sc -> sc.s_kind = Syntax.Ast.Concept) in
  let event () =
    match int rs 21 with
    | k when k < 10 && percepts <> [] ->
      let priority = if chance rs 0.3 then Some (pick rs [ 0; int rs 12; int rs 1000 ]) else None in
      Ev.Notify_text { agent = agent (); percept = constructor rs env (pick rs percepts); priority }
    | k when k < 12 ->
      let obj = match int rs 4 with
        | 0 when concepts <> [] -> constructor rs env (pick rs concepts)
        | 1 when percepts <> [] -> constructor rs env (pick rs percepts)
        | 2 -> literal rs env (T.List T.Text)
        | _ -> literal rs env (pick rs [ T.Integer; T.Text; T.Double; T.Boolean ]) in
      Ev.Put_text { agent = agent (); obj }
    | k when k < 15 && contents <> [] ->
      (* a content of a kind the performative carries *)
      let perf = if chance rs 0.2 then None else Some (pick rs performatives) in
      let fits = List.filter (carries (Option.value perf ~default:"inform")) contents in
      let (perf, fits) = if fits = [] then (None, List.filter (carries "inform") contents) else (perf, fits) in
      if fits = [] then Ev.Run_rounds 1
      else
        (* now and then during the agent's next behaviour step (D42, R5d) *)
        Ev.Message_text { agent = agent (); perf; content = constructor rs env (pick rs fits);
                          during_step = chance rs 0.5 }
    | k when k < 19 -> Ev.Run_rounds (pick rs [ 0; 1; 1; 2; 3; 10 ])
    | 19 -> Ev.Run_single_rules (pick rs [ 0; 1; 2; 3; 7 ])   (* D23: the host acts between rules *)
    | _ -> Ev.Run_until_idle in
  let events = List.init (int rs 25) (fun _ -> event ()) in
  let variant = pick rs [ Mc.Reference; Mc.Reference; Mc.Printed; Mc.Budgeted; Mc.Native ] in
  let tie = if chance rs 0.7 then Mc.Stable else Mc.Unstable in
  let budget = 1 + int rs 3 in
  let capacity = if chance rs 0.6 then None else Some (pick rs [ 1; 2; 5; 100 ]) in
  let seed = if chance rs 0.5 then None else Some (int rs 1000) in
  let fuel = pick rs [ 100_000; 100_000; 5_000; 50; 1 ] in
  let max_steps = pick rs [ 2_000; 500; 50; 1 ] in
  { agents; events; variant; tie; budget; capacity; seed; fuel; max_steps }

let events_file s = String.concat "" (List.map (fun e -> Ev.source_to_line e ^ "\n") s.events)

let agent_args s =
  List.map (fun (n, ty, args) -> n ^ ":" ^ ty ^ (if args = [] then "" else ":" ^ String.concat "," args)) s.agents

let run_args s =
  List.concat
    [ (match s.seed with Some k -> [ "--seed"; string_of_int k ] | None -> []);
      [ "--variant"; Mc.string_of_variant s.variant; "--fuel"; string_of_int s.fuel;
        "--max-steps"; string_of_int s.max_steps ];
      (match s.capacity with Some c -> [ "--o2a-capacity"; string_of_int c ] | None -> []) ]

(* Small literals for the tests' own random hosts (test/interp,
   test/fastpath, test/validate, test/backend): a few values per type, so
   that equal percepts and messages happen. *)
let rec small_literal rand (ty : Typing.Types.t) =
  match Typing.Types.repr ty with
  | Typing.Types.Integer -> string_of_int (Random.State.int rand 5)
  | Typing.Types.Double | Typing.Types.Float -> Printf.sprintf "%d.5" (Random.State.int rand 5)
  | Typing.Types.Text -> Printf.sprintf "\"t%d\"" (Random.State.int rand 3)
  | Typing.Types.Boolean -> if Random.State.bool rand then "true" else "false"
  | Typing.Types.List t -> "[" ^ small_literal rand t ^ "]"
  | _ -> "0"

let percept_types env =
  List.filter (fun (s : Typing.Tenv.schema) -> s.s_percept) (Typing.Tenv.schemas env)
