module Mc = Semantics.Machine

type verdict = { solved : bool; says : string }

type t = {
  id : string;
  title : string;
  task : string;
  hints : string list;
  start : Session.setup;
  events : string list;
  solution : Session.setup;
  why : string;
}

(* ---------------------------------------------------------- programs *)

let robome_text =
  match Examples.find "robome" with
  | Some x -> (match x.files with (_, text) :: _ -> text | [] -> "")
  | None -> ""

(* [s] with the first [sub] replaced by [by] (unchanged when [sub] is not
   there: the engine's test then finds the exercise broken). *)
let subst ~sub ~by s =
  let n = String.length sub and m = String.length s in
  let rec find i = if i + n > m then None else if String.sub s i n = sub then Some i else find (i + 1) in
  match find 0 with
  | None -> s
  | Some i -> String.sub s 0 i ^ by ^ String.sub s (i + n) (m - i - n)

let lines l = String.concat "\n" l ^ "\n"

let setup ?(variant = Mc.Reference) ?(budget = 1) ~agents files =
  { Session.default_setup with files; agents; variant; budget }

let robome ?variant ?budget text = setup ?variant ?budget ~agents:[ "r:RoboMe:@robome" ] [ "robome.jade", text ]

let notify ?priority p =
  match priority with
  | None -> Printf.sprintf {|{"agent": "r", "notify": %S}|} p
  | Some k -> Printf.sprintf {|{"agent": "r", "notify": %S, "priority": %d}|} p k

(* ----------------------------------------------------- reading a run *)

let trace_lines t =
  match Session.trace t with
  | [] -> []
  | _ :: lines ->
    List.filter_map (fun l ->
        match Trace.line_of_json (Yojson.Safe.from_string l) with
        | Ok x -> Some x
        | Error _ -> None
        | exception Yojson.Json_error _ -> None) lines

let handled t =
  List.filter_map (fun (l : Trace.line) -> match l.event with
      | Trace.Handle { percept; seq; _ } -> Some (l.step, percept, seq)
      | _ -> None) (trace_lines t)

let logs t =
  List.filter_map (fun (l : Trace.line) -> match l.event with
      | Trace.Body { body = Trace.Log s; _ } -> Some s
      | _ -> None) (trace_lines t)

let count p t = List.length (List.filter (fun (l : Trace.line) -> p l.event) (trace_lines t))

let is_discard = function Trace.End_dispatch { discarded = true; _ } -> true | _ -> false
let is_error = function Trace.Body { body = Trace.Error _; _ } -> true | _ -> false

let notified t =
  List.filter_map (fun (l : Trace.line) -> match l.event with
      | Trace.Notify { entry; _ } -> Some entry
      | _ -> None) (trace_lines t)

let starts p s = String.length s >= String.length p && String.sub s 0 (String.length p) = p

let property t agent name =
  let field k = function `Assoc f -> List.assoc_opt k f | _ -> None in
  match field "agents" (Session.view t) with
  | Some (`List agents) ->
    List.find_map (fun a ->
        if field "name" a = Some (`String agent) then
          match field "props" a with
          | Some (`List ps) ->
            List.find_map (fun p ->
                if field "name" p = Some (`String name) then
                  (match field "value" p with Some (`String v) -> Some v | _ -> None)
                else None) ps
          | _ -> None
        else None) agents
  | _ -> None

let yes says = { solved = true; says }
let no says = { solved = false; says }

let seqs l = String.concat ", " (List.map (fun s -> "#" ^ string_of_int s) l)

(* --------------------------------------------------------- exercises *)

let obstacle_first = {
  id = "obstacle-first";
  title = "1. Obstacles before positions";
  task = "Someone lowered the obstacle's priority in RoboMe's ontology. With the events below \
          (a position, an obstacle, another position), make the obstacle handler run before any \
          position is handled. Every percept must still be handled.";
  hints = [
    "Run the events and look at the priority queue after the Transfer: it is in dispatch order (R3b).";
    "The order of the handlers in the behaviour does not matter here: every percept goes through \
     the priority queue, highest priority first (R3b).";
    "Change the number after \"with priority =\" in the obstacle's declaration: it must beat \
     position's 2.";
  ];
  start = robome (subst ~sub:"proposition obstacle extends percept with priority = 8"
                    ~by:"proposition obstacle extends percept with priority = 1" robome_text);
  events = [ notify "position(0, 1)"; notify "obstacle"; notify "position(0, 2)" ];
  solution = robome robome_text;
  why = "The Transfer moves all three percepts at once (R3a); the dispatch then takes the highest \
         priority first (R3b). With a priority above position's 2, the obstacle leaves the \
         priority queue first, although it arrived second.";
}

