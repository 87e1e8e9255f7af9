(* From a run to its trace events. *)

module Mc = Semantics.Machine
module T = Typing.Tenv
module V = Value

type config = (V.t, Eval.message, V.t, Eval.beh, Eval.agent) Mc.config
type label = (V.t, Eval.message, V.t) Mc.label

(* Per agent: instance id -> the behaviour type the instance had when last
   seen active (a Skip may name an instance deactivated earlier in its
   dispatch), in an array indexed by id ("?": never seen); and the active
   list last noted, so that a rule that did not change it costs nothing. *)
type names = { mutable types : string array; mutable noted : Eval.beh Mc.instance list }

(* The text of the last percept written, with the values its slots held
   then: a percept's dequeue and handle lines carry the same value, and its
   text is taken again only if a slot changed since (a handler may set one,
   [k of content = 5]). Only a schema whose slots hold integers, texts,
   booleans or numbers is kept: values of those kinds never change. *)
type text_kept = { mutable value : V.t; mutable leaves : V.t array; mutable text : string }

type t = {
  w : Trace.writer;
  observable : bool;   (* the loop's own steps are not written *)
  on_body : string -> Eval.event -> unit;
  names : (string, names) Hashtbl.t;
  mutable last : string * names;   (* the agent's names last looked up, by address *)
  kept : text_kept;
}

let no_names = { types = [||]; noted = [] }
let create ?(level = "full") w ~on_body =
  { w; observable = level = "observable"; on_body; names = Hashtbl.create 16; last = ("", no_names);
    kept = { value = V.Unit; leaves = [||]; text = "" } }

let unchanging = function
  | V.Int _ | V.Text _ | V.Bool _ | V.Float _ | V.Double _ -> true
  | _ -> false

let rec all_unchanging slots i = i < 0 || (unchanging !(snd slots.(i)) && all_unchanging slots (i - 1))
let rec same_leaves slots leaves i = i < 0 || (!(snd slots.(i)) == leaves.(i) && same_leaves slots leaves (i - 1))

(* [V.to_literal v] (by [V.to_literal]); with [keep] (a dequeue: its
   handle lines follow) kept for the next lines *)
let percept_text ?(keep = false) t (v : V.t) =
  let k = t.kept in
  match v with
  | V.Schema s when v == k.value && Array.length s.slots = Array.length k.leaves
                    && same_leaves s.slots k.leaves (Array.length s.slots - 1) ->
    k.text
  | V.Schema s when keep ->
    let text = V.to_literal v in
    let n = Array.length s.slots in
    if all_unchanging s.slots (n - 1) then begin
      let leaves = if Array.length k.leaves = n then k.leaves else Array.make n V.Unit in
      for i = 0 to n - 1 do leaves.(i) <- !(snd s.slots.(i)) done;
      k.value <- v; k.leaves <- leaves; k.text <- text
    end;
    text
  | _ -> V.to_literal v

(* The names of an agent, [None] if none noted yet: the last agent's
   without hashing (a run writes the same agent's lines in a row). *)
let names_of t agent =
  match t.last with
  | (a, n) when a == agent -> Some n
  | _ ->
    match Hashtbl.find_opt t.names agent with
    | Some n as r -> t.last <- (agent, n); r
    | None -> None
let writer t = t.w

(* The program's part of the header: its behaviour types and percept types. *)
let program_summary env =
  let behaviours = List.map (fun (b : T.behaviour) ->
      let hs = T.behaviour_handlers env b.b_name in
      let percept (h : T.handler) = h.h_kind = T.On_percept in
      { Trace.name = b.b_name;
        kind = (match b.b_kind with Syntax.Ast.Cyclic -> "cyclic" | Syntax.Ast.OneShot -> "oneshot");
        has_action = T.behaviour_action env b.b_name <> None;
        percept_handlers = List.length (List.filter percept hs);
        message_handlers = List.length (List.filter (fun h -> not (percept h)) hs) }) (T.behaviours env) in
  (behaviours, List.filter_map (fun (s : T.schema) ->
       if s.s_percept then Some (s.s_name, s.s_priority) else None) (T.schemas env))

let header t env (p : Mc.params) ~seed agents =
  let (behaviours, percepts) = program_summary env in
  Trace.write_header t.w {
    variant = Mc.string_of_variant p.variant;
    tie_policy = (match p.tie with Mc.Stable -> "stable" | Mc.Unstable -> "unstable");
    budget = p.budget; o2a_capacity = p.o2a_capacity; seed;
    level = (if t.observable then "observable" else "full"); agents; containers = []; behaviours; percepts }

let message (m : Eval.message) =
  { Trace.performative = m.perf; content = V.to_literal m.content; from = m.sender }

let effect = function
  | Mc.Activate b -> Trace.Activated (Eval.beh_type b)
  | Mc.Deactivate -> Trace.Deactivated

let body (e : Eval.event) : Trace.body option =
  match e with
  | Eval.Log s -> Some (Trace.Log s)
  | Eval.Invoke { meth; cls; args; result } ->
    Some (Trace.Invoke { meth; obj = cls; args = List.map V.to_literal args; result = V.to_literal result })
  | Eval.Sent { perf; content; receivers } ->
    Some (Trace.Send { performative = perf; content = V.to_literal content; receivers })
  | Eval.Activated b -> Some (Trace.Activate b)
  | Eval.Deactivated id -> Some (Trace.Deactivate id)
  | Eval.Error (_, at, message) -> Some (Trace.Error { at = Syntax.Source.string_of_region at; message })
  | Eval.Ran _ -> None

let bodies t agent action evs =
  List.iter (fun e -> match e with
      | Eval.Ran _ -> ()
      | _ ->
        t.on_body agent e;
        Trace.write_with t.w ~agent (fun () ->
            match body e with
            | Some b -> Trace.Body { action; body = b }
            | None -> Semantics.Fault.crash "Tracer: an event with no body")) evs

(* Each rule notes the active instances before and after it: one pass over
   the list, no hashing (with many instances, D19, this was most of a
   step's time). *)
let note_active t agent (c : config) =
  let n = match names_of t agent with
    | Some n -> n
    | None -> let n = { types = [||]; noted = [] } in Hashtbl.replace t.names agent n; t.last <- (agent, n); n in
  if n.noted != c.active then begin
    n.noted <- c.active;
    List.iter (fun (a : Eval.beh Mc.instance) ->
        if a.id >= Array.length n.types then begin
          let bigger = Array.make (max (a.id + 1) (2 * Array.length n.types)) "?" in
          Array.blit n.types 0 bigger 0 (Array.length n.types);
          n.types <- bigger
        end;
        n.types.(a.id) <- Eval.beh_type a.beh) c.active
  end

let name t agent id =
  match names_of t agent with
  | Some n when id >= 0 && id < Array.length n.types -> n.types.(id)
  | _ -> "?"

(* The effects of the body that ran as [which] in this step. *)
let ran which evs =
  List.find_map (function
      | Eval.Ran { handler; effects } when which handler -> Some (handler, List.map effect effects)
      | _ -> None) evs

let created t ~agent ~agent_type args behs evs =
  Trace.write t.w ~agent (Trace.Create { agent_type; args = List.map V.to_literal args;
                                          behaviours = List.map Eval.beh_type behs });
  bodies t agent "Init" evs

(* The event of rule [l], which reached [c] (its [puts] for a Put) and
   whose bodies recorded [evs]: [percept] writes a percept ([keep]: a
   dequeue, whose handle lines follow), [name] an instance's behaviour. *)
let event_of ~(percept : ?keep:bool -> V.t -> string) ~(name : int -> string) (c : config) (l : label) evs
  : Trace.event =
  let entry ?keep (e : V.t Mc.entry) = { Trace.percept = percept ?keep e.p; priority = e.prio; seq = e.seq } in
  match l with
  | Mc.Init -> Semantics.Fault.crash "Tracer: Init is not a rule of the run"
  | Mc.Notify e -> Trace.Notify { entry = entry e; overridden = false }
  | Mc.Notify_with e -> Trace.Notify { entry = entry e; overridden = true }
  | Mc.Put o -> Trace.Put { obj = V.to_literal o; index = c.puts }
  | Mc.Send (m, seq) -> Trace.Deliver { message = message m; seq; in_step = false }
  | Mc.Transfer n -> Trace.Transfer n
  | Mc.Transfer_one e -> Trace.Transfer_one (entry e)
  | Mc.Transfer_spin o -> Trace.Transfer_spin (V.to_literal o)
  | Mc.Transfer_end -> Trace.Transfer_end
  | Mc.Dequeue e -> Trace.Dequeue (entry ~keep:true e)
  | Mc.Handle { id; h; p; seq } ->
    Trace.Handle { instance = id; behaviour = name id; handler = h; percept = percept p; seq;
                   effects = (match ran (fun _ -> true) evs with Some (_, e) -> e | None -> []) }
  | Mc.Skip { id; h } -> Trace.Skip { instance = id; behaviour = name id; handler = h }
  | Mc.End_dispatch { seq; discarded } -> Trace.End_dispatch { seq; discarded }
  | Mc.Behaviour_step { id; msg } ->
    Trace.Behaviour_step {
      instance = id; behaviour = name id;
      taken = (match msg with
          | None -> None
          | Some (Mc.M_message { m; mseq }) -> Some (Trace.Took_message (message m, mseq))
          | Some (Mc.M_percept e) -> Some (Trace.Took_percept (entry e)));
      action_effects = Option.map snd (ran (fun h -> h = 0) evs);
      handler = (match msg, ran (fun h -> h > 0) evs with
          | Some _, Some (h, e) -> Some (h, e)
          | _ -> None) }
  | Mc.Next_iteration -> Trace.Next_iteration
  | Mc.Idle -> Trace.Idle

let label_event t agent (c : config) (l : label) evs : Trace.event =
  event_of ~percept:(fun ?keep v -> percept_text ?keep t v) ~name:(name t agent) c l evs

let host ?(in_step = false) t ~agent (c : config) =
  Trace.write_with t.w ~agent (fun () ->
      match label_event t agent c c.last [] with
      | Trace.Deliver d -> Trace.Deliver { d with in_step }
      | e -> e)

let refused t ~agent v =
  Trace.write t.w ~agent (Trace.Refused { percept = V.to_literal v; reason = "the O2A queue is full (R2d)" })

let refused_put t ~agent v =
  Trace.write t.w ~agent (Trace.Refused_put { obj = V.to_literal v; reason = "the O2A queue is full (R2d)" })

let undeliverable t ~sender ~receiver (m : Eval.message) =
  Trace.write t.w ~agent:sender
    (Trace.Undeliverable { receiver; performative = m.perf; content = V.to_literal m.content })

(* Without a trace (a writer from [Trace.nowhere]) nothing but the bodies'
   logs and errors is wanted, and the lines are only counted: no event is
   built and no behaviour name kept. *)
(* The line of a rule, unless it is one of the loop's own steps and the
   trace is observable. *)
let write_rule t ~agent c l evs =
  if not t.observable then Trace.write_with t.w ~agent (fun () -> label_event t agent c l evs)
  else
    let e = label_event t agent c l evs in
    if Trace.observable e then Trace.write t.w ~agent e

let step t ~agent ~before ~after l evs =
  let writes = Trace.writes t.w in
  if writes then note_active t agent before;
  write_rule t ~agent after l evs;
  if writes then note_active t agent after;
  match evs with
  | [] -> ()
  | _ -> bodies t agent (Mc.action_name l) evs

(* D33: the rules of a derived Dispatch but its last, from the labels the
   engine's dispatch reports, each as it is taken, with the events its
   body recorded: [start] is the configuration the dispatch started from
   (its instances name the handlers' behaviours). The last rule,
   EndDispatch, is the platform's step, written by [step]. *)
let inside t ~agent ~(start : config) l evs =
  note_active t agent start;
  write_rule t ~agent start l evs;
  match evs with
  | [] -> ()
  | _ -> bodies t agent (Mc.action_name l) evs

let destroyed t ~agent evs =
  Trace.write t.w ~agent Trace.Destroy;
  bodies t agent "destroy" evs
