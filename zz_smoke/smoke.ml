let () =
  let sc = Corridor_sim.Scenario.load Sys.argv.(1) in
  let t0 = Unix.gettimeofday () in
  let r = Corridor_sim.Sim.run ~trace:true (module Corridor_sim.Reference_controller) sc ~seed:1 in
  let t1 = Unix.gettimeofday () in
  Printf.printf "wall %.3f events %d handled %d pending %d collisions %d falls %d odo %.2f cov %.3f map %d cmds %d\n"
    (t1 -. t0) r.events (List.length r.handled) (List.length r.pending) (List.length r.collisions) (List.length r.falls)
    r.odometer r.coverage (List.length r.world_map) (List.length r.commands);
  List.iter (fun (x, y, s) -> Printf.printf "  %.2f %.2f %s\n" x y s) r.world_map;
  let oc = open_out "/tmp/smoke/trace.txt" in output_string oc r.trace; close_out oc