let obstacle_first_judge t =
  let hs = handled t in
  let obstacle = List.find_opt (fun (_, p, _) -> p = "obstacle") hs in
  let positions = List.filter (fun (_, p, _) -> starts "position(" p) hs in
  let pseqs = List.sort_uniq compare (List.map (fun (_, _, s) -> s) positions) in
  match obstacle with
  | None -> no "The obstacle was never handled."
  | Some (step, _, oseq) ->
    if List.length pseqs < 2 then
      no (Printf.sprintf "Only %d of the two positions %s handled: every percept must still be handled."
            (List.length pseqs) (if List.length pseqs = 1 then "was" else "were"))
    else match positions with
      | (pstep, p, pseq) :: _ when pstep < step ->
        no (Printf.sprintf "%s #%d was handled (trace step %d) before obstacle #%d (step %d)." p pseq pstep oseq step)
      | _ -> yes (Printf.sprintf "obstacle #%d was handled (trace step %d) before both positions." oseq step)

let budget = {
  id = "budget";
  title = "2. A budget for obstacle #3";
  task = "Two positions are notified and moved into the priority queue; then an obstacle arrives \
          (#3) while they wait. Keep the program and the events; choose the loop and its budget so \
          that obstacle #3 never waits behind more than one dispatch of a lower-priority percept.";
  hints = [
    "Step through the events in the reference loop and watch Counters: obstacle #3 waits in the \
     O2A queue while both positions are dispatched (BoundedInversion).";
    "TLC's counterexample 3 (MCInversion) is this very run; 3b (MCBudgeted) is its cure.";
    "Set the loop to budgeted: it dispatches at most Budget percepts per iteration, then runs a \
     behaviour step, and the next Transfer brings the obstacle in. Which budget?";
  ];
  start = robome robome_text;
  events = [ notify "position(0, 1)"; notify "position(0, 2)"; {|{"run": {"rules": 1}}|};
             notify "obstacle" ];
  solution = robome ~variant:Mc.Budgeted ~budget:1 robome_text;
  why = "The budgeted loop with budget 1 dispatches position #1, runs a behaviour step, and its \
         next Transfer brings obstacle #3 into the priority queue, where it wins over position #2: \
         one lower-priority dispatch, the bound of MCBudgeted. Budget trades percept latency \
         against behaviour and message latency.";
}

let budget_judge t =
  let ls = trace_lines t in
  let index p = let rec go i = function [] -> None | (l : Trace.line) :: r -> if p l.event then Some i else go (i + 1) r in go 0 ls in
  let dequeued = List.filter_map (fun (l : Trace.line) -> match l.event with Trace.Dequeue e -> Some e | _ -> None) ls in
  match List.find_opt (fun (e : Trace.entry) -> e.percept = "obstacle") (notified t) with
  | None -> no "No obstacle was notified: the program must keep the percept type obstacle."
  | Some o ->
    let positions = List.filter (fun (e : Trace.entry) -> starts "position(" e.percept) dequeued in
    if List.length positions < 2 then
      no "Both positions must be dispatched (here fewer were): keep the program's percepts and events."
    else
      match index (function Trace.Notify { entry; _ } -> entry.seq = o.seq | _ -> false),
            index (function Trace.Dequeue e -> e.seq = o.seq | _ -> false) with
      | Some n, Some d ->
        let between = List.filteri (fun i _ -> i > n && i < d) ls in
        let lower = List.filter_map (fun (l : Trace.line) -> match l.event with
            | Trace.Dequeue e when e.priority < o.priority -> Some e.seq
            | _ -> None) between in
        let k = List.length lower in
        let says = Printf.sprintf "obstacle #%d waited behind %d dispatch%s of lower-priority percepts%s."
            o.seq k (if k = 1 then "" else "es") (if k = 0 then "" else " (" ^ seqs lower ^ ")") in
        if k <= 1 then yes says else no (says ^ " At most one is asked.")
      | _ -> no (Printf.sprintf "obstacle #%d was never dispatched." o.seq)

