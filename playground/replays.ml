module Mc = Semantics.Machine

type action =
  | Host of Session.host_action
  | Rule
  | Dequeue_seq of int

type step = { action : action; tla : string; say : string }

type t = {
  id : string;
  title : string;
  finding : string;
  command : string;
  setup : Session.setup;
  steps : step list;
  final : string;
  violated : bool;
}

(* The models' agent: one cyclic behaviour Main with a percept handler per
   accepted percept type, in the model's declaration order, and a message
   handler for the model's one message ("inform" there, [hello] here). *)
let program ?(handlers = [ "obstacle"; "position" ]) ?(extra = "") () =
  String.concat "\n" ([
      "# The agent of the TLC models of docs/spec.md: one cyclic behaviour Main,";
      "# a handler per percept it accepts (in the model's order) and one message";
      "# handler (the models' message \"inform\" is the proposition hello here).";
      "ontology Model";
      "\tproposition obstacle extends percept with priority = 8";
      "\tproposition position extends percept with priority = 2" ]
      @ (if extra = "" then [] else [ extra ])
      @ [ "\tproposition hello";
          "";
          "agent Robot uses ontology Model";
          "\ton create do";
          "\t\tactivate behaviour Main";
          "";
          "cyclic behaviour Main for agent Robot" ]
      @ List.concat_map (fun p ->
          [ "\ton percept when content matches " ^ p ^ " do"; "\t\tlog \"" ^ p ^ " handled\""; "" ]) handlers
      @ [ "\ton inform when content matches hello do"; "\t\tlog \"hello handled\""; "" ])

let setup ?(tie = Mc.Stable) ?(budget = 1) ~variant ~capacity text =
  { Session.default_setup with files = [ "model.jade", text ]; agents = [ "r:Robot" ];
                               variant; tie; budget; o2a_capacity = Some capacity }

let notify p = Host (Session.Notify { agent = "r"; percept = p; priority = None })
let put o = Host (Session.Put { agent = "r"; obj = o })
let send c = Host (Session.Message { agent = "r"; perf = "inform"; content = c; during = false })
let s action tla say = { action; tla; say }

(* The one command that has TLC check the model's expected outcomes (the
   violations included) and print the results table. *)
let tlc m = Printf.sprintf "make spec SPEC_MODELS=%s" m

let printed_object = {
  id = "MCPrintedObject";
  title = "1. The printed loop spins on a non-percept object";
  finding = "NoLoss, BehaviourProgress, MessageProgress and NoLivelock are violated: one object in \
             the O2A queue freezes an agent that runs Algorithm 1 as printed.";
  command = tlc "MCPrintedObject";
  setup = setup ~variant:Mc.Printed ~capacity:2 (program ());
  steps = [
    s (send "hello") "Send" "The host sends a message: it waits in Main's message queue.";
    s Rule "TransferEnd" "The O2A queue is empty, so the transfer loop of Algorithm 1 ends at once.";
    s Rule "BehaviourStep" "Nothing to dispatch: Main runs one step and takes the message. All is well so far.";
    s (put "\"obj\"") "Put" "The host puts a non-percept object into the O2A queue: JADE's O2A interface accepts any Java object (R2c).";
    s (notify "position") "Notify" "A percept arrives behind the object: o2a = <<obj, position#1>>.";
    s Rule "TransferSpin" "The loop peeks at the head of O2A: not a percept, so it is not moved, and the queue is still not empty...";
    s Rule "TransferSpin" "...so the while loop peeks at it again. Nothing changes, and nothing ever will.";
    s (send "hello") "Send" "A new message arrives; Main would handle it, if it ever ran.";
    s Rule "TransferSpin" "Still spinning: position#1 is never transferred (NoLoss), Main never runs (BehaviourProgress), the message is never read (MessageProgress), and the agent does no work although work is pending (NoLivelock).";
  ];
  final = "last.act = \"TransferSpin\", o2a = <<obj, position#1>>, pq = {}, one message waiting, forever";
  violated = true;
}

