type verdict =
  | Accepted of { agent : string; steps : int }
  | Rejected of { agent : string; line : int; step : string; after : int }
  | Cannot of { agent : string; line : int; reason : string }

exception Cannot_express of int * string

let str s = Tla.Str s
let int i = Tla.Int i

let read_lines path =
  let text = Tlc.read_file path in
  String.split_on_char '\n' text
  |> List.rev_map String.trim |> List.rev
  |> List.fold_left (fun (n, acc) l -> (n + 1, if l = "" then acc else (n, l) :: acc)) (1, [])
  |> snd |> List.rev_map (fun (n, l) ->
      match Yojson.Safe.from_string l with
      | `Assoc f -> (n, f)
      | _ -> failwith (Printf.sprintf "%s:%d:1: error: not a JSON object" path n)
      | exception Yojson.Json_error m ->
        failwith (Printf.sprintf "%s:%d:1: error: not JSON: %s" path n (String.concat " " (String.split_on_char '\n' m))))

let get f fields = List.assoc_opt f fields
let get_str f fields = match get f fields with Some (`String s) -> s | _ -> ""
let get_int f fields = match get f fields with Some (`Int i) -> i | _ -> 0
let get_strs f fields = match get f fields with
  | Some (`List l) -> List.filter_map (function `String s -> Some s | _ -> None) l
  | _ -> []

let percept_type lit =
  match String.index_opt lit '(' with Some i -> String.sub lit 0 i | None -> lit

let machine_events = [ "create"; "notify"; "put"; "deliver"; "transfer"; "transfer_one";
                       "transfer_spin"; "transfer_end"; "dequeue"; "handle"; "skip"; "discard";
                       "end_dispatch"; "behaviour_step"; "next_iteration"; "idle" ]

let effect_value line s =
  match String.split_on_char ' ' s with
  | [ "deactivate" ] -> Tla.record [ "op", str "deactivate" ]
  | [ "activate"; b ] -> Tla.record [ "op", str "activate"; "b", str b ]
  | _ -> raise (Cannot_express (line, "unknown effect " ^ s))

let model_of_trace path ~agent =
  try
    let lines = read_lines path in
    let (header, events) = match lines with
      | (_, h) :: rest when get_str "trace" h = "jadescript-ref" -> (h, rest)
      | _ -> failwith (Printf.sprintf "%s:1:1: error: not a jadescript-ref trace (no header line)" path) in
    let events = List.filter (fun (_, e) -> get_str "agent" e = agent) events in
    let program = match get "program" header with Some (`Assoc p) -> p | _ -> [] in
    let behaviours = match get "behaviours" program with
      | Some (`List l) -> List.filter_map (function `Assoc b -> Some b | _ -> None) l
      | _ -> [] in
    let percept_defaults = match get "percepts" program with
      | Some (`Assoc l) -> List.filter_map (function (n, `Int k) -> Some (n, k) | _ -> None) l
      | _ -> [] in
    (* The values of this run. *)
    let notified = ref [] and overrides = ref [] and puts = ref 0 and msgs = ref 0 in
    let initial = ref [] and activations = ref 0 in
    (* (behaviour, handler index) -> (value name, effects, line) list *)
    let ph = Hashtbl.create 8 and mh = Hashtbl.create 8 and action = Hashtbl.create 8 in
    (* Skips by instances still active, to find handlers whose when differs
       between instances of one type (a model cannot say that). *)
    let skipped = Hashtbl.create 8 and deactivated = Hashtbl.create 8 in
    let current = ref 0 in   (* the seq of the percept being dispatched *)
    let add tbl k v = Hashtbl.replace tbl k (v :: Option.value (Hashtbl.find_opt tbl k) ~default:[]) in
    let records = List.filter_map (fun (line, e) ->
        let ev = get_str "event" e in
        (match ev with
         | "deactivate" -> Hashtbl.replace deactivated (get_int "instance" e) ()
         | "activate" -> Hashtbl.reset deactivated
         | _ -> ());
        if not (List.mem ev machine_events) then None
        else
          let act = get_str "action" e in
          let r fields = Some (Tla.record (("act", str act) :: fields), line) in
          let entry e = [ "p", str ("n" ^ string_of_int (get_int "seq" e)); "prio", int (get_int "priority" e);
                          "seq", int (get_int "seq" e) ] in
          let effects_of f = List.map (effect_value line) (get_strs f e) in
          match ev with
          | "create" ->
            initial := get_strs "behaviours" e;
            Some (Tla.record [ "act", str "Init" ], line)
          | "notify" ->
            let seq = get_int "seq" e and prio = get_int "priority" e in
            let ty = percept_type (get_str "percept" e) in
            let default = match List.assoc_opt ty percept_defaults with
              | Some k -> k
              | None -> raise (Cannot_express (line, "percept type " ^ ty ^ " is not in the trace header")) in
            notified := (seq, default) :: !notified;
            if act = "NotifyWith" then overrides := prio :: !overrides;
            r (entry e)
          | "put" -> incr puts; r [ "obj", str ("o" ^ string_of_int (get_int "index" e)) ]
          | "deliver" ->
            msgs := max !msgs (get_int "seq" e);
            r [ "m", str ("m" ^ string_of_int (get_int "seq" e)); "seq", int (get_int "seq" e) ]
          | "transfer" -> r [ "moved", int (get_int "moved" e) ]
          | "transfer_one" -> r (entry e)
          | "transfer_spin" -> r [ "obj", str "o1" ]
          | "transfer_end" | "next_iteration" | "idle" -> r []
          | "dequeue" -> current := get_int "seq" e; r [ "e", Tla.record (entry e) ]
          | "handle" ->
            let effs = effects_of "effects" in
            activations := !activations + List.length effs;
            add ph (get_str "behaviour" e, get_int "handler" e)
              ("n" ^ string_of_int (get_int "seq" e), effs, line);
            r [ "id", int (get_int "instance" e); "h", int (get_int "handler" e);
                "p", str ("n" ^ string_of_int (get_int "seq" e)); "seq", int (get_int "seq" e) ]
          | "skip" ->
            if not (Hashtbl.mem deactivated (get_int "instance" e)) then
              Hashtbl.replace skipped (get_str "behaviour" e, get_int "handler" e, "n" ^ string_of_int !current) line;
            r [ "id", int (get_int "instance" e); "h", int (get_int "handler" e) ]
          | "discard" | "end_dispatch" ->
            r [ "seq", int (get_int "seq" e); "discarded", Tla.Bool (ev = "discard") ]
          | "behaviour_step" ->
            let b = get_str "behaviour" e in
            (match get "action_effects" e with
             | Some _ ->
               let effs = effects_of "action_effects" in
               activations := !activations + List.length effs;
               add action b (effs, line)
             | None -> ());
            let msg = match get "message" e with
              | Some (`Assoc m) when get "performative" m <> None ->
                let name = "m" ^ string_of_int (get_int "seq" m) in
                let effs = effects_of "effects" in
                activations := !activations + List.length effs;
                add mh (b, get_int "handler" e) (name, effs, line);
                Tla.record [ "kind", str "message"; "m", str name; "seq", int (get_int "seq" m) ]
              | Some (`Assoc m) ->
                let name = "n" ^ string_of_int (get_int "seq" m) in
                let effs = effects_of "effects" in
                activations := !activations + List.length effs;
                add ph (b, get_int "handler" e) (name, effs, line);
                Tla.record (("kind", str "percept") :: entry m)
              | _ -> Tla.record [ "kind", str "none" ] in
            r [ "id", int (get_int "instance" e); "msg", msg ]
          | _ -> None) events in
    if records = [] then raise (Cannot_express (1, "the trace has no step of agent " ^ agent));
    Hashtbl.iter (fun (b, h) uses ->
        List.iter (fun (n, _, _) ->
            match Hashtbl.find_opt skipped (b, h, n) with
            | Some line ->
              raise (Cannot_express (line, Printf.sprintf
                                       "handler %d of %s applied to percept %s for one instance and not for another \
                                        (its when depends on the instance); a model gives each handler of a behaviour \
                                        type one set of accepted percepts" h b n))
            | None -> ()) uses) ph;
    let names prefix n = if n = 0 then [ prefix ^ "0" ] else List.init n (fun i -> prefix ^ string_of_int (i + 1)) in
    let percepts = if !notified = [] then [ ("n0", 0) ]
      else List.sort compare (List.map (fun (s, d) -> ("n" ^ string_of_int s, d)) !notified) in
    let handlers tbl b count =
      Tla.Seq (List.init count (fun i ->
          let uses = List.rev (Option.value (Hashtbl.find_opt tbl (b, i + 1)) ~default:[]) in
          let accepts = Tla.set (List.map (fun (n, _, _) -> str n) uses) in
          let distinct = List.sort_uniq compare (List.map (fun (_, effs, _) -> effs) uses) in
          match distinct with
          | [] -> Tla.record [ "accepts", accepts; "effects", Tla.Seq [] ]
          | [ effs ] -> Tla.record [ "accepts", accepts; "effects", Tla.Seq effs ]
          | _ -> Tla.record [ "accepts", accepts; "effects", Tla.Seq [];
                              "byValue", Tla.record (List.map (fun (n, effs, _) -> (n, Tla.Seq effs)) uses) ])) in
    let bnames = List.map (get_str "name") behaviours in
    let per f = Tla.record (List.map (fun b -> (get_str "name" b, f b)) behaviours) in
    let action_effects b =
      let uses = List.rev (Option.value (Hashtbl.find_opt action (get_str "name" b)) ~default:[]) in
      match List.sort_uniq compare (List.map fst uses) with
      | [] -> Tla.Seq []
      | [ effs ] -> Tla.Seq effs
      | _ ->
        let (_, line) = List.nth uses 1 in
        raise (Cannot_express (line, Printf.sprintf
                                 "the action block of %s has different activate/deactivate effects in different steps; \
                                  a model gives each action block one list of effects" (get_str "name" b))) in
    let p = Semantics.Machine.string_of_variant in
    ignore p;
    let capacity = match get "o2a_capacity" header with
      | Some (`Int c) -> c
      | _ -> List.length !notified + !puts + 1 in
    let n_notify = List.length !notified in
    let constants = [
      "Variant", str (get_str "variant" header);
      "TiePolicy", str (if get_str "tie_policy" header = "unstable" then "Unstable" else "Stable");
      "Budget", int (max 1 (get_int "budget" header));
      "Percepts", Tla.set (List.map (fun (n, _) -> str n) percepts);
      "DefaultPriority", Tla.record (List.map (fun (n, d) -> (n, int d)) percepts);
      "Overrides", Tla.set (List.map int !overrides);
      "Objects", Tla.set (List.map str (names "o" !puts));
      "Messages", Tla.set (List.map str (names "m" !msgs));
      "MaxNotify", int n_notify;
      "MaxPut", int !puts;
      "MaxSend", int !msgs;
      "Flood", Tla.Bool false;
      "O2ACapacity", int (max 1 capacity);
      "Behaviours", Tla.set (List.map str bnames);
      "Kind", per (fun b -> str (get_str "kind" b));
      "HasAction", per (fun b -> Tla.Bool (get "action" b = Some (`Bool true)));
      "ActionEffects", per action_effects;
      "PerceptHandlers", per (fun b -> handlers ph (get_str "name" b) (get_int "percept_handlers" b));
      "MessageHandlers", per (fun b -> handlers mh (get_str "name" b) (get_int "message_handlers" b));
      "InitialBehaviours", Tla.Seq (List.map str !initial);
      "MaxActive", int (1 + List.length !initial + !activations);
      "InversionBound", int (n_notify + 1);
    ] in
    Ok (constants, records)
  with Cannot_express (line, reason) -> Error (line, reason)

