module P = Semantics.Platform.Make (Eval.Bodies)
module M = P.M
module Mc = Semantics.Machine
module T = Typing.Tenv

type engine = Reference | Fast

type options = {
  params : Mc.params;
  engine : engine;
  seed : int option;
  interleave : int option;
  fuel : int;
  max_steps : int;
  max_memory : int option;
  trace : out_channel option;
  level : string;
  on_log : string -> string -> unit;
  on_error : Eval.error_kind -> Syntax.Source.region -> string -> unit;
}

type rules = {
  step : Mc.params -> M.t -> (M.lbl * M.t) list;
  dispatch : (?observe:(M.lbl -> Eval.agent -> Eval.agent) -> Mc.params -> M.t -> M.t option) option;
}

type hooks = {
  rules : string -> rules;
  notify_event : Mc.params -> P.t -> int -> M.t -> Value.t -> default:int -> priority:int option ->
    (M.t, Mc.refusal) result;
  put : Mc.params -> P.t -> int -> M.t -> Value.t -> (M.t, Mc.refusal) result;
  round : Random.State.t option -> P.t -> int list;
  create_agent : config:Eval.config -> T.t -> name:string -> atype:string -> args:Value.t list ->
    Eval.agent * Eval.beh list;
  destroy_agent : Eval.agent -> Eval.agent;
  failure : receiver:string -> Eval.message;
  in_step : Mc.params -> P.t -> sender:string -> receiver:string -> Eval.message -> (P.t * P.event) option;
}

let reference_rules = { step = M.step; dispatch = None }

let engine_rules () =
  let module E = (val Engine.for_agent () : Engine.INTERP) in
  { step = E.step; dispatch = Some E.dispatch }

(* R5e, D43: the failure ams sends the sender of a message to an agent that
   is not on the platform, its content the receiver's aid. (A message to ams
   or df themselves is never answered: D44.) *)
let failure ~receiver = { Eval.perf = "failure"; content = Value.Aid receiver; sender = "ams" }

let hooks_of engine = {
  rules = (match engine with Reference -> (fun _ -> reference_rules) | Fast -> (fun _ -> engine_rules ()));
  notify_event = (fun p _ _ c v ~default ~priority -> M.notify_event p c v ~default ~priority);
  (* R2d: a put into a full O2A queue is refused and changes nothing *)
  put = (fun p _ _ c v -> if M.o2a_has_room p c then Ok (M.put p c v) else Error Mc.O2a_full);
  round = P.round;
  create_agent = (fun ~config env ~name ~atype ~args -> Eval.create_agent ~config env ~name ~atype ~args);
  destroy_agent = Eval.destroy_agent;
  failure;
  in_step = (fun p pl ~sender ~receiver m -> P.deliver_in_step p pl ~sender ~receiver m);
}

let reference_hooks = hooks_of Reference

