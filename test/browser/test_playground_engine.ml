(* The playground's engine against the command line's traces. *)

module S = Playground_core.Session
module Mc = Semantics.Machine

let conformance = Filename.concat Test_support.Support.root "conformance"

module Astring_like = struct
  let contains s sub =
    let n = String.length sub and m = String.length s in
    let rec go i = i + n <= m && (String.sub s i n = sub || go (i + 1)) in
    go 0
end

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
             let during = get "during" = Some (`String "step") in
             ignore (S.host t (S.Message { agent = agent (); perf; content = c; during }))
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

(* Every exercise: its starting program fails the check (so the check can
   fail) and its solution passes it. *)
let exercise_case (x : Playground_core.Exercises.t) =
  Alcotest.test_case x.id `Quick (fun () ->
      let attempt what s =
        match Playground_core.Exercises.attempt x s with
        | Error e -> Alcotest.failf "%s: %s" what (String.concat "\n" e)
        | Ok (_, v) -> v in
      let v = attempt "the start" x.start in
      Alcotest.(check bool) ("the starting program fails: " ^ v.says) false v.solved;
      let v = attempt "the solution" x.solution in
      Alcotest.(check bool) ("the solution passes: " ^ v.says) true v.solved)

(* A session saved (export) and restored gives the same trace, view and
   output, and steps back as the original does. *)
let restore_case (v : Interp.Oracle.vector) =
  Alcotest.test_case v.name `Quick (fun () ->
      match S.create (setup_of v) with
      | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
      | Ok t ->
        play t v;
        let snap t = (S.trace t, S.output t, Yojson.Safe.to_string (S.view t), S.history_length t) in
        let saved = Yojson.Safe.from_string (Yojson.Safe.to_string (S.export t)) in
        match S.restore (setup_of v) saved with
        | Error e -> Alcotest.failf "restore: %s" (String.concat "\n" e)
        | Ok u ->
          Alcotest.(check bool) "restored = saved" true (snap t = snap u);
          for _ = 1 to 3 do ignore (S.back t); ignore (S.back u) done;
          Alcotest.(check bool) "three steps back, both" true (snap t = snap u))

let restore_errors_case () =
  let s = { S.default_setup with files = [ "p.jade", "agent A\n" ]; agents = [ "a:A" ] } in
  List.iter (fun j ->
      match S.restore s (Yojson.Safe.from_string j) with
      | Error [ m ] -> Alcotest.(check bool) ("refused: " ^ m) true (String.length m > 6)
      | Error _ -> Alcotest.fail "one line"
      | Ok _ -> Alcotest.failf "accepted %s" j) [ "{}"; "[1]"; {|[{"rules": -1}]|}; {|[{"what": 1}]|} ]

(* A rule's label names its behaviour after the instance has left: the
   Shapes example's one-shot RequestNewShape, after its step (R5c). *)
let names_case () =
  let v = List.find (fun (v : Interp.Oracle.vector) -> v.name = "062-paper-shapes-two-agents")
      (Interp.Oracle.load conformance) in
  match S.create (setup_of v) with
  | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
  | Ok t ->
    let labels = ref [] in
    let rec go n = if n < 200 && S.step t = S.Stepped then begin
        (match S.view t with
         | `Assoc f ->
           (match List.assoc "agents" f with
            | `List l -> List.iter (function `Assoc a -> (match List.assoc "last" a with `String s -> labels := s :: !labels | _ -> ()) | _ -> ()) l
            | _ -> ())
         | _ -> ());
        go (n + 1) end in
    go 0;
    Alcotest.(check bool) "RequestNewShape's step is labelled" true
      (List.mem "BehaviourStep of RequestNewShape #2" !labels);
    Alcotest.(check (list string)) "no label with an unknown behaviour" []
      (List.filter (fun l -> Astring_like.contains l "of ? " || Astring_like.contains l ": ? ") !labels)

(* run_at: in the middle of a dispatch it is the line of the handler tried
   next, and that line declares a percept handler. *)
let run_at_case () =
  let v = List.find (fun (v : Interp.Oracle.vector) -> v.name = "060-paper-fig7-robome")
      (Interp.Oracle.load conformance) in
  match S.create (setup_of v) with
  | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
  | Ok t ->
    ignore (S.host t (S.Notify { agent = "r"; percept = "obstacle"; priority = None }));
    let seen = ref 0 in
    for _ = 1 to 12 do
      ignore (S.step t);
      match S.view t with
      | `Assoc f ->
        (match List.assoc "agents" f with
         | `List (`Assoc a :: _) ->
           (match List.assoc "run_at" a, List.assoc "phase" a with
            | `Assoc at, `String ph ->
              let file = (match List.assoc "file" at with `String s -> s | _ -> "") in
              let line = (match List.assoc "line" at with `Int n -> n | _ -> 0) in
              let text = List.nth (String.split_on_char '\n' (List.assoc file (S.setup t).files)) (line - 1) in
              let kind = (match List.assoc "kind" at with `String s -> s | _ -> "") in
              incr seen;
              if ph = "handle" then
                Alcotest.(check bool) ("a handler's line: " ^ text) true (Astring_like.contains text "on percept")
              else Alcotest.(check string) "a behaviour" "behaviour" kind
            | `Null, _ -> ()
            | _ -> Alcotest.fail "run_at")
         | _ -> Alcotest.fail "agents")
      | _ -> Alcotest.fail "view"
    done;
    Alcotest.(check bool) "run_at was given" true (!seen >= 3)

(* The glossary explains every ruling, decision and property name that the
   page's own texts cite: the examples, the replays, the exercises. *)
let glossary_case () =
  let module G = Playground_core.Glossary in
  let terms = List.map (fun (e : G.entry) -> e.term) G.all in
  Alcotest.(check int) "no term twice" (List.length terms) (List.length (List.sort_uniq compare terms));
  let texts =
    List.concat_map (fun (x : Playground_core.Examples.t) -> [ x.title; x.about ]) Playground_core.Examples.all
    @ List.concat_map (fun (r : Playground_core.Replays.t) ->
        r.title :: r.finding :: r.final :: List.map (fun (s : Playground_core.Replays.step) -> s.say) r.steps)
      Playground_core.Replays.all
    @ List.concat_map (fun (x : Playground_core.Exercises.t) -> x.title :: x.task :: x.why :: x.hints)
      Playground_core.Exercises.all in
  let is_word c = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c = '_' in
  let words s =
    let n = String.length s in
    let rec go i acc =
      if i >= n then List.rev acc
      else if is_word s.[i] then
        let j = ref i in
        while !j < n && is_word s.[!j] do incr j done;
        go !j (String.sub s i (!j - i) :: acc)
      else go (i + 1) acc in
    go 0 [] in
  let cited w =
    let n = String.length w in
    n >= 2 && (w.[0] = 'R' || w.[0] = 'D') && w.[1] >= '1' && w.[1] <= '9'
    && (let rec digits i = i >= n || (w.[i] >= '0' && w.[i] <= '9' && digits (i + 1))
                         || (i = n - 1 && w.[0] = 'R' && w.[i] >= 'a' && w.[i] <= 'h') in digits 2) in
  let props = List.map (fun (p, _, _) -> p) Playground_core.Glossary_data.properties in
  let needed = List.sort_uniq compare
      (List.filter (fun w -> cited w || List.mem w props) (List.concat_map words texts)) in
  Alcotest.(check bool) "the texts cite something" true (List.length needed > 20);
  Alcotest.(check (list string)) "cited but not explained" [] (List.filter (fun w -> not (List.mem w terms)) needed);
  List.iter (fun t -> Alcotest.(check bool) (t ^ " explained") true (List.mem t terms))
    [ "R1a"; "R3b"; "R8"; "D1"; "D39"; "NoLoss"; "BoundedInversion"; "ghosts"; "MCBudgeted" ]

(* The finer interleaving (the Concurrency tab, D45): the vector's host
   actions done, then events drawn from a seed until nothing can happen, and
   the run ended; the judge compiled into the page accepts the trace,
   complete, after every tenth draw and at the end; export and restore give
   the same trace; and the same trace with its arrivals' order broken (the
   last deliver line moved before the send it answers) is rejected. *)
let fine_case (v : Interp.Oracle.vector) =
  Alcotest.test_case v.name `Quick (fun () ->
      let path = Filename.temp_file "judge" ".jsonl" in
      Fun.protect ~finally:(fun () -> Sys.remove path) (fun () ->
          let seed = Hashtbl.hash v.name mod 1000 in
          match S.create { (setup_of v) with interleave = Some seed } with
          | Error e -> Alcotest.failf "%s" (String.concat "\n" e)
          | Ok t ->
            List.iter (fun line ->
                match Yojson.Safe.from_string line with
                | `Assoc f ->
                  let text k = match List.assoc_opt k f with Some (`String x) -> Some x | _ -> None in
                  let agent = Option.value (text "agent") ~default:"" in
                  (match text "notify", text "put", text "message" with
                   | Some p, _, _ ->
                     let priority = match List.assoc_opt "priority" f with Some (`Int k) -> Some k | _ -> None in
                     ignore (S.host t (S.Notify { agent; percept = p; priority }))
                   | _, Some o, _ -> ignore (S.host t (S.Put { agent; obj = o }))
                   | _, _, Some c ->
                     ignore (S.host t (S.Message { agent; content = c; perf = Option.value (text "performative") ~default:"inform";
                                                   during = text "during" = Some "step" }))
                   | _ -> ())
                | _ -> ()
                | exception _ -> ())
              (List.filter (fun l -> l.[0] <> '#') (lines (read (Filename.concat v.dir "events.jsonl"))));
            let judged what =
              match Playground_core.Judging.session ~path t with
              | Judge.Accepted { lines; _ } ->
                Alcotest.(check int) (what ^ ": every line judged") (List.length (S.trace t)) lines
              | Judge.Rejected { line; message } ->
                Alcotest.failf "%s: line %d rejected: %s\n%s" what line message (List.nth (S.trace t) (line - 1)) in
            let rec go n =
              if n < 600 then
                match S.draw t with
                | Ok _ -> if n mod 10 = 0 then judged (Printf.sprintf "after %d draws" n); go (n + 1)
                | Error _ -> () in
            go 0;
            Alcotest.(check bool) "the run ends" true (S.finish t);
            (match Playground_core.Judging.session ~path t with
             | Judge.Accepted { complete; _ } -> Alcotest.(check bool) "complete" true complete
             | Judge.Rejected { line; message } -> Alcotest.failf "the whole run: line %d rejected: %s" line message);
            (match S.restore (S.setup t) (S.export t) with
             | Ok u -> Alcotest.(check (list string)) "export and restore" (S.trace t) (S.trace u)
             | Error e -> Alcotest.failf "restore: %s" (String.concat "\n" e));
            let tr = Array.of_list (S.trace t) in
            let event k = match Yojson.Safe.from_string tr.(k) with
              | `Assoc f -> (match List.assoc_opt "event" f with Some (`String e) -> e | _ -> "")
              | _ -> "" in
            let last_deliver = ref None in
            Array.iteri (fun k _ -> if event k = "deliver" then last_deliver := Some k) tr;
            match !last_deliver with
            | None -> ()
            | Some d ->
              (* moved to the first line after the header and the creations *)
              let first = ref 1 in
              while !first < d && List.mem (event !first) [ "create"; "activate"; "send"; "log"; "invoke" ] do incr first done;
              if !first < d then begin
                let l = Array.to_list tr in
                let moved = List.filteri (fun k _ -> k <> d) l in
                let moved = List.concat (List.mapi (fun k x -> if k = !first then [ tr.(d); x ] else [ x ]) moved) in
                match Playground_core.Judging.text ~path t (String.concat "" (List.map (fun x -> x ^ "\n") moved)) with
                | Judge.Rejected { line; _ } ->
                  Alcotest.(check bool) "rejected at or before the moved line" true (line <= !first + 1)
                | Judge.Accepted _ -> Alcotest.failf "a deliver moved from line %d to %d was accepted" (d + 1) (!first + 1)
              end))