let trace_module name (records : (Tla.t * int) list) =
  let b = Buffer.create 4096 in
  Printf.bprintf b "---- MODULE %s ----\n(* Generated by jadescript-ref validate. *)\nEXTENDS MCTrace, Naturals, Sequences\n\n" name;
  Buffer.add_string b "T == <<\n";
  List.iteri (fun i (r, _) ->
      if i > 0 then Buffer.add_string b ",\n";
      Buffer.add_string b "  "; Buffer.add_string b (Tla.to_string r)) records;
  Buffer.add_string b "\n>>\n\nVARIABLE traceIndex\n\n";
  Buffer.add_string b "TraceInit == Init /\\ traceIndex = 1 /\\ last = T[1]\n";
  Buffer.add_string b "TraceNext == \\/ /\\ traceIndex < Len(T)\n              /\\ Next\n              /\\ last' = T[traceIndex + 1]\n              /\\ traceIndex' = traceIndex + 1\n";
  Buffer.add_string b "             \\/ /\\ traceIndex = Len(T)\n                /\\ UNCHANGED <<vars, traceIndex>>\n====\n";
  Buffer.contents b

let agents_of path =
  match read_lines path with
  | (_, h) :: _ ->
    (match get "agents" h with
     | Some (`List l) when l <> [] -> List.filter_map (function `Assoc a -> Some (get_str "name" a) | _ -> None) l
     | _ -> failwith (Printf.sprintf "%s:1:1: error: the first line is not a trace header naming the agents" path))
  | [] -> failwith (Printf.sprintf "%s:1:1: error: the trace is empty" path)

