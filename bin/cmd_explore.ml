(* jadescript-ref explore MODEL [--against-tlc] *)

open Cmdliner
open Explore

let resolve_model arg =
  let candidates = [ arg; arg ^ ".tla";
                     Filename.concat "spec/models" arg; Filename.concat "spec/models" (arg ^ ".tla") ] in
  match List.find_opt (fun p -> Sys.file_exists p && not (Sys.is_directory p)) candidates with
  | Some p -> p
  | None ->
    (match Tlc.spec_dir () with
     | sd ->
       let p = Filename.concat (Filename.concat sd "models") (Filename.remove_extension (Filename.basename arg) ^ ".tla") in
       if Sys.file_exists p then p else raise (Model.Error (Printf.sprintf "no model %s (looked in spec/models/)" arg))
     | exception Tlc.Error _ -> raise (Model.Error (Printf.sprintf "no model %s" arg)))

let error_line file msg = prerr_endline (Printf.sprintf "%s:1:1: error: %s" file msg)

let run model_arg against =
  match
    let path = resolve_model model_arg in
    let m = Model.load path in
    let g = Explorer.explore m in
    let n = Array.length g.states in
    Printf.printf "model %s (variant %s%s): %d states, %d transitions, %d deadlock states (final), %.3f s, %.0f states/s\n%!"
      m.name (Semantics.Machine.string_of_variant m.params.variant)
      (if m.params.tie = Semantics.Machine.Unstable then ", unstable ties" else "")
      n (Array.length g.edges) (List.length g.deadlocks) g.seconds
      (if g.seconds > 0. then float_of_int n /. g.seconds else 0.);
    if against then begin
      let (dot, run) = Tlc.state_graph m in
      Printf.printf "TLC: %d states in %.1f s\n%!" (List.length dot.nodes) run.seconds;
      let r = Compare.graphs g dot in
      print_string (Compare.render r);
      if Compare.agree r then 0 else 1
    end else 0
  with
  | code -> code
  | exception Model.Error msg -> error_line model_arg msg; 1
  | exception Tlc.Error msg -> error_line model_arg msg; 1
  | exception Failure msg -> error_line model_arg msg; 1
  | exception Tla.Parse_error msg -> error_line model_arg ("cannot read a TLA+ value: " ^ msg); 1

let cmd =
  let model = Arg.(required & pos 0 (some string) None & info [] ~docv:"MODEL"
                     ~doc:"A model of spec/models: a path to MC*.tla or its name (MCReference).") in
  let against = Arg.(value & flag & info ["against-tlc"]
                       ~doc:"Also run TLC on the model and compare the two state graphs.") in
  Cmd.v (Cmd.info "explore" ~doc:"Enumerate the reachable configurations of a TLA+ model with the OCaml semantics."
           ~man:[`S Manpage.s_description;
                 `P "Reads the model's constants from its MC*.tla and MC*.cfg, builds the \
                     abstract bodies they describe and explores every reachable \
                     configuration of lib/semantics breadth-first. With \
                     $(b,--against-tlc) it runs TLC with $(i,-dump dot,actionlabels), maps \
                     both graphs to canonical TLA+ states and compares states, initial \
                     states and labelled transitions; on a difference it prints the \
                     shortest path to it. Exit status 1 when the graphs differ."])
    Term.(const run $ model $ against)
