let seed =
  match Sys.getenv_opt "QCHECK_SEED" with
  | Some s -> (match int_of_string_opt s with Some n -> n | None -> 42)
  | None -> 42

let long = Sys.getenv_opt "JSREF_LONG" = Some "1"

(* JSREF_QCHECK_COUNT=N: every property N times (the fuzz campaign's
   engine target runs one property with a seed and a count of its own). *)
let qcheck ?(count = 200) ?(long_factor = 10) name arb prop =
  let count = if long then count * long_factor else count in
  let count = match Option.bind (Sys.getenv_opt "JSREF_QCHECK_COUNT") int_of_string_opt with
    | Some n when n > 0 -> n
    | _ -> count in
  let test = QCheck.Test.make ~count ~name arb prop in
  Alcotest.test_case name `Quick (fun () ->
      try QCheck.Test.check_exn ~rand:(Random.State.make [| seed |]) test
      with e ->
        Alcotest.failf "%s (QCHECK_SEED=%d)" (Printexc.to_string e) seed)

let rec find_root dir =
  if Sys.file_exists (Filename.concat dir "dune-project")
  && Sys.file_exists (Filename.concat dir "examples") then dir
  else
    let parent = Filename.dirname dir in
    if parent = dir then failwith "repository root not found" else find_root parent

(* The build directory: _build, or DUNE_BUILD_DIR when set. *)
let build_dir = match Sys.getenv_opt "DUNE_BUILD_DIR" with
  | Some d when d <> "" -> Filename.basename d
  | _ -> "_build"

let root =
  (* Under dune the tests run in _build/default/test: climb out of _build. *)
  let cwd = Sys.getcwd () in
  let rec strip_build d =
    if Filename.basename d = build_dir then Filename.dirname d
    else let p = Filename.dirname d in if p = d then cwd else strip_build p in
  find_root (strip_build cwd)

let read_file path =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in ic)
    (fun () -> really_input_string ic (in_channel_length ic))

let run_command cmd =
  let out = Filename.temp_file "jsref" ".out" and err = Filename.temp_file "jsref" ".err" in
  let status = Sys.command (Printf.sprintf "%s >%s 2>%s </dev/null" cmd
                              (Filename.quote out) (Filename.quote err)) in
  let o = read_file out and e = read_file err in
  Sys.remove out; Sys.remove err;
  (status, o, e)

let exe = Filename.concat root (build_dir ^ "/default/bin/main.exe")

(* The bench's workload (bench/programs/percepts.jade) with a log in each
   handler, for the tests that hold the engine equal to the rules; [types]
   and [handlers] (of the behaviour Others) are added to it. *)
let bench_workload ?(types = []) ?(handlers = []) () =
  String.concat "\n" ([
    "ontology Load";
    "\tproposition falling extends percept with priority = 10";
    "\tpredicate obstacle(d as integer) extends percept with priority = 8";
    "\tpredicate qrCodeRead(qrCode as text) extends percept with priority = 4";
    "\tpredicate position(k as integer) extends percept with priority = 2" ]
    @ List.map (fun t -> "\t" ^ t) types
    @ [ "";
        "agent Ag uses ontology Load";
        "\tproperty counts as map of integer:integer = {}";
        "\tproperty falls as integer = 0";
        "";
        "\ton create do";
        "\t\tactivate behaviour Positions";
        "\t\tactivate behaviour Others";
        "\t\tactivate behaviour Watch";
        "";
        "cyclic behaviour Positions for agent Ag";
        "\ton percept when content matches position(k) do";
        "\t\tcounts[k] = k";
        "\t\tlog \"position \" + k";
        "";
        "cyclic behaviour Others for agent Ag";
        "\ton percept when content matches obstacle(d) do";
        "\t\tcounts[d] = d";
        "\t\tlog \"obstacle \" + d";
        "";
        "\ton percept when content matches qrCodeRead(q) do";
        "\t\tfalls = falls + 1";
        "\t\tlog \"qr \" + q" ]
    @ List.concat_map (fun (head, body) -> [ ""; "\ton percept when content matches " ^ head ^ " do"; "\t\t" ^ body ]) handlers
    @ [ "";
        "cyclic behaviour Watch for agent Ag";
        "\ton percept when content matches falling do";
        "\t\tfalls = falls + 1";
        "\t\tlog \"falling\"";
        "" ])

(* A file of this name and text in a directory of its own (so that two
   test processes running at once never share it), removed after [f]. *)
let with_file name text f =
  let dir = Filename.temp_file "jsref_test" "" in
  Sys.remove dir;
  Unix.mkdir dir 0o700;
  let p = Filename.concat dir name in
  let oc = open_out_bin p in output_string oc text; close_out oc;
  Fun.protect ~finally:(fun () -> (try Sys.remove p with Sys_error _ -> ()); (try Unix.rmdir dir with Unix.Unix_error _ -> ()))
    (fun () -> f p)

(* Texts for the escaping functions' round trips: each piece an ASCII byte
   (any, control characters, NUL and DEL included), one of the bytes every
   escaper treats apart, or a UTF-8 character of 2, 3 or 4 bytes. *)
let tricky_text =
  let open QCheck.Gen in
  let utf8 cp =
    let b = Buffer.create 4 in
    Buffer.add_utf_8_uchar b (Uchar.of_int cp);
    Buffer.contents b in
  let piece = frequency [
      (3, map (fun c -> String.make 1 (Char.chr c)) (int_bound 127));
      (3, oneofl [ "\""; "\\"; "\n"; "\r"; "\t"; "\012"; "\b"; "\000"; "\127"; "'"; "\\u0041"; "*/"; "&"; "<" ]);
      (1, map utf8 (int_range 0x80 0x7FF));
      (1, map utf8 (oneof [ int_range 0x800 0xD7FF; int_range 0xE000 0xFFFF ]));
      (1, map utf8 (int_range 0x10000 0x10FFFF));
      (1, oneofl [ utf8 0xE9; utf8 0x2028; utf8 0xFEFF; utf8 0xFFFD; utf8 0x1F600 ]) ] in
  QCheck.make ~print:(Printf.sprintf "%S") (map (String.concat "") (list_size (int_bound 12) piece))

let write_lines path lines =
  let oc = open_out_bin path in
  List.iter (fun l -> output_string oc l; output_char oc '\n') lines;
  close_out oc

let lines_of path =
  List.filter (fun l -> String.trim l <> "") (String.split_on_char '\n' (read_file path))

let with_lines lines k =
  let f = Filename.temp_file "jsref-lines" ".jsonl" in
  write_lines f lines;
  Fun.protect ~finally:(fun () -> Sys.remove f) (fun () -> k f)