let flood_printed = {
  id = "MCFloodPrinted";
  title = "2. Endless percepts starve the printed loop";
  finding = "BehaviourProgress and MessageProgress are violated: under a steady stream of percepts the \
             transfer loop of Algorithm 1 never sees an empty O2A queue, so no percept is handled, \
             no behaviour runs and no message is read.";
  command = tlc "MCFloodPrinted";
  setup = setup ~variant:Mc.Printed ~capacity:1 (program ());
  steps = [
    s (notify "position") "Notify" "A position percept arrives (O2A capacity 1, as in the model).";
    s Rule "TransferOne" "The transfer loop moves it to the priority queue; O2A is empty again.";
    s (send "hello") "Send" "A message arrives for Main.";
    s (notify "obstacle") "Notify" "Before the loop checks O2A again, the next percept arrives...";
    s Rule "TransferOne" "...so the loop moves it and goes round again.";
    s (notify "position") "Notify" "And the next one: the sensors never pause.";
    s Rule "TransferOne" "The while loop still sees a non-empty O2A queue.";
    s (notify "obstacle") "Notify" "TLC's lasso goes back here, forever (its flood abstraction merges equal percepts; here every notification is a new percept, so the priority queue grows too).";
    s Rule "TransferOne" "The priority queue is never drained, Main never runs and the message is never read: the agent is busy (NoLivelock holds) but starved by its own transfer loop.";
  ];
  final = "last.act = \"TransferOne\", ready = <<1>> never run, msgq = <<inform>> never read, pq growing";
  violated = true;
}

let inversion_steps tail = [
  s (notify "position") "Notify" "position#1 arrives (priority 2).";
  s (notify "position") "Notify" "position#2 arrives.";
  s Rule "Transfer" "The atomic Transfer (R3a) moves both into the priority queue.";
  s (notify "obstacle") "Notify" "An obstacle (priority 8) arrives just after the Transfer: it waits in O2A for the next iteration (R3d).";
  s Rule "Dequeue" "position#1 is dispatched: obstacle#3 has now waited behind one lower-priority dispatch.";
  s Rule "Skip" "Main's obstacle handler does not apply to a position.";
  s Rule "Handle" "Main's position handler runs.";
  s Rule "EndDispatch" "position#1 leaves the system.";
] @ tail

let inversion = {
  id = "MCInversion";
  title = "3. The reference loop is fair, but its wait is unbounded";
  finding = "BoundedInversion and DispatchesWithinBudget are violated: one iteration dispatches \
             whatever accumulated in O2A, so a late high-priority percept (and every behaviour \
             and message) waits as many dispatches as the O2A capacity allows.";
  command = tlc "MCInversion";
  setup = setup ~variant:Mc.Reference ~capacity:3 (program ());
  steps = inversion_steps [
      s Rule "Dequeue" "position#2 is dispatched too: obstacle#3 has waited behind two lower-priority dispatches (BoundedInversion, bound 1, violated) and this iteration has dispatched two percepts (DispatchesWithinBudget, budget 1, violated). With an unbounded O2A both numbers are unbounded.";
    ];
  final = "last.act = \"Dequeue\" of position#2, dispatched = 2, waits of obstacle#3 = 2 inversions";
  violated = true;
}

let budgeted = {
  id = "MCBudgeted";
  title = "3b. The budget bounds both waits";
  finding = "Every property holds in MCBudgeted: with the same events, the budgeted loop dispatches \
             at most Budget = 1 percept per iteration, runs a behaviour step, and the next Transfer \
             brings the obstacle in, where it wins at once.";
  command = tlc "MCBudgeted";
  setup = setup ~variant:Mc.Budgeted ~budget:1 ~capacity:3 (program ());
  steps = inversion_steps [
      s Rule "BehaviourStep" "The budget (1) is spent: instead of dispatching position#2, Main runs one step (no message for it, so it blocks).";
      s Rule "Transfer" "The next iteration's Transfer brings obstacle#3 into the priority queue.";
      s Rule "Dequeue" "obstacle#3 (priority 8) is dispatched before position#2: it waited behind one lower-priority dispatch, within the bound.";
    ];
  final = "last.act = \"Dequeue\" of obstacle#3, dispatched = 1, position#2 still queued";
  violated = false;
}