let sensors_text = lines [
    "# A proximity sensor: reading(v) is 100 divided by the distance, so";
    "# reading(0) means that something touches the sensor.";
    "ontology Sensors";
    "\tpredicate reading(v as integer) extends percept with priority = 3";
    "";
    "agent Probe uses ontology Sensors";
    "\ton create do";
    "\t\tactivate behaviour Watch";
    "";
    "cyclic behaviour Watch for agent Probe";
    "\ton percept when content matches reading(v) and 100 / v > 10 do";
    "\t\tlog \"close: \" + v";
    "";
    "\ton percept when content matches reading(v) and 100 / v <= 10 do";
    "\t\tlog \"far: \" + v";
  ]

let when_error = {
  id = "when-error";
  title = "3. A handler that survives an error in its when";
  task = "reading(0) makes both when expressions divide by zero: the error is recorded and the \
          handler does not apply (R3b, R7), so the percept is discarded. Change the when \
          expressions so that the run has no error and no discard, and logs exactly \
          close: 5, close: 0, far: 20 (reading(0) counts as close).";
  hints = [
    "Step to the dispatch of reading(0): both handlers are Skipped, each with an error in the trace, then the percept is discarded.";
    "and and or are evaluated from left to right, and stop as soon as the answer is known: in \
     a and b, b is not evaluated when a is false.";
    "Test v before dividing by it: (v = 0 or 100 / v > 10) for the first handler, and v != 0 and ... for the second.";
  ];
  start = setup ~agents:[ "p:Probe" ] [ "sensors.jade", sensors_text ];
  events = [ {|{"agent": "p", "notify": "reading(5)"}|}; {|{"agent": "p", "notify": "reading(0)"}|};
             {|{"agent": "p", "notify": "reading(20)"}|} ];
  solution = setup ~agents:[ "p:Probe" ] [ "sensors.jade",
      subst ~sub:"reading(v) and 100 / v <= 10 do" ~by:"reading(v) and v != 0 and 100 / v <= 10 do"
        (subst ~sub:"reading(v) and 100 / v > 10 do" ~by:"reading(v) and (v = 0 or 100 / v > 10) do"
           sensors_text) ];
  why = "A run-time error in a when makes that handler not applicable for that percept (R3b); \
         the error is recorded (R7) and, with no handler left, the percept is discarded. Guards \
         that test before they divide never fail: or and and stop at the first operand that \
         decides.";
}

let when_error_judge t =
  let errors = count is_error t and discards = count is_discard t and got = logs t in
  let want = [ "close: 5"; "close: 0"; "far: 20" ] in
  if errors > 0 then no (Printf.sprintf "The run recorded %d error%s (R7)." errors (if errors = 1 then "" else "s"))
  else if discards > 0 then no (Printf.sprintf "%d percept%s discarded (R3b)." discards (if discards = 1 then " was" else "s were"))
  else if got <> want then
    no (Printf.sprintf "The run logged [%s]; the task asks for [%s]." (String.concat "; " got) (String.concat "; " want))
  else yes "No error, no discard, and the three readings logged as asked."

let unfreeze = {
  id = "unfreeze";
  title = "4. Unfreeze the agent";
  task = "RoboMe runs Algorithm 1 as printed. The host puts a non-percept object into the O2A \
          queue, then notifies an obstacle. Keep the program and the events: choose a loop in \
          which the obstacle is handled and the agent then goes idle.";
  hints = [
    "Run to idle: the page stops after 5,000 rules of TransferSpin. Why does the printed loop never get past the object?";
    "TLC's counterexample 1 (MCPrintedObject) shows the same spin: NoLoss, BehaviourProgress, MessageProgress and NoLivelock are all violated.";
    "Which loop moves every percept at once and leaves other objects where they are (R3a)?";
  ];
  start = robome ~variant:Mc.Printed robome_text;
  events = [ {|{"agent": "r", "put": "\"obj\""}|}; notify "obstacle" ];
  solution = robome robome_text;
  why = "The reference loop's Transfer moves every percept of the O2A queue at once and leaves \
         objects in place (R3a), so an object can never block the percepts behind it; the \
         object stays in the O2A queue, and the agent sleeps (R3e).";
}

