(* window.jsref: the engine for playground/ui.js. Structured values cross as
   JSON text. *)

open Js_of_ocaml
open Playground_core
module Mc = Semantics.Machine

(* The sessions, one per slot: the page keeps one for each of its tabs
   (the playground, the replays, the exercises, the two columns of side by
   side); [use] picks the slot the other functions act on. *)
let sessions : (string, Session.t) Hashtbl.t = Hashtbl.create 8
let slot = ref "play"
let set_session = function
  | Some t -> Hashtbl.replace sessions !slot t
  | None -> Hashtbl.remove sessions !slot

let json j = Js.string (Yojson.Safe.to_string j)
let err m = `Assoc [ "ok", `Bool false; "error", `String m ]

let protect f =
  try f () with
  | Stack_overflow -> json (err "error: the evaluation went too deep (stack overflow)")
  | e -> json (err ("internal error: " ^ Printexc.to_string e))

let of_js s = Js.to_string s

let member k = function `Assoc f -> List.assoc_opt k f | _ -> None
let str_member k j = match member k j with Some (`String s) -> s | _ -> ""
let int_member k j = match member k j with Some (`Int n) -> Some n | _ -> None

let files_of j = match member "files" j with
  | Some (`List l) -> List.map (fun f -> (str_member "name" f, str_member "text" f)) l
  | _ -> []

let setup_of j : Session.setup =
  { files = files_of j;
    agents = (match member "agents" j with
        | Some (`List l) -> List.filter_map (function `String s -> Some s | _ -> None) l
        | _ -> []);
    variant = Option.value (Mc.variant_of_string (str_member "variant" j)) ~default:Mc.Reference;
    tie = (if str_member "tie" j = "unstable" then Mc.Unstable else Mc.Stable);
    budget = Option.value (int_member "budget" j) ~default:1;
    o2a_capacity = int_member "o2a_capacity" j;
    seed = int_member "seed" j;
    fuel = Option.value (int_member "fuel" j) ~default:100_000;
    max_steps = Option.value (int_member "max_steps" j) ~default:1_000_000;
    interleave = int_member "interleave" j;
  }

let with_session f = match Hashtbl.find_opt sessions !slot with
  | None -> json (err "no program is loaded")
  | Some t -> f t

let outcome = function
  | Session.Stepped -> "stepped" | Session.All_idle -> "idle" | Session.Limit -> "limit"

let state t extra =
  json (`Assoc ([ "ok", `Bool true; "view", Session.view t ] @ extra))

(* Where the judge reads its trace: a file of js_of_ocaml's file system,
   which lives in the page's memory (the working directory is /static/). *)
let judge_path = "/static/judge-trace.jsonl"

let fn1 f = Js.Unsafe.inject (Js.wrap_callback (fun a -> protect (fun () -> f a)))
let fn0 f = Js.Unsafe.inject (Js.wrap_callback (fun () -> protect f))

let () =
  Js.Unsafe.set Js.Unsafe.global "jsref" (Js.Unsafe.obj [|
      "examples", fn0 (fun () -> json (`List (List.map Examples.to_json Examples.all)));
      "replays", fn0 (fun () -> json (Replays.to_json ()));
      "check", fn1 (fun s ->
          let j = Yojson.Safe.from_string (of_js s) in
          json (`List (List.map (fun l -> `String l) (Session.check (files_of j)))));
      "create", fn1 (fun s ->
          let j = Yojson.Safe.from_string (of_js s) in
          match Session.create (setup_of j) with
          | Ok t -> set_session (Some t); state t []
          | Error e -> set_session None;
            json (`Assoc [ "ok", `Bool false; "errors", `List (List.map (fun l -> `String l) e) ]));
      "host", fn1 (fun s ->
          with_session (fun t ->
              let j = Yojson.Safe.from_string (of_js s) in
              let agent = str_member "agent" j in
              let h = match str_member "kind" j with
                | "put" -> Session.Put { agent; obj = str_member "text" j }
                | "message" -> Session.Message { agent; perf = str_member "performative" j; content = str_member "text" j;
                                               during = str_member "during" j = "step" }
                | _ -> Session.Notify { agent; percept = str_member "text" j; priority = int_member "priority" j } in
              match Session.host t h with
              | Ok () -> state t []
              | Error m -> state t [ "error", `String m ]));
      "step", fn1 (fun c ->
          with_session (fun t ->
              let choice = int_of_float (Js.float_of_number (Js.Unsafe.coerce c)) in
              let o = Session.step ~choice t in
              state t [ "outcome", `String (outcome o) ]));
      "iteration", fn0 (fun () ->
          with_session (fun t -> state t [ "outcome", `String (outcome (Session.iteration t)) ]));
      "runIdle", fn1 (fun n ->
          with_session (fun t ->
              let limit = int_of_float (Js.float_of_number (Js.Unsafe.coerce n)) in
              let (k, o) = Session.run_idle ~limit t in
              state t [ "outcome", `String (outcome o); "taken", `Int k ]));
      "rounds", fn1 (fun n ->
          with_session (fun t ->
              Session.run_rounds t (int_of_float (Js.float_of_number (Js.Unsafe.coerce n)));
              state t []));
      "rules", fn1 (fun n ->
          with_session (fun t ->
              Session.run_rules t (int_of_float (Js.float_of_number (Js.Unsafe.coerce n)));
              state t []));
      "back", fn0 (fun () ->
          with_session (fun t -> let b = Session.back t in state t [ "undone", `Bool b ]));
      "view", fn0 (fun () -> with_session (fun t -> state t []));
      "trace", fn1 (fun k ->
          with_session (fun t ->
              let from = int_of_float (Js.float_of_number (Js.Unsafe.coerce k)) in
              let lines = Session.trace t in
              json (`Assoc [ "total", `Int (List.length lines);
                             "lines", `List (List.filteri (fun i _ -> i >= from) lines |> List.map (fun l -> `String l)) ])));
      "replayStep", Js.Unsafe.inject (Js.wrap_callback (fun id k -> protect (fun () ->
          with_session (fun t ->
              match Replays.find (of_js id) with
              | None -> json (err "no such replay")
              | Some r ->
                let k = int_of_float (Js.float_of_number (Js.Unsafe.coerce k)) in
                match List.nth_opt r.steps k with
                | None -> json (err "no such step")
                | Some st ->
                  match Replays.apply t st with
                  | Ok () -> state t []
                  | Error m -> state t [ "error", `String m ]))));
      "replayCheck", fn1 (fun id ->
          with_session (fun t ->
              match Replays.find (of_js id) with
              | None -> json (err "no such replay")
              | Some r ->
                match Replays.check r t with
                | Ok () -> json (`Assoc [ "ok", `Bool true ])
                | Error m -> json (err m)));
      "use", fn1 (fun s ->
          slot := of_js s;
          json (`Assoc [ "ok", `Bool true; "loaded", `Bool (Hashtbl.mem sessions !slot) ]));
      "export", fn0 (fun () -> with_session (fun t -> json (Session.export t)));
      "restore", Js.Unsafe.inject (Js.wrap_callback (fun s h -> protect (fun () ->
          let j = Yojson.Safe.from_string (of_js s) in
          match Session.restore (setup_of j) (Yojson.Safe.from_string (of_js h)) with
          | Ok t -> set_session (Some t); state t []
          | Error e -> set_session None;
            json (`Assoc [ "ok", `Bool false; "errors", `List (List.map (fun l -> `String l) e) ]))));
      "glossary", fn0 (fun () -> json (Glossary.to_json ()));
      "exercises", fn0 (fun () -> json (Exercises.to_json ()));
      "exerciseCheck", Js.Unsafe.inject (Js.wrap_callback (fun id s -> protect (fun () ->
          match Exercises.find (of_js id) with
          | None -> json (err "no such exercise")
          | Some x ->
            let j = Yojson.Safe.from_string (of_js s) in
            match Exercises.attempt x (setup_of j) with
            | Ok (t, v) ->
              set_session (Some t);
              state t [ "verdict", `Assoc [ "solved", `Bool v.solved; "says", `String v.says ] ]
            | Error e -> set_session None;
              json (`Assoc [ "ok", `Bool false; "errors", `List (List.map (fun l -> `String l) e) ]))));
      (* the Concurrency tab: the finer interleaving (D45) and the judge *)
      "ruleOf", fn1 (fun name ->
          with_session (fun t ->
              match Session.rule_of t (of_js name) with
              | Ok o -> state t [ "outcome", `String (outcome o) ]
              | Error m -> state t [ "error", `String m ]));
      "arrive", fn1 (fun s ->
          with_session (fun t ->
              let j = Yojson.Safe.from_string (of_js s) in
              match Session.arrival t ~receiver:(str_member "receiver" j) ~during:(member "during" j = Some (`Bool true)) with
              | Ok () -> state t []
              | Error m -> state t [ "error", `String m ]));
      "draw", fn0 (fun () ->
          with_session (fun t ->
              match Session.draw t with
              | Ok m -> state t [ "drawn", `String m ]
              | Error m -> state t [ "error", `String m ]));
      "finish", fn0 (fun () ->
          with_session (fun t -> let b = Session.finish t in state t [ "ended", `Bool b ]));
      "judge", fn0 (fun () ->
          with_session (fun t -> json (Judging.to_json (Judging.session ~path:judge_path t))));
      "judgeText", fn1 (fun s ->
          with_session (fun t -> json (Judging.to_json (Judging.text ~path:judge_path t (of_js s)))));
      "output", fn0 (fun () ->
          with_session (fun t -> json (`List (List.map (fun l -> `String l) (Session.output t)))));
    |])