let ties = {
  id = "MCTiesUnstable";
  title = "4. Ties under java.util.PriorityQueue";
  finding = "FifoAmongEquals is violated: a binary heap is not stable, so two percepts of equal \
             priority may be handled in the wrong order. R3b's tie rule needs the seq as a \
             secondary key.";
  command = tlc "MCTiesUnstable";
  setup = setup ~variant:Mc.Reference ~tie:Mc.Unstable ~capacity:3
      (String.concat "\n" [
          "# MCTiesUnstable: two percept types of equal priority, one handler for both.";
          "ontology Model";
          "\tproposition a extends percept with priority = 1";
          "\tproposition b extends percept with priority = 1";
          "";
          "agent Robot uses ontology Model";
          "\ton create do";
          "\t\tactivate behaviour Main";
          "";
          "cyclic behaviour Main for agent Robot";
          "\ton percept do";
          "\t\tlog \"handled \" + content";
          "" ]);
  steps = [
    s (notify "a") "Notify" "a#1 arrives (priority 1).";
    s (notify "a") "Notify" "a#2 arrives, with the same priority.";
    s Rule "Transfer" "Both move into the priority queue.";
    s (Dequeue_seq 2) "Dequeue" "Under the unstable policy any entry of the highest priority may leave first: a#2 is taken while a#1, notified earlier, still waits (FifoAmongEquals violated). Try the other choice in the rule list: both are enabled.";
  ];
  final = "last.act = \"Dequeue\" of a#2 while a#1 is in pq";
  violated = true;
}

let native = {
  id = "MCNative";
  title = "5. Native delivery: handler order replaces priority";
  finding = "PriorityOrder, BoundedInversion and NoLoss are violated: percepts delivered as messages \
             are taken by the first handler that matches, in declaration order, whatever their \
             priority, and a percept no handler accepts stays in the message queue forever.";
  command = tlc "MCNative";
  setup = setup ~variant:Mc.Native ~capacity:2
      (program ~handlers:[ "position"; "obstacle" ] ~extra:"\tproposition noise extends percept with priority = 1" ());
  steps = [
    s (notify "obstacle") "Notify" "obstacle#1 (priority 8) arrives.";
    s (notify "position") "Notify" "position#2 (priority 2) arrives.";
    s Rule "Transfer" "In the native variant both go into the message queue, in arrival order.";
    s Rule "BehaviourStep" "Main's first handler with a matching entry is its position handler (declared first): it takes position#2 while obstacle#1, of higher priority, waits (PriorityOrder violated).";
    s Rule "Transfer" "The next iteration: nothing new to move.";
    s Rule "BehaviourStep" "Only now is the obstacle handled.";
    s (notify "noise") "Notify" "A percept that no handler accepts arrives.";
    s Rule "Transfer" "It goes into the message queue.";
    s Rule "BehaviourStep" "No handler takes it; Main took nothing, so it blocks.";
    s Rule "Transfer" "Nothing to move.";
    s Rule "Idle" "The agent sleeps with noise#3 still in its message queue, forever (NoLoss violated); the reference loop would have discarded it with a trace record (R3b).";
  ];
  final = "last.act = \"Idle\", msgq = <<noise#3>>, position#2 handled before obstacle#1";
  violated = true;
}

let flood_native = {
  id = "MCFloodNative";
  title = "6. Native delivery under a stream: messages starve";
  finding = "MessageProgress is violated: a behaviour tries its percept handlers before its \
             message handlers, so under a steady stream of percepts the message is never read, \
             although the behaviour keeps running (BehaviourProgress holds).";
  command = tlc "MCFloodNative";
  setup = setup ~variant:Mc.Native ~capacity:1 (program ());
  steps = [
    s (send "hello") "Send" "A message arrives first.";
    s (notify "obstacle") "Notify" "Then an obstacle percept.";
    s Rule "Transfer" "msgq = <<inform, obstacle#1>>: the message is ahead.";
    s Rule "BehaviourStep" "Main tries its percept handlers first and takes the obstacle, although the message arrived earlier.";
    s (notify "obstacle") "Notify" "The next percept arrives...";
    s Rule "Transfer" "...and joins the message queue behind the message.";
    s Rule "BehaviourStep" "Main takes the percept again. The message waits.";
    s (notify "obstacle") "Notify" "TLC's lasso goes back here, forever.";
    s Rule "Transfer" "The stream goes on.";
    s Rule "BehaviourStep" "Main runs in every iteration, but the message is never consumed (MessageProgress violated): the paper's \"percepts before messages\" moved into each behaviour's handler list.";
  ];
  final = "last.act = \"BehaviourStep\" taking a percept, msgq = <<inform>> never read";
  violated = true;
}

