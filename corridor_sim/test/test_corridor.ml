(* Tests of the corridor simulation: scenario files, the agenda, the
   reference controller's loop (R2, R3), command latency, determinism per
   seed, the starvation of the printed loop under a flood, the outputs, and
   TLC's validation of the traces of short runs. *)

open Corridor_sim

let qtest ?(count = 200) name gen prop =
  Alcotest.test_case name `Quick (fun () ->
      QCheck.Test.check_exn ~rand:(Random.State.make [| 42 |]) (QCheck.Test.make ~count ~name gen prop))

let scenario name = Scenario.load (Run.find_scenario name)
let short name d = { (scenario name) with Scenario.duration = d }

let all_scenarios = [ "paper"; "dense"; "narrow"; "long"; "noisy_uwb"; "flood_printed"; "flood_reference"; "dropoff" ]

(* ------------------------------------------------------------- scenarios *)

let test_load_all () =
  List.iter (fun n ->
      let sc = scenario n in
      Alcotest.(check string) "name" n sc.name;
      ignore (Scenario.world sc ~seed:1)) all_scenarios

let rejects msg json =
  match Scenario.of_json (Yojson.Safe.from_string json) with
  | _ -> Alcotest.failf "%s: accepted" msg
  | exception Scenario.Error _ -> ()

let test_bad_files () =
  let base = {|"name": "x", "duration_s": 10, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}|} in
  ignore (Scenario.of_json (Yojson.Safe.from_string ("{" ^ base ^ "}")));
  rejects "unknown field" ("{" ^ base ^ {|, "durration": 3}|});
  rejects "missing duration" {|{"name": "x", "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}}|};
  rejects "start outside" {|{"name": "x", "duration_s": 10, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 9, "y": 1}}|};
  rejects "three faces" ("{" ^ base ^ {|, "cubes": [{"id": "a", "x": 2, "y": 1, "faces": ["1", "2", "3"]}]}|});
  rejects "bad loop" ("{" ^ base ^ {|, "agent": {"loop": "fast"}}|});
  rejects "bad percept override" ("{" ^ base ^ {|, "sensors": {"priority_overrides": {"bump": 3}}}|})

(* Every number has a range (docs/simulation.md, "Ranges"): each out-of-range
   case below rejected, naming the field. *)
let rejects_field msg field json =
  match Scenario.of_json (Yojson.Safe.from_string json) with
  | _ -> Alcotest.failf "%s: accepted" msg
  | exception Scenario.Error e ->
    let n = String.length field in
    let rec has i = i + n <= String.length e && (String.sub e i n = field || has (i + 1)) in
    Alcotest.(check bool) (msg ^ ": names " ^ field ^ ": " ^ e) true (has 0)

let test_ranges () =
  let base = {|"name": "x", "duration_s": 10, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}|} in
  let with_ extra = "{" ^ base ^ ", " ^ extra ^ "}" in
  let cubes n = with_ (Printf.sprintf {|"random_cubes": {"count": %s}|} n) in
  rejects_field "negative random cubes" "random_cubes.count" (cubes "-1");
  rejects_field "huge random cubes" "random_cubes.count" (cubes "4611686018427387903");
  ignore (Scenario.of_json (Yojson.Safe.from_string (cubes "1000")));
  rejects_field "start inside a cube" "start"
    (with_ {|"cubes": [{"id": "a", "x": 1.05, "y": 1, "faces": ["1", "2", "3", "4"]}]|});
  let corridor l = Printf.sprintf
      {|{"name": "x", "duration_s": 10, "corridor": {"length_m": %s, "width_m": 2}, "start": {"x": 1, "y": 1}}|} l in
  rejects_field "infinite corridor" "length_m" (corridor "Infinity");
  rejects_field "1e999 corridor" "length_m" (corridor "1e999");
  rejects_field "NaN corridor" "length_m" (corridor "NaN");
  rejects_field "huge corridor" "length_m" (corridor "1e6");
  let duration d = Printf.sprintf
      {|{"name": "x", "duration_s": %s, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}}|} d in
  rejects_field "1e12 s" "duration_s" (duration "1e12");
  ignore (Scenario.of_json (Yojson.Safe.from_string (duration "3600")));
  rejects_field "1e9 Hz sensor" "imu_rate_hz" (with_ {|"sensors": {"imu_rate_hz": 1e9}|});
  rejects_field "every sensor at 1000 Hz for an hour" "sensors: 14400000 samples"
    ({|{"name": "x", "duration_s": 3600, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}, |}
     ^ {|"sensors": {"position_rate_hz": 1000, "proximity_rate_hz": 1000, "camera_rate_hz": 1000, "imu_rate_hz": 1000}}|});
  rejects_field "negative override" "priority_overrides.position"
    (with_ {|"sensors": {"priority_overrides": {"position": -1}}|});
  rejects_field "override beyond 32 bits" "priority_overrides.position"
    (with_ {|"sensors": {"priority_overrides": {"position": 4611686018427387903}}|});
  rejects_field "1e7-percept flood" "flood"
    ({|{"name": "x", "duration_s": 1000, "corridor": {"length_m": 5, "width_m": 2}, "start": {"x": 1, "y": 1}, |}
     ^ {|"flood": {"percept": "position", "rate_hz": 10000}}|});
  rejects_field "flood rate" "flood.rate_hz" (with_ {|"flood": {"percept": "position", "rate_hz": 1e9}|});
  rejects_field "flood ends before it starts" "flood.end_s"
    (with_ {|"flood": {"percept": "position", "rate_hz": 10, "start_s": 5, "end_s": 2}|});
  rejects_field "a tiny physics step" "physics_step_s" (with_ {|"physics_step_s": 1e-9|});
  rejects_field "a budget of 0" "agent.budget" (with_ {|"agent": {"budget": 0}|});
  rejects_field "a speed of 1e300" "forward_speeds_m_s" (with_ {|"robot": {"forward_speeds_m_s": [0.1, 0.2, 0.3, 0.4, 1e300]}|});
  rejects_field "1001 walls" "corridor.walls"
    (Printf.sprintf {|{"name": "x", "duration_s": 10, "corridor": {"length_m": 5, "width_m": 2, "walls": [%s]}, "start": {"x": 1, "y": 1}}|}
       (String.concat ", " (List.init 1001 (fun _ -> {|{"from": [0, 0], "to": [1, 1]}|}))));
  rejects_field "a cube far away" "cubes[0].x"
    (with_ {|"cubes": [{"id": "a", "x": 1e300, "y": 1, "faces": ["1", "2", "3", "4"]}]|})

let test_random_cubes () =
  let sc = scenario "dense" in
  let w1 = Scenario.world sc ~seed:1 and w1' = Scenario.world sc ~seed:1 and w2 = Scenario.world sc ~seed:2 in
  Alcotest.(check int) "fourteen cubes" 14 (Array.length w1.cubes);
  Alcotest.(check bool) "same seed, same cubes" true (w1.cubes = w1'.cubes);
  Alcotest.(check bool) "another seed, other cubes" true (w1.cubes <> w2.cubes);
  Array.iteri (fun i (a : Robome.World.cube) ->
      Array.iteri (fun j (b : Robome.World.cube) ->
          if i < j then Alcotest.(check bool) "apart" true (Float.hypot (a.cx -. b.cx) (a.cy -. b.cy) > 0.28)) w1.cubes) w1.cubes

(* ---------------------------------------------------------------- agenda *)

let prop_agenda =
  qtest "the agenda pops by time, ties in scheduling order"
    QCheck.(list (int_range 0 20))
    (fun times ->
       let q = Event_queue.create () in
       List.iteri (fun i t -> Event_queue.add q (float_of_int t) i) times;
       let rec drain acc = match Event_queue.pop q with Some (t, i) -> drain ((t, i) :: acc) | None -> List.rev acc in
       let got = drain [] in
       let expected = List.stable_sort (fun (a, _) (b, _) -> compare a b) (List.mapi (fun i t -> (float_of_int t, i)) times) in
       got = expected)

(* Adds and takes interleaved, as the simulation does, against a list kept
   sorted by (time, scheduling number); times from a few values, so that
   ties are many; next_time and size checked at every step. *)
let prop_agenda_interleaved =
  qtest ~count:300 "the agenda, adds and takes interleaved = a sorted list"
    QCheck.(list (pair bool (int_range 0 6)))
    (fun ops ->
       let q = Event_queue.create () and model = ref [] and n = ref 0 in
       List.for_all (fun (take, t) ->
           if take && !model <> [] then begin
             let expected_t = Event_queue.next_time q in
             let v = Event_queue.take q in
             match !model with
             | (t0, v0) :: rest -> model := rest; expected_t = t0 && v = v0
             | [] -> false
           end else begin
             let t = float_of_int t /. 2. in
             Event_queue.add q t !n;
             (* after every entry of equal or earlier time *)
             let rec ins = function
               | (t', v') :: rest when t' <= t -> (t', v') :: ins rest
               | l -> (t, !n) :: l in
             model := ins !model;
             incr n;
             true
           end
           && Event_queue.size q = List.length !model
           && Event_queue.next_time q = (match !model with (t, _) :: _ -> t | [] -> infinity)) ops)

(* Metrics.sort_floats against Array.stable_sort Float.compare, bit for bit:
   arrays with many equal values, both zeros, nan and infinities. *)
let prop_sort_floats =
  let value = QCheck.(oneof [ map float_of_int (int_range 0 5); always 0.; always (-0.); always nan;
                              always infinity; always neg_infinity; float ]) in
  qtest ~count:500 "sort_floats = Array.stable_sort Float.compare, bit for bit"
    QCheck.(array value)
    (fun a ->
       let b = Array.copy a and c = Array.copy a in
       Metrics.sort_floats b;
       Array.stable_sort Float.compare c;
       Array.for_all2 (fun x y -> Int64.equal (Int64.bits_of_float x) (Int64.bits_of_float y)) b c)

(* The same on arrays made of runs already in order, as a run's latencies
   come (some forty runs of a few values each). *)
let prop_sort_floats_runs =
  let run = QCheck.(map (fun l -> List.sort Float.compare (List.map (fun k -> float_of_int k /. 4.) l))
                      (list_of_size Gen.(int_range 0 30) (int_range 0 6))) in
  qtest ~count:500 "sort_floats on runs in order = Array.stable_sort Float.compare"
    QCheck.(list_of_size Gen.(int_range 0 12) run)
    (fun runs ->
       let a = Array.of_list (List.concat runs) in
       let b = Array.copy a and c = Array.copy a in
       Metrics.sort_floats b;
       Array.stable_sort Float.compare c;
       Array.for_all2 (fun x y -> Int64.equal (Int64.bits_of_float x) (Int64.bits_of_float y)) b c)

(* ------------------------------------------------------------ controller *)

let quiet_host () =
  let cmds = ref [] in
  (Robome.Host.make Robome.Host.default_mapping ~enqueue:(fun c -> cmds := c :: !cmds) ~start_listening:(fun () -> ()), cmds)

let rec drain a acc =
  match Reference_controller.step a with
  | None -> List.rev acc
  | Some w -> drain a (w :: acc)

let dispatched works = List.filter_map (function Agent.Dispatch d -> Some (d.percept, d.priority, d.seq) | _ -> None) works

let test_priorities () =
  let (h, cmds) = quiet_host () in
  let a = Reference_controller.create Agent.default_loop h in
  Alcotest.(check (list string)) "on create: moveForward" [ "forward(3)" ] (List.map Robome.Command.to_string !cmds);
  cmds := [];
  let n p = match Reference_controller.notify a p ~priority:None with Ok s -> s | Error e -> Alcotest.fail e in
  let s1 = n (Position (1., 2.)) in
  let s2 = n (Qr_code_read "A") in
  let s3 = n Obstacle in
  let s4 = n Falling in
  let s5 = n (Position (3., 4.)) in
  Alcotest.(check (list int)) "seqs from 1 (R2b)" [ 1; 2; 3; 4; 5 ] [ s1; s2; s3; s4; s5 ];
  let ws = drain a [] in
  Alcotest.(check (list (pair int int))) "highest priority first, ties by seq (R3b)"
    [ (10, 4); (8, 3); (4, 2); (2, 1); (2, 5) ]
    (List.map (fun (_, p, s) -> (p, s)) (dispatched ws));
  Alcotest.(check (list string)) "falling then obstacle handlers' commands"
    [ "stop"; "backward(3)"; "head_down"; "stop"; "turn_left(90deg)"; "forward(3)" ]
    (List.rev_map Robome.Command.to_string !cmds);
  (* the qrCodeRead was mapped at position(0, 0): it came before both positions *)
  Alcotest.(check (list (triple (float 0.) (float 0.) string))) "worldMap" [ (0., 0., "A") ] (Reference_controller.world_map a);
  Alcotest.(check (pair (float 0.) (float 0.))) "current position" (3., 4.) (Reference_controller.current_position a);
  Alcotest.(check bool) "idle" true (Reference_controller.step a = None)

(* A dispatch is taken in one call of the engine's derived rule (D29);
   the work it reports and the labels it logs are those of its rules taken
   one at a time: Dequeue e, one Handle or Skip per handler (4), EndDispatch
   of e; handlers_run counts the Handles. *)
let test_dispatch_in_one_call () =
  let (h, _) = quiet_host () in
  let a = Reference_controller.create Agent.default_loop h in
  Reference_controller.enable_log a;
  let n p = match Reference_controller.notify a p ~priority:None with Ok _ -> () | Error e -> Alcotest.fail e in
  List.iter n [ Position (1., 2.); Qr_code_read "A"; Obstacle; Falling; Position (3., 4.) ];
  let rec go () =
    let before = List.length (Reference_controller.log a) in
    match Reference_controller.step a with
    | None -> ()
    | Some w ->
      let labels = List.filteri (fun i _ -> i >= before) (Reference_controller.log a) in
      (match w, labels with
       | Agent.Dispatch d, Semantics.Machine.Dequeue e :: rest ->
         Alcotest.(check (pair int int)) "the percept dequeued" (d.priority, d.seq) (e.prio, e.seq);
         let rec body hs sk = function
           | [ Semantics.Machine.End_dispatch { seq; _ } ] ->
             Alcotest.(check int) "EndDispatch of the same seq" e.seq seq; (hs, sk)
           | Semantics.Machine.Handle _ :: r -> body (hs + 1) sk r
           | Semantics.Machine.Skip _ :: r -> body hs (sk + 1) r
           | _ -> Alcotest.fail "a dispatch's labels: Dequeue, Handle or Skip, EndDispatch" in
         let (hs, sk) = body 0 0 rest in
         Alcotest.(check int) "handlers_run = the Handles" hs d.handlers_run;
         Alcotest.(check int) "one Handle or Skip per handler" 4 (hs + sk)
       | Agent.Dispatch _, _ -> Alcotest.fail "a dispatch that does not start with Dequeue"
       | _, l -> Alcotest.(check int) "other work: one rule" 1 (List.length l));
      go () in
  go ()

let test_override_and_refusals () =
  let (h, _) = quiet_host () in
  let a = Reference_controller.create { Agent.default_loop with o2a_capacity = Some 2 } h in
  ignore (drain a []);
  ignore (Reference_controller.notify a (Position (1., 1.)) ~priority:(Some 9));
  ignore (Reference_controller.notify a Obstacle ~priority:None);
  Alcotest.(check bool) "O2A full (R2d)" true (Result.is_error (Reference_controller.notify a Falling ~priority:None));
  Alcotest.(check bool) "negative priority (R2a)" true
    (Result.is_error (Reference_controller.notify a Falling ~priority:(Some (-1))));
  Alcotest.(check (list int)) "the override wins over obstacle's 8" [ 9; 8 ]
    (List.map (fun (_, p, _) -> p) (dispatched (drain a [])))

let test_budgeted () =
  let (h, _) = quiet_host () in
  let a = Reference_controller.create { Agent.default_loop with variant = Budgeted; budget = 2 } h in
  ignore (drain a []);
  List.iter (fun p -> ignore (Reference_controller.notify a p ~priority:None))
    [ Agent.Position (0., 0.); Position (1., 1.); Position (2., 2.) ];
  let ws = drain a [] in
  let transfers = List.length (List.filter (function Agent.Transfer { moved; _ } -> moved > 0 | _ -> false) ws) in
  Alcotest.(check int) "three dispatches" 3 (List.length (dispatched ws));
  Alcotest.(check bool) "an iteration boundary between 2 and 3" true
    (transfers = 1 && List.exists (function Agent.Loop _ | Agent.Transfer { moved = 0; _ } -> true | _ -> false) ws)

(* ------------------------------------------------------------ simulation *)

let test_determinism () =
  let sc = short "paper" 40. in
  let a = Sim.run ~trace:true (module Reference_controller) sc ~seed:7 in
  let b = Sim.run ~trace:true (module Reference_controller) sc ~seed:7 in
  let c = Sim.run ~trace:true (module Reference_controller) sc ~seed:8 in
  Alcotest.(check bool) "a trace" true (String.length a.trace > 1000);
  Alcotest.(check bool) "same seed, same trace byte for byte" true (String.equal a.trace b.trace);
  Alcotest.(check string) "same report" (Report.to_string a (Metrics.of_result a)) (Report.to_string b (Metrics.of_result b));
  Alcotest.(check bool) "another seed, another trace" false (String.equal a.trace c.trace)

let test_command_latency () =
  let r = Sim.run (module Reference_controller) (short "paper" 120.) ~seed:1 in
  let p = r.scenario.params in
  Alcotest.(check bool) "commands played" true (List.length r.commands > 4);
  List.iter (fun (issued, at, _) ->
      Alcotest.(check bool) "a command acts after its tone" true (at >= issued +. p.sound_duration -. 1e-9)) r.commands;
  let rec gaps = function
    | (_, a, _) :: ((_, b, _) :: _ as rest) ->
      Alcotest.(check bool) "tones one after another, with the gap" true
        (b -. a >= p.sound_duration +. p.sound_gap -. 1e-9);
      gaps rest
    | _ -> () in
  gaps r.commands;
  (* the obstacle handler's three commands: stop at +0.1 s, turn at +0.3 s, forward at +0.5 s *)
  let rec find = function
    | (i1, a1, Robome.Command.Stop) :: (i2, a2, Turn_left _) :: (i3, a3, Forward _) :: _ when i1 = i2 && i2 = i3 ->
      Alcotest.(check (list (float 1e-9))) "0.1, 0.3, 0.5 s late" [ 0.1; 0.3; 0.5 ] [ a1 -. i1; a2 -. i1; a3 -. i1 ]
    | _ :: rest -> find rest
    | [] -> Alcotest.fail "no obstacle handled" in
  find r.commands

let test_latency_sane () =
  let r = Sim.run (module Reference_controller) (short "paper" 60.) ~seed:3 in
  let m = Metrics.of_result r in
  List.iter (fun (h : Sim.handled) ->
      Alcotest.(check bool) "dispatch after notify" true (h.dispatched >= h.notified)) (Lazy.force r.handled);
  Alcotest.(check bool) "positions at 10 Hz" true
    (match List.find_opt (fun (l : Metrics.latency) -> l.priority = 2) m.latency with
     | Some l -> l.count >= 590 && l.count <= 601 | None -> false);
  Alcotest.(check bool) "latency under 5 ms" true (m.latency_max < 0.005)

let test_flood_starvation () =
  let printed = Metrics.of_result (Sim.run (module Reference_controller) (short "flood_printed" 12.) ~seed:1) in
  let reference = Metrics.of_result (Sim.run (module Reference_controller) (short "flood_reference" 12.) ~seed:1) in
  Alcotest.(check bool) "printed: the flood starves dispatch" true
    (printed.unhandled > 30_000 && printed.unhandled_oldest > 6.);
  Alcotest.(check bool) "reference: keeps up" true (reference.unhandled < 100 && reference.latency_max < 0.01)

let test_falling_handled () =
  let r = Sim.run (module Reference_controller) (scenario "dropoff") ~seed:1 in
  let m = Metrics.of_result r in
  Alcotest.(check bool) "falling percepts dispatched" true
    (List.exists (fun (l : Metrics.latency) -> l.priority = 10 && l.count >= 1) m.latency);
  Alcotest.(check int) "backed off in time: no fall" 0 m.falls;
  Alcotest.(check bool) "after a near fall" true (m.near_falls >= 1);
  Alcotest.(check bool) "head down" true
    (List.exists (fun (_, _, c) -> c = Robome.Command.Head_down) r.commands)

(* A tiny XML well-formedness check: balanced tags. *)
let well_formed s =
  let n = String.length s in
  let stack = ref [] and ok = ref true and i = ref 0 in
  while !ok && !i < n do
    if s.[!i] = '<' then begin
      let j = String.index_from s !i '>' in
      let tag = String.sub s (!i + 1) (j - !i - 1) in
      (if String.length tag > 0 && (tag.[0] = '?' || tag.[0] = '!') then ()
       else if tag.[String.length tag - 1] = '/' then ()
       else if tag.[0] = '/' then begin
         let name = String.sub tag 1 (String.length tag - 1) in
         match !stack with x :: rest when x = name -> stack := rest | _ -> ok := false
       end else
         let name = List.hd (String.split_on_char ' ' tag) in
         stack := name :: !stack);
      i := j + 1
    end else incr i
  done;
  !ok && !stack = []

let test_outputs () =
  let dir = Filename.concat (Filename.get_temp_dir_name ()) (Printf.sprintf "jsref-sim-out-%d" (Unix.getpid ())) in
  let o = Run.run (short "paper" 60.) ~seed:2 ~out_dir:(Some dir) in
  let read f =
    let ic = open_in_bin (Filename.concat dir f) in
    let s = really_input_string ic (in_channel_length ic) in
    close_in ic; s in
  let j = Yojson.Safe.from_string (read "report.json") in
  let open Yojson.Safe.Util in
  Alcotest.(check int) "seed" 2 (j |> member "seed" |> to_int);
  Alcotest.(check int) "cubes_total" 5 (j |> member "metrics" |> member "cubes_total" |> to_int);
  Alcotest.(check int) "collisions" o.metrics.collisions (j |> member "metrics" |> member "collisions" |> to_int);
  List.iter (fun f ->
      let s = read f in
      Alcotest.(check bool) (f ^ " is well-formed") true (well_formed s);
      Alcotest.(check bool) (f ^ " is SVG") true
        (String.length s > 100 && String.sub s 0 5 = "<?xml")) [ "map.svg"; "timeline.svg" ];
  Alcotest.(check bool) "trace written" true (String.length (read "trace.txt") > 100)

let test_batch () =
  let (stats, outcomes) = Run.batch ~progress:false (short "paper" 30.) ~first_seed:1 ~runs:3 in
  Alcotest.(check int) "three runs" 3 (List.length outcomes);
  List.iter (fun (s : Run.stats) ->
      if s.n > 0 then Alcotest.(check bool) s.name true (s.min <= s.mean +. 1e-9 && s.mean <= s.max +. 1e-9)) stats;
  let t = Run.table (short "paper" 30.) ~first_seed:1 ~runs:3 stats in
  Alcotest.(check bool) "table" true (String.length t > 200)

(* -------------------------------------------------------- TLC validation *)

let tlc_available () = match Explore.Tlc.jar () with _ -> true | exception _ -> false

let validate name loop duration () =
  if not (tlc_available ()) then print_endline "TLC not available: not validated" else
  let sc = { (short name duration) with loop } in
  let module S = Sim.Make (Reference_controller) in
  let (_, agent) = S.run ~on_create:Reference_controller.enable_log sc ~seed:1 in
  let log = Reference_controller.log agent in
  Alcotest.(check bool) "a few dozen steps" true (List.length log > 20);
  match Trace_check.check sc.loop log with
  | Ok n -> Alcotest.(check int) "every state accepted" (List.length log + 1) n
  | Error e -> Alcotest.fail e

let test_replay_rejects () =
  (* a run whose log is tampered with: the abstract machine cannot follow *)
  let sc = short "paper" 0.5 in
  let module S = Sim.Make (Reference_controller) in
  let (_, agent) = S.run ~on_create:Reference_controller.enable_log sc ~seed:1 in
  let log = Reference_controller.log agent in
  let tampered = List.filter (function Semantics.Machine.Transfer _ -> false | _ -> true) log in
  let m_dir = Filename.concat (Filename.get_temp_dir_name ()) (Printf.sprintf "jsref-sim-tamper-%d" (Unix.getpid ())) in
  (try Unix.mkdir m_dir 0o700 with Unix.Unix_error (Unix.EEXIST, _, _) -> ());
  let path = Explore.Random_model.write ~dir:m_dir ~name:"MCTamper" (Trace_check.model_constants sc.loop tampered) in
  let m = Explore.Model.load path in
  Alcotest.(check bool) "rejected" true (Result.is_error (Trace_check.replay m tampered));
  Alcotest.(check bool) "the genuine log replays" true
    (Result.is_ok (Trace_check.replay (Explore.Model.load (Explore.Random_model.write ~dir:m_dir ~name:"MCGenuine"
                                                           (Trace_check.model_constants sc.loop log))) log))

let test_bench () =
  let (sim, wall) = Run.bench () in
  Alcotest.(check (float 1e-9)) "the paper scenario's 300 s" 300. sim;
  Alcotest.(check bool) "measured" true (wall > 0.)

(* The dispatched percepts kept in columns (Sim.dispatch_log, docs/simulation.md)
   are the run's dispatches: each record [handled] makes from them prints as
   the trace's dispatch line of the same run (time, seq, percept, priority,
   latency, handlers), in the same order, for both agents; and each one's
   source is its sensor's. *)
let test_dispatch_log () =
  let seen = ref [] in
  List.iter (fun (name, duration, agent) ->
      let sc = short name duration in
      let r = Sim.run ~trace:true agent sc ~seed:2 in
      (* the flood: more dispatches than the room made for the position
         fixes (1,024 more than they), so that the columns grow *)
      let room = 1024 + int_of_float (sc.duration *. sc.sensors.position_rate) in
      if name = "flood_reference" && r.dispatches.d_n <= room then
        Alcotest.failf "%s: only %d dispatches" name r.dispatches.d_n;
      let lines = List.filter (fun l ->
          match String.index_opt l ' ' with
          | Some i -> String.length l > i + 9 && String.sub l (i + 1) 9 = "dispatch "
          | None -> false) (String.split_on_char '\n' r.trace) in
      let handled = Lazy.force r.handled in
      let made = List.map (fun (h : Sim.handled) ->
          Printf.sprintf "%.6f dispatch seq=%d %s prio=%d latency=%.6f handlers=%d" h.dispatched h.seq
            (Agent.percept_to_string h.percept) h.priority (h.dispatched -. h.notified) h.handlers) handled in
      Alcotest.(check int) (name ^ ": dispatches") (List.length lines) r.dispatches.d_n;
      Alcotest.(check (list string)) (name ^ ": the trace's dispatch lines") lines made;
      List.iter (fun (h : Sim.handled) ->
          let ok = match h.percept, h.source with
            | Position _, ("uwb" | "flood") | Obstacle, ("proximity" | "edge" | "flood") | Qr_code_read _, ("camera" | "flood")
            | Falling, ("imu" | "flood") -> true
            | _ -> false in
          if not ok then Alcotest.failf "%s from %s" (Agent.percept_to_string h.percept) h.source;
          seen := Agent.percept_name h.percept :: !seen) handled)
    [ ("flood_reference", 5.6, (module Reference_controller : Agent.AGENT)); ("paper", 150., Interp_agent.make ()) ];
  List.iter (fun k -> if not (List.mem k !seen) then Alcotest.failf "no %s dispatched" k)
    [ "position"; "obstacle"; "qrCodeRead" ]

let () =
  Alcotest.run "corridor" [
    ("scenarios", [
        Alcotest.test_case "every scenario file loads" `Quick test_load_all;
        Alcotest.test_case "bad files are rejected" `Quick test_bad_files;
        Alcotest.test_case "every number in its range" `Quick test_ranges;
        Alcotest.test_case "random cubes per seed" `Quick test_random_cubes ]);
    ("agenda", [ prop_agenda; prop_agenda_interleaved; prop_sort_floats; prop_sort_floats_runs ]);
    ("controller", [
        Alcotest.test_case "priorities, seqs and handlers (R2b, R3b)" `Quick test_priorities;
        Alcotest.test_case "override and refusals (R2a, R2d)" `Quick test_override_and_refusals;
        Alcotest.test_case "a dispatch in one call = its rules" `Quick test_dispatch_in_one_call;
        Alcotest.test_case "budgeted loop" `Quick test_budgeted ]);
    ("simulation", [
        Alcotest.test_case "determinism per seed" `Quick test_determinism;
        Alcotest.test_case "command latency through the sound channel" `Quick test_command_latency;
        Alcotest.test_case "percept latency" `Quick test_latency_sane;
        Alcotest.test_case "the dispatch log = the trace's dispatches" `Quick test_dispatch_log;
        Alcotest.test_case "flood: printed loop starves, reference copes" `Quick test_flood_starvation;
        Alcotest.test_case "falling handled before the fall" `Quick test_falling_handled;
        Alcotest.test_case "report, map, timeline, trace" `Quick test_outputs;
        Alcotest.test_case "batch statistics" `Quick test_batch;
        Alcotest.test_case "bench function" `Quick test_bench ]);
    ("tlc", [
        Alcotest.test_case "replay follows the run, not a tampered one" `Quick test_replay_rejects;
        Alcotest.test_case "reference loop run validated by TLC" `Slow (validate "paper" Agent.default_loop 1.5);
        Alcotest.test_case "printed loop run validated by TLC" `Slow
          (validate "paper" { Agent.default_loop with variant = Printed } 0.01);
        Alcotest.test_case "budgeted loop run under a flood validated by TLC" `Slow
          (validate "flood_reference" { Agent.default_loop with variant = Budgeted; budget = 2 } 5.003) ]);
  ]