let () =
  let vectors = Interp.Oracle.load conformance in
  Alcotest.run "playground engine" [
    "conformance vectors", List.map vector_case vectors;
    "counterexample replays", List.map replay_case Playground_core.Replays.all;
    "session", [ Alcotest.test_case "step back" `Quick back_case;
                 Alcotest.test_case "errors" `Quick errors_case;
                 Alcotest.test_case "labels name behaviours that left" `Quick names_case;
                 Alcotest.test_case "run_at: the line that runs next" `Quick run_at_case;
                 Alcotest.test_case "restore refuses what export never writes" `Quick restore_errors_case ];
    (* not 083 and 084: they build a text of 1,000,000 bytes and compare ten
       million values (D21, D37), seconds per replay, and a restore and three
       steps back replay eight times; export does the same for every vector *)
    "export and restore", List.map restore_case
      (List.filter (fun (v : Interp.Oracle.vector) ->
           not (List.mem v.name [ "083-r7-value-too-large"; "084-r7-shared-value-compare" ])) vectors);
    "finer interleaving judged", List.map fine_case
      (List.filter (fun (v : Interp.Oracle.vector) ->
           not (List.mem v.name [ "083-r7-value-too-large"; "084-r7-shared-value-compare" ])) vectors);
    "exercises", List.map exercise_case Playground_core.Exercises.all;
    "glossary", [ Alcotest.test_case "every cited term explained" `Quick glossary_case ];
  ]
