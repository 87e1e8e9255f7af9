(* The OCaml checks of validate: trace_check.mli, docs/trace-format.md. *)

exception Invalid of int * string

type agent = {
  name : string;
  atype : string;
  mutable created : bool;
  mutable destroyed : int;            (* the line of its destroy, 0 before *)
  mutable last_action : string;       (* the action of its last step *)
  notified : (int, Trace.entry) Hashtbl.t;   (* seq -> the percept notified (R2b) *)
  taken : (int, unit) Hashtbl.t;      (* seqs dequeued (or taken, native) *)
  transferred : (int, unit) Hashtbl.t;   (* printed: seqs moved by transfer_one *)
  mutable next_seq : int;
  mutable puts : int;
  mutable o2a_percepts : int;
  mutable o2a_objects : int;
  mutable msgq_percepts : int;        (* native: percepts moved to the message queue (D6) *)
  mutable dispatch : Trace.entry option;   (* the percept being dispatched *)
  delivered : (int, Trace.message) Hashtbl.t;   (* seq -> the message delivered *)
  consumed : (int, unit) Hashtbl.t;
  mutable msg_seq : int;
  undeliverable : (string * string * string) Queue.t;
      (* sent to agents that do not exist, not yet reported: receiver, performative, content *)
  failures : string Queue.t;
      (* ams's failures owed to this agent, not yet delivered: their contents (R5e, D43) *)
  mutable window : bool;
      (* its last agent rule was a behaviour step, and no message delivered
         after that step has come since: a SendInStep may come (R5d) *)
}

(* The platform's own agents (R5e): never in a header, never answer a
   program's message (D44); ams sends the failures. *)
let platform_agents = [ "ams"; "df" ]

let check (h : Trace.header) lines =
  let line_no = ref 1 in
  let fail fmt = Printf.ksprintf (fun s -> raise (Invalid (!line_no, s))) fmt in
  try
    (* The header's own consistency. *)
    if h.agents = [] then fail "the header names no agent";
    let rec distinct what = function
      | x :: rest -> if List.mem x rest then fail "the header names %s %s twice" what x else distinct what rest
      | [] -> () in
    distinct "agent" (List.map fst h.agents);
    distinct "behaviour" (List.map (fun (b : Trace.behaviour_info) -> b.name) h.behaviours);
    List.iter (fun (n, _) ->
        if n = "" then fail "the header names an agent with an empty name";
        (* D25 *)
        if n = "host" then fail "the header names an agent host: that is the sender of the host's messages (R5e)";
        if List.mem n platform_agents then fail "the header names an agent %s: that is one of the platform's own agents (R5e)" n)
      h.agents;
    let agents = List.map (fun (name, atype) ->
        (name, { name; atype; created = false; destroyed = 0; last_action = "Init";
                 notified = Hashtbl.create 16; taken = Hashtbl.create 16; transferred = Hashtbl.create 16; next_seq = 0; puts = 0;
                 o2a_percepts = 0; o2a_objects = 0; msgq_percepts = 0; dispatch = None;
                 delivered = Hashtbl.create 16; consumed = Hashtbl.create 16; msg_seq = 0;
                 undeliverable = Queue.create (); failures = Queue.create (); window = false })) h.agents in
    let to_create = ref h.agents in
    (* the messages sent by agents, not yet delivered, in the order they
       must arrive (R5e, D47): performative and content *)
    let pending = In_flight.create h in
    let is_agent = Hashtbl.create 8 in
    List.iter (fun (n, _) -> Hashtbl.replace is_agent n ()) h.agents;
    let printed = h.variant = "printed" and native = h.variant = "native" in
    let known_behaviour b =
      if not (List.exists (fun (i : Trace.behaviour_info) -> i.name = b) h.behaviours) then
        fail "behaviour %s is not in the header" b in
    let effects = List.iter (function Trace.Activated b -> known_behaviour b | Trace.Deactivated -> ()) in
    let used a = a.o2a_percepts + a.o2a_objects + (if native then a.msgq_percepts else 0) in
    let room what a =
      match h.o2a_capacity with
      | Some c when used a >= c ->
        fail "the O2A queue of %s already holds %d entries, its capacity: this %s must be refused (R2d)" a.name c what
      | _ -> () in
    let refused what a =
      match h.o2a_capacity with
      | None -> fail "a refused %s, but the O2A queue is unbounded (o2a_capacity is null): nothing is refused (R2d)" what
      | Some c when used a < c ->
        fail "a refused %s, but the O2A queue of %s holds %d of %d entries: it has room (R2d)" what a.name (used a) c
      | Some _ -> () in
    let same_entry a what (e : Trace.entry) =
      match Hashtbl.find_opt a.notified e.seq with
      | None -> fail "%s of seq %d, but %s was notified no percept with seq %d" what e.seq a.name e.seq
      | Some n when n.percept <> e.percept ->
        fail "%s of seq %d carries %s, but the percept notified with seq %d is %s" what e.seq e.percept e.seq n.percept
      | Some n when n.priority <> e.priority ->
        fail "%s of seq %d has priority %d, but the percept %s was notified with priority %d"
          what e.seq e.priority n.percept n.priority
      | Some _ -> () in
    let take a what (e : Trace.entry) =
      same_entry a what e;
      if Hashtbl.mem a.taken e.seq then fail "%s of seq %d: that percept was already taken" what e.seq;
      Hashtbl.replace a.taken e.seq () in
    let expected_step = ref 1 in
    List.iter (fun (n, (l : Trace.line)) ->
        line_no := n;
        if l.step <> !expected_step then
          fail "step %d, but the steps of a trace are numbered 1, 2, 3... in order: %d expected" l.step !expected_step;
        incr expected_step;
        let a = match List.assoc_opt l.agent agents with
          | Some a -> a
          | None -> fail "agent %s is not in the header" l.agent in
        (* The life of the agent. *)
        (match l.event with
         | Trace.Create { agent_type; behaviours; _ } ->
           if a.created then fail "agent %s is created twice" a.name;
           (match !to_create with
            | (next, _) :: rest when next = a.name -> to_create := rest
            | (next, _) :: _ -> fail "agent %s is created before %s, but the header lists the agents in creation order" a.name next
            | [] -> ());
           if agent_type <> a.atype then
             fail "agent %s is created with type %s, but the header gives it type %s" a.name agent_type a.atype;
           List.iter known_behaviour behaviours;
           a.created <- true
         | _ when not a.created -> fail "an event of agent %s before its create" a.name
         | Trace.Body { action = "destroy"; _ } when a.destroyed > 0 -> ()
         | _ when a.destroyed > 0 ->
           fail "an event of agent %s after its destroy (line %d)" a.name a.destroyed
         | _ -> ());
        (* An event inside a step names the action of that step. *)
        (match l.event, Trace.action l.event with
         | Trace.Body { action; _ }, _ ->
           if action <> a.last_action then
             fail "this event happens inside a step of %s, whose last step was %s, not %s" a.name a.last_action action
         | Trace.Destroy, _ -> a.last_action <- "destroy"
         | _, Some act -> a.last_action <- act
         | _, None -> ());
        (* The window of SendInStep (R5d): a behaviour step opens it; any
           other rule of the agent closes it (a delivery after the step, below). *)
        (match l.event with
         | Trace.Behaviour_step _ -> a.window <- true
         | Trace.Deliver _ | Trace.Notify _ | Trace.Put _ | Trace.Refused _ | Trace.Refused_put _
         | Trace.Undeliverable _ | Trace.Body _ -> ()
         | _ -> a.window <- false);
        (* A dispatch (Dequeue ... EndDispatch) is not interrupted by another
           loop step (R3b). *)
        (match l.event, a.dispatch with
         | (Trace.Dequeue _ | Trace.Transfer _ | Trace.Transfer_one _ | Trace.Transfer_spin _ | Trace.Transfer_end
           | Trace.Behaviour_step _ | Trace.Next_iteration | Trace.Idle), Some e ->
           fail "%s, but the dispatch of seq %d has not ended" (Trace.event_name l.event) e.seq
         | _ -> ());
        match l.event with
        | Trace.Create _ -> ()
        | Trace.Destroy -> a.destroyed <- n
        | Trace.Notify { entry = e; overridden } ->
          if e.seq <> a.next_seq + 1 then
            fail "notify with seq %d, but the seqs of %s are 1, 2, 3...: %d expected (R2b)" e.seq a.name (a.next_seq + 1);
          let ty = match String.index_opt e.percept '(' with Some i -> String.sub e.percept 0 i | None -> e.percept in
          (match List.assoc_opt ty h.percepts with
           | None -> fail "percept type %s is not in the header" ty
           | Some d when not overridden && d <> e.priority ->
             fail "notify of %s with priority %d, but its default priority is %d (R1a); an override is NotifyWith" ty e.priority d
           | Some _ -> ());
          room "notify" a;
          a.next_seq <- e.seq;
          Hashtbl.replace a.notified e.seq e;
          a.o2a_percepts <- a.o2a_percepts + 1
        | Trace.Refused _ -> refused "notify" a
        | Trace.Refused_put _ -> refused "put" a
        | Trace.Put { index; _ } ->
          if index <> a.puts + 1 then
            fail "put with index %d, but the objects put into %s are numbered 1, 2, 3...: %d expected" index a.name (a.puts + 1);
          room "put" a;
          a.puts <- index;
          a.o2a_objects <- a.o2a_objects + 1
        | Trace.Deliver { message = m; seq; in_step } ->
          if in_step && not a.window then
            fail "a delivery during a behaviour step of %s (SendInStep), but its last rule was not a behaviour step, \
                  or a message that came after that step was delivered since (R5d)" a.name;
          if not in_step then a.window <- false;
          if seq <> a.msg_seq + 1 then
            fail "deliver with seq %d, but the messages to %s are numbered 1, 2, 3...: %d expected" seq a.name (a.msg_seq + 1);
          a.msg_seq <- seq;
          Hashtbl.replace a.delivered seq m;
          if m.from = "ams" then begin
            match Queue.peek_opt a.failures with
            | Some content when m.performative = "failure" && m.content = content -> ignore (Queue.pop a.failures)
            | _ -> fail "a message %s %s from ams to %s, but ams owes %s no such failure: it sends one for each message \
                         reported undeliverable, whose content is the receiver's aid (R5e, D43)" m.performative m.content a.name a.name
          end
          else if m.from <> "host" then begin
            if not (List.mem_assoc m.from agents) then fail "a message from %s, which is neither an agent of the header, nor host, nor ams" m.from;
            match In_flight.take pending ~receiver:a.name ~sender:m.from with
            | None ->
              fail "a message to %s delivered from %s, but no message sent to %s waits for delivery (R5e)" a.name m.from a.name
            | Some (from, (perf, content)) ->
              if from <> m.from || perf <> m.performative || content <> m.content then
                fail "this delivery to %s is %s %s from %s, but the next message sent to %s is %s %s from %s (R5e: in the order sent%s)"
                  a.name m.performative m.content m.from a.name perf content from
                  (if In_flight.containers pending = 1 then ""
                   else Printf.sprintf " from container %s, D47" (In_flight.container pending m.from))
          end
        | Trace.Undeliverable { receiver; performative; content } ->
          if List.mem_assoc receiver agents then
            fail "a message to %s is undeliverable, but %s is an agent of the header" receiver receiver;
          (* the oldest message to that receiver not yet reported: the order
             of the sends holds per receiver, not across receivers (R6) *)
          let owed = List.of_seq (Queue.to_seq a.undeliverable) in
          let rec split before = function
            | ((r, _, _) as x) :: rest when r = receiver -> Some (List.rev before, x, rest)
            | x :: rest -> split (x :: before) rest
            | [] -> None in
          (match split [] owed with
           | Some (before, (_, p, c), after) when p = performative && c = content ->
             Queue.clear a.undeliverable;
             List.iter (fun x -> Queue.push x a.undeliverable) (before @ after);
             Queue.push (Interp_eval.Value.to_literal (Interp_eval.Value.Aid receiver)) a.failures
           | _ -> fail "%s reports undeliverable a message %s %s to %s that it did not send" a.name performative content receiver)
        | Trace.Transfer moved ->
          if printed then fail "a transfer in the printed loop, which moves one percept at a time (TransferOne)";
          if moved <> a.o2a_percepts then
            fail "transfer of %d percepts, but the O2A queue of %s holds %d (R3a: all move)" moved a.name a.o2a_percepts;
          a.o2a_percepts <- 0;
          if native then a.msgq_percepts <- a.msgq_percepts + moved
        | Trace.Transfer_one e ->
          if not printed then fail "transfer_one only happens in the printed loop";
          same_entry a "transfer_one" e;
          if Hashtbl.mem a.transferred e.seq then fail "transfer_one of seq %d: that percept was already moved" e.seq;
          Hashtbl.replace a.transferred e.seq ();
          if a.o2a_percepts = 0 then fail "transfer_one, but the O2A queue of %s holds no percept" a.name;
          a.o2a_percepts <- a.o2a_percepts - 1
        | Trace.Transfer_spin _ | Trace.Transfer_end ->
          if not printed then fail "%s only happens in the printed loop" (Trace.event_name l.event)
        | Trace.Dequeue e ->
          if native then fail "a dequeue in the native loop, which has no priority queue";
          take a "dequeue" e;
          a.dispatch <- Some e
        | Trace.Handle { percept; seq; effects = effs; behaviour; _ } ->
          known_behaviour behaviour;
          (match a.dispatch with
           | None -> fail "handle, but %s is dispatching no percept" a.name
           | Some e when e.seq <> seq || e.percept <> percept ->
             fail "handle of %s with seq %d, but the percept being dispatched is %s with seq %d" percept seq e.percept e.seq
           | Some _ -> ());
          effects effs
        | Trace.Skip { behaviour; _ } ->
          known_behaviour behaviour;
          if a.dispatch = None then fail "skip, but %s is dispatching no percept" a.name
        | Trace.End_dispatch { seq; _ } ->
          (match a.dispatch with
           | Some e when e.seq = seq -> a.dispatch <- None
           | Some e -> fail "the dispatch of seq %d ends with seq %d" e.seq seq
           | None -> fail "%s, but %s is dispatching no percept" (Trace.event_name l.event) a.name)
        | Trace.Behaviour_step { behaviour; taken; action_effects; handler; _ } ->
          known_behaviour behaviour;
          Option.iter effects action_effects;
          Option.iter (fun (_, e) -> effects e) handler;
          (match taken with
           | None -> ()
           | Some (Trace.Took_percept e) ->
             if not native then fail "a behaviour step takes a percept only in the native loop";
             take a "a behaviour step's percept" e;
             a.msgq_percepts <- a.msgq_percepts - 1
           | Some (Trace.Took_message (m, seq)) ->
             (match Hashtbl.find_opt a.delivered seq with
              | None -> fail "a behaviour step takes message seq %d, but no message with seq %d was delivered to %s" seq seq a.name
              | Some d when d <> m ->
                fail "a behaviour step takes message seq %d as %s %s from %s, but it was delivered as %s %s from %s"
                  seq m.performative m.content m.from d.performative d.content d.from
              | Some _ -> ());
             if Hashtbl.mem a.consumed seq then fail "message seq %d of %s is taken twice" seq a.name;
             Hashtbl.replace a.consumed seq ())
        | Trace.Next_iteration | Trace.Idle -> ()
        | Trace.Body { body; action } ->
          match body with
          | Trace.Activate b -> known_behaviour b
          | Trace.Send { performative; content; receivers } when action <> "destroy" ->
            (* delivered after the step (R5e); what on destroy sends never is (D26) *)
            List.iter (fun r ->
                if Hashtbl.mem is_agent r then In_flight.push pending ~receiver:r ~sender:a.name (performative, content)
                else if not (List.mem r platform_agents) then Queue.push (r, performative, content) a.undeliverable)
              receivers
          | Trace.Send _ | Trace.Log _ | Trace.Invoke _ | Trace.Deactivate _ | Trace.Error _ -> ())
      lines;
    line_no := (match List.rev lines with (n, _) :: _ -> n | [] -> 1);
    (match !to_create with
     | (next, _) :: _ -> fail "agent %s of the header is never created" next
     | [] -> ());
    (* A complete trace (every agent destroyed, D14) has delivered every message (D26). *)
    if List.for_all (fun (_, a) -> a.destroyed > 0) agents then begin
      In_flight.iter pending (fun ~receiver ~sender (perf, content) ->
          fail "the run ended, but the message %s %s from %s to %s was never delivered (R5e)" perf content sender receiver);
      List.iter (fun (_, a) -> match Queue.peek_opt a.undeliverable with
          | Some (r, perf, content) ->
            fail "the run ended, but the message %s %s from %s to %s, which does not exist, was never reported undeliverable"
              perf content a.name r
          | None -> ()) agents;
      List.iter (fun (_, a) -> match Queue.peek_opt a.failures with
          | Some content ->
            fail "the run ended, but the failure %s that ams owes %s was never delivered (R5e, D43)" content a.name
          | None -> ()) agents
    end;
    Ok ()
  with Invalid (n, m) -> Error (n, m)