let all = [ printed_object; flood_printed; inversion; budgeted; ties; native; flood_native ]

let find id = List.find_opt (fun r -> r.id = id) all

let apply t step =
  match step.action with
  | Host h -> Session.host t h
  | Rule ->
    (match Session.step t with
     | Session.Stepped -> Ok ()
     | _ -> Error "no rule is enabled")
  | Dequeue_seq seq ->
    let suffix = Printf.sprintf "#%d)" seq in
    let ends s = let n = String.length s and k = String.length suffix in
      n >= k && String.sub s (n - k) k = suffix in
    let rec index k = function
      | [] -> 0
      | c :: rest -> if ends c then k else index (k + 1) rest in
    (match Session.step ~choice:(index 0 (Session.choices t)) t with
     | Session.Stepped -> Ok ()
     | _ -> Error "no rule is enabled")

(* ------------------------------------------------------------ check *)

let member k = function `Assoc f -> List.assoc_opt k f | _ -> None
let list k j = match member k j with Some (`List l) -> l | _ -> []
let str k j = match member k j with Some (`String s) -> s | _ -> ""
let num k j = match member k j with Some (`Int n) -> n | _ -> -1

let entries k j =
  List.map (fun e -> if str "kind" e = "object" then str "object" e
             else if str "kind" e = "message" then "m:" ^ str "content" e
             else Printf.sprintf "%s#%d" (str "percept" e) (num "seq" e)) (list k j)

let expect what got want =
  if got = want then Ok () else Error (Printf.sprintf "%s is %s, TLC: %s" what got want)

let ( let* ) = Result.bind

let show l = "<<" ^ String.concat ", " l ^ ">>"