let unfreeze_judge t =
  let obstacle = List.exists (fun (_, p, _) -> p = "obstacle") (handled t) in
  let idle = Session.next_agent t = None in
  match obstacle, idle with
  | true, true -> yes "The obstacle was handled and the agent went idle."
  | false, _ -> no (Printf.sprintf "The obstacle was never handled (%d TransferSpin rules)."
                      (count (function Trace.Transfer_spin _ -> true | _ -> false) t))
  | true, false -> no "The obstacle was handled, but the agent never went idle."

let rover_text = lines [
    "ontology Robot";
    "\tproposition obstacle extends percept with priority = 8";
    "\tproposition position extends percept with priority = 2";
    "";
    "agent Rover uses ontology Robot";
    "\ton create do";
    "\t\tactivate behaviour Drive";
    "";
    "cyclic behaviour Drive for agent Rover";
    "\ton percept when content matches position do";
    "\t\tlog \"position handled\"";
    "";
    "\ton percept when content matches obstacle do";
    "\t\tlog \"obstacle handled\"";
  ]

let native_order = {
  id = "native-order";
  title = "5. Native delivery: the obstacle first";
  task = "With the native loop (percepts delivered as messages, as in Jadescript 1.0), the \
          position is handled before the obstacle, although the obstacle's priority is higher. \
          Keep the native loop and the events; change the program so that the obstacle is \
          handled first.";
  hints = [
    "In the native loop the Transfer puts the percepts into the message queue; a behaviour step \
     takes one, with the first handler that matches any entry (MCNative).";
    "Priorities play no part in native delivery: the order of the handlers in the behaviour does.";
    "Move the obstacle handler above the position handler.";
  ];
  start = setup ~variant:Mc.Native ~agents:[ "r:Rover" ] [ "rover.jade", rover_text ];
  events = [ {|{"agent": "r", "notify": "position"}|}; {|{"agent": "r", "notify": "obstacle"}|} ];
  solution = setup ~variant:Mc.Native ~agents:[ "r:Rover" ] [ "rover.jade", lines [
      "ontology Robot";
      "\tproposition obstacle extends percept with priority = 8";
      "\tproposition position extends percept with priority = 2";
      "";
      "agent Rover uses ontology Robot";
      "\ton create do";
      "\t\tactivate behaviour Drive";
      "";
      "cyclic behaviour Drive for agent Rover";
      "\ton percept when content matches obstacle do";
      "\t\tlog \"obstacle handled\"";
      "";
      "\ton percept when content matches position do";
      "\t\tlog \"position handled\"";
    ] ];
  why = "Delivered as messages, percepts are taken by the first handler that matches, in \
         declaration order, whatever their priority (MCNative). The paper's RoboMe is safe only \
         because it declares its handlers in priority order (MCNativePaperOrder); the priority \
         queue of the reference loop makes the order of declaration irrelevant.";
}

let native_order_judge t =
  if (Session.setup t).variant <> Mc.Native then no "The loop must stay native."
  else
    let taken = List.filter_map (fun (l : Trace.line) -> match l.event with
        | Trace.Behaviour_step { taken = Some (Trace.Took_percept e); _ } -> Some e.percept
        | _ -> None) (trace_lines t) in
    match taken with
    | "obstacle" :: rest when List.mem "position" rest -> yes "The obstacle was taken first, then the position."
    | "obstacle" :: _ -> no "The obstacle was taken first, but the position was never handled."
    | [] -> no "No percept was taken by a behaviour step."
    | p :: _ -> no (Printf.sprintf "The first percept a behaviour step took was %s." p)

