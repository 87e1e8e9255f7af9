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

let load root =
  Sys.readdir root |> Array.to_list |> List.sort compare
  |> List.filter (fun d -> Sys.is_directory (Filename.concat root d)
                           && Sys.file_exists (Filename.concat (Filename.concat root d) "vector.json"))
  |> List.map (fun d ->
      let dir = Filename.concat root d in
      let meta = match Yojson.Safe.from_file (Filename.concat dir "vector.json") with
        | `Assoc f -> f
        | _ -> failwith (dir ^ "/vector.json: not an object")
        | exception Yojson.Json_error m -> failwith (dir ^ "/vector.json: " ^ m) in
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
  read_file path |> String.split_on_char '\n'
  |> List.filter (fun l -> String.trim l <> "")
  |> List.rev_map (fun l -> match Yojson.Safe.from_string l with
      | j -> j
      | exception Yojson.Json_error m -> failwith (path ^ ": " ^ m))
  |> List.rev
  |> (function
      | `Assoc h :: rest when List.mem_assoc "trace" h -> rest
      | l -> l)

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

let strip ev = `Assoc (List.filter (fun (k, _) -> k <> "step") (fields ev))

let compare_traces ~expected ~got =
  let rec go i = function
    | [], [] -> Pass
    | e :: es, g :: gs ->
      if Yojson.Safe.equal (strip e) (strip g) then go (i + 1) (es, gs)
      else Diverge { index = i; expected = show (strip e); got = show (strip g) }
    | e :: _, [] -> Diverge { index = i; expected = show (strip e); got = "(the trace ends)" }
    | [], g :: _ -> Diverge { index = i; expected = "(the trace ends)"; got = show (strip g) } in
  go 1 (expected, got)

let run_vector ~impl v =
  let trace = Filename.temp_file "jsref-conform" ".jsonl" in
  Fun.protect ~finally:(fun () -> try Sys.remove trace with Sys_error _ -> ()) (fun () ->
      let cmd = Printf.sprintf "cd %s && %s %s %s --events events.jsonl --trace %s > /dev/null 2>&1"
          (Filename.quote v.dir) impl
          (String.concat " " (List.map Filename.quote v.files))
          (String.concat " " (List.map Filename.quote v.args))
          (Filename.quote trace) in
      let _code = Sys.command cmd in
      match read_trace trace with
      | [] -> Failed "the implementation wrote no trace"
      | got -> compare_traces ~expected:(read_trace (Filename.concat v.dir "expected.jsonl")) ~got
      | exception Failure m -> Failed m
      | exception Sys_error m -> Failed m)
