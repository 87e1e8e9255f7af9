(* The engine's contract with the reference, held by one property test
   (lib/engine/engine.mli): two copies of an agent get the same host
   operations; one takes the reference's rules (Machine.step on
   Eval.Bodies, one rule at a time), the other the engine
   (Engine.Make on the compiled bodies, D38) in one of three ways: one
   rule at a time ([step]); a whole dispatch in one call, observed, as
   [run --trace] takes it (D33: its labels, each rule's body events); a
   whole dispatch in one call, unobserved, as [run] takes it without a
   trace (D29: the dispatch's body events, in order, and the configuration
   it reaches). After each operation: the same labels, body events,
   configuration, properties (agent and instances, maps in their order).
   The engine on the models' bodies is held to the reference on every
   state of every model of spec/models the same way. And [run] and
   [run --reference] write the same trace and the same output on every
   vector, every example and generated programs. *)

open Syntax
open Test_support
open Support
module V = Interp.Value
module Mc = Semantics.Machine
module RM = Interp.Runtime.P.M
module CB = Engine.Private.Compiled_bodies

let contains s sub =
  let n = String.length s and m = String.length sub in
  let rec go i = i + m <= n && (String.sub s i m = sub || go (i + 1)) in
  go 0

(* Text replacement without Str. *)
module Str_free = struct
  let find s sub from =
    let n = String.length s and m = String.length sub in
    let rec go i = if i + m > n then None else if String.sub s i m = sub then Some i else go (i + 1) in
    go from
  let replace_first sub by s = match find s sub 0 with
    | Some i -> String.sub s 0 i ^ by ^ String.sub s (i + String.length sub) (String.length s - i - String.length sub)
    | None -> s
  let rec replace_all sub by s = match find s sub 0 with
    | Some _ -> let s' = replace_first sub by s in if s' = s then s else replace_all sub by s'
    | None -> s
end

let check_program ~file text =
  let env, diags = Typing.check [ Parse.string ~file text ] in
  if List.exists (fun d -> d.Diag.severity = Diag.Error) diags then
    QCheck.Test.fail_reportf "the program does not check:\n%s" text;
  env

(* The agent's properties and every active instance's, as text. *)
let props env (c : RM.t) =
  let a = c.world in
  let agent = List.map (fun (pr : Typing.Tenv.property) ->
      pr.p_name ^ "=" ^ (match Interp.Eval.property a pr.p_name with Some v -> V.to_literal v | None -> "?"))
      (Typing.Tenv.agent_properties env a.atype.a_name) in
  let behs = List.map (fun (i : Interp.Eval.beh Mc.instance) ->
      let l = ref [] in
      Strtbl.iter (fun x (cell : Interp.Eval.cell) -> l := (x ^ "=" ^ V.to_literal cell.v) :: !l) i.beh.bprops;
      Printf.sprintf "%d:%s{%s}" i.id (Interp.Eval.beh_type i.beh) (String.concat "," (List.sort compare !l)))
      c.active in
  String.concat ";" agent ^ " | " ^ String.concat ";" behs

(* Host operations: a notify (the percept in Jadescript, made afresh for
   each copy, and its priority), rules one at a time, dispatches observed,
   dispatches unobserved. *)
type op = Notify of string * int | Steps of int | Dispatches of int | Quiet of int

