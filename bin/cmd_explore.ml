(* jadescript-ref explore: the OCaml semantics against the TLA+ spec. *)

open Cmdliner
open Explore

let resolve_model arg =
  let local = [ arg; arg ^ ".tla" ] in
  match List.find_opt (fun p -> Sys.file_exists p && not (Sys.is_directory p)) local with
  | Some p -> p
  | None ->
    let dir = Filename.concat (Tlc.spec_dir ()) "models" in
    let p = Filename.concat dir (Filename.remove_extension (Filename.basename arg) ^ ".tla") in
    if Sys.file_exists p then p
    else raise (Model.Error (Printf.sprintf "no model %s (looked in %s)" arg dir))

let summary (g : Explorer.graph) =
  let m = g.model in
  let n = Array.length g.states in
  Printf.printf "model %s (variant %s%s): %d states, %d transitions, %d final states, %.3f s, %.0f states/s\n%!"
    m.name (Semantics.Machine.string_of_variant m.params.variant)
    (if m.params.tie = Semantics.Machine.Unstable then ", unstable ties" else "")
    n (Array.length g.edges) (List.length g.deadlocks) g.seconds
    (if g.seconds > 0. then float_of_int n /. g.seconds else 0.)

let one ~max_states model_arg against mutant =
  let m = Model.load (resolve_model model_arg) in
  Model.check_explorable m;
  let g = Explorer.explore ~max_states ?rules:(Option.map Mutant.rules mutant) m in
  summary g;
  if not against then 0
  else begin
    let dot = Conformance.tlc_graph m in
    let r = Compare.graphs g dot in
    print_string (Compare.render r);
    if Compare.agree r then 0 else 1
  end

(* D31: the counting path, fingerprints only, no graph *)
let count ~max_states model_arg mutant =
  let m = Model.load (resolve_model model_arg) in
  Model.check_explorable m;
  let c = Explorer.count ~max_states ?rules:(Option.map Mutant.rules mutant) m in
  Printf.printf "model %s (variant %s%s): %d distinct states (by 63-bit fingerprint), %d generated, \
                 %d final states, depth %d, %.3f s, %.0f states/s; fingerprint table %d bytes; \
                 probability of a missed state at most %.1e\n%!"
    m.name (Semantics.Machine.string_of_variant m.params.variant)
    (if m.params.tie = Semantics.Machine.Unstable then ", unstable ties" else "")
    c.distinct c.generated c.final c.depth c.c_seconds
    (if c.c_seconds > 0. then float_of_int c.distinct /. c.c_seconds else 0.)
    c.table_bytes (Explorer.collision_probability c);
  0

let all ~max_states ~full ~mutants ~simulate ~validate =
  let paths = Conformance.models ~full () in
  let ms = List.map Model.load paths in
  List.iter Model.check_explorable ms;
  let failures = ref 0 in
  Printf.printf "%-20s %-10s %9s %11s %9s  %s\n" "model" "variant" "states" "transitions" "TLC s" "graphs";
  List.iter (fun (m : Model.t) ->
      let g = Explorer.explore ~max_states m in
      let t0 = Unix.gettimeofday () in
      let dot = Conformance.tlc_graph m in
      let dt = Unix.gettimeofday () -. t0 in
      let r = Compare.graphs g dot in
      if not (Compare.agree r) then incr failures;
      Printf.printf "%-20s %-10s %9d %11d %9.1f  %s\n%!" m.name
        (Semantics.Machine.string_of_variant m.params.variant)
        (Array.length g.states) (Array.length g.edges) dt
        (if Compare.agree r then "identical" else "DIFFER");
      if not (Compare.agree r) then print_string (Compare.render r)) ms;
  if mutants then begin
    Printf.printf "\n%-22s %-20s %s\n" "mutant" "caught by" "steps to the difference";
    List.iter (fun (row : Conformance.mutant_row) ->
        (match row.caught_by with None -> incr failures | Some _ -> ());
        Printf.printf "%-22s %-20s %s\n%!" row.mutant
          (Option.value row.caught_by ~default:"NOT CAUGHT")
          (if row.caught_by = None then "-" else string_of_int row.witness_length))
      (Conformance.mutant_table ms)
  end;
  if simulate > 0 then begin
    Printf.printf "\nTLC behaviours replayed by the OCaml machine (%d per model, depth 40):\n" simulate;
    List.iter (fun (m : Model.t) ->
        match Conformance.replay_simulation m ~traces:simulate ~depth:40 ~seed:7 with
        | Ok n -> Printf.printf "  %-20s %d replayed\n%!" m.name n
        | Error e -> incr failures; Printf.printf "  %-20s FAILED: %s\n%!" m.name e) ms
  end;
  if validate > 0 then begin
    Printf.printf "\nOCaml runs validated by TLC as traces (%d per model, depth 40):\n" validate;
    List.iter (fun (m : Model.t) ->
        let runs = Conformance.random_runs m ~runs:validate ~depth:40 ~seed:11 in
        match Conformance.validate_runs m runs with
        | Ok n -> Printf.printf "  %-20s %d accepted\n%!" m.name n
        | Error e -> incr failures; Printf.printf "  %-20s FAILED: %s\n%!" m.name e) ms
  end;
  if !failures = 0 then 0 else 1

