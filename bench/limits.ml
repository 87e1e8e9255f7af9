(* bench.exe limits: each reader and command at its documented limit
   (README.md, "Limits"), run as a child process under /usr/bin/time: its
   wall-clock time and peak memory (maximum resident set). Each documented
   limit must be one the machine holds (2 cores, 24 GB).

     bench.exe limits            every measure but the 25,000,000 states
     bench.exe limits all        also explore --max-states 25000000
     bench.exe limits NAME...    only these (the names of the table) *)

let root () =
  let rec up d =
    if Sys.file_exists (Filename.concat d "bench/models/MCBenchLarge.tla") then d
    else let u = Filename.dirname d in if u = d then Sys.getcwd () else up u in
  (* the tree the command is run in (make bench runs it at the root) *)
  up (Sys.getcwd ())

let write_file path f =
  let oc = open_out_bin path in
  Fun.protect ~finally:(fun () -> close_out oc) (fun () -> f oc)

let rec remove_tree p =
  match (Unix.lstat p).st_kind with
  | Unix.S_DIR ->
    Array.iter (fun f -> remove_tree (Filename.concat p f)) (Sys.readdir p);
    (try Unix.rmdir p with Unix.Unix_error _ -> ())
  | _ -> (try Sys.remove p with Sys_error _ -> ())
  | exception Unix.Unix_error _ -> ()

(* Runs argv under /usr/bin/time in [dir]: (exit status, wall-clock
   seconds, processor seconds (user and system: on a loaded machine the
   wall clock counts the other tenants too), peak MB, the last line of
   standard error). *)
let measure ~dir argv =
  let tf = Filename.concat dir "time.txt" and err = Filename.concat dir "stderr.txt" in
  let cmd = Printf.sprintf "cd %s && /usr/bin/time -f '%%e %%U %%S %%M' -o %s %s > /dev/null 2> %s"
      (Filename.quote dir) (Filename.quote tf) (String.concat " " (List.map Filename.quote argv)) (Filename.quote err) in
  let status = Sys.command cmd in
  let first f = try let ic = open_in f in Fun.protect ~finally:(fun () -> close_in ic)
                      (fun () -> let rec last l = match input_line ic with
                           | s -> last (if l = "" then s else l) | exception End_of_file -> l in last "")
    with Sys_error _ -> "" in
  let times = try let ic = open_in tf in
      Fun.protect ~finally:(fun () -> close_in ic) (fun () ->
          (* /usr/bin/time writes "Command exited with non-zero status N" first *)
          let rec go l = match input_line ic with s -> go s | exception End_of_file -> l in go "")
    with Sys_error _ -> "" in
  let (secs, cpu, kb) = match String.split_on_char ' ' times with
    | [ s; u; y; k ] -> (float_of_string_opt s,
                         (match float_of_string_opt u, float_of_string_opt y with
                          | Some u, Some y -> Some (u +. y) | _ -> None), int_of_string_opt k)
    | _ -> (None, None, None) in
  let e = first err in
  (status, Option.value secs ~default:nan, Option.value cpu ~default:nan, (match kb with Some k -> float_of_int k /. 1024. | None -> nan),
   if String.length e > 110 then String.sub e 0 110 ^ "..." else e)