let check r t =
  let v = Session.view t in
  match list "agents" v with
  | [] -> Error "no agent"
  | a :: _ ->
    let last = str "last_action" a in
    let trace = Session.trace t in
    let count ev = List.length (List.filter (fun l ->
        let n = String.length ev in
        let rec has i = i + n <= String.length l && (String.sub l i n = ev || has (i + 1)) in
        has 0) trace) in
    let dequeued_seq () = match member "cur" a with Some (`Assoc _ as c) -> (match member "entry" c with Some e -> num "seq" e | None -> -1) | _ -> -1 in
    let waits_of seq = List.fold_left (fun acc w -> if num "seq" w = seq then num "inversions" w else acc) (-1) (list "waits" a) in
    match r.id with
    | "MCPrintedObject" ->
      let* () = expect "last.act" last "TransferSpin" in
      let* () = expect "o2a" (show (entries "o2a" a)) "<<\"obj\", position#1>>" in
      let* () = expect "pq" (show (entries "pq" a)) "<<>>" in
      expect "msgq" (show (entries "msgq" a)) "<<m:hello>>"
    | "MCFloodPrinted" ->
      let* () = expect "last.act" last "TransferOne" in
      let* () = expect "msgq" (show (entries "msgq" a)) "<<m:hello>>" in
      let* () = expect "behaviour steps" (string_of_int (count "\"event\":\"behaviour_step\"")) "0" in
      expect "dispatches" (string_of_int (count "\"event\":\"dequeue\"")) "0"
    | "MCInversion" ->
      let* () = expect "last.act" last "Dequeue" in
      let* () = expect "dequeued" (string_of_int (dequeued_seq ())) "2" in
      let* () = expect "dispatched" (string_of_int (num "dispatched" a)) "2" in
      expect "waits[obstacle#3]" (string_of_int (waits_of 3)) "2"
    | "MCBudgeted" ->
      let* () = expect "last.act" last "Dequeue" in
      let* () = expect "dequeued" (string_of_int (dequeued_seq ())) "3" in
      let* () = expect "dispatched" (string_of_int (num "dispatched" a)) "1" in
      expect "pq" (show (entries "pq" a)) "<<position#2>>"
    | "MCTiesUnstable" ->
      let* () = expect "last.act" last "Dequeue" in
      let* () = expect "dequeued" (string_of_int (dequeued_seq ())) "2" in
      expect "pq" (show (entries "pq" a)) "<<a#1>>"
    | "MCNative" ->
      let* () = expect "last.act" last "Idle" in
      let* () = expect "msgq" (show (entries "msgq" a)) "<<noise#3>>" in
      let handled = List.filter_map (fun l ->
          match Trace.line_of_json (Yojson.Safe.from_string l) with
          | Ok { event = Trace.Behaviour_step { taken = Some (Trace.Took_percept e); _ }; _ } ->
            Some (Printf.sprintf "%s#%d" e.percept e.seq)
          | _ -> None) (List.tl trace) in
      expect "percepts taken, in order" (show handled) "<<position#2, obstacle#1>>"
    | "MCFloodNative" ->
      let* () = expect "last.act" last "BehaviourStep" in
      let* () = expect "msgq" (show (entries "msgq" a)) "<<m:hello>>" in
      expect "messages handled" (string_of_int (count "hello handled")) "0"
    | _ -> Ok ()

let run r =
  match Session.create r.setup with
  | Error e -> Error (String.concat "\n" e)
  | Ok t ->
    let rec go k = function
      | [] -> Ok t
      | st :: rest ->
        (match apply t st with
         | Ok () ->
           (* the label of the rule taken is the step's TLA+ action *)
           let v = Session.view t in
           let last = match list "agents" v with a :: _ -> str "last_action" a | [] -> "" in
           if last <> st.tla then Error (Printf.sprintf "%s step %d: the machine took %s, TLC %s" r.id k last st.tla)
           else go (k + 1) rest
         | Error m -> Error (Printf.sprintf "%s step %d (%s): %s" r.id k st.tla m)) in
    go 1 r.steps

let host_json = function
  | Session.Notify { agent; percept; priority } ->
    `Assoc ([ "kind", `String "notify"; "agent", `String agent; "text", `String percept ]
            @ (match priority with Some k -> [ "priority", `Int k ] | None -> []))
  | Session.Put { agent; obj } -> `Assoc [ "kind", `String "put"; "agent", `String agent; "text", `String obj ]
  | Session.Message { agent; perf; content; during = _ } ->
    `Assoc [ "kind", `String "message"; "agent", `String agent; "performative", `String perf; "text", `String content ]

let to_json () =
  `List (List.map (fun r ->
      let s = r.setup in
      `Assoc [
        "id", `String r.id; "title", `String r.title; "finding", `String r.finding;
        "command", `String r.command; "final", `String r.final; "violated", `Bool r.violated;
        "files", `List (List.map (fun (n, t) -> `Assoc [ "name", `String n; "text", `String t ]) s.files);
        "agents", `List (List.map (fun a -> `String a) s.agents);
        "variant", `String (Mc.string_of_variant s.variant);
        "tie", `String (match s.tie with Mc.Stable -> "stable" | Mc.Unstable -> "unstable");
        "budget", `Int s.budget;
        "o2a_capacity", (match s.o2a_capacity with Some c -> `Int c | None -> `Null);
        "steps", `List (List.map (fun st ->
            `Assoc [ "tla", `String st.tla; "say", `String st.say;
                     "do", (match st.action with
                         | Host h -> host_json h
                         | Rule -> `Assoc [ "kind", `String "rule" ]
                         | Dequeue_seq n -> `Assoc [ "kind", `String "dequeue"; "seq", `Int n ]) ]) r.steps) ])
      all)