(* The largest --max-states: at about 650 bytes a state (docs/spec.md,
   "Ranges"), 25,000,000 states take about 16 GB, which a machine of 24 GB
   holds beside the system and other work; 50,000,000 (about 30 GB) ended
   in SIGABRT there. *)
let max_max_states = 25_000_000

let run model_arg against mutant_name all_flag full mutants simulate validate max_states fingerprints =
  let error msg = prerr_endline (Printf.sprintf "%s:1:1: error: %s"
                                   (Option.value model_arg ~default:"spec/models") msg); 1 in
  if max_states < 1 || max_states > max_max_states then begin
    prerr_endline (Printf.sprintf "jadescript-ref: error: --max-states %d: from 1 to %d" max_states max_max_states);
    1
  end else if simulate < 0 || simulate > 100_000 || validate < 0 || validate > 100_000 then begin
    prerr_endline "jadescript-ref: error: --simulate and --validate: from 0 to 100000 runs";
    1
  end else
  match
    let mutant = match mutant_name with
      | None -> None
      | Some n -> (match List.assoc_opt n Mutant.all with
          | Some m -> Some m
          | None -> raise (Model.Error (Printf.sprintf "unknown mutant %s (known: %s)" n
                                          (String.concat ", " (List.map fst Mutant.all))))) in
    match model_arg, all_flag with
    | Some _, false when fingerprints && against ->
      raise (Model.Error "--fingerprints counts states; --against-tlc needs the exact graph: give one of them")
    | Some m, false when fingerprints -> count ~max_states m mutant
    | Some m, false -> one ~max_states m against mutant
    | None, true when fingerprints -> raise (Model.Error "--fingerprints: give one MODEL, not --all")
    | None, true -> all ~max_states ~full ~mutants ~simulate ~validate
    | _ -> raise (Model.Error "give one MODEL, or --all")
  with
  | code -> code
  | exception Model.Error msg -> error msg
  | exception Tlc.Error msg -> error msg
  | exception Failure msg -> error msg
  | exception Tla.Parse_error msg -> error ("cannot read a TLA+ value: " ^ msg)

let cmd =
  let model = Arg.(value & pos 0 (some string) None & info [] ~docv:"MODEL"
                     ~doc:"A model of spec/models: a path to MC*.tla or its name (MCReference).") in
  let against = Arg.(value & flag & info ["against-tlc"]
                       ~doc:"Also run TLC on the model and compare the two state graphs.") in
  let mutant = Arg.(value & opt (some string) None & info ["mutant"] ~docv:"NAME"
                      ~doc:"Explore with a deliberate semantic mutant of the step function.") in
  let all = Arg.(value & flag & info ["all"] ~doc:"Every model of spec/models, each against TLC.") in
  let full = Arg.(value & flag & info ["full"] ~doc:"With --all: include the models marked full.") in
  let mutants = Arg.(value & flag & info ["mutants"]
                       ~doc:"With --all: show that every mutant disagrees with TLC on some model.") in
  let simulate = Arg.(value & opt int 0 & info ["simulate"] ~docv:"N"
                        ~doc:"With --all: replay N random TLC behaviours of each model.") in
  let validate = Arg.(value & opt int 0 & info ["validate"] ~docv:"N"
                        ~doc:"With --all: have TLC validate N random OCaml runs of each model as traces.") in
  let max_states = Arg.(value & opt int Explorer.default_max_states & info ["max-states"] ~docv:"N"
                          ~doc:"Stop with an exhaustion error when a model has more than N states \
                                (default 1,000,000, about 650 MB; at most 25,000,000, about 16 GB).") in
  let fingerprints = Arg.(value & flag & info ["fingerprints"]
                            ~doc:"Only count the states, depth first, keeping a 63-bit fingerprint of each \
                                  (8 bytes, in a table at most three quarters full) and the current path, \
                                  as TLC keeps fingerprints; prints the probability that a collision hid \
                                  a state (D31).") in
  Cmd.v (Cmd.info "explore" ~doc:"Enumerate the reachable configurations of a TLA+ model with the OCaml semantics."
           ~man:[`S Manpage.s_description;
                 `P "Reads the model's constants from its MC*.tla and MC*.cfg, builds the \
                     abstract bodies they describe and explores every reachable \
                     configuration of lib/semantics breadth-first. With \
                     $(b,--against-tlc) it runs TLC with $(i,-dump dot,actionlabels), maps \
                     both graphs to canonical TLA+ states and compares states, initial \
                     states and labelled transitions; on a difference it prints the \
                     shortest path to it. Exit status 1 when the graphs differ.";
                 `P "$(b,--all) does this for every model and prints a table; \
                     $(b,--mutants), $(b,--simulate) and $(b,--validate) add the other \
                     conformance checks (make conformance)."])
    Term.(const run $ model $ against $ mutant $ all $ full $ mutants $ simulate $ validate $ max_states $ fingerprints)
