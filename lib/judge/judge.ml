(* The judge: a trace replayed through the reference semantics of the
   program that ran (docs/trace-format.md, "Judging a run"). The trace
   gives only the choices the rulings leave open: which agent's rule comes
   next (R6), when each host event and each delivery comes, which entry
   of the highest priority a Dequeue takes under unstable ties. The
   program gives everything else; the first line no run of the program
   explains is the verdict.

   For each agent the judge keeps the configurations of the reference
   machine the run can be in at this point of the trace (its
   candidates), each with the body lines its last rule still owes.
   In a full trace every rule has its line, and there is one candidate.
   In an observable trace the loop's own steps have none: before each line
   of an agent, a candidate may take any of them first, so the candidates
   are every configuration those hidden steps reach; each line keeps those
   that explain it. The candidates share the program's data (the agents'
   properties, which no hidden step changes) and are bounded in number;
   bodies change lists and maps in place, so a body tried on several
   candidates (or run while searching the hidden steps) starts each time
   from a deep copy of the data (snapshot, restore), and a full trace's
   one candidate runs on the data itself.

   Speed: the trace's lines come from Trace's reader (most of them read
   without a JSON tree, Trace.fast_line); a line is compared with the
   program's event as a structure, trying only the rules that write lines
   of its kind (rules_of_event). *)

module Mc = Semantics.Machine
module P = Interp.Runtime.P
module M = P.M
module V = Interp.Value
module E = Interp.Eval
module T = Typing.Tenv

type level = Full | Observable

let level_of_string = function "full" -> Some Full | "observable" -> Some Observable | _ -> None
let string_of_level = function Full -> "full" | Observable -> "observable"

type options = {
  fuel : int;
  max_memory : int option;
  bound : int;
}

let default_options = { fuel = 100_000; max_memory = None; bound = 64 }

type verdict =
  | Accepted of { lines : int; complete : bool; cut : bool; level : level; containers : int }
  | Rejected of { line : int; message : string }

exception Reject of int * string

(* ------------------------------------------------------------ state *)

(* A configuration the agent can be in, and the body lines (action,
   body) its last rule still owes, oldest first, with the message each
   send line posts. *)
type cand = {
  c : M.t;
  owed : (string * Trace.body * E.message list) list;
}

(* The platform's own agents (R5e): messages to them are answered by the
   platform, never traced as theirs. *)
let platform_agents = [ "ams"; "df" ]

type agent = {
  name : string;
  atype : string;
  args : V.t list;
  mutable cands : cand list;
  mutable created : bool;
  mutable destroyed : bool;
  names : (int, string) Hashtbl.t;   (* instance id -> its behaviour, when last seen *)
  mutable undeliverable : (string * E.message) list;   (* sent to absent agents, oldest first *)
  mutable holding : (E.message list * string list) list;
      (* the messages of the send lines of the step under way, newest
         first, with their receivers: they leave when the step ends (R5e,
         R6 revised), not at their send line *)
}

