type verdict =
  | Accepted of { agent : string; steps : int; total : int }
  | Rejected of { agent : string; line : int; step : string; after : int }
  | Cannot of { agent : string; line : int; reason : string }
  | Invalid of { line : int; message : string }

exception Cannot_express of int * string

let str s = Tla.Str s
let int i = Tla.Int i

let percept_type lit =
  match String.index_opt lit '(' with Some i -> String.sub lit 0 i | None -> lit

let effect_value = function
  | Trace.Deactivated -> Agent_loop.deactivate
  | Trace.Activated b -> Agent_loop.activate b

let model_of_trace (header : Trace.header) lines ~agent =
  try
    let events = List.filter (fun (_, (l : Trace.line)) -> l.agent = agent) lines in
    let behaviours = header.behaviours in
    let percept_defaults = header.percepts in
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
    let n seq = "n" ^ string_of_int seq in
    let entry (e : Trace.entry) = [ "p", str (n e.seq); "prio", int e.priority; "seq", int e.seq ] in
    let effects l = List.map effect_value l in
    let records = List.filter_map (fun (line, (l : Trace.line)) ->
        let r fields = match Trace.action l.event with
          | Some act -> Some (Tla.record (("act", str act) :: fields), line)
          | None -> None in
        match l.event with
        | Trace.Body { body = Trace.Deactivate id; _ } -> Hashtbl.replace deactivated id (); None
        | Trace.Body { body = Trace.Activate _; _ } -> Hashtbl.reset deactivated; None
        | Trace.Body _ | Trace.Refused _ | Trace.Refused_put _ | Trace.Undeliverable _ | Trace.Destroy -> None
        | Trace.Create { behaviours; _ } ->
          initial := behaviours;
          Some (Tla.record [ "act", str "Init" ], line)
        | Trace.Notify { entry = e; overridden } ->
          let ty = percept_type e.percept in
          let default = match List.assoc_opt ty percept_defaults with
            | Some k -> k
            | None -> raise (Cannot_express (line, "percept type " ^ ty ^ " is not in the trace header")) in
          notified := (e.seq, default) :: !notified;
          if overridden then overrides := e.priority :: !overrides;
          r (entry e)
        | Trace.Put { index; _ } -> incr puts; r [ "obj", str ("o" ^ string_of_int index) ]
        | Trace.Deliver { seq; _ } ->
          msgs := max !msgs seq;
          r [ "m", str ("m" ^ string_of_int seq); "seq", int seq ]
        | Trace.Transfer moved -> r [ "moved", int moved ]
        | Trace.Transfer_one e -> r (entry e)
        | Trace.Transfer_spin _ -> r [ "obj", str "o1" ]
        | Trace.Transfer_end | Trace.Next_iteration | Trace.Idle -> r []
        | Trace.Dequeue e -> current := e.seq; r [ "e", Tla.record (entry e) ]
        | Trace.Handle { instance; behaviour; handler; seq; effects = effs; _ } ->
          let effs = effects effs in
          activations := !activations + List.length effs;
          add ph (behaviour, handler) (n seq, effs, line);
          r [ "id", int instance; "h", int handler; "p", str (n seq); "seq", int seq ]
        | Trace.Skip { instance; behaviour; handler } ->
          if not (Hashtbl.mem deactivated instance) then
            Hashtbl.replace skipped (behaviour, handler, n !current) line;
          r [ "id", int instance; "h", int handler ]
        | Trace.End_dispatch { seq; discarded } ->
          r [ "seq", int seq; "discarded", Tla.Bool discarded ]
        | Trace.Behaviour_step { instance; behaviour = b; taken; action_effects; handler } ->
          (match action_effects with
           | Some effs ->
             let effs = effects effs in
             activations := !activations + List.length effs;
             add action b (effs, line)
           | None -> ());
          let handler_effects () = match handler with Some (h, e) -> (h, effects e) | None -> (0, []) in
          let msg = match taken with
            | Some (Trace.Took_message (_, seq)) ->
              let name = "m" ^ string_of_int seq in
              let (h, effs) = handler_effects () in
              activations := !activations + List.length effs;
              add mh (b, h) (name, effs, line);
              Tla.record [ "kind", str "message"; "m", str name; "seq", int seq ]
            | Some (Trace.Took_percept e) ->
              let (h, effs) = handler_effects () in
              activations := !activations + List.length effs;
              add ph (b, h) (n e.seq, effs, line);
              Tla.record (("kind", str "percept") :: entry e)
            | None -> Tla.record [ "kind", str "none" ] in
          r [ "id", int instance; "msg", msg ]) events in
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
          | _ ->
            (* effects by percept: one list per percept, or the model
               cannot say it (two instances of the behaviour handled one
               percept with different effects) *)
            let by_value = List.sort_uniq compare (List.map (fun (n, effs, _) -> (n, effs)) uses) in
            let rec twice = function
              | (n, _) :: ((m, _) :: _) when n = m -> Some n
              | _ :: rest -> twice rest
              | [] -> None in
            (match twice by_value with
             | Some n ->
               let (_, _, line) = List.find (fun (m, _, _) -> m = n) (List.rev uses) in
               raise (Cannot_express (line, Printf.sprintf
                                        "handler %d of %s had different effects for percept %s in two instances \
                                         (they depend on the instance); a model gives each handler one list of \
                                         effects per percept" (i + 1) b n))
             | None -> ());
            Tla.record [ "accepts", accepts; "effects", Tla.Seq [];
                         "byValue", Tla.record (List.map (fun (n, effs) -> (n, Tla.Seq effs)) by_value) ])) in
    (* behaviour names are record fields and strings of the model: a name
       that is not a Jadescript name (docs/syntax.md) cannot be written *)
    List.iter (fun (i : Trace.behaviour_info) ->
        let ok = i.name <> "" && String.for_all (function 'a'..'z' | 'A'..'Z' | '0'..'9' | '_' -> true | _ -> false) i.name
                 && not (i.name.[0] >= '0' && i.name.[0] <= '9') in
        if not ok then raise (Cannot_express (1, Printf.sprintf "behaviour %S is not a Jadescript name: a model cannot hold it" i.name)))
      behaviours;
    let info b = match List.find_opt (fun (i : Trace.behaviour_info) -> i.name = b) behaviours with
      | Some i -> i
      | None -> raise (Cannot_express (1, "behaviour " ^ b ^ " is not in the trace header")) in
    let action_effects b =
      let uses = List.rev (Option.value (Hashtbl.find_opt action b) ~default:[]) in
      match List.sort_uniq compare (List.map fst uses) with
      | [] -> Tla.Seq []
      | [ effs ] -> Tla.Seq effs
      | _ ->
        let (_, line) = List.nth uses 1 in
        raise (Cannot_express (line, Printf.sprintf
                                 "the action block of %s has different activate/deactivate effects in different steps; \
                                  a model gives each action block one list of effects" b)) in
    let capacity = match header.o2a_capacity with
      | Some c -> c
      | None -> List.length !notified + !puts + 1 in
    let n_notify = List.length !notified in
    let constants = Agent_loop.constants {
        variant = header.variant;
        tie_policy = (if header.tie_policy = "unstable" then "Unstable" else "Stable");
        budget = max 1 header.budget;
        percepts = List.map fst percepts;
        default_priority = percepts;
        overrides = !overrides;
        objects = names "o" !puts;
        messages = names "m" !msgs;
        max_notify = n_notify; max_put = !puts; max_send = !msgs;
        flood = false;
        o2a_capacity = max 1 capacity;
        behaviours = List.map (fun (b : Trace.behaviour_info) -> b.name) behaviours;
        kind = (fun b -> (info b).kind);
        has_action = (fun b -> (info b).has_action);
        action_effects;
        percept_handlers = (fun b -> handlers ph b (info b).percept_handlers);
        message_handlers = (fun b -> handlers mh b (info b).message_handlers);
        initial = !initial;
        max_active = 1 + List.length !initial + !activations;
        inversion_bound = n_notify + 1 } in
    Ok (constants, records)
  with Cannot_express (line, reason) -> Error (line, reason)

