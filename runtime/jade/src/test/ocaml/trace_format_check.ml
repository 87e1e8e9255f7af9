(* The Java runtime's trace writer against the OCaml owner of the format,
   lib/trace (docs/jade.md, "The trace"). runtime/jade/test runs
   TraceFormatCheck.java, which writes a trace with one line of every kind,
   each by its method of the Java writer (SAMPLES), and the names its class
   TraceFormat declares (NAMES); then this program checks:
   - every line of SAMPLES is read by Trace.header_of_json or
     Trace.line_of_json (strictly: every field and no other, of its JSON
     type, the action of its event) and written again byte for byte as the
     Java wrote it (so the names, their order and the values' encoding are
     the OCaml codec's);
   - the Java wrote every kind of line that the OCaml samples below have,
     and no other: [kind] matches every constructor of Trace.event without a
     wildcard, so a new event does not compile until it has a kind, and
     then a sample here;
   - NAMES are exactly the names the OCaml codec writes: event names, fields
     of a line (and of a behaviour step's message), actions, and the
     header's fields.
   Usage: trace_format_check SAMPLES NAMES. Prints "N passed, M failed". *)

let passed = ref 0
let failed = ref 0

let check what ok =
  if ok then incr passed
  else begin incr failed; Printf.printf "FAIL: %s\n" what end

(* The kind of a line: its constructor, and the variants that write other
   fields or names. *)
let kind (l : Trace.line) =
  match l.event with
  | Trace.Create _ -> "create"
  | Trace.Notify { overridden = false; _ } -> "notify"
  | Trace.Notify { overridden = true; _ } -> "notify (NotifyWith)"
  | Trace.Refused _ -> "refused (a percept)"
  | Trace.Refused_put _ -> "refused (an object)"
  | Trace.Put _ -> "put"
  | Trace.Deliver _ -> "deliver"
  | Trace.Undeliverable _ -> "undeliverable"
  | Trace.Transfer _ -> "transfer"
  | Trace.Transfer_one _ -> "transfer_one"
  | Trace.Transfer_spin _ -> "transfer_spin"
  | Trace.Transfer_end -> "transfer_end"
  | Trace.Dequeue _ -> "dequeue"
  | Trace.Handle _ -> "handle"
  | Trace.Skip _ -> "skip"
  | Trace.End_dispatch { discarded = false; _ } -> "end_dispatch"
  | Trace.End_dispatch { discarded = true; _ } -> "discard"
  | Trace.Behaviour_step { taken; action_effects; handler; _ } ->
    Printf.sprintf "behaviour_step (%s%s%s)"
      (match taken with
       | None -> "took nothing"
       | Some (Trace.Took_message _) -> "took a message"
       | Some (Trace.Took_percept _) -> "took a percept")
      (match action_effects with None -> "" | Some _ -> ", action_effects")
      (match handler with None -> "" | Some _ -> ", handler")
  | Trace.Next_iteration -> "next_iteration"
  | Trace.Idle -> "idle"
  | Trace.Destroy -> "destroy"
  | Trace.Body { body; _ } ->
    (match body with
     | Trace.Log _ -> "log"
     | Trace.Invoke _ -> "invoke"
     | Trace.Send _ -> "send"
     | Trace.Activate _ -> "activate"
     | Trace.Deactivate _ -> "deactivate"
     | Trace.Error _ -> "error")

(* One line of every kind, and the events of on destroy (action "destroy"). *)
let samples =
  let e = { Trace.percept = "p"; priority = 2; seq = 1 } in
  let m = { Trace.performative = "inform"; content = "c"; from = "b" } in
  let events = [
    Trace.Create { agent_type = "A"; args = [ "1" ]; behaviours = [ "W" ] };
    Trace.Notify { entry = e; overridden = false }; Trace.Notify { entry = e; overridden = true };
    Trace.Refused { percept = "p"; reason = "full" }; Trace.Refused_put { obj = "o"; reason = "full" };
    Trace.Put { obj = "o"; index = 1 }; Trace.Deliver { message = m; seq = 1; in_step = false };
    Trace.Deliver { message = m; seq = 2; in_step = true };
    Trace.Undeliverable { receiver = "z"; performative = "inform"; content = "c" };
    Trace.Transfer 1; Trace.Transfer_one e; Trace.Transfer_spin "o"; Trace.Transfer_end; Trace.Dequeue e;
    Trace.Handle { instance = 1; behaviour = "W"; handler = 1; percept = "p"; seq = 1;
                   effects = [ Trace.Activated "H"; Trace.Deactivated ] };
    Trace.Skip { instance = 1; behaviour = "W"; handler = 1 };
    Trace.End_dispatch { seq = 1; discarded = false }; Trace.End_dispatch { seq = 1; discarded = true };
    Trace.Behaviour_step { instance = 1; behaviour = "W"; taken = None; action_effects = None; handler = None };
    Trace.Behaviour_step { instance = 1; behaviour = "W"; taken = None; action_effects = Some []; handler = None };
    Trace.Behaviour_step { instance = 1; behaviour = "W"; taken = Some (Trace.Took_message (m, 1));
                           action_effects = None; handler = Some (1, []) };
    Trace.Behaviour_step { instance = 1; behaviour = "W"; taken = Some (Trace.Took_message (m, 1));
                           action_effects = Some [ Trace.Deactivated ]; handler = Some (1, []) };
    Trace.Behaviour_step { instance = 1; behaviour = "W"; taken = Some (Trace.Took_percept e);
                           action_effects = Some []; handler = Some (1, []) };
    Trace.Next_iteration; Trace.Idle; Trace.Destroy;
    Trace.Body { action = "Handle"; body = Trace.Log "l" };
    Trace.Body { action = "Init"; body = Trace.Invoke { meth = "m"; obj = "O"; args = [ "1" ]; result = "nothing" } };
    Trace.Body { action = "Handle"; body = Trace.Send { performative = "inform"; content = "c"; receivers = [ "a" ] } };
    Trace.Body { action = "Handle"; body = Trace.Activate "H" };
    Trace.Body { action = "Handle"; body = Trace.Deactivate 1 };
    Trace.Body { action = "destroy"; body = Trace.Error { at = "f:1:2"; message = "m" } } ] in
  List.mapi (fun i event -> { Trace.step = i + 1; agent = "a"; event }) events

let header_sample = {
  Trace.variant = "reference"; tie_policy = "stable"; budget = 1; o2a_capacity = None; seed = None;
  level = "full"; agents = [ ("a", "A") ]; containers = [ ("a", "c1") ];
  behaviours = [ { Trace.name = "W"; kind = "cyclic"; has_action = true; percept_handlers = 1; message_handlers = 1 } ];
  percepts = [ ("p", 2) ] }

module S = Set.Make (String)

let keys = function `Assoc f -> List.map fst f | _ -> []
let field k = function `Assoc f -> List.assoc_opt k f | _ -> None

(* The names the OCaml codec writes for its samples, by category. *)
let ocaml_names () =
  let lines = List.map Trace.line_to_json samples in
  let events = S.of_list (List.map (fun (l : Trace.line) -> Trace.event_name l.event) samples) in
  let fields = List.fold_left (fun s j ->
      let nested = match field "message" j with Some (`Assoc _ as m) -> keys m | _ -> [] in
      S.union s (S.of_list (keys j @ nested))) S.empty lines in
  let actions = S.of_list (List.filter_map (fun (l : Trace.line) -> Trace.action l.event) samples) in
  let h = Trace.header_to_json header_sample in
  let sub k = match field k h with Some j -> j | None -> `Null in
  let first = function `List (x :: _) -> x | _ -> `Null in
  let program = sub "program" in
  let header = S.of_list (keys h @ keys program @ keys (first (sub "agents"))
                          @ keys (first (match field "behaviours" program with Some j -> j | None -> `Null))) in
  (events, fields, actions, header)

let read_lines path =
  let ic = open_in_bin path in
  let rec go acc = match input_line ic with
    | l -> go (if String.trim l = "" then acc else l :: acc)
    | exception End_of_file -> close_in ic; List.rev acc in
  go []

let show s = String.concat ", " (S.elements s)

let same what ~java ~ocaml =
  check (Printf.sprintf "%s: the Java's lack %s" what (show (S.diff ocaml java))) (S.subset ocaml java);
  check (Printf.sprintf "%s: the OCaml owner has no %s" what (show (S.diff java ocaml))) (S.subset java ocaml)

let () =
  match Sys.argv with
  | [| _; samples_file; names_file |] ->
    (* the Java's lines, read and written again by the OCaml codec *)
    (match read_lines samples_file with
     | [] -> check "the Java samples are there" false
     | header :: lines ->
       (match Trace.header_of_json (Yojson.Safe.from_string header) with
        | Ok h -> check (Printf.sprintf "the header is written as the OCaml writes it:\n  java:  %s\n  ocaml: %s" header
                           (Yojson.Safe.to_string (Trace.header_to_json h)))
                    (Yojson.Safe.to_string (Trace.header_to_json h) = header)
        | Error m -> check (Printf.sprintf "the header is read by the OCaml: %s\n  %s" m header) false);
       let java_kinds = List.fold_left (fun acc text ->
           match Trace.line_of_json (Yojson.Safe.from_string text) with
           | Ok l ->
             let again = Yojson.Safe.to_string (Trace.line_to_json l) in
             check (Printf.sprintf "a %s line is written as the OCaml writes it:\n  java:  %s\n  ocaml: %s"
                      (kind l) text again) (again = text);
             S.add (kind l) acc
           | Error m -> check (Printf.sprintf "a line is read by the OCaml: %s\n  %s" m text) false; acc
           | exception Yojson.Json_error m -> check (Printf.sprintf "a line is JSON: %s\n  %s" m text) false; acc)
           S.empty lines in
       same "kinds of line" ~java:java_kinds ~ocaml:(S.of_list (List.map kind samples)));
    (* the Java's names against the OCaml's *)
    let names = List.filter_map (fun l -> match String.split_on_char ' ' l with
        | [ c; n ] -> Some (c, n)
        | _ -> check ("a line of NAMES is CATEGORY NAME: " ^ l) false; None) (read_lines names_file) in
    let java c = S.of_list (List.filter_map (fun (c', n) -> if c = c' then Some n else None) names) in
    let (events, fields, actions, header) = ocaml_names () in
    same "event names" ~java:(java "event") ~ocaml:events;
    same "fields of a line" ~java:(java "field") ~ocaml:fields;
    same "actions" ~java:(java "action") ~ocaml:actions;
    check (Printf.sprintf "header fields: the Java's lack %s"
             (show (S.diff header (S.union (java "header") (java "field")))))
      (S.subset header (S.union (java "header") (java "field")));
    check (Printf.sprintf "header fields: the OCaml owner has no %s" (show (S.diff (java "header") header)))
      (S.subset (java "header") header);
    Printf.printf "%d passed, %d failed\n" !passed !failed;
    exit (if !failed = 0 then 0 else 1)
  | _ ->
    prerr_endline "usage: trace_format_check SAMPLES NAMES";
    exit 2