let home_text = lines [
    "ontology Home";
    "\tpredicate temperature(c as integer) extends percept with priority = 3";
    "\tpredicate humidity(p as integer) extends percept with priority = 2";
    "\tproposition doorbell extends percept with priority = 7";
    "";
    "agent House uses ontology Home";
    "\ton create do";
    "\t\tactivate behaviour Watch";
    "";
    "cyclic behaviour Watch for agent House";
    "\ton percept when content matches temperature(c) and c > 25 do";
    "\t\tlog \"too warm: \" + c";
    "";
    "\ton percept when content matches humidity(p) do";
    "\t\tlog \"humidity \" + p";
  ]

let no_discard = {
  id = "no-discard";
  title = "6. No percept discarded";
  task = "A percept that no handler accepts is discarded, and the trace says so (R3b). With the \
          events below, two are discarded. Add or change handlers so that every percept is \
          handled by at least one handler.";
  hints = [
    "Run to idle and look for discard in the trace: which percepts, and why?";
    "temperature(20) matches the pattern of the first handler, but its when is false; nothing accepts doorbell at all.";
    "A handler of its own for doorbell, and one for the temperatures that are not too warm (or one on percept do that takes anything).";
  ];
  start = setup ~agents:[ "h:House" ] [ "home.jade", home_text ];
  events = [ {|{"agent": "h", "notify": "temperature(20)"}|}; {|{"agent": "h", "notify": "humidity(40)"}|};
             {|{"agent": "h", "notify": "doorbell"}|}; {|{"agent": "h", "notify": "temperature(30)"}|} ];
  solution = setup ~agents:[ "h:House" ] [ "home.jade", home_text ^ lines [
      "";
      "\ton percept when content matches temperature(c) and c <= 25 do";
      "\t\tlog \"fine: \" + c";
      "";
      "\ton percept when content matches doorbell do";
      "\t\tlog \"ding dong\"";
    ] ];
  why = "Every applicable handler runs for each percept (R3b); a percept for which none applies \
         leaves the system as a discard, recorded in the trace (R3b, R8), so nothing is lost \
         silently (NoLoss).";
}

let no_discard_judge t =
  let hseqs = List.map (fun (_, _, s) -> s) (handled t) in
  let missed = List.filter (fun (e : Trace.entry) -> not (List.mem e.seq hseqs)) (notified t) in
  match missed with
  | [] when count is_discard t = 0 ->
    yes (Printf.sprintf "All %d percepts were handled." (List.length (notified t)))
  | [] -> no "Some percept was discarded."
  | l -> no (Printf.sprintf "Not handled: %s."
               (String.concat ", " (List.map (fun (e : Trace.entry) -> Printf.sprintf "%s #%d" e.percept e.seq) l)))

let map_where_read = {
  id = "map-where-read";
  title = "7. File the QR code where it was read";
  task = "The tutorial's events: the robot is at (0, 1) when it reads the QR code A7; then the \
          host notifies position(0, 2) with the priority 9 (notifyEvent(p, 9), R2a). With these \
          events, worldMap files A7 under position(0.0, 2.0): the override reordered what the \
          map believes. Keep the events and the handlers; change the ontology's priorities so \
          that worldMap ends as {position(0.0, 1.0): \"A7\"}.";
  hints = [
    "Run to idle and read the dispatch order in the trace: position(0, 2) (priority 9) first, \
     then the obstacle, the QR code, and position(0, 1) last.";
    "The QR code handler files the code under currentPosition, which is whatever position was \
     handled last before it. So position(0, 1) must be dispatched before the QR code, and the \
     QR code before position(0, 2).";
    "The override of position(0, 2) is 9. A QR code of priority 9 still goes before it (R3b: \
     ties by seq, and the code arrived first); position's default must then beat 9.";
  ];
  start = robome robome_text;
  events = [ notify "position(0, 1)"; notify "qrCodeRead(\"A7\")"; notify "obstacle";
             notify ~priority:9 "position(0, 2)" ];
  solution = robome (subst ~sub:"\t\twith priority = 2\n" ~by:"\t\twith priority = 10\n"
                       (subst ~sub:"\t\twith priority = 4\n" ~by:"\t\twith priority = 9\n" robome_text));
  why = "Priorities reorder the handlers' view of the world: the map is built from the order of \
         dispatch, not the order of arrival. With positions above QR codes, each code is filed \
         under the position known just before it; the host's override still decides where \
         position(0, 2) goes. The corridor tab shows the same effect at scale: map entries drawn \
         away from the cube that was read.";
}