type t = {
  env : T.t;
  opts : options;
  hooks : hooks;
  platform : P.t;   (* owned by the run: agents replaced in place (set_config) *)
  index : (string, int) Hashtbl.t;   (* agent name -> its index in the platform *)
  rules : rules array;           (* each agent's, in creation order *)
  mutable steps : int;           (* agent steps so far *)
  rand : Random.State.t option;
  tr : Tracer.t;
  sends : bool;                  (* has the program a send statement? (D33) *)
  fine : Random.State.t option;  (* D45: the finer interleaving, drawn from this *)
  inflight : (string, (string * Eval.message) Queue.t) Hashtbl.t;
      (* D45: per receiver (an agent, a platform agent, an absent name), the
         messages sent to it and not yet delivered, in the order of the sends *)
  during : (string, Eval.message Queue.t) Hashtbl.t;
      (* D42: per agent, the host's messages to deliver during its next
         behaviour step *)
}

(* D33: does any body of the program hold a send statement? Only a body
   that sends makes the platform act inside a dispatch (it delivers each
   rule's messages right after the rule, with a trace line each). *)
let program_sends env =
  let rec stmt (s : Syntax.Ast.stmt) = match s.it with
    | Send _ -> true
    | If (branches, els) -> List.exists (fun (_, b) -> block b) branches || Option.fold ~none:false ~some:block els
    | While (_, b) | For (_, _, b) -> block b
    | _ -> false
  and block b = List.exists stmt b in
  let routines = List.exists (fun (r : T.routine) -> block r.r_body) in
  List.exists (fun (a : T.agent) ->
      routines a.a_functions || routines a.a_procedures || routines (Option.to_list a.a_create)
      || Option.fold ~none:false ~some:block a.a_destroy) (T.agents env)
  || List.exists (fun (b : T.behaviour) ->
      routines b.b_functions || routines b.b_procedures || routines (Option.to_list b.b_create)
      || Option.fold ~none:false ~some:block b.b_action
      || List.exists (fun (h : T.handler) -> block h.h_body) b.b_handlers) (T.behaviours env)

(* An agent's index, by its name (the names are the run's, unique). *)
let find t name = Hashtbl.find_opt t.index name

(* The run owns its platform: an agent's configuration is replaced in
   place (a copy of the whole array at every rule made a run of n agents
   cost n^2). Nothing keeps an older platform of the run. *)
let set_config t i c =
  t.platform.agents.(i) <- { (t.platform.agents.(i)) with config = c }

(* The configuration with the bodies' events taken out of its agent. *)
let take_events (c : M.t) =
  match Eval.take_events c.world with
  | (_, []) -> (c, [])
  | (world, evs) -> ({ c with world }, evs)


let queue t r = match Hashtbl.find_opt t.inflight r with
  | Some q -> q
  | None -> let q = Queue.create () in Hashtbl.replace t.inflight r q; q

(* A message that reaches [receiver] now (R5e), with its trace line. One for
   ams or df is theirs and never answered (D44); for an agent not on the
   platform, ams's failure goes back to the sender: delivered at once in the
   deterministic schedule (D44), in flight in the finer one (D45).
   [in_step]: during the receiver's last behaviour step (R5d, D42). *)
let rec arrive ?(in_step = false) t ~sender ~receiver m =
  let back answer =
    if t.fine = None then arrive t ~sender:answer.Eval.sender ~receiver:sender answer
    else Queue.push (answer.Eval.sender, answer) (queue t sender) in
  let at = find t receiver in
  let (change, ev) =
    let plain () = P.arrival t.opts.params t.platform at ~sender ~receiver m in
    if in_step then
      (* the hooks' SendInStep answers a platform: the receiver's
         configuration is taken from it *)
      match t.hooks.in_step t.opts.params t.platform ~sender ~receiver m with
      | Some (pl, ev) -> (Option.map (fun i -> (i, pl.P.agents.(i).config)) at, ev)
      | None -> plain ()
    else plain () in
  Option.iter (fun (i, c) -> set_config t i c) change;
  match ev, change with
  | P.Delivered _, Some (_, c) -> Tracer.host ~in_step t.tr ~agent:receiver c
  | P.Delivered _, None -> Semantics.Fault.crash "Runtime: a delivery that changed no agent"
  | P.To_platform _, _ -> ()
  | P.Undeliverable { sender; receiver; message }, _ ->
    Tracer.undeliverable t.tr ~sender ~receiver message;
    back (t.hooks.failure ~receiver)
  | P.Step _, _ -> ()

(* What agent [i]'s bodies sent (R5e), in order: delivered at once (the
   deterministic schedule), or in flight (D45). *)
let deliver_outbox t i =
  let ag = t.platform.agents.(i) in
  match Eval.Bodies.take_outbox ag.config.world with
  | (_, []) -> ()
  | (world, out) ->
    set_config t i { ag.config with world };
    List.iter (fun (receiver, m) ->
        if t.fine = None then arrive t ~sender:ag.name ~receiver m
        else Queue.push (ag.name, m) (queue t receiver)) out

(* ---------------------------------------------------------- create *)

let create ?hooks env opts specs =
  let hooks = match hooks with Some h -> h | None -> hooks_of opts.engine in
  let w = match opts.trace with Some oc -> Trace.to_channel oc | None -> Trace.nowhere () in
  let on_body agent = function
    | Eval.Log s -> opts.on_log agent s
    | Eval.Error (kind, at, msg) -> opts.on_error kind at msg
    | _ -> () in
  let tr = Tracer.create ~level:opts.level w ~on_body in
  Tracer.header tr env opts.params ~seed:opts.seed (List.map (fun (n, ty, _) -> (n, ty)) specs);
  (* the bodies' Ran records (the effects of each handler) are for the
     trace's lines only *)
  let config = { Eval.default_config with fuel = opts.fuel; max_memory = opts.max_memory;
                                          record_effects = Trace.writes w } in
  let created = List.map (fun (name, ty, args) ->
      let (a, behs) = hooks.create_agent ~config env ~name ~atype:ty ~args in
      let (a, evs) = Eval.take_events a in
      Tracer.created tr ~agent:name ~agent_type:ty args behs evs;
      (name, M.init opts.params ~world:a behs)) specs in
  let index = Hashtbl.create (List.length specs) in
  List.iteri (fun i (name, _, _) -> Hashtbl.replace index name i) specs;
  let t = { env; opts; hooks; platform = P.create created; index;
            rules = Array.of_list (List.map (fun (name, _, _) -> hooks.rules name) specs); steps = 0;
            rand = Option.map (fun s -> Random.State.make [| s |]) opts.seed;
            tr; sends = program_sends env;
            fine = Option.map (fun s -> Random.State.make [| s; 45 |]) opts.interleave;
            inflight = Hashtbl.create 8; during = Hashtbl.create 4 } in
  (* Messages sent by on create, once every agent exists (D13). *)
  Array.iteri (fun i _ -> deliver_outbox t i) t.platform.agents;
  t

(* ------------------------------------------------------------ host *)

let with_agent t agent k =
  match find t agent with
  | None -> Error (Printf.sprintf "there is no agent %s" agent)
  | Some i -> k i t.platform.agents.(i).config

let notify t ~agent v ~default ~priority =
  with_agent t agent (fun i c ->
      match t.hooks.notify_event t.opts.params t.platform i c v ~default ~priority with
      | Error (Mc.Negative_priority k) -> Error (Printf.sprintf "priority %d is negative (R2a)" k)
      | Error Mc.O2a_full ->
        Tracer.refused t.tr ~agent v;
        Error (Printf.sprintf "agent %s refused the percept %s: the O2A queue is full (R2d)" agent (Value.to_literal v))
      | Ok c -> set_config t i c; Tracer.host t.tr ~agent c; Ok ())

let put t ~agent v =
  with_agent t agent (fun i c ->
      match t.hooks.put t.opts.params t.platform i c v with
      | Error _ ->
        (* R2d, D24: refused, and recorded as [refused] with the object *)
        Tracer.refused_put t.tr ~agent v;
        Error (Printf.sprintf "agent %s refused the object %s: the O2A queue is full (R2d)" agent (Value.to_literal v))
      | Ok c -> set_config t i c; Tracer.host t.tr ~agent c; Ok ())

let message ?(during_step = false) t ~agent ~perf content =
  with_agent t agent (fun _ _ ->
      let m = { Eval.perf; content; sender = "host" } in
      if during_step then begin
        (* D42: held until the agent's next behaviour step *)
        let q = match Hashtbl.find_opt t.during agent with
          | Some q -> q
          | None -> let q = Queue.create () in Hashtbl.replace t.during agent q; q in
        Queue.push m q
      end else arrive t ~sender:"host" ~receiver:agent m;
      Ok ())

(* ------------------------------------------------------------- run *)

(* One rule of agent [i], its line and its bodies' events in the trace,
   then the messages it sent delivered; [false] when no rule is enabled. *)
let rule t i =
  let ag = t.platform.agents.(i) in
  match t.rules.(i).step t.opts.params ag.config with
  | [] -> None
  | (l, c) :: _ ->
    let (c, evs) = take_events c in
    set_config t i c;
    Tracer.step t.tr ~agent:ag.name ~before:ag.config ~after:c l evs;
    (* D42: the host's messages held for this behaviour step arrive during
       it: right after the step's lines, before what the step sent leaves
       (a failure of ams, or a message to the agent itself, would close the
       step's window) *)
    (match l, Hashtbl.find_opt t.during ag.name with
     | Mc.Behaviour_step _, Some q ->
       Queue.iter (fun m -> arrive ~in_step:true t ~sender:"host" ~receiver:ag.name m) q;
       Queue.clear q
     | _ -> ());
    deliver_outbox t i;
    t.steps <- t.steps + 1;
    Some l

(* The most rules the derived rule Dispatch can take from [c]: Dequeue, a
   Handle or Skip for each percept handler of each active instance, and
   EndDispatch; in a dispatch under way, one for each handler still to do
   and EndDispatch. *)
let dispatch_bound (c : M.t) =
  match c.phase, c.cur with
  | Mc.Handle_phase, Some d -> List.length d.todo + 1
  | _ -> List.fold_left (fun n (a : Eval.beh Mc.instance) -> n + Eval.Bodies.percept_handlers a.beh) 2 c.active

(* A percept's whole dispatch in one call of the engine's derived rule,
   where it may be taken (D29, D33): the engine has one; the steps left
   cover every rule it may take, so --max-steps stops at the same rule;
   and, with a trace, no body of the program sends (each rule's line is
   written as the engine reports it; with sends, each rule is a step of
   its own, its messages delivered right after it). [None] where it is not
   taken. *)
let derived_dispatch t i =
  match t.rules.(i).dispatch with
  | None -> None
  | Some dispatch ->
    let ag = t.platform.agents.(i) in
    let c = ag.config in
    let writes = Trace.writes (Tracer.writer t.tr) in
    let room = t.opts.max_steps - t.steps in
    if (writes && t.sends) || room < dispatch_bound c then None
    else begin
      (* with a trace, each rule's line as the engine reports it; without,
         nothing sees the rules inside: the engine's plans by kind of
         percept, and exactly [dispatch_bound c] rules taken *)
      let taken = ref 0 in
      let observe l world =
        incr taken;
        match l with
        | Mc.End_dispatch _ -> world   (* written as the step below *)
        | _ ->
          let (world, evs) = Eval.take_events world in
          Tracer.inside t.tr ~agent:ag.name ~start:c l evs;
          world in
      match (if writes then dispatch ~observe t.opts.params c else dispatch t.opts.params c) with
      | None -> None
      | Some c' ->
        if not writes then taken := dispatch_bound c;
        let (c', evs) = take_events c' in
        set_config t i c';
        (* the last rule, EndDispatch, is the platform's step *)
        Tracer.step t.tr ~agent:ag.name ~before:c ~after:c' c'.last evs;
        if writes && c'.world.outbox <> [] then
          (* D33 holds only while nothing is sent: a body that sent would be
             a broken invariant, not a reordered trace *)
          Semantics.Fault.crash "Runtime: a message sent in a dispatch taken in one call (D33)";
        (* without a trace, what the dispatch sent is delivered after it: no
           other agent runs inside an iteration (R6) *)
        deliver_outbox t i;
        t.steps <- t.steps + !taken;
        Some c'.last
    end

let ends_iteration (l : M.lbl) = match l with
  | Mc.Behaviour_step _ | Mc.Next_iteration | Mc.Idle -> true
  | _ -> false

(* One loop iteration of agent [i] (R6: atomic with respect to the other
   agents): its rules from where it stands up to the end of the iteration
   (its behaviour step, NextIteration or Idle), or until the step limit. *)
let iterate t i =
  let rec go () =
    if t.steps < t.opts.max_steps then
      match (match derived_dispatch t i with Some l -> Some l | None -> rule t i) with
      | None -> ()
      | Some l -> if not (ends_iteration l) then go () in
  go ()

(* ------------------------------------------- the finer interleaving *)

(* D45: rules of different agents in any order, deliveries delayed (R6
   revised): at each point one of the possible next events is drawn at
   random: a rule of an agent that may take one ([may_step]) and is not
   idle, or the arrival of the oldest message in flight to some receiver;
   a message to an agent whose last rule was a behaviour step may arrive
   during that step (SendInStep, R5d), drawn at random too. [on_rule i l]
   sees each rule taken. It ends when nothing can happen, or at the step
   limit. *)
let fine_run t rand ~may_step ~on_rule =
  let rec go () =
    if t.steps < t.opts.max_steps then begin
      let agents = List.filter (fun i -> may_step i && not (M.is_idle t.platform.agents.(i).config))
          (List.init (Array.length t.platform.agents) Fun.id) in
      let receivers = Hashtbl.fold (fun r q acc -> if Queue.is_empty q then acc else r :: acc) t.inflight []
                      |> List.sort compare in
      let choices = List.map (fun i -> `Rule i) agents @ List.map (fun r -> `Arrive r) receivers in
      match choices with
      | [] -> ()
      | _ ->
        (match List.nth choices (Random.State.int rand (List.length choices)) with
         | `Rule i -> (match rule t i with Some l -> on_rule i l | None -> ())
         | `Arrive r ->
           let (sender, m) = Queue.pop (queue t r) in
           let in_step = match find t r with
             | Some i -> t.platform.agents.(i).config.stepped <> Mc.Not_stepped && Random.State.bool rand
             | None -> false in
           arrive ~in_step t ~sender ~receiver:r m);
        go ()
    end in
  go ()

(* D42: the messages held for a behaviour step that did not come arrive
   at the end of the run's rounds, as plain deliveries. *)
let release_held t =
  let held = Hashtbl.fold (fun a q acc -> if Queue.is_empty q then acc else (a, q) :: acc) t.during [] in
  List.iter (fun (a, q) -> Queue.iter (fun m -> arrive t ~sender:"host" ~receiver:a m) q; Queue.clear q)
    (List.sort compare held);
  held <> []

(* D20: rounds end as soon as every agent is idle (nothing can change until
   the host acts again: an idle round would only draw a seeded order) or the
   step limit is reached, or a round takes no step (it changed nothing, nor
   would the next); so [n] may be any count. With the finer interleaving
   (D45), [n] rounds are up to [n] loop iterations of each agent, in any
   order with the deliveries. *)
let run_rounds t n =
  match t.fine with
  | Some rand ->
    let done_ = Array.make (Array.length t.platform.agents) 0 in
    fine_run t rand ~may_step:(fun i -> done_.(i) < n)
      ~on_rule:(fun i l -> if ends_iteration l then done_.(i) <- done_.(i) + 1)
  | None ->
    let rec go n =
      if n > 0 && t.steps < t.opts.max_steps && not (P.all_idle t.platform) then begin
        let before = t.steps in
        List.iter (fun i -> if not (M.is_idle t.platform.agents.(i).config) then iterate t i) (t.hooks.round t.rand t.platform);
        if t.steps > before then go (n - 1)
      end in
    go n

(* {"run": {"rules": n}} (D23, docs/trace-format.md): n single rules, each
   taken by the first agent in creation order that is not idle; fewer when
   every agent is idle or the step limit is reached. The messages a rule
   sends are delivered right after it. An agent left in the middle of an
   iteration goes on from there at its next turn. With the finer
   interleaving (D45), n rules of agents drawn at random. *)
let run_rules t n =
  match t.fine with
  | Some rand ->
    let taken = ref 0 in
    fine_run t rand ~may_step:(fun _ -> !taken < n) ~on_rule:(fun _ _ -> incr taken)
  | None ->
    let rec go k =
      if k > 0 && t.steps < t.opts.max_steps then
        let rec first i =
          if i >= Array.length t.platform.agents then None
          else if M.is_idle t.platform.agents.(i).config then first (i + 1) else Some i in
        match first 0 with
        | None -> ()
        | Some i -> (match rule t i with Some _ -> go (k - 1) | None -> ()) in
    go n

let run_until_idle t =
  let rec go () =
    run_rounds t max_int;
    if t.steps < t.opts.max_steps && release_held t then go () in
  go ()

(* The run is over (D26, D45): every message still in flight arrives, the
   oldest first for each receiver, receivers in name order (with ams's
   failures they cause), then the host's messages held for a step that did
   not come (D42); only then are the agents destroyed, so that a trace that
   ends with every agent destroyed has delivered every message sent before
   on destroy. Arrivals are the platform's, not rules: the step limit does
   not stop them. *)
let deliver_in_flight t =
  let rec go () =
    let receivers = Hashtbl.fold (fun r q acc -> if Queue.is_empty q then acc else r :: acc) t.inflight [] in
    match List.sort compare receivers with
    | [] -> ()
    | r :: _ ->
      let (sender, m) = Queue.pop (queue t r) in
      arrive t ~sender ~receiver:r m;
      go () in
  go ();
  ignore (release_held t)

let finish t =
  deliver_in_flight t;
  Array.iter (fun (ag : P.agent) ->
      let (_, evs) = Eval.take_events (t.hooks.destroy_agent ag.config.world) in
      Tracer.destroyed t.tr ~agent:ag.name evs) t.platform.agents;
  (* the lines the writer holds, then the channel *)
  Trace.flush (Tracer.writer t.tr)

let steps t = t.steps
let platform t = t.platform
let env t = t.env

(* A run allocates many short-lived values (configurations, frames): a larger
   minor heap keeps them out of the major heap. Percepts waiting in O2A or in
   the priority queue are the opposite: under a flood every one of them is
   live until it is dispatched, and the major heap is mostly that backlog.
   A space overhead of 1000 lets the major collector mark it about a fifth as
   often as 200 would (OCaml's default is 120; bench/README.md: the host's
   notifies under a flood of 10M went from 730 ns to 270-370 ns each);
   garbage reaches the major heap slowly in this interpreter (configurations
   die young), so the heap stays close to the live data. *)
let tune_gc () =
  Gc.set { (Gc.get ()) with Gc.minor_heap_size = 4 * 1024 * 1024; space_overhead = 1000 }