let trace ?keep path =
  List.map (fun agent ->
      match model_of_trace path ~agent with
      | Error (line, reason) -> Cannot { agent; line; reason }
      | Ok (constants, records) ->
        let dir = Filename.concat (Filename.get_temp_dir_name ())
            (Printf.sprintf "jsref-validate-%d-%d" (Unix.getpid ()) (Random.bits ())) in
        Unix.mkdir dir 0o700;
        let tla = Random_model.write ~dir ~name:"MCTrace" constants in
        let m = Model.load tla in
        let text = trace_module "TraceCheck" records in
        (match keep with
         | Some k ->
           (try Unix.mkdir k 0o755 with Unix.Unix_error (Unix.EEXIST, _, _) -> ());
           let copy f = let oc = open_out_bin (Filename.concat k (agent ^ "_" ^ f)) in
             output_string oc (if f = "TraceCheck.tla" then text else Tlc.read_file (Filename.concat dir f));
             close_out oc in
           copy "MCTrace.tla"; copy "MCTrace.cfg"; copy "TraceCheck.tla"
         | None -> ());
        let r = Tlc.run_module m ~module_name:"TraceCheck" ~text
            ~cfg_lines:[ "INIT TraceInit"; "NEXT TraceNext" ] ~options:[ "-workers"; "1" ] in
        Array.iter (fun f -> Sys.remove (Filename.concat dir f)) (Sys.readdir dir);
        Unix.rmdir dir;
        match r.exit_code with
        | 0 -> Accepted { agent; steps = List.length records }
        | 11 ->
          (* The last state of the counterexample says how far the trace went. *)
          let k = ref 1 in
          List.iter (fun l ->
              let l = String.trim l in
              try Scanf.sscanf l "/\\ traceIndex = %d" (fun n -> k := n) with _ -> ())
            (String.split_on_char '\n' r.output);
          let (record, line) = List.nth records (min !k (List.length records - 1)) in
          Rejected { agent; line; after = !k;
                     step = Tla.to_string record }
        | c ->
          let o = r.output in
          let n = String.length o in
          failwith (Printf.sprintf "TLC failed (exit %d) validating agent %s: %s" c agent
                      (if n > 800 then String.sub o (n - 800) 800 else o)))
    (agents_of path)