let map_where_read_judge t =
  let want = "{position(0.0, 1.0): \"A7\"}" in
  match property t "r" "worldMap" with
  | Some v when v = want -> yes ("worldMap = " ^ v ^ ".")
  | Some v -> no (Printf.sprintf "worldMap = %s; the task asks for %s." v want)
  | None -> no "The agent r has no property worldMap."

let judges = [
  obstacle_first.id, obstacle_first_judge; budget.id, budget_judge; when_error.id, when_error_judge;
  unfreeze.id, unfreeze_judge; native_order.id, native_order_judge; no_discard.id, no_discard_judge;
  map_where_read.id, map_where_read_judge ]

let all = [ obstacle_first; budget; when_error; unfreeze; native_order; no_discard; map_where_read ]

let find id = List.find_opt (fun x -> x.id = id) all

(* ------------------------------------------------------------ running *)

let event t line =
  let field k = function `Assoc f -> List.assoc_opt k f | _ -> None in
  let text k j = match field k j with Some (`String s) -> Some s | _ -> None in
  match Yojson.Safe.from_string line with
  | exception Yojson.Json_error m -> Error m
  | j ->
    let agent = Option.value (text "agent" j) ~default:"" in
    match text "notify" j, text "put" j, text "message" j, field "run" j with
    | Some percept, _, _, _ ->
      let priority = match field "priority" j with Some (`Int k) -> Some k | _ -> None in
      Session.host t (Session.Notify { agent; percept; priority })
    | _, Some obj, _, _ -> Session.host t (Session.Put { agent; obj })
    | _, _, Some content, _ ->
      Session.host t (Session.Message { agent; content; perf = Option.value (text "performative" j) ~default:"inform";
                                 during = text "during" j = Some "step" })
    | _, _, _, Some (`Int n) -> Session.run_rounds t n; Ok ()
    | _, _, _, Some (`String "idle") -> ignore (Session.run_idle t); Ok ()
    | _, _, _, Some r ->
      (match field "rules" r with
       | Some (`Int n) -> Session.run_rules t n; Ok ()
       | _ -> Error "an unknown run")
    | _ -> Error "neither a host action nor a run"

let attempt x s =
  match Session.create s with
  | Error e -> Error e
  | Ok t ->
    let rec go k = function
      | [] ->
        ignore (Session.run_idle ~limit:5000 t);
        (match List.assoc_opt x.id judges with
         | Some judge ->
           (match judge t with
            | v -> Ok (t, v)
            | exception e -> Ok (t, no ("internal error: " ^ Printexc.to_string e)))
         | None -> Ok (t, no "this exercise has no check"))
      | line :: rest ->
        (match event t line with
         | Ok () -> go (k + 1) rest
         | Error m -> Ok (t, no (Printf.sprintf "Event %d (%s) was refused: %s" k line m))) in
    go 1 x.events

let setup_json (s : Session.setup) =
  `Assoc [
    "files", `List (List.map (fun (n, t) -> `Assoc [ "name", `String n; "text", `String t ]) s.files);
    "agents", `List (List.map (fun a -> `String a) s.agents);
    "variant", `String (Mc.string_of_variant s.variant);
    "tie", `String (match s.tie with Mc.Stable -> "stable" | Mc.Unstable -> "unstable");
    "budget", `Int s.budget;
    "o2a_capacity", (match s.o2a_capacity with Some c -> `Int c | None -> `Null);
  ]

let to_json () =
  `List (List.map (fun x ->
      `Assoc [ "id", `String x.id; "title", `String x.title; "task", `String x.task;
               "hints", `List (List.map (fun h -> `String h) x.hints); "why", `String x.why;
               "events", `List (List.map (fun e -> `String e) x.events);
               "start", setup_json x.start; "solution", setup_json x.solution ]) all)