type case = {
  name : string;        (* the table's row *)
  limit : string;       (* the documented limit *)
  prepare : string -> string list;   (* writes its inputs in the folder, gives the command's arguments *)
}

let program_tick =
  "ontology O\n\tproposition tick extends percept\n\tpredicate t(x as integer) extends percept\n\n\
   agent Ag uses ontology O\n\ton create do\n\t\tactivate behaviour H\n\n\
   cyclic behaviour H for agent Ag\n\ton percept when content matches tick do\n\t\tlog \"tick\"\n\
   \ton percept when content matches t(x) do\n\t\tlog x\n"

let events_line_bytes = 16 * 1024 * 1024

let cases exe = [
  { name = "events-line"; limit = "an events line of 16 MB (16,777,216 bytes)";
    prepare = (fun d ->
        write_file (Filename.concat d "p.jade") (fun oc -> output_string oc program_tick);
        write_file (Filename.concat d "e.jsonl") (fun oc ->
            (* the longest line the reader takes: padding inside the object *)
            let head = "{\"agent\": \"g\", \"notify\": \"tick\"" in
            output_string oc head;
            output_string oc (String.make (events_line_bytes - String.length head - 1) ' ');
            output_string oc "}\n{\"run\": 1}\n");
        [ exe; "run"; "p.jade"; "--agent"; "g:Ag"; "--events"; "e.jsonl" ]) };
  { name = "events-line+1"; limit = "an events line of 16 MB + 1 byte (refused)";
    prepare = (fun d ->
        write_file (Filename.concat d "p.jade") (fun oc -> output_string oc program_tick);
        write_file (Filename.concat d "e.jsonl") (fun oc ->
            let head = "{\"agent\": \"g\", \"notify\": \"tick\"" in
            output_string oc head;
            output_string oc (String.make (events_line_bytes - String.length head) ' ');
            output_string oc "}\n");
        [ exe; "run"; "p.jade"; "--agent"; "g:Ag"; "--events"; "e.jsonl" ]) };
  { name = "events-file"; limit = "an events file of 1,000,000 notifies (no byte limit: read once, line by line)";
    prepare = (fun d ->
        write_file (Filename.concat d "p.jade") (fun oc -> output_string oc program_tick);
        write_file (Filename.concat d "e.jsonl") (fun oc ->
            for i = 1 to 1_000_000 do Printf.fprintf oc "{\"agent\": \"g\", \"notify\": \"t(%d)\"}\n" i done);
        [ exe; "run"; "p.jade"; "--agent"; "g:Ag"; "--events"; "e.jsonl" ]) };
  { name = "json-1000"; limit = "an events line nested 1,000 deep (JSON's limit)";
    prepare = (fun d ->
        write_file (Filename.concat d "p.jade") (fun oc -> output_string oc program_tick);
        write_file (Filename.concat d "e.jsonl") (fun oc ->
            (* the object is level 1: 999 arrays inside it *)
            output_string oc "{\"agent\": \"g\", \"notify\": \"tick\", \"x\": ";
            output_string oc (String.make 999 '['); output_string oc (String.make 999 ']');
            output_string oc "}\n");
        [ exe; "run"; "p.jade"; "--agent"; "g:Ag"; "--events"; "e.jsonl" ]) };
  { name = "agents"; limit = "50,000 agents (run --agents FILE)";
    prepare = (fun d ->
        write_file (Filename.concat d "p.jade") (fun oc -> output_string oc program_tick);
        write_file (Filename.concat d "agents.txt") (fun oc ->
            for i = 1 to 50_000 do Printf.fprintf oc "a%d:Ag\n" i done);
        write_file (Filename.concat d "e.jsonl") (fun oc -> output_string oc "{\"agent\": \"a1\", \"notify\": \"tick\"}\n");
        [ exe; "run"; "p.jade"; "--agents"; "agents.txt"; "--events"; "e.jsonl" ]) };
  { name = "source-64mb"; limit = "a source file of 64 MB (check; a flat program of many behaviours)";
    prepare = (fun d ->
        write_file (Filename.concat d "big.jade") (fun oc ->
            let head = "ontology O\n\tproposition tick extends percept\n\nagent Ag uses ontology O\n\ton create do\n\t\tactivate behaviour B0\n\n" in
            output_string oc head;
            let written = ref (String.length head) and i = ref 0 in
            let limit = 64 * 1024 * 1024 - 200 in
            while !written < limit do
              let b = Printf.sprintf "cyclic behaviour B%d for agent Ag\n\ton percept when content matches tick do\n\t\tlog %d\n\n" !i !i in
              output_string oc b; written := !written + String.length b; incr i
            done);
        [ exe; "check"; "big.jade" ]) };
  { name = "sim-samples"; limit = "sim: 2,000,000 sensor samples (2,000 s, the four rates summing to 1,000 Hz)";
    prepare = (fun d ->
        write_file (Filename.concat d "s.json") (fun oc -> output_string oc
          "{\"name\": \"samples\", \"seed\": 1, \"duration_s\": 2000, \"corridor\": {\"length_m\": 10.0, \"width_m\": 2.0}, \"cubes\": [], \"start\": {\"x\": 0.5, \"y\": 1.0, \"heading_deg\": 0}, \"sensors\": {\"position_rate_hz\": 997, \"proximity_rate_hz\": 1, \"camera_rate_hz\": 1, \"imu_rate_hz\": 1}, \"agent\": {\"loop\": \"reference\"}}");
        [ exe; "sim"; "s.json"; "--out"; "out"; "--program"; Filename.concat (root ()) "examples/robome/robome.jade" ]) };
  { name = "sim-flood"; limit = "sim: a flood of 1,000,000 percepts (20,000 Hz for 50 s)";
    prepare = (fun d ->
        write_file (Filename.concat d "s.json") (fun oc -> output_string oc
          "{\"name\": \"flood\", \"seed\": 1, \"duration_s\": 60, \"corridor\": {\"length_m\": 10.0, \"width_m\": 2.0}, \"cubes\": [], \"start\": {\"x\": 0.5, \"y\": 1.0, \"heading_deg\": 0}, \"sensors\": {\"position_rate_hz\": 10}, \"flood\": {\"percept\": \"position\", \"rate_hz\": 20000, \"start_s\": 5, \"end_s\": 55, \"priority\": 2}, \"agent\": {\"loop\": \"reference\"}}");
        [ exe; "sim"; "s.json"; "--out"; "out"; "--program"; Filename.concat (root ()) "examples/robome/robome.jade" ]) };
  { name = "max-states-default"; limit = "explore --max-states 1,000,000 (the default) on MCBenchLarge (1.49M states)";
    prepare = (fun _ -> [ exe; "explore"; Filename.concat (root ()) "bench/models/MCBenchLarge.tla" ]) };
  { name = "max-states-max"; limit = "explore --max-states 25,000,000 (the maximum)";
    prepare = (fun _ -> [ exe; "explore"; Filename.concat (root ()) "bench/models/MCBenchLarge.tla";
                          "--max-states"; "25000000" ]) };
]

let run args =
  let r = root () in
  let exe = Filename.concat r "_build/default/bin/main.exe" in
  if not (Sys.file_exists exe) then (Printf.printf "limits: %s not found (dune build first)\n" exe; exit 2);
  let all = cases exe in
  let chosen = match args with
    | [] -> List.filter (fun c -> c.name <> "max-states-max") all
    | [ "all" ] -> all
    | names -> List.filter (fun c -> List.mem c.name names) all in
  Printf.printf "limits: %s\n" exe;
  Printf.printf "limits: each command at a documented limit, one child each (/usr/bin/time: wall clock, user + system time, max RSS)\n%!";
  Printf.printf "  %-20s %9s %8s %10s %7s  %s\n%!" "limit" "wall (s)" "cpu (s)" "peak (MB)" "status" "what";
  List.iter (fun c ->
      let d = Filename.concat (Filename.get_temp_dir_name ()) (Printf.sprintf "jsref-limits-%d-%s" (Unix.getpid ()) c.name) in
      (try Unix.mkdir d 0o700 with Unix.Unix_error _ -> ());
      Fun.protect ~finally:(fun () -> remove_tree d) (fun () ->
          let argv = c.prepare d in
          let (st, secs, cpu, mb, err) = measure ~dir:d argv in
          Printf.printf "  %-20s %9.1f %8.1f %10.0f %7d  %s%s\n%!" c.name secs cpu mb st c.limit
            (if err = "" then "" else "\n  " ^ String.make 20 ' ' ^ "  stderr: " ^ err))) chosen
