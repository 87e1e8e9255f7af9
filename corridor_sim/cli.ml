open Cmdliner

let print_metrics (o : Run.outcome) =
  let m = o.metrics in
  let opt = function Some x -> Printf.sprintf "%.3f m" x | None -> "-" in
  Printf.printf "cubes mapped        %d/%d (%d map entries)\n" m.cubes_mapped m.cubes_total m.map_entries;
  Printf.printf "map error           mean %s, max %s\n" (opt m.map_error_mean) (opt m.map_error_max);
  Printf.printf "collisions          %d\n" m.collisions;
  Printf.printf "falls               %d (near falls %d)\n" m.falls m.near_falls;
  Printf.printf "distance            %.2f m\n" m.distance;
  Printf.printf "coverage            %.1f%%\n" (100. *. m.coverage);
  List.iter (fun (l : Metrics.latency) ->
      Printf.printf "latency priority %-2d %6d percepts, mean %.3f ms, p95 %.3f ms, max %.3f ms\n"
        l.priority l.count (1000. *. l.mean) (1000. *. l.p95) (1000. *. l.max)) m.latency;
  Printf.printf "latency max         %.3f ms\n" (1000. *. m.latency_max);
  Printf.printf "never dispatched    %d (oldest waited %.3f s)\n" m.unhandled m.unhandled_oldest;
  Printf.printf "agent utilisation   %.1f%%\n" (100. *. m.utilisation)

let controller_module ~controller ~program =
  match controller with
  | "reference" -> Ok (module Reference_controller : Agent.AGENT)
  | "jadescript" ->
    (match Interp_agent.make ?program () with
     | m -> Ok m
     | exception Failure e -> Error e)
  | other -> Error (Printf.sprintf "--controller: unknown controller %s (jadescript or reference)" other)

let main ?(controller = "jadescript") ?program ~scenario ~seed ~out ~batch () =
  let located file e =
    (* Scenario and program errors: one line FILE:LINE:COL: error: message. *)
    let has_location = match String.split_on_char ':' e with
      | _ :: l :: c :: _ -> int_of_string_opt l <> None && int_of_string_opt (String.trim c) <> None
      | _ -> false in
    let e = String.concat " " (List.filter (( <> ) "") (List.map String.trim (String.split_on_char '\n' e))) in
    if has_location then e else Printf.sprintf "%s:1:1: error: %s" file e in
  match Scenario.load (Run.find_scenario scenario) with
  | exception Scenario.Error e -> prerr_endline (located scenario e); 1
  | sc ->
    match controller_module ~controller ~program with
    | Error e -> prerr_endline (located (Option.value program ~default:"examples/robome/robome.jade") e); 1
    | Ok agent ->
    let seed = match seed with Some s -> s | None -> sc.seed in
    match batch with
    | Some n when n < 1 || n > 100_000 ->
      prerr_endline (Printf.sprintf "jadescript-ref: error: --batch %d: from 1 to 100000 runs" n); 1
    | _ ->
    match
    (match batch with
     | Some n ->
       let (stats, _) = Run.batch ~agent sc ~first_seed:seed ~runs:n in
       print_string (Run.table sc ~first_seed:seed ~runs:n stats)
     | _ ->
       Run.tune_gc ();
       let dir = match out with Some d -> d | None -> Printf.sprintf "out/sim/%s-s%d" sc.name seed in
       let o = Run.run ~agent sc ~seed ~out_dir:(Some dir) in
       Printf.printf "scenario %s, seed %d, %.0f s simulated, agent %s, %s loop\n" sc.name seed sc.duration
         o.result.agent_name (Semantics.Machine.string_of_variant sc.loop.variant);
       print_metrics o;
       Printf.printf "wrote %s/{report.json,map.svg,timeline.svg,trace.txt}\n" dir)
    with
    | () -> 0
    | exception Sys_error m ->
      (* the outputs of --out: one line, exit 1 *)
      prerr_endline ("jadescript-ref: error: cannot write the simulation's outputs: " ^ m); 1

let cmd =
  let scenario = Arg.(required & pos 0 (some string) None & info [] ~docv:"SCENARIO"
                        ~doc:"A scenario file, or the name of one in scenarios/ (e.g. $(b,paper)).") in
  let seed = Arg.(value & opt (some int) None & info [ "seed" ] ~docv:"N"
                    ~doc:"The seed (default: the scenario's). With $(b,--batch), the first seed.") in
  let out = Arg.(value & opt (some string) None & info [ "out" ] ~docv:"DIR"
                   ~doc:"Where to write report.json, map.svg, timeline.svg and trace.txt \
                         (default out/sim/NAME-sSEED).") in
  let batch = Arg.(value & opt (some int) None & info [ "batch" ] ~docv:"N"
                     ~doc:"Run N seeds and print a table of the metrics (mean, min, max).") in
  let controller = Arg.(value & opt string "jadescript" & info [ "controller" ] ~docv:"C"
                         ~doc:"$(b,jadescript): the paper's program run by the interpreter (default); \
                               $(b,reference): the OCaml mirror of it.") in
  let program = Arg.(value & opt (some string) None & info [ "program" ] ~docv:"FILE"
                       ~doc:"The Jadescript program (default examples/robome/robome.jade).") in
  Cmd.v (Cmd.info "sim" ~doc:"Simulate the RoboMe case study in a corridor."
           ~man:[ `S Manpage.s_description;
                  `P "Runs the paper's RoboMe agent (examples/robome/robome.jade on the interpreter) in a simulated \
                      corridor described by a scenario file (docs/simulation.md): the robot's \
                      kinematics, the sound channel of its commands, its sensors and the phone's \
                      (UWB position, camera, accelerometer), with percepts notified to the agent \
                      as R2 rules and its loop run in simulated time. The same seed gives the \
                      same run." ])
    Term.(const (fun scenario seed out batch controller program ->
        main ~controller ?program ~scenario ~seed ~out ~batch ())
          $ scenario $ seed $ out $ batch $ controller $ program)