(* The data of one agent's check, for spec/AgentLoopTrace.tla: the
   constants of AgentLoop read off the trace and the records of its steps
   (TraceLog), as definitions; the checking itself (one predicate per kind
   of line, TraceInit, TraceNext) is the checked-in module's. *)
let data_module name (constants, (records : (Tla.t * int) list)) =
  let b = Buffer.create 4096 in
  Printf.bprintf b "---- MODULE %s ----\n(* Generated by jadescript-ref validate: the steps of one agent and the \
                    constants read off its trace, for AgentLoopTrace. *)\nEXTENDS AgentLoopTrace\n\n" name;
  List.iter (fun (c, v) -> Printf.bprintf b "MC%s == %s\n" c (Tla.to_string v)) constants;
  Buffer.add_string b "\nMCTraceLog == <<\n";
  List.iteri (fun i (r, _) ->
      if i > 0 then Buffer.add_string b ",\n";
      Buffer.add_string b "  "; Buffer.add_string b (Tla.to_string r)) records;
  Buffer.add_string b "\n>>\n====\n";
  let cfg = List.map (fun (c, _) -> Printf.sprintf "CONSTANT %s <- MC%s" c c) constants
            @ [ "CONSTANT TraceLog <- MCTraceLog"; "INIT TraceInit"; "NEXT TraceNext" ] in
  (Buffer.contents b, cfg)

(* TLC's output, on one line: its first error message, else its last line. *)
let tlc_summary output =
  let ls = List.filter (fun l -> l <> "") (List.map String.trim (String.split_on_char '\n' output)) in
  let is_error l = try ignore (Str_find.find l "rror"); true with Not_found -> false in
  match List.find_opt is_error ls, List.rev ls with
  | Some l, _ | None, l :: _ -> l
  | None, [] -> "no output"

(* The last value TLC printed for [name] in its counterexample. *)
let last_value output name =
  List.fold_left (fun acc l ->
      try Scanf.sscanf (String.trim l) ("/\\ " ^^ "%s@ = %d") (fun v n -> if v = name then Some n else acc)
      with _ -> acc) None (String.split_on_char '\n' output)

let rejected agent records k =
  let (record, line) = List.nth records (min k (List.length records - 1)) in
  Rejected { agent; line; after = k; step = Tla.to_string record }

(* One agent alone: its data module (TraceCheck) extends AgentLoopTrace. *)
let tlc_one ?keep agent ((_, records) as job) =
  let (text, cfg) = data_module "TraceCheck" job in
  (match keep with
   | Some k ->
     (try Unix.mkdir k 0o755 with Unix.Unix_error (Unix.EEXIST, _, _) -> ());
     let write f s = let oc = open_out_bin (Filename.concat k (agent ^ "_" ^ f)) in
       output_string oc s; close_out oc in
     write "TraceCheck.tla" text; write "TraceCheck.cfg" (String.concat "\n" cfg ^ "\n")
   | None -> ());
  let r = Tlc.run_text ~module_name:"TraceCheck" ~text ~cfg_lines:cfg ~options:[ "-workers"; "1" ] in
  match r.exit_code with
  | 0 -> Accepted { agent; steps = List.length records; total = List.length records }
  | 11 ->
    (* The last state of the counterexample says how far the trace went. *)
    rejected agent records (Option.value (last_value r.output "traceIndex") ~default:1)
  | c -> raise (Tlc.Error (Printf.sprintf "TLC failed (exit %d) validating agent %s: %s" c agent (tlc_summary r.output)))

(* The variables of spec/AgentLoop.tla (its [vars]), given to each instance
   under a name of its own. *)
let spec_variables =
  [ "o2a"; "pq"; "msgq"; "nextSeq"; "msgSeq"; "puts"; "active"; "ready"; "blocked"; "pos"; "phase";
    "cur"; "dispatched"; "done"; "waits"; "last"; "stepped" ]

(* Several agents (of one trace or of several) in one TLC run, so that one
   JVM checks them all: each agent is an instance [A<i>] of AgentLoopTrace
   with its own constants, its own trace [T<i>] and its own copies of the
   spec's variables; the shared [traceIndex] counts the records of the agent
   being followed. The behaviour follows agent 1's records (A1!TraceAdvance),
   then agent 2's, ...; a deadlock says which agent ([agentIdx]) and how far
   ([traceIndex]). The agents are independent: the facts between them are
   Trace_check's. Only this sequencing is generated; each agent's check is
   the checked-in module's. *)
let combined_module jobs =
  let b = Buffer.create 16384 in
  let pr fmt = Printf.bprintf b fmt in
  let k = List.length jobs in
  let vars i = String.concat ", " (List.map (fun v -> Printf.sprintf "%s_%d" v i) spec_variables) in
  let all_vars = String.concat ", " (List.init k (fun i -> Printf.sprintf "vars%d" (i + 1))) in
  pr "---- MODULE TraceCheckAll ----\n(* Generated by jadescript-ref validate: the steps of %d agents and the \
      constants read off their traces, each checked by AgentLoopTrace, one after another. *)\n\
      EXTENDS Naturals, Sequences\n\n" k;
  List.iteri (fun i _ -> pr "VARIABLES %s\n" (vars (i + 1))) jobs;
  pr "VARIABLES agentIdx, traceIndex\n\n";
  List.iteri (fun i (_, (constants, records)) ->
      let n = i + 1 in
      pr "T%d == <<\n  %s\n>>\n\n" n
        (String.concat ",\n  " (List.map (fun (r, _) -> Tla.to_string r) records));
      pr "A%d == INSTANCE AgentLoopTrace WITH\n    %s\n\nvars%d == <<%s>>\n\n" n
        (String.concat ",\n    "
           (List.map (fun (c, v) -> Printf.sprintf "%s <- %s" c (Tla.to_string v)) constants
            @ [ Printf.sprintf "TraceLog <- T%d" n ]
            @ List.map (fun v -> Printf.sprintf "%s <- %s_%d" v v n) spec_variables
            @ [ "traceIndex <- traceIndex" ])) n (vars n)) jobs;
  pr "TraceInit == /\\ agentIdx = 1 /\\ traceIndex = 1\n";
  List.iteri (fun i _ -> pr "             /\\ A%d!TraceInit\n" (i + 1)) jobs;
  pr "\nTraceNext ==\n";
  List.iteri (fun i _ ->
      let n = i + 1 in
      let others = String.concat "" (List.filter_map (fun j ->
          if j = n then None else Some (Printf.sprintf ", vars%d" j)) (List.init k (fun j -> j + 1))) in
      pr "  \\/ /\\ agentIdx = %d /\\ A%d!TraceAdvance /\\ UNCHANGED <<agentIdx%s>>\n" n n others;
      if n < k then
        pr "  \\/ /\\ agentIdx = %d /\\ A%d!TraceAccepted /\\ agentIdx' = %d /\\ traceIndex' = 1 /\\ UNCHANGED <<%s>>\n"
          n n (n + 1) all_vars
      else
        pr "  \\/ /\\ agentIdx = %d /\\ A%d!TraceAccepted /\\ UNCHANGED <<agentIdx, traceIndex, %s>>\n" n n all_vars)
    jobs;
  pr "====\n";
  Buffer.contents b

(* At most this many agents in one TLC run: TLC's evaluation of the
   initial state recurses through the module's conjunctions, and overflows
   its stack somewhere below a hundred agents. *)
let agents_per_run = 10

(* [jobs]: (agent, model) in order -> a verdict for each, in one TLC run per
   [agents_per_run] agents when it can (again after a rejection, for the
   agents after it); one run per agent if TLC fails on a combined module. *)
let rec tlc_all ?keep jobs =
  match jobs with
  | [] -> []
  | [ (agent, job) ] -> [ tlc_one ?keep agent job ]
  | _ when List.length jobs > agents_per_run ->
    let first = List.filteri (fun i _ -> i < agents_per_run) jobs
    and rest = List.filteri (fun i _ -> i >= agents_per_run) jobs in
    let v = tlc_all ?keep first in
    v @ tlc_all ?keep rest
  | _ ->
    let text = combined_module jobs in
    (match keep with
     | Some k ->
       (try Unix.mkdir k 0o755 with Unix.Unix_error (Unix.EEXIST, _, _) -> ());
       let oc = open_out_bin (Filename.concat k "TraceCheckAll.tla") in
       output_string oc text; close_out oc
     | None -> ());
    let r = Tlc.run_text ~module_name:"TraceCheckAll" ~text ~cfg_lines:[ "INIT TraceInit"; "NEXT TraceNext" ]
        ~options:[ "-workers"; "1" ] in
    let accepted (agent, (_, records)) = Accepted { agent; steps = List.length records; total = List.length records } in
    match r.exit_code, last_value r.output "agentIdx", last_value r.output "traceIndex" with
    | 0, _, _ -> List.map accepted jobs
    | 11, Some a, Some k when a >= 1 && a <= List.length jobs ->
      let before = List.filteri (fun i _ -> i < a - 1) jobs and after = List.filteri (fun i _ -> i >= a) jobs in
      let (agent, (_, records)) = List.nth jobs (a - 1) in
      List.map accepted before @ [ rejected agent records k ] @ tlc_all ?keep after
    | _ -> List.map (fun (agent, job) -> tlc_one ?keep agent job) jobs

(* A trace read strictly, as [Trace.read_located] reads it, except its
   last line when it has no newline and is not JSON: a run killed while it
   wrote that line (SIGKILL, which no program can catch) leaves the lines
   before it, which are checked; the cut line's number is told ([cut]). *)
let read path =
  let header = ref None and lines = ref [] in
  match Trace.stream_cut path ~header:(fun h -> header := Some h)
          ~line:(fun n l -> lines := (n, l) :: !lines) with
  | Error e -> Error e
  | Ok cut -> match !header with
    | Some h -> Ok (h, List.rev !lines, cut)
    | None -> Error (1, "not a jadescript-ref trace (no header line)")

(* Trace_check's checks, then Trace_more's (bodies against their effects,
   percept literals): a separate module, called from here. *)
let more header lines =
  match Trace_check.check header lines with
  | Ok () -> Trace_more.check header lines
  | Error e -> Error e

let check path =
  match read path with
  | Error e -> Error e
  | Ok (header, lines, _) -> more header lines


(* TLC follows at most this many steps of each agent (its first ones, from
   the spec's initial state): the model holds a percept value per notify
   and a constant per step, and TLC's time grows faster than the trace. *)
let default_window = 300

(* The model of [agent] on its first [window] steps: the lines up to its
   [window]-th step (the step's own body lines after it are left out with
   the rest); the number of its steps in the whole trace. *)
let windowed ~window header lines ~agent =
  match model_of_trace header lines ~agent with
  | Error e -> Error e
  | Ok (_, records) as whole ->
    let total = List.length records in
    if window <= 0 || total <= window then Result.map (fun j -> (j, total)) whole
    else begin
      let (_, last) = List.nth records (window - 1) in
      let prefix = List.filter (fun (n, _) -> n <= last) lines in
      Result.map (fun j -> (j, total)) (model_of_trace header prefix ~agent)
    end

let traces ?keep ?(window = default_window) ?(on_cut = fun _ _ -> ()) paths =
  (* per trace: Invalid, or per agent Cannot or a model for TLC *)
  let prepared = List.map (fun path ->
      match read path with
      | Error (line, message) -> (path, `Invalid (Invalid { line; message }))
      | Ok (header, lines, cut) ->
        Option.iter (on_cut path) cut;
        match more header lines with
        | Error (line, message) -> (path, `Invalid (Invalid { line; message }))
        | Ok () ->
          (path, `Agents (List.map (fun (agent, _) ->
               match windowed ~window header lines ~agent with
               | Error (line, reason) -> (agent, Error (Cannot { agent; line; reason }))
               | Ok job -> (agent, Ok job)) header.agents))) paths in
  let jobs = List.concat_map (fun (_, p) -> match p with
      | `Invalid _ -> []
      | `Agents l -> List.filter_map (fun (agent, r) -> match r with Ok (job, _) -> Some (agent, job) | Error _ -> None) l)
      prepared in
  let totals = List.concat_map (fun (_, p) -> match p with
      | `Invalid _ -> []
      | `Agents l -> List.filter_map (fun (_, r) -> match r with Ok (_, total) -> Some total | Error _ -> None) l)
      prepared in
  let verdicts = ref (List.map2 (fun v total -> match v with
      | Accepted a -> Accepted { a with total }
      | v -> v) (tlc_all ?keep jobs) totals) in
  List.map (fun (path, p) ->
      match p with
      | `Invalid v -> (path, [ v ])
      | `Agents l ->
        (path, List.map (fun (_, r) -> match r with
             | Error v -> v
             | Ok _ -> (match !verdicts with
                 | v :: rest -> verdicts := rest; v
                 | [] -> Semantics.Fault.crash "Validate: fewer TLC verdicts than agents")) l)) prepared

let trace ?keep ?window ?on_cut path = snd (List.hd (traces ?keep ?window ?on_cut [ path ]))
