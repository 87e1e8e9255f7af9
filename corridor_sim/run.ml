type outcome = { result : Sim.result; metrics : Metrics.t }

let default_agent : (module Agent.AGENT) = (module Reference_controller)

let write_file path s =
  let oc = open_out_bin path in
  output_string oc s;
  close_out oc

let rec mkdir_p d =
  if d <> "" && d <> "." && d <> "/" && not (Sys.file_exists d) then begin
    mkdir_p (Filename.dirname d);
    Sys.mkdir d 0o755
  end

let run ?(agent = default_agent) ?trace (sc : Scenario.t) ~seed ~out_dir =
  let trace = match trace with Some t -> t | None -> out_dir <> None in
  let result = Sim.run ~trace agent sc ~seed in
  let metrics = Metrics.of_result result in
  (match out_dir with
   | None -> ()
   | Some dir ->
     mkdir_p dir;
     write_file (Filename.concat dir "report.json") (Report.to_string result metrics);
     write_file (Filename.concat dir "map.svg") (Svg.map result metrics);
     write_file (Filename.concat dir "timeline.svg") (Svg.timeline result metrics);
     if trace then write_file (Filename.concat dir "trace.txt") result.trace);
  { result; metrics }

type stats = { name : string; mean : float; min : float; max : float; n : int }

let progress_bar done_ total =
  let width = 30 in
  let filled = done_ * width / max 1 total in
  Printf.eprintf "\r[%s%s] %d/%d%!" (String.make filled '#') (String.make (width - filled) '.') done_ total

let batch ?(agent = default_agent) ?(progress = true) sc ~first_seed ~runs =
  if progress then progress_bar 0 runs;
  let outcomes = List.init runs (fun i ->
      let o = run ~agent ~trace:false sc ~seed:(first_seed + i) ~out_dir:None in
      if progress then progress_bar (i + 1) runs;
      o) in
  if progress then prerr_newline ();
  let stats = List.map (fun (name, f) ->
      let xs = List.filter (fun x -> not (Float.is_nan x)) (List.map (fun o -> f o.metrics) outcomes) in
      let n = List.length xs in
      if n = 0 then { name; mean = nan; min = nan; max = nan; n }
      else { name; n; mean = List.fold_left ( +. ) 0. xs /. float_of_int n;
             min = List.fold_left Float.min infinity xs; max = List.fold_left Float.max neg_infinity xs })
      Metrics.summary_fields in
  (stats, outcomes)

let table (sc : Scenario.t) ~first_seed ~runs stats =
  let b = Buffer.create 1024 in
  Printf.bprintf b "scenario %s, seeds %d..%d (%d runs), %.0f s each\n" sc.name first_seed (first_seed + runs - 1) runs sc.duration;
  let cell x = if Float.is_nan x then "-" else Printf.sprintf "%.3f" x in
  Printf.bprintf b "%-24s %12s %12s %12s\n" "metric" "mean" "min" "max";
  Printf.bprintf b "%s\n" (String.make 63 '-');
  List.iter (fun s ->
      Printf.bprintf b "%-24s %12s %12s %12s%s\n" s.name (cell s.mean) (cell s.min) (cell s.max)
        (if s.n < runs && s.n > 0 then Printf.sprintf "  (%d runs)" s.n else "")) stats;
  Buffer.contents b

let find_scenario name =
  if Sys.file_exists name then name
  else begin
    let file = if Filename.check_suffix name ".json" then name else name ^ ".json" in
    let rec up dir n =
      let p = Filename.concat (Filename.concat dir "scenarios") file in
      if Sys.file_exists p then p
      else if n = 0 || Filename.dirname dir = dir then raise (Scenario.Error ("no scenario " ^ name))
      else up (Filename.dirname dir) (n - 1) in
    up (Sys.getcwd ()) 8
  end

(* A run keeps little live (some 3 MB at the end of the paper
   scenario) and promotes steadily (the record of every dispatched percept),
   so the major collector's default pace marks the same live data again and
   again: a space overhead of 1000 (as Interp.Runtime.tune_gc for run) took
   15% off the instructions of a run and as much off its CPU time. The minor
   heap stays at the default 256k words (2 MB): the 32 MB of run's setting
   made the simulation 30% slower by CPU time (its allocation no longer fits
   the caches), and the bench's earlier parts set it in the same process.
   No compaction (max_overhead): with that space overhead the heap looked
   fragmented and was compacted in the middle of a run (4% of the
   interpreted agent's instructions). Once the dispatched percepts were
   kept in columns, a space overhead of 4000 took another 4% off the
   instructions of bench.exe sim (the marking), for 0.7 MB more at the
   peak of a run of the paper scenario (14.3 MB) and none over a batch of
   200 seeds (159 MB either way); 10000 and 100000 took less off. *)
let tune_gc () = Gc.set { (Gc.get ()) with Gc.space_overhead = 4000; max_overhead = 1_000_000; minor_heap_size = 262_144 }

let bench ?agent ?scenario ?(position_rate = 50.) () =
  let path = match scenario with Some p -> p | None -> find_scenario "paper" in
  let sc = Scenario.with_position_rate (Scenario.load path) position_rate in
  let t0 = Unix.gettimeofday () in
  let o = run ?agent ~trace:false sc ~seed:sc.seed ~out_dir:None in
  let t1 = Unix.gettimeofday () in
  (o.result.end_time, t1 -. t0)
