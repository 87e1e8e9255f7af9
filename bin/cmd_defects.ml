(* jadescript-ref defects [--vectors DIR] [--first] [DEFECT...]: the vectors'
   kill count over the bug catalogue (lib/defects). Each defect is run as an
   implementation (jadescript-ref run --defect NAME) on the vectors; a vector
   kills it when conform fails. *)

open Cmdliner
module O = Interp.Oracle

let self () =
  let exe = Sys.executable_name in
  if Filename.is_relative exe then Filename.concat (Sys.getcwd ()) exe else exe

let short name = match String.index_opt name '-' with Some i -> String.sub name 0 i | None -> name

let run vectors first only =
  let dir = Cmd_conform.find_vectors vectors in
  match O.load dir with
  | exception (Failure m | Sys_error m) -> prerr_endline (dir ^ ":1:1: error: " ^ m); 1
  | vs ->
    let unknown = List.filter (fun n -> Defects.find n = None) only in
    if unknown <> [] then begin
      prerr_endline ("jadescript-ref: error: unknown defect " ^ String.concat ", " unknown); 1
    end else
    let ds = if only = [] then Defects.all else List.filter (fun (d : Defects.t) -> List.mem d.name only) Defects.all in
    let exe = Filename.quote (self ()) in
    (* a vector the reference itself fails judges nothing: it is left out *)
    let vs = List.filter (fun (v : O.vector) ->
        match O.run_vector ~impl:(exe ^ " run") v with
        | O.Pass -> true
        | _ -> Printf.printf "vector %s: the reference fails it; left out\n%!" v.name; false) vs in
    let rows = List.map (fun (d : Defects.t) ->
        let impl = exe ^ " run --defect " ^ Filename.quote d.name in
        let rec go acc = function
          | [] -> List.rev acc
          | (v : O.vector) :: rest ->
            (match O.run_vector ~impl v with
             | O.Pass -> go acc rest
             | O.Diverge _ | O.Failed _ ->
               if first then [ v.name ] else go (v.name :: acc) rest) in
        let killers = go [] vs in
        let verdict = match killers, d.can_differ with
          | [], true -> "SURVIVES"
          | [], false -> "survives (no trace can show it)"
          | l, _ -> "killed by " ^ String.concat " " (List.map short l) ^ (if first then " (first found)" else "") in
        Printf.printf "%-30s %-5s %-60s %s\n%!" d.name d.ruling d.about verdict;
        (d, killers)) ds in
    let killed = List.filter (fun (_, k) -> k <> []) rows in
    let must = List.filter (fun ((d : Defects.t), _) -> d.can_differ) rows in
    let survivors = List.filter (fun ((d : Defects.t), k) -> d.can_differ && k = []) rows in
    Printf.printf "%d of %d defects killed by the vectors alone (%d vectors; %d defects can show in a trace)\n"
      (List.length killed) (List.length rows) (List.length vs) (List.length must);
    if survivors <> [] then
      Printf.printf "survivors that a trace can show: %s\n"
        (String.concat ", " (List.map (fun ((d : Defects.t), _) -> d.name) survivors));
    (* one test per defect: killed, or no trace can show it *)
    Printf.printf "%d passed, %d failed\n" (List.length rows - List.length survivors) (List.length survivors);
    if survivors = [] then 0 else 1

let cmd =
  let vectors = Arg.(value & opt (some string) None & info ["vectors"] ~docv:"DIR"
                       ~doc:"The folder of vectors (default: conformance/ of the repository).") in
  let first = Arg.(value & flag & info ["first"]
                     ~doc:"Stop at the first vector that kills each defect (fast: the test suite's way).") in
  let only = Arg.(value & pos_all string [] & info [] ~docv:"DEFECT" ~doc:"Only these defects.") in
  Cmd.v (Cmd.info "defects" ~doc:"The conformance vectors' kill count over the bug catalogue."
           ~man:[`S Manpage.s_description;
                 `P "Runs every deliberate defect of the bug catalogue (lib/defects, \
                     conformance/README.md) as an implementation, $(i,jadescript-ref run --defect NAME), \
                     on every conformance vector, and prints which vectors kill it (conform \
                     fails). Ends with $(i,K of N defects killed by the vectors alone) and \
                     $(i,N passed, M failed) (a defect passes when a vector kills it, or when \
                     no trace can show it). Exit status 1 when a defect a trace can show \
                     survives every vector."])
    Term.(const run $ vectors $ first $ only)