type st = {
  env : T.t;
  params : Mc.params;
  config : E.config;
  level : level;
  bound : int;
  agents : agent array;
  by_name : (string, agent) Hashtbl.t;   (* the agents by name (a run may have thousands) *)
  inflight : E.message In_flight.t;
      (* the messages agents sent and not yet delivered, in the order
         they must arrive (R5e, D47) *)
  answers : (string, (string * E.message) Queue.t) Hashtbl.t;
      (* per receiver, the platform's answers to it not yet delivered (its
         agents answer when they get to it: in their order, not in the
         order of the agents' sends) *)
  mutable from_destroy : E.message list;
      (* the messages of on destroy, which a run that ended need not have
         delivered (D26), told apart by identity *)
  mutable ncreated : int;
  mutable lines : int;
}

let reject n fmt = Printf.ksprintf (fun m -> raise (Reject (n, m))) fmt

let find_agent st name = Hashtbl.find_opt st.by_name name

let answers st r = match Hashtbl.find_opt st.answers r with
  | Some q -> q
  | None -> let q = Queue.create () in Hashtbl.replace st.answers r q; q

(* ------------------------------------------------- what a rule writes *)

let show_event (e : Trace.event) =
  let j = Trace.line_to_json { Trace.step = 1; agent = ""; event = e } in
  Yojson.Safe.to_string (Trace.without_step (match j with
      | `Assoc f -> `Assoc (List.remove_assoc "agent" f) | j -> j))

let show_body action b = show_event (Trace.Body { action; body = b })

let note_names ag (c : M.t) =
  List.iter (fun (i : E.beh Mc.instance) -> Hashtbl.replace ag.names i.id (E.beh_type i.beh)) c.active

(* The behaviour of instance [id] as a line names it: active before the
   rule, else after it, else when last seen (a Skip of an instance an
   earlier handler of the dispatch deactivated). *)
let name_of ag (before : M.t) (after : M.t) id =
  let find (c : M.t) = List.find_map (fun (i : E.beh Mc.instance) ->
      if i.id = id then Some (E.beh_type i.beh) else None) c.active in
  match find before with
  | Some n -> n
  | None -> match find after with
    | Some n -> n
    | None -> match Hashtbl.find_opt ag.names id with Some n -> n | None -> "?"

(* The line rule [l] writes, reaching [c'] with these body events. *)
let expected ag ~(before : M.t) (c' : M.t) l evs =
  Interp.Tracer.event_of ~percept:(fun ?keep:_ v -> V.to_literal v) ~name:(name_of ag before c') c' l evs

(* The body lines of a rule's events (Ran is no line), each send with the
   messages it posts, one per receiver. *)
let owed_of sender action evs =
  List.filter_map (fun (ev : E.event) ->
      match Interp.Tracer.body ev with
      | None -> None
      | Some b ->
        let msgs = match ev with
          | E.Sent { perf; content; receivers } ->
            List.map (fun _ -> { E.perf; content; sender }) receivers
          | _ -> [] in
        Some (action, b, msgs)) evs

(* The configuration after a rule, its events and messages taken out (the
   events are the rule's, the messages are posted by its send lines). *)
let settle (c : M.t) =
  let (world, evs) = E.take_events c.world in
  let (world, _) = E.Bodies.take_outbox world in
  ({ c with world }, evs)

(* ------------------------------------------------------ hidden steps *)

(* The rules an observable trace does not show: the loop's own steps
   (docs/trace-format.md, "Observable traces"). *)
let hidden (l : M.lbl) = match l with
  | Mc.Transfer _ | Mc.Transfer_one _ | Mc.Transfer_spin _ | Mc.Transfer_end | Mc.Dequeue _
  | Mc.Skip _ | Mc.Next_iteration | Mc.Idle -> true
  | Mc.End_dispatch { discarded; _ } -> not discarded
  | _ -> false

(* A key of a candidate, for merging equal ones: the configuration but its
   agent's data (shared) and its last label, and what it owes. *)
let key (x : cand) =
  let c = x.c in
  let b = Buffer.create 128 in
  let add s = Buffer.add_string b s; Buffer.add_char b ' ' in
  let int i = add (string_of_int i) in
  add (match c.phase with Mc.Transfer_phase -> "t" | Dispatch_phase -> "d" | Handle_phase -> "h" | Idle_phase -> "i");
  Semantics.Fqueue.fold (fun () -> function Mc.O_percept e -> int e.seq | Mc.O_object _ -> add "o") () c.o2a;
  add "|";
  Semantics.Pqueue.fold (fun () (e : V.t Mc.entry) -> int e.seq) () c.pq;
  add "|";
  Semantics.Fqueue.fold (fun () -> function Mc.M_message { mseq; _ } -> int mseq | Mc.M_percept e -> int (- e.seq)) () c.msgq;
  add "|"; int c.next_seq; int c.msg_seq; int c.puts; int c.pos; int c.dispatched;
  List.iter (fun (i : E.beh Mc.instance) -> int i.id) c.active; add "|";
  List.iter int c.ready; add "|"; List.iter int c.blocked; add "|";
  (match c.cur with
   | Some d -> int d.e.seq; List.iter (fun (i, h) -> int i; int h) d.todo; add (string_of_bool d.applied)
   | None -> add "-");
  int c.world.next_uid; int (List.length x.owed);
  List.iter (fun (a, body, _) -> add a; add (show_body a body)) x.owed;
  Buffer.contents b

let merge st n cands =
  match cands with
  | [] | [ _ ] -> cands
  | _ ->
  let seen = Hashtbl.create 8 in
  let out = List.filter (fun x ->
      let k = key x in
      if Hashtbl.mem seen k then false else (Hashtbl.replace seen k (); true)) cands in
  if List.length out > st.bound then
    reject n "more than %d configurations of the agent explain the trace so far (the judge's search bound, --bound)" st.bound;
  out

(* The data a body can change: the cells of the agent's properties and of
   its active behaviours' properties. Lists, maps and the slots of schema
   values are changed in place by bodies (V: "mutable and shared by
   reference"), so putting a cell's value back does not undo a body: a
   snapshot holds a deep copy of every cell's value, taken in one pass so
   that what two cells share stays shared, and each restore puts a fresh
   copy of it back (the snapshot itself is never given to a body). *)
let copy_values (vs : V.t list) =
  let seen : (Obj.t * V.t) list ref = ref [] in
  let memo o make =
    match List.assq_opt (Obj.repr o) !seen with
    | Some v -> v
    | None -> make () in
  let rec copy (v : V.t) : V.t = match v with
    | V.List l -> memo l (fun () ->
        let l' = { V.items = [||]; len = l.len } in
        let v' = V.List l' in
        seen := (Obj.repr l, v') :: !seen;
        l'.items <- Array.map copy (Array.sub l.items 0 l.len); v')
    | V.Map m -> memo m (fun () ->
        let v' = V.map_empty () in
        seen := (Obj.repr m, v') :: !seen;
        (match v' with
         | V.Map m' -> List.iter (fun (k, x) -> V.map_set m' (copy k) (copy x)) (V.map_bindings m)
         | _ -> ());
        v')
    | V.Schema s -> memo s (fun () ->
        let s' = { V.sname = s.sname; slots = Array.map (fun (n, r) -> (n, ref !r)) s.slots } in
        let v' = V.Schema s' in
        seen := (Obj.repr s, v') :: !seen;
        Array.iter (fun (_, r) -> r := copy !r) s'.slots; v')
    | v -> v in
  List.map copy vs

let cells_of (c : M.t) =
  let out = ref [] in
  let add tbl = Syntax.Strtbl.iter (fun _ (cell : E.cell) -> out := cell :: !out) tbl in
  add c.world.props;
  List.iter (fun (i : E.beh Mc.instance) -> add i.beh.bprops) c.active;
  !out

type snapshot = { cells : E.cell list; values : V.t list }

let snapshot (cs : M.t list) =
  let cells = List.fold_left (fun acc c ->
      List.fold_left (fun acc cell -> if List.memq cell acc then acc else cell :: acc) acc (cells_of c)) [] cs in
  { cells; values = copy_values (List.map (fun (cell : E.cell) -> cell.v) cells) }

let restore s = List.iter2 (fun (cell : E.cell) v -> cell.v <- v) s.cells (copy_values s.values)

(* The rules an observable trace may hide, each tried alone (a behaviour
   step is never hidden: its body is not run before its line). *)
let hidden_rules =
  let r = M.rules in
  [ r.transfer; r.transfer_one; r.transfer_spin; r.transfer_end; r.dequeue; r.handle_or_skip;
    r.end_dispatch; r.next_iteration; r.idle ]

(* Every configuration a candidate may be in before its next line: itself
   and, in an observable trace, those hidden steps reach (a hidden step
   whose bodies record something, an error of a guard, stops there: its
   lines come next). *)
let expand st ag n (cands : cand list) =
  if st.level = Full then cands
  else begin
    let out = ref [] and count = ref 0 and seen = Hashtbl.create 16 in
    let rec go (x : cand) depth =
      (* a configuration reached before is not explored again: hidden steps
         that go round (the printed loop spinning on an object) end *)
      let k = key x in
      if not (Hashtbl.mem seen k) then begin
      Hashtbl.replace seen k ();
      out := x :: !out;
      incr count;
      if !count > 100 * st.bound then
        reject n "agent %s: the hidden steps before this line go on past the judge's search bound" ag.name;
      if x.owed = [] && depth < 10_000 then begin
        (* Handle or Skip decides by running the handler (a Handle runs its
           body, whose line comes later): the data is put back after it *)
        let saved = if x.c.phase = Mc.Handle_phase then Some (snapshot [ x.c ]) else None in
        let next = List.concat_map (fun (rule : M.rule) -> rule st.params x.c) hidden_rules in
        Option.iter restore saved;
        List.iter (fun (l, c') ->
            if hidden l then begin
              let (c', evs) = settle c' in
              go { c = c'; owed = owed_of ag.name (Mc.action_name l) evs } (depth + 1)
            end) next
      end
      end in
    List.iter (fun x -> go x 0) cands;
    merge st n (List.rev !out)
  end

(* ------------------------------------------------------------- lines *)

(* The messages a matched send line posts: in flight to its receivers; to
   an absent one, owed as undeliverable by the sender; to a platform agent,
   theirs, never answered (R5e, D44). *)
let post st ag (msgs : E.message list) receivers =
  List.iter2 (fun r (m : E.message) ->
      if find_agent st r <> None then In_flight.push st.inflight ~receiver:r ~sender:ag.name m
      else if List.mem r platform_agents then ()
      else ag.undeliverable <- ag.undeliverable @ [ (r, m) ]) receivers msgs

(* The step under way has ended (every candidate wrote every line it owed):
   the messages of its send lines leave, in the order sent. Before that, no
   delivery of them can be explained (R5e, R6 revised: a step is one rule;
   docs/trace-format.md, "What each step writes"). *)
let release st ag =
  if ag.holding <> [] && List.for_all (fun x -> x.owed = []) ag.cands then begin
    List.iter (fun (msgs, receivers) -> post st ag msgs receivers) (List.rev ag.holding);
    ag.holding <- []
  end

(* D46: a body line as the judge compares it: all of it but an error's
   wording (its place, [at], is normative). *)
let same_body (b : Trace.body) (b' : Trace.body) = match b, b' with
  | Trace.Error { at; _ }, Trace.Error { at = at'; _ } -> String.equal at at'
  | _ -> b = b'

(* The agent rules in the spec's order (Machine.step_by's), and those whose
   label writes a line of this kind: only they can explain it. *)
let all_rules =
  let r = M.rules in
  [ r.transfer; r.transfer_one; r.transfer_spin; r.transfer_end; r.dequeue; r.handle_or_skip;
    r.end_dispatch; r.behaviour_step; r.next_iteration; r.idle ]

let rules_of_event (ev : Trace.event) =
  let r = M.rules in
  match ev with
  | Trace.Transfer _ -> [ r.transfer ]
  | Trace.Transfer_one _ -> [ r.transfer_one ]
  | Trace.Transfer_spin _ -> [ r.transfer_spin ]
  | Trace.Transfer_end -> [ r.transfer_end ]
  | Trace.Dequeue _ -> [ r.dequeue ]
  | Trace.Handle _ | Trace.Skip _ -> [ r.handle_or_skip ]
  | Trace.End_dispatch _ -> [ r.end_dispatch ]
  | Trace.Behaviour_step _ -> [ r.behaviour_step ]
  | Trace.Next_iteration -> [ r.next_iteration ]
  | Trace.Idle -> [ r.idle ]
  | _ -> all_rules

let agent_line st n ag (ev : Trace.event) =
  match ev with
  | Trace.Body { action; body } ->
    let cands = expand st ag n ag.cands in
    let posted = ref None in
    let kept = List.filter_map (fun x -> match x.owed with
        | (a, b, msgs) :: rest when a = action && same_body b body -> posted := Some msgs; Some { x with owed = rest }
        | _ -> None) cands in
    (match kept with
     | [] ->
       let owes = List.filter_map (fun x -> match x.owed with (a, b, _) :: _ -> Some (show_body a b) | [] -> None) cands in
       reject n "agent %s: %s" ag.name
         (match owes with
          | [] -> Printf.sprintf "no rule of the program writes %s here" (show_event ev)
          | o :: _ -> Printf.sprintf "the program writes %s here, not %s" o (show_event ev))
     | _ ->
       (match body, !posted with
        | Trace.Send { receivers; _ }, Some msgs ->
          if action = "destroy" then st.from_destroy <- msgs @ st.from_destroy;
          ag.holding <- (msgs, receivers) :: ag.holding
        | _ -> ());
       ag.cands <- merge st n kept;
       release st ag)
  | _ ->
    let cands = expand st ag n ag.cands in
    let alternatives = ref [] in
    let note l e = if not (st.level = Observable && hidden l) then alternatives := e :: !alternatives in
    let rules = rules_of_event ev in
    (* with several candidates, each one's rule runs its body on the shared
       data: a snapshot is put back before each, and the data after the
       first rule that explains the line kept at the end (one candidate, the
       case of a full trace, needs none) *)
    let ready = List.filter (fun x -> x.owed = []) cands in
    let saved = match ready with _ :: _ :: _ -> Some (snapshot (List.map (fun x -> x.c) ready)) | _ -> None in
    let after = ref None in
    let kept = List.concat_map (fun x ->
        if x.owed <> [] then begin
          (match x.owed with (a, b, _) :: _ -> alternatives := `Shown (show_body a b) :: !alternatives | [] -> ());
          []
        end else
        begin
          (match saved, !after with Some s, _ -> restore s | None, _ -> ());
          let matched = List.filter_map (fun (l, c') ->
              let (c', evs) = settle c' in
              let e = expected ag ~before:x.c c' l evs in
              if e = ev then Some { c = c'; owed = owed_of ag.name (Mc.action_name l) evs }
              else (note l (`Event e); None)) (List.concat_map (fun (rule : M.rule) -> rule st.params x.c) rules) in
          (match saved, !after with
           | Some s, None when matched <> [] ->
             after := Some (List.map (fun (cell : E.cell) -> cell.v) s.cells)
           | _ -> ());
          matched
        end) cands in
    (match saved, !after with
     | Some s, Some vs -> List.iter2 (fun (cell : E.cell) v -> cell.v <- v) s.cells vs
     | _ -> ());
    (match kept with
     | [] ->
       (* what the other rules take here, for the verdict (the rules of
          this line's kind were tried above) *)
       List.iter (fun x -> if x.owed = [] then
                     List.iter (fun (rule : M.rule) ->
                         if not (List.memq rule rules) then
                           List.iter (fun (l, c') ->
                               let (c', evs) = settle c' in
                               note l (`Event (expected ag ~before:x.c c' l evs))) (rule st.params x.c))
                       all_rules) cands;
       let alternatives = List.map (function `Shown s -> s | `Event e -> show_event e) !alternatives in
       reject n "agent %s: %s" ag.name
         (match List.sort_uniq compare alternatives with
          | [] -> Printf.sprintf "the program takes no rule here (the agent is idle), not %s" (show_event ev)
          | [ a ] -> Printf.sprintf "the program takes %s here, not %s" a (show_event ev)
          | alts -> Printf.sprintf "the program takes one of %s here, not %s" (String.concat " or " alts) (show_event ev))
     | _ -> List.iter (fun x -> note_names ag x.c) kept; ag.cands <- merge st n kept)

(* ------------------------------------------------------------- host *)

(* A host operation on the agent: [f] on every candidate (after hidden
   steps, in an observable trace), each answering the configuration after
   it, or [None] when the operation cannot be there; [what] for the
   verdict. *)
let host st n ag what f =
  let cands = List.filter (fun x -> x.owed = []) (expand st ag n ag.cands) in
  match List.filter_map (fun x -> Option.map (fun c -> { c; owed = [] }) (f x.c)) cands with
  | [] -> reject n "agent %s: %s" ag.name (what ())
  | kept -> ag.cands <- merge st n kept

(* The trees of the literals read last, by their text (a run notifies the
   same percepts again and again); emptied when full, so that it does not
   grow with the trace. *)
let parsed : (string, Syntax.Ast.expr) Hashtbl.t = Hashtbl.create 1024

let parse_value ~file n text =
  match Hashtbl.find_opt parsed text with
  | Some e -> e
  | None ->
    match Syntax.Parse.expr ~file text with
    | e -> if Hashtbl.length parsed >= 4096 then Hashtbl.reset parsed; Hashtbl.replace parsed text e; e
    | exception Syntax.Diag.Failed d -> reject n "%s is not a Jadescript value: %s" text d.message

let percept_of st n ag text =
  match E.percept_value st.env ~agent_type:ag.atype (parse_value ~file:"trace" n text) with
  | r -> r
  | exception (E.Trap (_, m) | E.Link (_, m)) -> reject n "the percept %s: %s" text m

let literal_of st n text =
  match E.literal_value st.env (parse_value ~file:"trace" n text) with
  | v -> v
  | exception (E.Trap (_, m) | E.Link (_, m)) -> reject n "the value %s: %s" text m

let notify st n ag (entry : Trace.entry) overridden =
  let (v, default) = percept_of st n ag entry.percept in
  let priority = if overridden then Some entry.priority else None in
  host st n ag (fun () -> Printf.sprintf "the notify of %s (priority %d, seq %d) cannot be here" entry.percept entry.priority entry.seq)
    (fun c ->
       match M.notify_event st.params c v ~default ~priority with
       | Ok c' ->
         (match c'.last with
          | Mc.Notify e | Mc.Notify_with e when e.prio = entry.priority && e.seq = entry.seq -> Some c'
          | _ -> None)
       | Error _ -> None)

let refused st n ag text =
  let (v, default) = percept_of st n ag text in
  host st n ag (fun () -> Printf.sprintf "the O2A queue has room: %s is not refused (R2d)" text) (fun c ->
      match M.notify_event st.params c v ~default ~priority:None with
      | Error Mc.O2a_full -> Some c
      | _ -> None)

let refused_put st n ag text =
  ignore (literal_of st n text);
  host st n ag (fun () -> Printf.sprintf "the O2A queue has room: %s is not refused (R2d)" text) (fun c ->
      if M.o2a_has_room st.params c then None else Some c)

let put st n ag text index =
  let v = literal_of st n text in
  host st n ag (fun () -> Printf.sprintf "the put of %s (index %d) cannot be here" text index) (fun c ->
      if not (M.o2a_has_room st.params c) then None
      else let c' = M.put st.params c v in if c'.puts = index then Some c' else None)

(* A delivery (R5e): from the host (what the events file sent), or the
   oldest message in flight to the agent, which must be this one. *)
let deliver st n ag (m : Trace.message) seq in_step =
  let msg =
    if m.from = "host" then { E.perf = m.performative; content = literal_of st n m.content; sender = "host" }
    else if List.mem m.from platform_agents then
      match Queue.peek_opt (answers st ag.name) with
      | Some (sender, msg) when sender = m.from && msg.perf = m.performative && V.to_literal msg.content = m.content ->
        ignore (Queue.pop (answers st ag.name)); msg
      | _ ->
        reject n "agent %s: the platform owes it no %s %s from %s (R5e)" ag.name m.performative m.content m.from
    else match In_flight.take st.inflight ~receiver:ag.name ~sender:m.from with
      | Some (sender, msg) when sender = m.from && msg.perf = m.performative && V.to_literal msg.content = m.content -> msg
      | Some (sender, msg) ->
        reject n "agent %s: the next message to reach it is %s %s from %s (R5e: in the order of the sends%s), not %s %s from %s"
          ag.name msg.perf (V.to_literal msg.content) sender
          (if In_flight.containers st.inflight = 1 then ""
           else Printf.sprintf " made in container %s, D47" (In_flight.container st.inflight m.from))
          m.performative m.content m.from
      | None ->
        let held = match find_agent st m.from with
          | Some s -> List.exists (fun ((msgs : E.message list), rs) ->
              List.exists2 (fun (x : E.message) r -> r = ag.name && x.perf = m.performative
                                                     && V.to_literal x.content = m.content) msgs rs) s.holding
          | None -> false in
        if held then
          reject n "agent %s: %s %s from %s cannot reach it yet: the step of %s that sent it has not ended \
                    (a step's messages leave when it ends, R5e, R6)" ag.name m.performative m.content m.from m.from
        else
          reject n "agent %s: no message sent to it waits for delivery (%s %s from %s)" ag.name m.performative m.content m.from in
  host st n ag (fun () -> Printf.sprintf "the delivery of seq %d cannot be here%s" seq
                  (if in_step then " (during the agent's last behaviour step: it took another rule since, R5d)" else ""))
    (fun c ->
       let c' = if in_step then M.send_in_step st.params c msg else Some (M.send st.params c msg) in
       match c' with
       | Some c' when c'.msg_seq = seq -> Some c'
       | _ -> None)

(* The oldest message of [ag] to [receiver] not yet reported: reports keep
   the order of the sends to one receiver, not across receivers (R6: each
   receiver's messages arrive in order, the receivers in any). *)
let undeliverable st n ag receiver perf content =
  let rec split before = function
    | (r, m) :: rest when r = receiver -> Some (List.rev before, m, rest)
    | x :: rest -> split (x :: before) rest
    | [] -> None in
  match split [] ag.undeliverable with
  | Some (before, m, after) when m.perf = perf && V.to_literal m.content = content ->
    ag.undeliverable <- before @ after;
    (* R5e: the platform answers the sender with a failure from ams, which
       reaches it like any message *)
    Queue.push ("ams", Interp.Runtime.failure ~receiver) (answers st ag.name)
  | _ ->
    reject n "agent %s: no message of it to %s waits to be reported undeliverable (%s %s)" ag.name receiver perf content

let create st n ag (agent_type, args, behaviours) =
  if ag.created then reject n "agent %s is created twice" ag.name;
  let want = st.agents.(st.ncreated) in
  if want != ag then reject n "agent %s is created before %s (R5g: in the order the host gives)" ag.name want.name;
  if agent_type <> ag.atype then reject n "agent %s is a %s, not a %s" ag.name ag.atype agent_type;
  let lits = List.map V.to_literal ag.args in
  if lits <> args then
    reject n "agent %s is created with [%s], not [%s]" ag.name (String.concat ", " lits) (String.concat ", " args);
  let (a, behs) = match E.create_agent ~config:st.config st.env ~name:ag.name ~atype:ag.atype ~args:ag.args with
    | r -> r
    | exception E.Link (_, m) -> reject n "agent %s cannot be created: %s" ag.name m in
  let names = List.map E.beh_type behs in
  if names <> behaviours then
    reject n "agent %s's on create activates [%s], not [%s]" ag.name (String.concat ", " names) (String.concat ", " behaviours);
  let c = M.init st.params ~world:a behs in
  let (c, evs) = settle c in
  ag.created <- true;
  st.ncreated <- st.ncreated + 1;
  note_names ag c;
  ag.cands <- [ { c; owed = owed_of ag.name "Init" evs } ]

let destroy st n ag =
  if ag.destroyed then reject n "agent %s is destroyed twice" ag.name;
  let cands = expand st ag n ag.cands in
  let cands = List.filter (fun x -> x.owed = []) cands in
  (match cands with
   | [] -> reject n "agent %s: its last rule still owes its lines: %s" ag.name
             (String.concat ", " (List.filter_map (fun x -> match x.owed with (a, b, _) :: _ -> Some (show_body a b) | [] -> None) ag.cands))
   | _ -> ());
  ag.destroyed <- true;
  (* on destroy runs on each candidate: on the same data each time *)
  let saved = match cands with _ :: _ :: _ -> Some (snapshot (List.map (fun x -> x.c) cands)) | _ -> None in
  ag.cands <- List.map (fun x ->
      Option.iter restore saved;
      let a = E.destroy_agent x.c.world in
      let (a, evs) = E.take_events a in
      let (a, _) = E.Bodies.take_outbox a in
      { c = { x.c with world = a }; owed = owed_of ag.name "destroy" evs }) cands

(* ------------------------------------------------------------ a line *)

let line st n (l : Trace.line) =
  st.lines <- st.lines + 1;
  (* the lines are numbered 1, 2, 3... after the header (docs/trace-format.md) *)
  if l.step <> st.lines - 1 then reject n "step %d, but this is line %d of the trace's events: the steps are 1, 2, 3..." l.step (st.lines - 1);
  let ag = match find_agent st l.agent with
    | Some a -> a
    | None -> reject n "%s is not an agent of the run" l.agent in
  (match l.event with
   | Trace.Create _ -> ()
   | _ when not ag.created -> reject n "agent %s is not created yet" ag.name
   | Trace.Body _ when ag.destroyed -> ()
   | _ when ag.destroyed -> reject n "agent %s was destroyed" ag.name
   | _ -> ());
  if st.level = Observable then begin
    match l.event with
    | Trace.Transfer _ | Trace.Transfer_one _ | Trace.Transfer_spin _ | Trace.Transfer_end | Trace.Dequeue _
    | Trace.Skip _ | Trace.Next_iteration | Trace.Idle | Trace.End_dispatch { discarded = false; _ } ->
      reject n "a %s line in an observable trace (its header says so): the loop's own steps are not written"
        (Trace.event_name l.event)
    | _ -> ()
  end;
  match l.event with
  | Trace.Create { agent_type; args; behaviours } -> create st n ag (agent_type, args, behaviours)
  | Trace.Notify { entry; overridden } -> notify st n ag entry overridden
  | Trace.Refused { percept; _ } -> refused st n ag percept
  | Trace.Refused_put { obj; _ } -> refused_put st n ag obj
  | Trace.Put { obj; index } -> put st n ag obj index
  | Trace.Deliver { message; seq; in_step } -> deliver st n ag message seq in_step
  | Trace.Undeliverable { receiver; performative; content } -> undeliverable st n ag receiver performative content
  | Trace.Destroy -> destroy st n ag
  | ev -> agent_line st n ag ev

(* ------------------------------------------------------------- a run *)

let check_header env (h : Trace.header) specs =
  let fail fmt = Printf.ksprintf (fun m -> raise (Reject (1, m))) fmt in
  let expected = Interp.Tracer.program_summary env in
  if h.behaviours <> fst expected then fail "the header's behaviours are not the program's";
  if List.sort compare h.percepts <> List.sort compare (snd expected) then fail "the header's percept types are not the program's";
  let agents = List.map (fun (n, ty, _) -> (n, ty)) specs in
  if h.agents <> agents then begin
    (* the first place they differ: a run may have thousands of agents *)
    let show = function Some (n, t) -> n ^ ":" ^ t | None -> "no agent" in
    let rec first k a b = match a, b with
      | x :: a', y :: b' when x = y -> first (k + 1) a' b'
      | _ -> (k, List.nth_opt a 0, List.nth_opt b 0) in
    let (k, x, y) = first 1 h.agents agents in
    fail "the header's agents are not the judge's (%d in the header, %d given): agent %d is %s in the header, %s given"
      (List.length h.agents) (List.length agents) k (show x) (show y)
  end

let params_of (h : Trace.header) =
  let variant = Option.get (Mc.variant_of_string h.variant) in
  { Mc.default_params with variant; tie = (if h.tie_policy = "unstable" then Mc.Unstable else Mc.Stable);
                           budget = h.budget; o2a_capacity = h.o2a_capacity }

let judge env ~agents ?(options = default_options) path =
  let st = ref None in
  let header (h : Trace.header) =
    check_header env h agents;
    let level = match level_of_string h.level with Some l -> l | None -> Full in
    let all = Array.of_list (List.map (fun (name, atype, args) ->
        { name; atype; args; cands = []; created = false; destroyed = false;
          names = Hashtbl.create 8; undeliverable = []; holding = [] }) agents) in
    let by_name = Hashtbl.create (Array.length all) in
    Array.iter (fun a -> Hashtbl.replace by_name a.name a) all;
    st := Some { env; params = params_of h;
                 config = { E.default_config with fuel = options.fuel; max_memory = options.max_memory };
                 level; bound = options.bound; agents = all; by_name;
                 inflight = In_flight.create h; answers = Hashtbl.create 8; from_destroy = []; ncreated = 0; lines = 1 };
    () in
  let on_line n l = match !st with Some s -> line s n l | None -> () in
  match Trace.stream path ~header ~line:on_line with
  | Error (n, m) -> Rejected { line = n; message = m }
  | exception Reject (n, m) -> Rejected { line = n; message = m }
  | Ok cut ->
    let s = Option.get !st in
    let complete = Array.for_all (fun a -> a.destroyed) s.agents in
    (match
       if complete && not cut then begin
         (* D26: a run that ended has delivered every message but those of
            on destroy; every line a rule owed is written *)
         Array.iter (fun a ->
             if List.for_all (fun x -> x.owed <> []) a.cands then
               raise (Reject (s.lines + 1, Printf.sprintf "agent %s: the trace ends before the lines its on destroy owes" a.name));
             (match a.undeliverable with
              | (r, _) :: _ -> raise (Reject (s.lines + 1, Printf.sprintf "agent %s: its message to %s was never reported undeliverable (R5e)" a.name r))
              | [] -> ())) s.agents;
         (* every message sent, but those of on destroy, was delivered;
            every failure of ams too (D26, D43) *)
         let left what ~receiver ~sender (m : E.message) =
           raise (Reject (s.lines + 1, Printf.sprintf "the run ended, but %s %s %s from %s to %s was never delivered (D26)"
                            what m.perf (V.to_literal m.content) sender receiver)) in
         In_flight.iter s.inflight (fun ~receiver ~sender m ->
             if not (List.memq m s.from_destroy) then left "the message" ~receiver ~sender m);
         Hashtbl.iter (fun receiver q -> Queue.iter (fun (sender, m) -> left "the platform's answer" ~receiver ~sender m) q)
           s.answers
       end
     with
     | () ->
       Accepted { lines = s.lines; complete; cut; level = s.level; containers = In_flight.containers s.inflight }
     | exception Reject (n, m) -> Rejected { line = n; message = m })
