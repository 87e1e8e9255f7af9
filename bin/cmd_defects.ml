(* jadescript-ref defects [--vectors DIR] [--first] [--judge | --generated N
   [--seed S]] [DEFECT...]: the kill counts over the bug catalogue
   (lib/defects). Each defect is run as an implementation (jadescript-ref run
   --defect NAME) on the vectors; a vector kills it when conform fails:
   compared with the expected trace (the default), or judged by the
   program's semantics (--judge, as conform --judge). With --generated N,
   the cases are conform --generated's programs instead of the vectors,
   each judged. Judged, the first case that kills a defect ends its row. *)

open Cmdliner
module O = Interp.Oracle

let self () =
  let exe = Sys.executable_name in
  if Filename.is_relative exe then Filename.concat (Sys.getcwd ()) exe else exe

let short name = match String.index_opt name '-' with Some i -> String.sub name 0 i | None -> name

(* The generated cases' kill count: for each defect, cases 1..n of the seed
   until the first that the judge rejects. *)
let run_generated ds n seed =
  let exe = Filename.quote (self ()) in
  let t0 = Unix.gettimeofday () in
  (* a defect no trace can show is not run: nothing could kill it *)
  let first_kill (d : Defects.t) =
    let impl = exe ^ " run --defect " ^ Filename.quote d.name in
    let rec go k =
      if k > n then None
      else match Judged.judge_case ~spawn:Cmd_conform.spawn ~timeout:60. ~impl (Judged.generated ~seed k) with
        | Ok () -> go (k + 1)
        | Error _ -> Some k in
    if d.can_differ && d.blind = None then go 1 else None in
  let row (d : Defects.t) killer =
    let verdict = match killer, d.can_differ, d.blind with
      | None, true, Some why -> "survives (the judge cannot see it: " ^ why ^ ")"
      | None, true, None -> "SURVIVES"
      | None, false, _ -> "survives (no trace can show it)"
      | Some k, _, _ -> Printf.sprintf "killed by generated-%d-%d" seed k in
    Printf.printf "%-30s %-5s %-60s %s\n%!" d.name d.ruling d.about verdict in
  (* two workers (the machine's two cores): this process takes the defects
     of even place, a child the others, each printing its rows as they end;
     the child hands its results back in a file *)
  let indexed = List.mapi (fun i d -> (i, d)) ds in
  let (mine, theirs) = List.partition (fun (i, _) -> i mod 2 = 0) indexed in
  let results = Filename.temp_file "jsref_defects" ".txt" in
  flush stdout;
  let child = match Unix.fork () with
    | 0 ->
      let oc = open_out results in
      List.iter (fun (i, d) ->
          let k = first_kill d in
          row d k;
          Printf.fprintf oc "%d %d\n%!" i (Option.value k ~default:0)) theirs;
      close_out oc;
      Unix._exit 0
    | pid -> pid in
  let own = List.map (fun (i, d) -> let k = first_kill d in row d k; (i, k)) mine in
  let rec wait () = match Unix.waitpid [] child with
    | _ -> ()
    | exception Unix.Unix_error (Unix.EINTR, _, _) -> wait () in
  wait ();
  let others =
    let ic = open_in results in
    let rec read acc = match input_line ic with
      | l -> (match String.split_on_char ' ' l with
          | [ i; k ] -> let k = int_of_string k in read ((int_of_string i, if k = 0 then None else Some k) :: acc)
          | _ -> read acc)
      | exception End_of_file -> acc in
    let l = read [] in close_in ic; Sys.remove results; l in
  let rows = List.map (fun (i, d) ->
      (d, match List.assoc_opt i own with Some k -> k | None -> Option.join (List.assoc_opt i others))) indexed in
  let killed = List.filter (fun (_, k) -> k <> None) rows in
  let survivors = List.filter (fun ((d : Defects.t), k) -> d.can_differ && d.blind = None && k = None) rows in
  Printf.printf "%d of %d defects killed by %d generated programs (seed %d), judged (%d defects can show in a trace)\n"
    (List.length killed) (List.length rows) n seed
    (List.length (List.filter (fun ((d : Defects.t), _) -> d.can_differ) rows));
  Printf.printf "(in %.0f s)\n" (Unix.gettimeofday () -. t0);
  if survivors <> [] then
    Printf.printf "survivors that a trace can show: %s\n"
      (String.concat ", " (List.map (fun ((d : Defects.t), _) -> d.name) survivors));
  0

let run vectors first only judge generated seed =
  match generated with
  | Some n when n < 1 || n > 1_000_000 ->
    prerr_endline (Printf.sprintf "jadescript-ref: error: --generated %d: a number of programs from 1 to 1000000" n); 1
  | _ ->
  let unknown = List.filter (fun n -> Defects.find n = None) only in
  if unknown <> [] then begin
    prerr_endline ("jadescript-ref: error: unknown defect " ^ String.concat ", " unknown); 1
  end else
  let ds = if only = [] then Defects.all else List.filter (fun (d : Defects.t) -> List.mem d.name only) Defects.all in
  match generated with
  | Some n -> run_generated ds n seed
  | None ->
  let first = first || judge in
  let t0 = Unix.gettimeofday () in
  let dir = Cmd_conform.find_vectors vectors in
  match O.load dir with
  | exception (Failure m | Sys_error m) -> prerr_endline (dir ^ ":1:1: error: " ^ m); 1
  | vs ->
    let exe = Filename.quote (self ()) in
    (* a vector the reference itself fails judges nothing: it is left out *)
    let vs = List.filter (fun (v : O.vector) ->
        match O.run_vector ~impl:(exe ^ " run") v with
        | O.Pass -> true
        | _ -> Printf.printf "vector %s: the reference fails it; left out\n%!" v.name; false) vs in
    let rows = List.map (fun (d : Defects.t) ->
        let impl = exe ^ " run --defect " ^ Filename.quote d.name in
        let kills (v : O.vector) =
          if judge then
            Result.is_error (Judged.judge_case ~spawn:Cmd_conform.spawn ~timeout:(O.default_timeout v) ~impl
                               (Judged.of_vector v))
          else match O.run_vector ~impl v with O.Pass -> false | O.Diverge _ | O.Failed _ -> true in
        let rec go acc = function
          | [] -> List.rev acc
          | (v : O.vector) :: rest ->
            if not (kills v) then go acc rest
            else if first then [ v.name ] else go (v.name :: acc) rest in
        (* judged, a defect the judge cannot see is not run *)
        let killers = match judge, d.blind with true, Some _ -> [] | _ -> go [] vs in
        let verdict = match killers, d.can_differ, d.blind with
          | [], true, Some why when judge -> "survives (the judge cannot see it: " ^ why ^ ")"
          | [], true, _ -> "SURVIVES"
          | [], false, _ -> "survives (no trace can show it)"
          | l, _, _ -> "killed by " ^ String.concat " " (List.map short l) ^ (if first then " (first found)" else "") in
        Printf.printf "%-30s %-5s %-60s %s\n%!" d.name d.ruling d.about verdict;
        (d, killers)) ds in
    let killed = List.filter (fun (_, k) -> k <> []) rows in
    let must = List.filter (fun ((d : Defects.t), _) -> d.can_differ) rows in
    let survivors = List.filter (fun ((d : Defects.t), k) -> d.can_differ && k = [] && not (judge && d.blind <> None)) rows in
    Printf.printf "%d of %d defects killed by the vectors%s (%d vectors; %d defects can show in a trace)\n"
      (List.length killed) (List.length rows) (if judge then ", judged" else " alone") (List.length vs)
      (List.length must);
    Printf.printf "(in %.0f s)\n" (Unix.gettimeofday () -. t0);
    if survivors <> [] then
      Printf.printf "survivors that a trace can show: %s\n"
        (String.concat ", " (List.map (fun ((d : Defects.t), _) -> d.name) survivors));
    (* one test per defect: killed, or no trace can show it; judged, the
       survivors are counted, not failed *)
    if judge then 0
    else begin
      Printf.printf "%d passed, %d failed\n" (List.length rows - List.length survivors) (List.length survivors);
      if survivors = [] then 0 else 1
    end

let cmd =
  let vectors = Arg.(value & opt (some string) None & info ["vectors"] ~docv:"DIR"
                       ~doc:"The folder of vectors (default: conformance/ of the repository).") in
  let first = Arg.(value & flag & info ["first"]
                     ~doc:"Stop at the first vector that kills each defect (fast: the test suite's way).") in
  let only = Arg.(value & pos_all string [] & info [] ~docv:"DEFECT" ~doc:"Only these defects.") in
  let judge = Arg.(value & flag & info ["judge"]
                     ~doc:"Judge each defect's run of a vector by the program's semantics (as conform \
                           --judge) instead of comparing it with the expected trace; the first vector \
                           that kills a defect ends its row.") in
  let generated = Arg.(value & opt (some int) None & info ["generated"] ~docv:"N"
                         ~doc:"Instead of the vectors, conform --generated's programs 1 to N of the seed, \
                               each judged; the first that kills a defect ends its row.") in
  let seed = Arg.(value & opt int 1 & info ["seed"] ~docv:"S" ~doc:"The seed of --generated (default 1).") in
  Cmd.v (Cmd.info "defects" ~doc:"The conformance vectors' kill count over the bug catalogue."
           ~man:[`S Manpage.s_description;
                 `P "Runs every deliberate defect of the bug catalogue (lib/defects, \
                     conformance/README.md) as an implementation, $(i,jadescript-ref run --defect NAME), \
                     on every conformance vector, and prints which vectors kill it (conform \
                     fails). Ends with $(i,K of N defects killed by the vectors alone) and \
                     $(i,N passed, M failed) (a defect passes when a vector kills it, or when \
                     no trace can show it). Exit status 1 when a defect a trace can show \
                     survives every vector.";
                 `P "With $(b,--judge) or $(b,--generated) N the runs are judged instead \
                     (conform --judge, conform --generated), each defect's row ends at its first \
                     killing case, and the last line is $(i,K of N defects killed by ...); exit \
                     status 0 (a judged survivor may run a schedule the rulings allow, R6)."])
    Term.(const run $ vectors $ first $ only $ judge $ generated $ seed)
