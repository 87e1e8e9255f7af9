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

let () =
  Alcotest.run "sim-agent" [
    ("interpreter = mirror",
     List.concat_map (fun (sc, seeds) ->
         List.map (fun s -> Alcotest.test_case (Printf.sprintf "%s seed %d" sc s) `Quick (same_run sc s)) seeds)
       [ ("paper", [ 1; 2; 3 ]); ("dense", [ 1 ]); ("dropoff", [ 1; 2 ]); ("narrow", [ 1 ]) ]) ]
