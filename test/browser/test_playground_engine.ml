(* The playground's engine against the command line's traces. *)

module S = Playground_core.Session
module Mc = Semantics.Machine

let conformance = Filename.concat Test_support.Support.root "conformance"

let read path =
  let ic = open_in_bin path in
  let s = really_input_string ic (in_channel_length ic) in
  close_in ic; s

let lines s = List.filter (fun l -> String.trim l <> "") (String.split_on_char '\n' s)

(* The vector's [args] as a session setup. *)
let setup_of (v : Interp.Oracle.vector) =
  let rec go (s : S.setup) = function
    | "--agent" :: a :: rest -> go { s with agents = s.agents @ [ a ] } rest
    | "--o2a-capacity" :: n :: rest -> go { s with o2a_capacity = Some (int_of_string n) } rest
    | "--max-steps" :: n :: rest -> go { s with max_steps = int_of_string n } rest
    | "--fuel" :: n :: rest -> go { s with fuel = int_of_string n } rest
    | "--seed" :: n :: rest -> go { s with seed = Some (int_of_string n) } rest
    | "--variant" :: x :: rest -> go { s with variant = Option.get (Mc.variant_of_string x) } rest
    | a :: _ -> Alcotest.failf "%s: unknown argument %s" v.name a
    | [] -> s in
  let files = List.map (fun f -> (f, read (Filename.concat v.dir f))) v.files in
  go { S.default_setup with files } v.args

(* The events file, done in the session as run does them. *)
let play t (v : Interp.Oracle.vector) =
  List.iter (fun line ->
      let line = String.trim line in
      if line <> "" && line.[0] <> '#' then
        match Yojson.Safe.from_string line with
        | `Assoc f ->
          let get k = List.assoc_opt k f in
          let agent () = match get "agent" with Some (`String a) -> a | _ -> "" in
          (match get "notify", get "put", get "message", get "run" with
           | Some (`String p), _, _, _ ->
             let priority = match get "priority" with Some (`Int k) -> Some k | _ -> None in
             ignore (S.host t (S.Notify { agent = agent (); percept = p; priority }))
           | _, Some (`String o), _, _ -> ignore (S.host t (S.Put { agent = agent (); obj = o }))
           | _, _, Some (`String c), _ ->
             let perf = match get "performative" with Some (`String p) -> p | _ -> "inform" in
             ignore (S.host t (S.Message { agent = agent (); perf; content = c }))
           | _, _, _, Some (`Int k) -> S.run_rounds t k
           | _, _, _, Some (`String "idle") -> ignore (S.run_idle ~limit:max_int t)
           | _, _, _, Some (`Assoc [ ("rules", `Int k) ]) -> S.run_rules t k
           | _ -> Alcotest.failf "%s: bad events line %s" v.name line)
        | _ -> Alcotest.failf "%s: bad events line %s" v.name line)
    (String.split_on_char '\n' (read (Filename.concat v.dir "events.jsonl")));
  ignore (S.run_idle ~limit:max_int t)

(* The expected trace up to the end of the run: [finish] (on destroy) is not
   something a playground session does. *)
let expected_until_destroy (v : Interp.Oracle.vector) =
  let rec take = function
    | [] -> []
    | l :: rest ->
      (match Yojson.Safe.from_string l with
       | `Assoc f when List.assoc_opt "event" f = Some (`String "destroy") -> []
       | _ -> l :: take rest) in
  take (lines (read (Filename.concat v.dir "expected.jsonl")))

let first_difference a b =
  let rec go k a b = match a, b with
    | x :: a, y :: b -> if x = y then go (k + 1) a b else Some (k, x, y)
    | x :: _, [] -> Some (k, x, "(nothing)")
    | [], y :: _ -> Some (k, "(nothing)", y)
    | [], [] -> None in
  go 1 a b

let vector_case (v : Interp.Oracle.vector) =
  Alcotest.test_case v.name `Quick (fun () ->
      match S.create (setup_of v) with
      | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
      | Ok t ->
        play t v;
        Alcotest.(check bool) "a trace beyond the header" true (List.length (S.trace t) > 2);
        match first_difference (expected_until_destroy v) (S.trace t) with
        | None -> ()
        | Some (k, e, g) -> Alcotest.failf "line %d differs:\nexpected %s\n     got %s" k e g)

(* Stepping back gives exactly the state before the undone command. *)
let back_case () =
  let v = List.find (fun (v : Interp.Oracle.vector) -> v.name = "060-paper-fig7-robome")
      (Interp.Oracle.load conformance) in
  match S.create (setup_of v) with
  | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
  | Ok t ->
    let snap () = (S.trace t, S.output t, Yojson.Safe.to_string (S.view t)) in
    let seen = ref [ snap () ] in
    let act f = f (); seen := snap () :: !seen in
    act (fun () -> ignore (S.host t (S.Notify { agent = "r"; percept = "position(0, 1)"; priority = None })));
    act (fun () -> ignore (S.host t (S.Notify { agent = "r"; percept = "obstacle"; priority = Some 1 })));
    for _ = 1 to 5 do act (fun () -> ignore (S.step t)) done;
    act (fun () -> ignore (S.host t (S.Notify { agent = "r"; percept = "falling"; priority = None })));
    for _ = 1 to 9 do act (fun () -> ignore (S.step t)) done;
    let rec undo = function
      | now :: (before :: _ as rest) ->
        Alcotest.(check bool) "state now" true (snap () = now);
        Alcotest.(check bool) "back" true (S.back t);
        Alcotest.(check bool) "state before" true (snap () = before);
        undo rest
      | _ -> Alcotest.(check bool) "nothing left to undo" false (S.back t) in
    undo !seen

(* Bad input is an error located as the command line locates it, never an
   exception. *)
let errors_case () =
  let files = [ "p.jade", "agent A\n\ton create do\n\t\tlog 1 +\n" ] in
  (match S.check files with
   | [ l ] -> Alcotest.(check bool) ("syntax error located: " ^ l) true
                (String.length l > 9 && String.sub l 0 9 = "p.jade:3:")
   | l -> Alcotest.failf "expected one diagnostic, got %d: %s" (List.length l) (String.concat " | " l));
  let files = [ "p.jade", "agent A\n\ton create do\n\t\tlog x\n" ] in
  Alcotest.(check bool) "type error" true
    (List.exists (fun l -> String.length l > 9 && String.sub l 0 9 = "p.jade:3:") (S.check files));
  (match S.create { S.default_setup with files = [ "p.jade", "agent A\n" ]; agents = [ "a:B" ] } with
   | Error [ m ] -> Alcotest.(check string) "agent" "--agent a:B: error: there is no agent type B" m
   | _ -> Alcotest.fail "expected an agent error");
  let prog = "ontology O\n\tproposition p extends percept\n\nagent A uses ontology O\n" in
  match S.create { S.default_setup with files = [ "p.jade", prog ]; agents = [ "a:A" ] } with
  | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
  | Ok t ->
    (match S.host t (S.Notify { agent = "a"; percept = "p(("; priority = None }) with
     | Error m -> Alcotest.(check bool) ("located: " ^ m) true (String.sub m 0 9 = "notify:1:")
     | Ok () -> Alcotest.fail "a bad percept was accepted");
    (match S.host t (S.Notify { agent = "a"; percept = "q"; priority = None }) with
     | Error _ -> ()
     | Ok () -> Alcotest.fail "an unknown percept was accepted");
    Alcotest.(check int) "nothing recorded" 0 (S.history_length t)

(* Every counterexample replay takes TLC's actions and ends in TLC's state;
   one step short of the end, the state is not yet TLC's. *)
let replay_case (r : Playground_core.Replays.t) =
  Alcotest.test_case r.id `Quick (fun () ->
      match Playground_core.Replays.run r with
      | Error m -> Alcotest.fail m
      | Ok t ->
        (match Playground_core.Replays.check r t with
         | Ok () -> ()
         | Error m -> Alcotest.failf "not TLC's state: %s" m);
        ignore (S.back t);
        (match Playground_core.Replays.check r t with
         | Ok () -> Alcotest.fail "TLC's state reached a step early: the check has no teeth"
         | Error _ -> ()))

let () =
  let vectors = Interp.Oracle.load conformance in
  Alcotest.run "playground engine" [
    "conformance vectors", List.map vector_case vectors;
    "counterexample replays", List.map replay_case Playground_core.Replays.all;
    "session", [ Alcotest.test_case "step back" `Quick back_case;
                 Alcotest.test_case "errors" `Quick errors_case ];
  ]