(* An engine and its compiled bodies, made for one agent (as
   Engine.for_agent makes it), or bodies of one's own. *)
module type ENGINE = sig
  module B : Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
                            and type obj = V.t and type beh = Interp.Eval.beh
                            and type world = Interp.Eval.agent
  module E : Engine.INTERP
  val compiled : Interp.Eval.agent -> id:int -> Interp.Eval.beh -> int
end

let engine () : (module ENGINE) =
  let module B = CB.Make () in
  (module struct
    module B = B
    module E = Engine.Make (B)
    let compiled = B.compiled_handlers
  end)

(* The configuration with its agent's events taken, as text. *)
let take (c : RM.t) =
  let (world, evs) = Interp.Eval.take_events c.world in
  ({ c with world }, List.map Show.event evs)

let compare_runs ?(engine = engine) ~env ~text ~fuel ~params ~agent_args ops =
  let module X = (val engine () : ENGINE) in
  let config = { Interp.Eval.default_config with fuel } in
  let args () = List.map (fun a -> Interp.Eval.literal_value env (Parse.expr ~file:"a" a)) agent_args in
  let agent () =
    let (a, behs) = Interp.Eval.create_agent ~config env ~name:"g" ~atype:"Ag" ~args:(args ()) in
    let (a, evs) = Interp.Eval.take_events a in
    (RM.init params ~world:a behs, List.map Show.event evs) in
  let (r0, er) = agent () and (k0, ek) = agent () in
  if er <> ek then QCheck.Test.fail_reportf "on create differs";
  let r = ref r0 and k = ref k0 in
  let history = Buffer.create 256 in
  let fail fmt = Printf.ksprintf (fun s ->
      QCheck.Test.fail_reportf "%s\nafter: %s\nfuel=%d variant=%s\n%s" s (Buffer.contents history) fuel
        (Mc.string_of_variant params.Mc.variant) text) fmt in
  let compare_now what er ek =
    Buffer.add_string history (what ^ " | ");
    if er <> ek then fail "events differ after %s:\nreference: %s\nengine:    %s" what (String.concat "|" er) (String.concat "|" ek);
    let sr = Show.config !r and sc = Show.config !k in
    if sr <> sc then fail "configurations differ after %s:\nreference: %s\nengine:    %s" what sr sc;
    let pr = props env !r and pc = props env !k in
    if pr <> pc then fail "properties differ after %s:\nreference: %s\nengine:    %s" what pr pc in
  (* one rule of the reference: its label and body events *)
  let ref_step () = match RM.step params !r with
    | [] -> None
    | (l, c) :: _ -> let (c, evs) = take c in r := c; Some (Show.label l, evs) in
  let show = function Some (l, _) -> l | None -> "none" in
  let events = function Some (_, e) -> e | None -> [] in
  let percept text = fst (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" text)) in
  List.iter (function
      | Notify (text, prio) ->
        r := RM.notify_with params !r (percept text) prio; k := RM.notify_with params !k (percept text) prio;
        compare_now ("notify " ^ text) [] []
      | Steps n ->
        for _ = 1 to n do
          let lr = ref_step () in
          let lk = match X.E.step params !k with
            | [] -> None
            | (l, c) :: _ -> let (c, evs) = take c in k := c; Some (Show.label l, evs) in
          if show lr <> show lk then fail "step: reference %s, engine %s" (show lr) (show lk);
          compare_now ("step " ^ show lr) (events lr) (events lk)
        done
      | Dispatches n ->
        (* observed (D33): each rule's label with its events *)
        for _ = 1 to n do
          let taken = ref [] in
          let observe l w = let (w, evs) = Interp.Eval.take_events w in
            taken := (Show.label l, List.map Show.event evs) :: !taken; w in
          match X.E.dispatch ~observe params !k with
          | None -> ()
          | Some c ->
            let (c, rest) = take c in
            if rest <> [] then fail "a dispatch left events its observer was not told of: %s" (String.concat "|" rest);
            k := c;
            let taken = List.rev !taken in
            List.iter (fun (l, evs) ->
                let lr = ref_step () in
                if show lr <> l then fail "dispatch: the engine reports %s, the reference takes %s" l (show lr);
                if events lr <> evs then
                  fail "events differ in dispatch rule %s:\nreference: %s\nengine:    %s" l
                    (String.concat "|" (events lr)) (String.concat "|" evs)) taken;
            compare_now ("dispatch " ^ String.concat " " (List.map fst taken)) [] []
        done
      | Quiet n ->
        (* unobserved (D29): the dispatch's events in order, and where it ends *)
        for _ = 1 to n do
          match X.E.dispatch params !k with
          | None -> ()
          | Some c ->
            let (c, ek) = take c in
            k := c;
            let rec follow acc =
              match ref_step () with
              | Some (l, evs) when contains l "EndDispatch" -> List.concat (List.rev (evs :: acc))
              | Some (_, evs) -> follow (evs :: acc)
              | None -> fail "the reference stops inside a dispatch the engine took whole" in
            compare_now "dispatch, unobserved" (follow []) ek
        done)
    ops;
  (* the rest, until idle *)
  let rec drain n =
    if n > 0 then
      match X.E.step params !k with
      | [] -> if ref_step () <> None then fail "the reference goes on after the engine stops"
      | (l, c) :: _ ->
        let (c, ek) = take c in
        k := c;
        let lr = ref_step () in
        if show lr <> Show.label l then fail "step: reference %s, engine %s" (show lr) (Show.label l);
        compare_now ("step " ^ Show.label l) (events lr) ek; drain (n - 1) in
  drain 2000;
  List.fold_left (fun (n, t) (i : Interp.Eval.beh Mc.instance) ->
      (n + X.compiled !k.world ~id:i.id i.beh, t + X.B.percept_handlers i.beh)) (0, 0) !k.active

let random_ops rand env =
  let percept () =
    let ps = Event_gen.percept_types env in
    let s = List.nth ps (Random.State.int rand (List.length ps)) in
    let args = List.map (fun (_, ty) -> Event_gen.small_literal rand ty) s.s_slots in
    let text = if args = [] then s.s_name else s.s_name ^ "(" ^ String.concat ", " args ^ ")" in
    (text, snd (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" text))) in
  List.init (5 + Random.State.int rand 30) (fun _ ->
      match Random.State.int rand 10 with
      | 0 | 1 | 2 | 3 ->
        let (text, prio) = percept () in
        Notify (text, if Random.State.int rand 4 = 0 then Random.State.int rand 9 else prio)
      | 4 | 5 -> Steps (1 + Random.State.int rand 20)
      | 6 | 7 -> Dispatches (1 + Random.State.int rand 3)
      | _ -> Quiet (1 + Random.State.int rand 3))

(* Fuel from tiny (the budget runs out in the middle of a body, at every
   statement in turn over the seeds) to generous. *)
let random_fuel rand = match Random.State.int rand 4 with
  | 0 -> 1 + Random.State.int rand 5
  | 1 -> 5 + Random.State.int rand 40
  | _ -> 500

let random_params seed rand =
  let variant = List.nth [ Mc.Reference; Mc.Budgeted; Mc.Printed; Mc.Reference ] (seed mod 4) in
  { Mc.default_params with variant; budget = 1 + Random.State.int rand 3; ghosts = seed mod 5 = 0 }

let args_for env rand =
  let params = match Typing.Tenv.agent_create env "Ag" with Some r -> r.r_params | None -> [] in
  List.map (fun (_, ty) -> Event_gen.small_literal rand ty) params

(* Does a percept handler of the program call one of the agent's
   functions or procedures (Typed_gen writes them)? *)
let calls_in_handlers env =
  let module A = Ast in
  let rec ex (e : A.expr) = match e.it with
    | Call (g, es) -> Typing.Tenv.agent_function env "Ag" g.it <> None || List.exists ex es
    | List es -> List.exists ex es
    | Map kvs -> List.exists (fun (k, v) -> ex k || ex v) kvs
    | Index (a, b) | Binop (_, a, b) -> ex a || ex b
    | Of (_, x) | Unop (_, x) | Matches (x, _) -> ex x
    | Invoke i -> ex i.target || List.exists ex i.args
    | Lit _ | Name _ | This | Agent | Content | Message -> false
  and st (s : A.stmt) = match s.it with
    | Do _ -> true
    | Assign (_, e) | Local (_, _, e) | Log e | Return (Some e) -> ex e
    | If (bs, els) -> List.exists (fun (c, b) -> ex c || List.exists st b) bs || (match els with Some b -> List.exists st b | None -> false)
    | While (c, b) | For (_, c, b) -> ex c || List.exists st b
    | _ -> false in
  List.exists (fun (b : Typing.Tenv.behaviour) ->
      List.exists (fun (h : Typing.Tenv.handler) -> h.h_kind = Typing.Tenv.On_percept && List.exists st h.h_body)
        (Typing.Tenv.behaviour_handlers env b.b_name)) (Typing.Tenv.behaviours env)


(* Random programs whose percept handlers call functions or procedures and
   all ran compiled: the random test must meet some (checked after it). *)
let compiled_calls = ref 0 and random_runs = ref 0

let on_random_programs ?engine (prog, seed) =
  let text = Print.program prog in
  let env = check_program ~file:"gen.jade" text in
  let rand = Random.State.make [| seed |] in
  let fuel = random_fuel rand and params = random_params seed rand in
  let agent_args = args_for env rand in
  let (compiled, total) = compare_runs ?engine ~env ~text ~fuel ~params ~agent_args (random_ops rand env) in
  incr random_runs;
  if compiled = total && total > 0 && calls_in_handlers env then incr compiled_calls;
  true

let constructs_text = lazy (read_file (Filename.concat root "test/fastpath/programs/constructs.jade"))

(* The fixed program, many seeds: every handler of it compiles (checked,
   so that this compares compiled code), and over the seeds every error it
   can meet is met (division by zero, a missing map key, an index out of
   bounds, the step budget, D8's 32-bit overflow). *)
let constructs_over_seeds () =
  let text = Lazy.force constructs_text in
  let env = check_program ~file:"constructs.jade" text in
  let errors = Hashtbl.create 8 in
  for seed = 0 to 299 do
    let rand = Random.State.make [| seed; 17 |] in
    let fuel = random_fuel rand and params = random_params seed rand in
    let ops = random_ops rand env in
    (match compare_runs ~env ~text ~fuel ~params ~agent_args:[] ops with
     | (n, t) -> if n <> t then Alcotest.failf "seed %d: %d of %d handlers compiled" seed n t
     | exception QCheck.Test.Test_fail (_, msgs) -> Alcotest.failf "seed %d: %s" seed (String.concat "\n" msgs));
    (* the errors the reference met on this seed *)
    let config = { Interp.Eval.default_config with fuel } in
    let (a, behs) = Interp.Eval.create_agent ~config env ~name:"g" ~atype:"Ag" ~args:[] in
    let c = ref (RM.init params ~world:a behs) in
    let percept t = fst (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" t)) in
    let rec go n = if n > 0 then match RM.step params !c with [] -> () | (_, c') :: _ -> c := c'; go (n - 1) in
    List.iter (function Notify (t, p) -> c := RM.notify_with params !c (percept t) p | Steps n | Dispatches n | Quiet n -> go (n * 8)) ops;
    go 2000;
    List.iter (function
        | Interp.Eval.Error (_, _, m) ->
          let key = List.find_opt (fun k -> contains m k)
              [ "division by zero"; "has no key"; "out of bounds"; "step budget" ] in
          Option.iter (fun k -> Hashtbl.replace errors k ()) key
        | _ -> ()) (snd (Interp.Eval.take_events !c.world))
  done;
  List.iter (fun k -> if not (Hashtbl.mem errors k) then Alcotest.failf "no seed met %S" k)
    [ "division by zero"; "has no key"; "out of bounds"; "step budget" ]

(* One handler [on percept when GUARD do BODY] of a behaviour [B] (with a
   property [seen]) of the agent of constructs.jade's ontology and
   properties, given one percept, on Eval.Bodies and on the compiled
   bodies: the same answer of the guard, events (logs, errors with region
   and message, Ran with effects), properties. [expect] is a piece of what
   the reference records, checked by hand: the case does what it says. *)
let unit_program ?(routines = []) ?(beh_routines = []) guard body =
  let text = Lazy.force constructs_text in
  (* the ontology and the agent, without their behaviours *)
  let cut = match Str_free.find text "cyclic behaviour" 0 with Some i -> i | None -> String.length text in
  let lines ls = String.concat "" (List.map (fun l -> "\t" ^ l ^ "\n") ls) in
  String.sub text 0 cut ^ lines routines
  ^ "cyclic behaviour B for agent Ag\n\tproperty seen as integer = 0\n\n\ton percept when " ^ guard ^ " do\n"
  ^ String.concat "" (List.map (fun l -> "\t\t" ^ l ^ "\n") body)
  ^ lines beh_routines

(* A handler's guard, then its body when it holds, on some bodies. *)
type 'g guard_and_body = {
  applicable : Interp.Eval.agent -> id:int -> Interp.Eval.beh -> int -> V.t -> Interp.Eval.agent * 'g option;
  run : Interp.Eval.agent -> id:int -> active:int -> Interp.Eval.beh -> int -> V.t -> 'g ->
    Interp.Eval.agent * Interp.Eval.beh Mc.effect list;
}

let reference_bodies = { applicable = Interp.Eval.Bodies.percept_applicable; run = Interp.Eval.Bodies.run_percept_handler }

let one_handler ?(fuel = 500) ?routines ?beh_routines ~guard ~body ~percept ~expect () =
  let text = unit_program ?routines ?beh_routines guard body in
  let text = Str_free.replace_first "activate behaviour Work\n\t\tactivate behaviour Other" "activate behaviour B" text in
  let env = check_program ~file:"unit.jade" text in
  let (p, _) = Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" percept) in
  let run (type g) (bodies : g guard_and_body) =
    let config = { Interp.Eval.default_config with fuel } in
    let (a, behs) = Interp.Eval.create_agent ~config env ~name:"g" ~atype:"Ag" ~args:[] in
    let (a, _) = Interp.Eval.take_events a in
    let b = List.hd behs in
    let (a, found) = bodies.applicable a ~id:1 b 1 p in
    let (a, effects) = match found with
      | Some bd -> let (a, e) = bodies.run a ~id:1 ~active:1 b 1 p bd in (a, List.length e)
      | None -> (a, -1) in
    let (a, evs) = Interp.Eval.take_events a in
    let c = RM.init Mc.default_params ~world:a [ b ] in
    (found <> None, effects, String.concat " | " (List.map Show.event evs), props env c, a, b) in
  let module B = CB.Make () in
  let (ok1, e1, ev1, p1, _, _) = run reference_bodies
  and (ok2, e2, ev2, p2, a2, b2) = run { applicable = B.percept_applicable; run = B.run_percept_handler } in
  if B.compiled_handlers a2 ~id:1 b2 <> 1 then Alcotest.fail "the handler did not compile";
  Alcotest.(check bool) "guard" ok1 ok2;
  Alcotest.(check int) "effects" e1 e2;
  Alcotest.(check string) "events" ev1 ev2;
  Alcotest.(check string) "properties" p1 p2;
  if not (contains (ev1 ^ " || " ^ p1) expect) then
    Alcotest.failf "the reference did not do what the case says (%S): %s || %s" expect ev1 p1

let tick = "content matches tick(k)"

let unit_cases = [
  ("pattern variable", tick, [ "log k" ], "tick(4)", "4");
  ("a local declared, shadowing a property", tick, [ "total as integer = 5"; "log total" ], "tick(4)", "total=0");
  ("a local by first assignment", tick, [ "x = k + 1"; "log x" ], "tick(4)", "5");
  ("a property updated", tick, [ "total = total + k"; "seen = seen + 1" ], "tick(4)", "total=4");
  ("a pattern variable shadowing a property", "content matches pair(seen, b)",
   [ "seen = seen + b"; "log seen" ], "pair(1, 2)", "seen=0");
  ("map insertions in order", tick, [ "counts[3] = 1"; "counts[1] = 2"; "counts[3] = k"; "log counts" ], "tick(4)",
   "counts={3: 4, 1: 2}");
  ("list index", tick, [ "items[1] = k"; "log items[1] + items[0]" ], "tick(4)", "5");
  ("index out of bounds", tick, [ "items[k] = 1" ], "tick(4)", "out of bounds");
  ("index out of bounds, read", tick, [ "log items[k]" ], "tick(4)", "out of bounds");
  ("a missing map key", tick, [ "log counts[k]" ], "tick(4)", "has no key");
  ("division by zero", tick, [ "log 10 / (k - 4)" ], "tick(4)", "division by zero");
  ("modulo by zero", tick, [ "log 10 % (k - 4)" ], "tick(4)", "division by zero");
  ("D8 32-bit integers", tick, [ "big = big + k * 1000"; "log big * 2" ], "tick(4)", "big=-2147480296");
  ("float and double properties", tick, [ "small = k"; "ratio = k / 3"; "s as double = k"; "log s / 3" ], "tick(4)", "small=");
  (* Eval applies equal_values to (expr f l) (expr f r): the right side is
     evaluated first, and its error is the one recorded *)
  ("= evaluates its right side first", tick, [ "log counts[k] = 10 / (k - 4)" ], "tick(4)", "division by zero");
  ("< evaluates its right side first", tick, [ "log counts[k] < items[k]" ], "tick(4)", "out of bounds");
  ("comparisons, and, or, not", tick, [ "log (k > 3 and not (k = 5)) or k < 0"; "log k >= 4 and k <= 4 and k != 3" ],
   "tick(4)", "true");
  ("text concatenation", tick, [ "log \"a\" + k + 1.5 + true" ], "tick(4)", "a41.5true");
  ("text comparison", "content matches word(t, m)", [ "log t < \"b\""; "log t = \"abc\"" ], "word(\"abc\", 2)", "true");
  ("if, else if, else", tick,
   [ "if k > 5 do"; "\tlog \"high\""; "else if k > 3 do"; "\tlog \"mid\""; "else do"; "\tlog \"low\"" ], "tick(4)", "mid");
  ("while, break and continue", tick,
   [ "i = 0"; "while true do"; "\ti = i + 1"; "\tif i % 2 = 0 do"; "\t\tcontinue"; "\tif i > k do"; "\t\tbreak"; "\tlog i" ],
   "tick(4)", "3");
  ("for over a list and a map", tick,
   [ "counts[7] = 1"; "counts[2] = 1"; "for x in items do"; "\tlog x"; "for y in counts do"; "\tlog y" ], "tick(4)", "7");
  ("return ends the body", tick, [ "log 1"; "return"; "log 2" ], "tick(4)", "1");
  ("the step budget mid-body", tick, [ "log 1"; "log 2"; "log 3"; "log 4" ], "tick(4)", "step budget");
  ("the step budget in a loop", tick, [ "while true do"; "\ttotal = total + 1" ], "tick(4)", "step budget");
  ("an error in the guard", "content matches tick(k) and 10 / (k - 4) > 0", [ "log k" ], "tick(4)", "division by zero");
  ("a guard that is false", "content matches tick(k) and k > 10", [ "log k" ], "tick(4)", "total=0");
  ("a guard on a subtype", "content matches ping", [ "log content" ], "hush", "hush");
  ("a guard on another type", "content matches ping", [ "log content" ], "tick(1)", "total=0");
  ("matches in a body binds", tick, [ "if content matches tick(j) do"; "\tlog j + k" ], "tick(4)", "8");
  ("matches a literal", "content matches tick(4)", [ "log content" ], "tick(4)", "tick(4)");
  ("of", tick, [ "counts[k] = 1"; "log size of counts"; "log length of \"abc\""; "log keys of counts"; "log priority of content" ],
   "tick(4)", "3");
  ("a slot of a schema value", tick, [ "p = tick(k)"; "n of p = 9"; "log p" ], "tick(4)", "tick(9)");
  ("a property of the agent", tick, [ "total of agent = 7"; "log total of agent" ], "tick(4)", "total=7");
  ("deactivate, twice", tick, [ "deactivate this"; "deactivate this"; "log 1" ], "tick(4)", "1");
  ("a schema without slots by name", tick, [ "log ping" ], "tick(4)", "ping");
  (* [this] is the instance's uid, which differs between the two agents *)
  ("content, this, agent", tick, [ "log content"; "log this = this"; "log agent" ], "tick(4)", "log agent g");
  ("list and map literals", tick, [ "log [k, 2] = [4, 2]"; "log {k: \"a\", 1: \"b\"}" ], "tick(4)", "true");
  ("negation", tick, [ "log -k"; "log -ratio" ], "tick(4)", "-4");
  ("a double slot", "content matches level(x)", [ "x = x * 2"; "ratio = x"; "log x" ], "level(1.5)", "ratio=3");
  ("a boolean property", tick, [ "flag = not flag"; "log flag" ], "tick(4)", "flag=true");
  (* a construction: the schema found at compile time, each slot converted
     to its type (R1c), the arguments in order *)
  ("a construction converts its slots", tick, [ "log level(k)"; "log pair(k, 10 / k)"; "log word(\"w\", k)" ], "tick(4)",
   "log level(4.0) | log pair(4, 2)");
]

let unit_tests =
  List.map (fun (name, guard, body, percept, expect) ->
      let fuel = if String.length name > 15 && String.sub name 0 15 = "the step budget" then 3 else 500 in
      Alcotest.test_case name `Quick (one_handler ~fuel ~guard ~body ~percept ~expect))
    unit_cases

(* Calls of the agent's and the behaviour's own functions and procedures,
   compiled (D38): each against Eval.Bodies, the reference's answer
   checked by hand. [routines] are the agent's, [beh] B's. *)
let call_cases = [
  ("a procedure's locals are its own", [ "procedure p with total as integer do"; "\tx = total + 1"; "\tlog x" ], [],
   tick, [ "x = 7"; "do p with total = k"; "log x" ], "tick(4)", "log 5 | log 7");
  ("a callee sees properties, not the caller's locals", [ "procedure p do"; "\tlog total" ], [],
   tick, [ "total as integer = 5"; "do p"; "log total" ], "tick(4)", "log 0 | log 5");
  ("a function's value, positional arguments", [ "function f(a as integer, b as integer) as integer do"; "\treturn a * 10 + b" ], [],
   tick, [ "log f(k, 2) + f(1, k)" ], "tick(4)", "log 56");
  ("named arguments, converted to the parameter's type",
   [ "procedure p with a as double, b as text do"; "\tlog a / 8"; "\tlog b" ], [],
   tick, [ "do p with b = \"x\", a = k" ], "tick(4)", "log 0.5 | log x");
  ("recursion", [ "function fact(n as integer) as integer do"; "\tif n <= 1 do"; "\t\treturn 1"; "\treturn n * fact(n - 1)" ], [],
   tick, [ "log fact(k + 1)" ], "tick(4)", "log 120");
  ("recursion too deep", [ "function f(n as integer) as integer do"; "\treturn f(n + 1) + 1" ], [],
   tick, [ "log 1"; "log f(k)"; "log 2" ], "tick(4)", "recursion too deep");
  ("an error in a callee, at the callee's place", [ "function f(n as integer) as integer do"; "\tx = n - 4"; "\treturn 10 / x" ], [],
   tick, [ "log f(k)"; "log 2" ], "tick(4)", "division by zero");
  ("the step budget runs out in a callee", [ "procedure p do"; "\tlog 1"; "\tlog 2"; "\tlog 3" ], [],
   tick, [ "do p"; "log 4" ], "tick(4)", "step budget");
  ("a procedure returns early; a function's return in a branch",
   [ "procedure p with n as integer do"; "\tif n > 2 do"; "\t\treturn"; "\tlog n";
     "function g(n as integer) as integer do"; "\ttotal = n"; "\tif n > 2 do"; "\t\treturn 7"; "\treturn 8" ], [],
   tick, [ "do p with n = k"; "do p with n = 1"; "log g(k)"; "log g(1) + total" ], "tick(4)", "log 1 | log 7 | log 9");
  ("a procedure invokes the host, sends, activates", [ "procedure p with n as integer do"; "\tsend inform tick(n) to aid(\"r\")";
                                                     "\tactivate behaviour B"; "\tlog n" ], [],
   tick, [ "do p with n = k" ], "tick(4)", "send inform tick(4) to r | activate B | log 4");
  ("a behaviour's procedure sees its properties and this", [],
   [ "procedure q with n as integer do"; "\tseen = seen + n"; "\tlog this = this"; "\tdeactivate this" ],
   tick, [ "do q with n = k"; "log seen" ], "tick(4)", "seen=4");
  ("an agent's procedure: this is the agent", [ "procedure p do"; "\tlog this"; "\ttotal = 3" ], [],
   tick, [ "do p"; "log total" ], "tick(4)", "log agent g");
  ("a call inside a loop, break after it", [ "function f(n as integer) as integer do"; "\treturn n + 1" ], [],
   tick, [ "i = 0"; "while true do"; "\ti = f(i)"; "\tif i > k do"; "\t\tbreak"; "log i" ], "tick(4)", "log 5");
]

let call_tests =
  List.map (fun (name, routines, beh_routines, guard, body, percept, expect) ->
      let fuel = if name = "the step budget runs out in a callee" then 4 else 500 in
      Alcotest.test_case name `Quick (one_handler ~fuel ~routines ~beh_routines ~guard ~body ~percept ~expect))
    call_cases

(* A handler the compiler does not take falls back, whole, and still
   agrees: a call in its guard (the entry points do not give a guard a
   fresh step budget, which a call's tick would need). *)
let fallback_case () =
  let text = unit_program ~routines:[ "function f(n as integer) as boolean do"; "\treturn n > 0" ]
      "content matches tick(k) and f(k)" [ "log k" ] in
  let text = Str_free.replace_first "activate behaviour Work\n\t\tactivate behaviour Other" "activate behaviour B" text in
  let env = check_program ~file:"unit.jade" text in
  let (a, behs) = Interp.Eval.create_agent env ~name:"g" ~atype:"Ag" ~args:[] in
  let module B = CB.Make () in
  Alcotest.(check int) "not compiled" 0 (B.compiled_handlers a ~id:1 (List.hd behs))

(* A handler inherited by a behaviour subtype is the very handler of its
   super type; where the subtype declares a property of a name the handler
   uses as a local, it means the property there. *)
let inherited_handler () =
  let text = String.concat "\n" [
      "ontology W";
      "\tpredicate tick(n as integer) extends percept with priority = 3";
      "agent Ag uses ontology W";
      "\tproperty total as integer = 0";
      "\ton create do";
      "\t\tactivate behaviour Parent";
      "\t\tactivate behaviour Child";
      "cyclic behaviour Parent for agent Ag";
      "\ton percept when content matches tick(k) do";
      "\t\tx = k";
      "\t\ttotal = total + x";
      "cyclic behaviour Child extends Parent for agent Ag";
      "\tproperty x as integer = 0";
      "" ] in
  let env = check_program ~file:"inherit.jade" text in
  let tick n = Printf.sprintf "tick(%d)" n in
  match compare_runs ~env ~text ~fuel:500 ~params:Mc.default_params ~agent_args:[]
          [ Notify (tick 3, 3); Dispatches 2; Notify (tick 5, 3); Steps 20 ] with
  | (n, t) -> Alcotest.(check int) "both instances' handlers compiled" t n
  | exception QCheck.Test.Test_fail (_, msgs) -> Alcotest.fail (String.concat "\n" msgs)

(* An agent's procedure names the agent's property even where the calling
   behaviour declares one of the same name (Eval runs it without the
   behaviour); an error in a callee ends the handler, and the next run of
   it finds its own slots. *)
let agent_routine_shadowed () =
  let text = String.concat "\n" [
      "ontology W";
      "\tpredicate tick(n as integer) extends percept with priority = 3";
      "agent Ag uses ontology W";
      "\tproperty x as integer = 1";
      "\ton create do";
      "\t\tactivate behaviour B";
      "\tprocedure bump with n as integer do";
      "\t\tx = x + 100 / (n - 2)";
      "\t\tlog x";
      "cyclic behaviour B for agent Ag";
      "\tproperty x as integer = 50";
      "\ton percept when content matches tick(k) do";
      "\t\ty = k";
      "\t\tdo bump with n = k";
      "\t\tx = x + y";
      "\t\tlog x";
      "" ] in
  let env = check_program ~file:"shadow.jade" text in
  let tick n = Printf.sprintf "tick(%d)" n in
  match compare_runs ~env ~text ~fuel:500 ~params:Mc.default_params ~agent_args:[]
          ([ Notify (tick 3, 3); Dispatches 1; Notify (tick 2, 3); Dispatches 1; Notify (tick 4, 3); Steps 20 ]
           (* more errors in the callee than calls may nest: the depth comes
              back after each *)
           @ List.concat (List.init 205 (fun _ -> [ Notify (tick 2, 3); Dispatches 1 ]))
           @ [ Notify (tick 5, 3); Steps 20 ]) with
  | (n, t) -> Alcotest.(check int) "compiled" t n
  | exception QCheck.Test.Test_fail (_, msgs) -> Alcotest.fail (String.concat "\n" msgs)

(* The paper's program (examples/robome/robome.jade, which the simulation
   runs): its four percept handlers compile, the two that call the agent's
   procedures (each an invoke on the host) included; an obstacle percept
   runs them as Eval.Bodies does, invoke by invoke. *)
let robome_compiles () =
  let text = read_file (Filename.concat root "examples/robome/robome.jade") in
  let env = check_program ~file:"robome.jade" text in
  let calls = ref [] in
  let host = V.Native { nid = 1; cls = "RoboMe"; methods = List.map (fun m -> (m, fun _ -> calls := m :: !calls; V.Unit))
      [ "startListening"; "callStop"; "callMoveForward"; "callTurnLeft"; "callTurnRight"; "callMoveBackward";
        "callHeadTiltUp"; "callHeadTiltDown"; "callHeadReset" ] } in
  let run (type g) (bodies : g guard_and_body) percept =
    let config = { Interp.Eval.default_config with fuel = 100 } in
    let (a, behs) = Interp.Eval.create_agent ~config env ~name:"robome" ~atype:"RoboMe" ~args:[ host ] in
    let (a, _) = Interp.Eval.take_events a in
    calls := [];   (* on create's *)
    let b = List.hd behs in
    let (p, _) = Interp.Eval.percept_value env ~agent_type:"RoboMe" (Parse.expr ~file:"e" percept) in
    let out = List.map (fun h ->
        let (a, found) = bodies.applicable a ~id:1 b h p in
        let a = match found with Some bd -> fst (bodies.run a ~id:1 ~active:1 b h p bd) | None -> a in
        String.concat " | " (List.map Show.event (snd (Interp.Eval.take_events a)))) [ 1; 2; 3; 4 ] in
    (a, b, out, List.rev !calls) in
  let module B = CB.Make () in
  let compiled = { applicable = B.percept_applicable; run = B.run_percept_handler } in
  List.iter (fun percept ->
      let (_, _, ev1, calls1) = run reference_bodies percept
      and (a, b, ev2, calls2) = run compiled percept in
      Alcotest.(check int) "every handler compiled" 4 (B.compiled_handlers a ~id:1 b);
      Alcotest.(check (list string)) ("events of " ^ percept) ev1 ev2;
      Alcotest.(check (list string)) ("host calls of " ^ percept) calls1 calls2)
    [ "obstacle"; "falling"; "qrCodeRead(\"A-east\")"; "position(1.5, 2)" ];
  let (_, _, _, calls) = run compiled "obstacle" in
  Alcotest.(check (list string)) "obstacle: stop, turn left, forward" [ "callStop"; "callTurnLeft"; "callMoveForward" ] calls

(* ------------------------------------------------------------ teeth *)

(* The comparison has teeth: engines on bodies with a planted bug fail it
   on some of the same random programs. A wrong pre-test (it says no to the
   first handler of every behaviour, whether or not it applies) shows in
   every dispatch; a wrong kind (every percept of the same kind, so that
   the plan made for one type of percept serves the others: a handler
   skipped or tried out of its place) shows only where nothing observes
   the dispatch, as in [run] without a trace (D29). *)
let planted (wrong : (module Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
                      and type obj = V.t and type beh = Interp.Eval.beh and type world = Interp.Eval.agent)
                     -> (module Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
                         and type obj = V.t and type beh = Interp.Eval.beh and type world = Interp.Eval.agent)) () :
  (module ENGINE) =
  let module B0 = CB.Make () in
  let module B = (val wrong (module B0)) in
  (module struct
    module B = B
    module E = Engine.Make (B)
    let compiled = B0.compiled_handlers
  end)

let wrong_pretest (module B0 : Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
                   and type obj = V.t and type beh = Interp.Eval.beh and type world = Interp.Eval.agent) =
  (module struct
    include B0
    let percept_may_apply a b h p = h <> 1 && B0.percept_may_apply a b h p
  end : Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
   and type obj = V.t and type beh = Interp.Eval.beh and type world = Interp.Eval.agent)

let wrong_kind (module B0 : Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
                and type obj = V.t and type beh = Interp.Eval.beh and type world = Interp.Eval.agent) =
  (module struct
    include B0
    let percept_kind p = if B0.percept_kind p >= 0 then 0 else -1
  end : Engine.BODIES with type percept = V.t and type message = Interp.Eval.message
   and type obj = V.t and type beh = Interp.Eval.beh and type world = Interp.Eval.agent)

let caught ~what engine ~only_quiet =
  let gen = QCheck.pair Typed_gen.arb_program QCheck.small_nat in
  let rand = Random.State.make [| seed |] in
  let hits = ref 0 and tried = ref 0 in
  while !hits = 0 && !tried < 300 do
    incr tried;
    let (prog, s) = QCheck.Gen.generate1 ~rand (QCheck.get_gen gen) in
    match on_random_programs ~engine (prog, s) with
    | _ -> ()
    | exception e ->
      (* the failure the comparison reports (QCheck's, of any name) *)
      let m = Printexc.to_string e in
      if not only_quiet || contains m "unobserved" then incr hits
  done;
  Alcotest.(check bool) (Printf.sprintf "%s is caught (%d programs tried)" what !tried) true (!hits > 0)

(* ------------------------------------------------- the spec's models *)

(* The engine on the models' bodies, with the pre-test the acceptance
   tables give. *)
module Model = Explore.Model
module Explorer = Explore.Explorer
module Fast_model_bodies = struct
  include Model.Bodies
  let percept_may_apply () (b : Model.beh) h p = List.mem p b.percept_handlers.(h - 1).accepts
  let percept_kind p = if p >= 0 && p < 4096 then p else -1
  let percept_handle w ~id ~active b h p = Engine.handle_in_two percept_applicable run_percept_handler w ~id ~active b h p
end

module FE = Engine.Make (Fast_model_bodies)

let model_paths = lazy (Explore.Conformance.models ())

(* On every reachable configuration of every model: the same rules with
   the same labels reach the same configurations; and wherever the derived
   rule Dispatch applies, the labels it reports and the configuration it
   returns are those of the reference's rules taken one at a time up to
   EndDispatch. The comparison has teeth: against the rules of the mutant
   that changes Handle, the dispatches differ. *)
let models_step_and_dispatch () =
  let checked = ref 0 and dispatches = ref 0 and differ = ref 0 in
  let models = List.map Model.load (Lazy.force model_paths) in
  let steps_to_end rules (m : Model.t) c =
    let rec go c acc =
      match Model.M.step_by rules m.params c with
      | [ ((Mc.End_dispatch _ as l), c1) ] -> (List.rev (l :: acc), c1)
      | [ (l, c1) ] -> go c1 (l :: acc)
      | r -> Alcotest.failf "%s: %d rules enabled in a dispatch from %s" m.name (List.length r) (Explorer.show m c) in
    go c [] in
  let dispatch_agrees rules (m : Model.t) c =
    let seen = ref [] in
    match FE.dispatch ~observe:(fun l w -> seen := l :: !seen; w) m.params c with
    | None -> None
    | Some c' ->
      let (labels, c1) = steps_to_end rules m c in
      Some (List.rev !seen = labels && Explorer.show m c' = Explorer.show m c1 && Explorer.key c' = Explorer.key c1) in
  List.iter (fun (m : Model.t) ->
      let g = Explorer.explore m in
      Array.iter (fun (c : Model.M.t) ->
          incr checked;
          let show r = String.concat " | " (List.map (fun (l, c') ->
              Mc.action_name l ^ " -> " ^ Explorer.show m c' ^ " " ^ Explorer.key c') r) in
          let fast = show (FE.step m.params c) and reference = show (Model.M.step m.params c) in
          if fast <> reference then
            Alcotest.failf "%s: from %s\nthe engine takes %s\nthe reference takes %s" m.name
              (Explorer.show m c) fast reference;
          (match dispatch_agrees Model.M.rules m c with
           | Some true -> incr dispatches
           | Some false -> Alcotest.failf "%s: the derived rule is not its steps from %s" m.name (Explorer.show m c)
           | None -> ());
          (match dispatch_agrees (Explore.Mutant.rules Explore.Mutant.First_handler_only) m c with
           | Some false -> incr differ
           | _ -> ())) g.states) models;
  Alcotest.(check bool) "the mutant of Handle differs" true (!differ > 0);
  Alcotest.(check bool) (Printf.sprintf "checked %d configurations, %d dispatches" !checked !dispatches)
    true (!checked > 10_000 && !dispatches > 1000)

(* ------------------------------------- run and run --reference *)

(* [run] and [run --reference]: the same trace and the same output. A
   difference is reported both ways: the first line where they part, and
   each side's line. *)
let same_run ~what ~dir args =
  let out = Filename.temp_file "jsref-engine" ".txt" in
  let trace m = Filename.concat (Filename.get_temp_dir_name ()) (Printf.sprintf "jsref-engine-%d-%s.jsonl" (Unix.getpid ()) m) in
  let go mode =
    let t = trace (if mode = "" then "fast" else "ref") in
    let (status, stdout, stderr) = run_command (Printf.sprintf "cd %s && %s run %s --trace %s %s"
                                                  (Filename.quote dir) exe args t mode) in
    let lines = if Sys.file_exists t then String.split_on_char '\n' (read_file t) else [] in
    (try Sys.remove t with Sys_error _ -> ());
    (status, stdout, stderr, lines) in
  let (s1, o1, e1, t1) = go "" and (s2, o2, e2, t2) = go "--reference" in
  (try Sys.remove out with Sys_error _ -> ());
  if s1 <> s2 then Alcotest.failf "%s: exit %d, with --reference %d" what s1 s2;
  if o1 <> o2 then Alcotest.failf "%s: the output differs:\n%s\nwith --reference:\n%s" what o1 o2;
  if e1 <> e2 then Alcotest.failf "%s: the errors differ:\n%s\nwith --reference:\n%s" what e1 e2;
  let rec first i a b = match a, b with
    | x :: a', y :: b' -> if x = y then first (i + 1) a' b' else Some (i, x, y)
    | x :: _, [] -> Some (i, x, "(nothing)")
    | [], y :: _ -> Some (i, "(nothing)", y)
    | [], [] -> None in
  match first 1 t1 t2 with
  | None -> List.length t1
  | Some (i, x, y) -> Alcotest.failf "%s: the traces part at line %d:\nrun:               %s\nrun --reference:   %s" what i x y

let vectors_same () =
  let dir = Filename.concat root "conformance" in
  let names = Sys.readdir dir |> Array.to_list |> List.filter (fun n -> n <> "" && n.[0] >= '0' && n.[0] <= '9')
              |> List.sort compare in
  List.iter (fun n ->
      let d = Filename.concat dir n in
      let v = Yojson.Safe.from_file (Filename.concat d "vector.json") in
      let args = match v with
        | `Assoc kvs -> (match List.assoc_opt "args" kvs with
            | Some (`List l) -> List.map (function `String s -> Filename.quote s | _ -> "") l
            | _ -> [])
        | _ -> [] in
      let files = Sys.readdir d |> Array.to_list |> List.filter (fun f -> Filename.check_suffix f ".jade") |> List.sort compare in
      let events = if Sys.file_exists (Filename.concat d "events.jsonl") then "--events events.jsonl" else "" in
      ignore (same_run ~what:n ~dir:d (String.concat " " (files @ args @ [ events ])))) names;
  Alcotest.(check bool) "every vector" true (List.length names >= 84)

(* Every example program with an agent type of its own, each agent type
   created once, on a few percepts of every type it can perceive. *)
let examples_same () =
  let ran = ref 0 in
  let rec files d = Sys.readdir d |> Array.to_list |> List.sort compare |> List.concat_map (fun f ->
      let p = Filename.concat d f in
      if Sys.is_directory p then files p else if Filename.check_suffix f ".jade" then [ p ] else []) in
  let groups = [ [ "examples/robome/robome.jade" ];
                 [ "examples/paper/fig5_robome_ontology.jade"; "examples/paper/fig6_robome_agent.jade";
                   "examples/paper/fig7_handle_percepts.jade" ] ]
               @ List.filter_map (fun f ->
                   let r = String.length root + 1 in
                   let rel = String.sub f r (String.length f - r) in
                   if contains rel "examples/paper/fig" then None else Some [ rel ]) (files (Filename.concat root "examples")) in
  let groups = List.sort_uniq compare groups in
  List.iter (fun group ->
      let texts = List.map (fun f -> Parse.string ~file:f (read_file (Filename.concat root f))) group in
      match Typing.check texts with
      | (env, diags) when not (List.exists (fun d -> d.Diag.severity = Diag.Error) diags) ->
        List.iter (fun (a : Typing.Tenv.agent) ->
            let params = match Typing.Tenv.agent_create env a.a_name with Some r -> r.r_params | None -> [] in
            let rand = Random.State.make [| 7 |] in
            let args = List.map (fun (_, ty) ->
                match Typing.Types.repr ty with Typing.Types.Any -> "@robome" | _ -> Event_gen.small_literal rand ty) params in
            let spec = "x:" ^ a.a_name ^ (if args = [] then "" else ":" ^ String.concat "," args) in
            let percepts = List.filter (fun (s : Typing.Tenv.schema) ->
                Typing.Tenv.visible_schema env a.a_visible s.s_name) (Event_gen.percept_types env) in
            let lines = List.concat_map (fun (s : Typing.Tenv.schema) ->
                List.init 3 (fun _ ->
                    let args = List.map (fun (_, ty) -> Event_gen.small_literal rand ty) s.s_slots in
                    let p = if args = [] then s.s_name else s.s_name ^ "(" ^ String.concat ", " args ^ ")" in
                    Yojson.Safe.to_string (`Assoc [ ("agent", `String "x"); ("notify", `String p) ]))) percepts in
            with_file "events.jsonl" (String.concat "\n" (lines @ [ "{\"run\": \"idle\"}" ]) ^ "\n") (fun ev ->
                incr ran;
                ignore (same_run ~what:(String.concat "+" group ^ " " ^ a.a_name) ~dir:root
                          (String.concat " " (List.map Filename.quote group)
                           ^ " --agent " ^ Filename.quote spec ^ " --events " ^ Filename.quote ev ^ " --max-steps 5000"))))
          (Typing.Tenv.agents env)
      | _ -> ()) groups;
  Alcotest.(check bool) (Printf.sprintf "%d example runs" !ran) true (!ran >= 3)

(* Generated programs and hosts (Typed_gen, Event_gen), as the fuzz
   campaign makes them. *)
let generated_same =
  qcheck ~count:25 ~long_factor:8 "run = run --reference, generated programs and hosts"
    (QCheck.pair Typed_gen.arb_program QCheck.small_nat) (fun (prog, s) ->
        let text = Print.program prog in
        let env = check_program ~file:"gen.jade" text in
        let sc = QCheck.Gen.generate1 ~rand:(Random.State.make [| s |]) (Event_gen.scenario env ~agent_type:"Ag") in
        with_file "gen.jade" text (fun p ->
            with_file "events.jsonl" (Event_gen.events_file sc) (fun ev ->
                let agents = String.concat " " (List.map (fun a -> "--agent " ^ Filename.quote a) (Event_gen.agent_args sc)) in
                let opts = String.concat " " (List.map Filename.quote (Event_gen.run_args sc)) in
                ignore (same_run ~what:"a generated program" ~dir:(Filename.get_temp_dir_name ())
                          (Printf.sprintf "%s %s --events %s %s" (Filename.quote p) agents (Filename.quote ev) opts));
                true)))

let () =
  Alcotest.run "engine" [
    ("runs", [
        qcheck ~count:300 ~long_factor:10 "engine = reference: steps, dispatches observed and not, random programs"
          (QCheck.pair Typed_gen.arb_program QCheck.small_nat) (fun x -> on_random_programs x);
        Alcotest.test_case "the random programs ran calls compiled" `Quick (fun () ->
            Printf.printf "%d of %d random programs ran handlers with calls, all compiled\n" !compiled_calls !random_runs;
            if !compiled_calls * 10 < !random_runs then
              Alcotest.failf "only %d of %d random programs ran handlers with calls, all compiled"
                !compiled_calls !random_runs);
        Alcotest.test_case "every construct and error, 300 seeds, fuel tiny to generous" `Quick constructs_over_seeds;
        Alcotest.test_case "the bench's workload, 50 seeds" `Quick (fun () ->
            let text = Support.bench_workload () in
            let text = Str_free.replace_first "agent Loader" "agent Ag" text in
            let text = Str_free.replace_all "for agent Loader" "for agent Ag" text in
            let env = check_program ~file:"bench.jade" text in
            for seed = 0 to 49 do
              let rand = Random.State.make [| seed; 6 |] in
              let fuel = random_fuel rand and params = random_params seed rand in
              match compare_runs ~env ~text ~fuel ~params ~agent_args:[] (random_ops rand env) with
              | (n, t) -> if n <> t then Alcotest.failf "%d of %d handlers compiled" n t
              | exception QCheck.Test.Test_fail (_, msgs) -> Alcotest.failf "seed %d: %s" seed (String.concat "\n" msgs)
            done);
        Alcotest.test_case "the spec's models: every state, every dispatch" `Quick models_step_and_dispatch ]);
    ("teeth", [
        Alcotest.test_case "a wrong pre-test is caught" `Quick (fun () ->
            caught ~what:"a wrong pre-test" (planted wrong_pretest) ~only_quiet:false);
        Alcotest.test_case "a wrong plan, seen only by run without a trace (D29), is caught" `Quick (fun () ->
            caught ~what:"a wrong kind of percept" (planted wrong_kind) ~only_quiet:true) ]);
    ("handlers", unit_tests @ call_tests @ [
        Alcotest.test_case "a call in a guard falls back" `Quick fallback_case;
        Alcotest.test_case "an inherited handler, a property of the subtype" `Quick inherited_handler;
        Alcotest.test_case "an agent's procedure, a behaviour's property of its name" `Quick agent_routine_shadowed;
        Alcotest.test_case "robome.jade: every handler compiles, and runs as Eval" `Quick robome_compiles ]);
    ("run --reference", [
        Alcotest.test_case "every vector: the same trace and output" `Slow vectors_same;
        Alcotest.test_case "every example: the same trace and output" `Slow examples_same;
        generated_same ]);
  ]
