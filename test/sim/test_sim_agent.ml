(* The paper's Jadescript program, run by the interpreter, drives the robot
   exactly as the OCaml mirror of it does: same runs, same metrics, for every
   seed and scenario tried. The two were written independently (the program
   is the paper's; the mirror follows its text), so agreement checks both. *)

open Corridor_sim

let same_run scenario seed () =
  let sc = Scenario.load (Run.find_scenario scenario) in
  let jade = Interp_agent.make () in
  let a = Run.run ~agent:jade sc ~seed ~out_dir:None in
  let b = Run.run ~agent:(module Reference_controller) sc ~seed ~out_dir:None in
  let show (o : Run.outcome) =
    let m = o.metrics in
    Printf.sprintf "mapped %d/%d entries %d collisions %d falls %d distance %.3f coverage %.4f latency %.6f unhandled %d"
      m.cubes_mapped m.cubes_total m.map_entries m.collisions m.falls m.distance m.coverage m.latency_max m.unhandled in
  Alcotest.(check string) (Printf.sprintf "%s seed %d: same metrics" scenario seed) (show b) (show a);
  Alcotest.(check bool) "the run did something" true (a.metrics.distance > 0.)

(* A short run of the interpreted agent, in the paper's corridor and with the
   printed and budgeted loops, is a behaviour of spec/AgentLoop.tla (TLC). *)
let validated variant () =
  let sc = Scenario.load (Run.find_scenario "paper") in
  let loop = { sc.loop with Agent.variant } in
  let sc = { sc with duration = 8.; loop } in
  let (agent, log) = Interp_agent.make_logged () in
  ignore (Run.run ~agent sc ~seed:3 ~out_dir:None);
  let labels = log () in
  Alcotest.(check bool) "a run of some length" true (List.length labels > 100);
  match Trace_check.check loop labels with
  | Ok n -> Alcotest.(check bool) "TLC accepts it" true (n > 100)
  | Error e -> Alcotest.fail e

let () =
  Alcotest.run "sim-agent" [
    ("tlc", [ Alcotest.test_case "reference loop run validated" `Slow (validated Semantics.Machine.Reference);
              Alcotest.test_case "budgeted loop run validated" `Slow (validated Semantics.Machine.Budgeted) ]);
    ("interpreter = mirror",
     List.concat_map (fun (sc, seeds) ->
         List.map (fun s -> Alcotest.test_case (Printf.sprintf "%s seed %d" sc s) `Quick (same_run sc s)) seeds)
       [ ("paper", [ 1; 2; 3 ]); ("dense", [ 1 ]); ("dropoff", [ 1; 2 ]); ("narrow", [ 1 ]) ]) ]
