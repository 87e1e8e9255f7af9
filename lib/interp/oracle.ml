type vector = {
  name : string;
  dir : string;
  about : string;
  rulings : string list;
  args : string list;
  files : string list;
  expect : Yojson.Safe.t list;
}

let read_file path =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic)
    (fun () -> really_input_string ic (in_channel_length ic))

(* A vector.json is a few hundred bytes; a longer one is not read. *)
let max_vector = 1024 * 1024

let load root =
  Sys.readdir root |> Array.to_list |> List.sort compare
  |> List.filter (fun d -> Sys.is_directory (Filename.concat root d)
                           && Sys.file_exists (Filename.concat (Filename.concat root d) "vector.json"))
  |> List.map (fun d ->
      let dir = Filename.concat root d in
      let file = Filename.concat dir "vector.json" in
      let meta = match Json_read.of_file ~max_bytes:max_vector file with
        | Ok (`Assoc f) -> f
        | Ok _ -> failwith (file ^ ":1:1: error: not an object")
        | Error e -> failwith (Printf.sprintf "%s:%d:%d: error: %s" file e.line e.column e.message) in
      let strs f = match List.assoc_opt f meta with
        | Some (`List l) -> List.filter_map (function `String s -> Some s | _ -> None) l
        | _ -> [] in
      { name = d; dir;
        about = (match List.assoc_opt "about" meta with Some (`String s) -> s | _ -> "");
        rulings = strs "rulings"; args = strs "args";
        files = Sys.readdir dir |> Array.to_list |> List.sort compare
                |> List.filter (fun f -> Filename.check_suffix f ".jade");
        expect = (match List.assoc_opt "expect" meta with Some (`List l) -> l | _ -> []) })

let read_trace path =
  List.rev (Trace.fold_file path (fun acc n j ->
      ignore n; if acc = [] && Trace.is_header j then acc else j :: acc) [])

let fields = function `Assoc f -> f | _ -> []

let matches pattern ev =
  List.for_all (fun (k, v) -> match List.assoc_opt k (fields ev) with
      | Some w -> Yojson.Safe.equal v w
      | None -> false) (fields pattern)

let show j = Yojson.Safe.to_string j

let index_of p evs =
  let rec go i = function [] -> None | e :: r -> if matches p e then Some i else go (i + 1) r in
  go 0 evs

let check_one evs (a : Yojson.Safe.t) =
  let f = fields a in
  let get k = List.assoc_opt k f in
  match get "has", get "lacks", get "count", get "before", get "order" with
  | Some p, _, _, _, _ ->
    if List.exists (matches p) evs then Ok () else Error ("no event matches " ^ show p)
  | _, Some p, _, _, _ ->
    (match List.find_opt (matches p) evs with
     | None -> Ok ()
     | Some e -> Error ("an event matches " ^ show p ^ ": " ^ show e))
  | _, _, Some p, _, _ ->
    let n = List.length (List.filter (matches p) evs) in
    (match get "is" with
     | Some (`Int k) when k = n -> Ok ()
     | Some (`Int k) -> Error (Printf.sprintf "%d events match %s, not %d" n (show p) k)
     | _ -> Error "count needs \"is\"")
  | _, _, _, Some (`List [ p; q ]), _ ->
    (match index_of p evs, index_of q evs with
     | Some i, Some j when i < j -> Ok ()
     | Some _, Some _ -> Error (Printf.sprintf "%s does not come before %s" (show p) (show q))
     | None, _ -> Error ("no event matches " ^ show p)
     | _, None -> Error ("no event matches " ^ show q))
  | _, _, _, _, Some p ->
    (match get "field", get "is" with
     | Some (`String fld), Some (`List want) ->
       let got = List.filter_map (fun e -> if matches p e then List.assoc_opt fld (fields e) else None) evs in
       if List.length got = List.length want && List.for_all2 Yojson.Safe.equal got want then Ok ()
       else Error (Printf.sprintf "%s of %s: %s, not %s" fld (show p) (show (`List got)) (show (`List want)))
     | _ -> Error "order needs \"field\" and \"is\"")
  | _ -> Error ("unknown assertion " ^ show a)

let check_expectations expect evs =
  List.fold_left (fun acc a -> match acc with Error _ -> acc | Ok () -> check_one evs a) (Ok ()) expect

type outcome =
  | Pass
  | Diverge of { index : int; expected : string; got : string }
  | Failed of string

let strip = Trace.without_step

(* ------------------------------------------------- judging a run *)

let sorted_fields j =
  let rec norm (j : Yojson.Safe.t) : Yojson.Safe.t = match j with
    | `Assoc f -> `Assoc (List.sort (fun (a, _) (b, _) -> compare a b) (List.map (fun (k, v) -> (k, norm v)) f))
    | `List l -> `List (List.map norm l)
    | j -> j in
  norm j

let header_problem ~expected (line : string) =
  match Json_read.of_string line with
  | Error _ -> Some "its first line is not JSON (a header is required, docs/trace-format.md)"
  | Ok (`Assoc _ as got) ->
    (match Trace.header_version got with
     | Some (`Int v) when v = Trace.version ->
       (* where the implementation ran its agents (D47) is its own: a
          vector fixes the program and the run, not the containers *)
       let deployed = Trace.without_containers got in
       if Yojson.Safe.equal (sorted_fields expected) (sorted_fields deployed) then None
       else Some (Printf.sprintf "its header differs: expected %s, got %s" (show expected) (show got))
     | Some v ->
       Some (Printf.sprintf "its header has version %s; this oracle reads version %d" (show v) Trace.version)
     | None -> Some (Printf.sprintf "its first line is not a header ({\"trace\":\"jadescript-ref\",\"version\":%d,...})" Trace.version))
   | Ok _ -> Some "its first line is not a header object"

let has_error_event evs = List.exists Trace.is_error evs

(* The longest trace line read: an event of the reference is a few hundred
   bytes; a line longer than this is not read into memory. *)
let max_line = 1 lsl 20

(* One line of at most [max_line] bytes (a longer one is cut there, and the
   rest of it skipped); None at the end of the file. *)
let bounded_line ic =
  let b = Buffer.create 256 in
  let rec go () = match input_char ic with
    | '\n' -> Some (Buffer.contents b)
    | c -> if Buffer.length b < max_line then Buffer.add_char b c; go ()
    | exception End_of_file -> if Buffer.length b = 0 then None else Some (Buffer.contents b) in
  go ()

(* Compare the trace file [got] with the expected events, reading it one line
   at a time: memory is bounded by the expected trace (and [max_line]),
   whatever [got] holds. *)
let compare_stream ~expected_header ~expected got =
  let ic = open_in_bin got in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      let rec next () = match bounded_line ic with
        | Some l when String.trim l = "" -> next ()
        | Some l when String.length l >= max_line ->
          Some (Printf.sprintf "(a line of more than %d bytes)" max_line)
        | r -> r in
      match next () with
      | None -> `Failed "the implementation wrote an empty trace"
      | Some h ->
        match header_problem ~expected:expected_header h with
        | Some p -> `Failed p
        | None ->
          let rec go i errors = function
            | [] ->
              (match next () with
               | None -> `Pass errors
               | Some l -> `Diverge (i, "(the trace ends)", l))
            | e :: es ->
              match next () with
              | None -> `Diverge (i, show (strip e), "(the trace ends)")
              | Some l ->
                match Json_read.of_string l with
                | Error m -> `Diverge (i, show (strip e), "not JSON (" ^ m.message ^ "): " ^ Json_read.printable l)
                | Ok g ->
                  if Yojson.Safe.equal (strip e) (strip g) then go (i + 1) (errors || has_error_event [ g ]) es
                  else `Diverge (i, show (strip e), show (strip g)) in
          go 1 false expected)

(* The first line of the implementation's stderr, at most 300 bytes. *)
let first_line path =
  match open_in_bin path with
  | exception Sys_error _ -> ""
  | ic -> Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      let b = Buffer.create 80 in
      let rec go () = match input_char ic with
        | '\n' -> ()
        | c -> if Buffer.length b < 300 then (Buffer.add_char b c; go ())
        | exception End_of_file -> () in
      go ();
      Buffer.contents b)

(* The shell's status: 0-125 an exit status, 124 from timeout(1), 128+n a signal. *)
let describe_status ~timeout code =
  if code = 124 then Printf.sprintf "timed out after %g s (--timeout)" timeout
  else if code = 137 then Printf.sprintf "killed after %g s (--timeout)" timeout
  else if code > 128 then Printf.sprintf "was killed by signal %d" (code - 128)
  else Printf.sprintf "exited with status %d" code

let default_timeout v =
  let n = try List.length (read_trace (Filename.concat v.dir "expected.jsonl")) with Failure _ | Sys_error _ -> 0 in
  30. +. 0.05 *. float_of_int n

(* Run [sh -c cmd] under timeout(1), standard output to /dev/null and standard
   error to [errs]; its status as the shell gives it (128 + n: signal n).
   [jadescript-ref conform] passes its own, which is interruptible
   (bin/cmd_conform.ml); this library does not link Unix, since the
   playground compiles it to JavaScript. *)
let system_under_timeout ~timeout ~errs cmd =
  Sys.command (Printf.sprintf "timeout --kill-after=5 %g /bin/sh -c %s > /dev/null 2> %s"
                 timeout (Filename.quote cmd) (Filename.quote errs))

let run_vector ?(spawn = system_under_timeout) ?timeout ?keep ?workdir ~impl v =
  let timeout = match timeout with Some t -> t | None -> default_timeout v in
  (* the expected trace is read before the implementation runs: what it
     might write there meanwhile changes nothing *)
  let expected =
    let path = Filename.concat v.dir "expected.jsonl" in
    match
      let header = match String.split_on_char '\n' (read_file path) with
        | h :: _ ->
          (match Json_read.of_string h with
           | Ok j -> j
           | Error e -> failwith (Printf.sprintf "%s:1:%d: error: %s" path e.column e.message))
        | [] -> failwith (path ^ ": empty") in
      (header, read_trace path)
    with
    | r -> Ok r
    | exception (Failure m | Sys_error m) -> Error m in
  match expected with
  | Error m -> Failed ("the vector is broken: " ^ m)
  | Ok (expected_header, expected) ->
  let trace = Filename.temp_file "jsref-conform" ".jsonl" in
  let errs = Filename.temp_file "jsref-conform" ".err" in
  Fun.protect ~finally:(fun () ->
      (match keep with
       | Some dir ->
         (* keep the implementation's trace: DIR/NAME.jsonl *)
         let dst = Filename.concat dir (v.name ^ ".jsonl") in
         (try Sys.rename trace dst
          with Sys_error _ -> ignore (Sys.command (Printf.sprintf "cp %s %s" (Filename.quote trace) (Filename.quote dst))))
       | None -> ());
      List.iter (fun f -> try Sys.remove f with Sys_error _ -> ()) [ trace; errs ]) (fun () ->
      let cmd = Printf.sprintf "cd %s && %s %s %s --events events.jsonl --trace %s"
          (Filename.quote (Option.value workdir ~default:v.dir)) impl
          (String.concat " " (List.map Filename.quote v.files))
          (String.concat " " (List.map Filename.quote v.args))
          (Filename.quote trace) in
      let code = spawn ~timeout ~errs cmd in
      let because m = match first_line errs with "" -> m | l -> m ^ " (its stderr: " ^ l ^ ")" in
      if code <> 0 && code <> 1 then Failed (because ("the implementation " ^ describe_status ~timeout code))
      else match compare_stream ~expected_header ~expected trace with
        | exception (Sys_error m) -> Failed (because m)
        | `Failed m -> Failed (because m)
        | `Diverge (index, expected, got) -> Diverge { index; expected; got }
        | `Pass errors ->
          (* D15: status 1 exactly when the run recorded a run-time error *)
          if code = 1 && not errors then Failed (because "the implementation exited with status 1, but its trace records no run-time error")
          else if code = 0 && errors then Failed "the implementation exited with status 0, but its trace records a run-time error (D15: status 1)"
          else Pass)
