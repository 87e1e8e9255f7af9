module P = Semantics.Platform.Make (Eval.Bodies)
module M = P.M
module E = Engine.Fast.Make (Engine.Compiled_bodies)   (* percept handlers compiled: D38 *)
module Mc = Semantics.Machine
module T = Typing.Tenv

type options = {
  params : Mc.params;
  seed : int option;
  fuel : int;
  max_steps : int;
  trace : out_channel option;
  on_log : string -> string -> unit;
  on_error : Eval.error_kind -> Syntax.Source.region -> string -> unit;
}

(* The platform operations a run takes: the reference's, or a defective
   implementation's (lib/defects) wrapped around them from the outside. *)
type hooks = {
  step : Mc.params -> M.t -> (M.lbl * M.t) list;
  notify_event : Mc.params -> P.t -> int -> M.t -> Value.t -> default:int -> priority:int option ->
    (M.t, Mc.refusal) result;
  put : Mc.params -> P.t -> int -> M.t -> Value.t -> (M.t, Mc.refusal) result;
  round : Random.State.t option -> P.t -> int list;
}

let reference_hooks = {
  step = E.step;
  notify_event = (fun p _ _ c v ~default ~priority -> M.notify_event p c v ~default ~priority);
  (* R2d: a put into a full O2A queue is refused and changes nothing *)
  put = (fun p _ _ c v -> if M.o2a_has_room p c then Ok (M.put p c v) else Error Mc.O2a_full);
  round = P.round;
}

type t = {
  env : T.t;
  opts : options;
  hooks : hooks;
  mutable platform : P.t;
  mutable steps : int;           (* agent steps so far *)
  rand : Random.State.t option;
  tr : Tracer.t;
  sends : bool;                  (* has the program a send statement? (D33) *)
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

(* ------------------------------------------------------------- trace *)

let find t name = P.find t.platform name

let index t name = match find t name with
  | Some i -> i
  | None -> Semantics.Fault.crash "Runtime: no agent %s on the platform" name

(* An event of the platform, with the platform right after it. [t.platform]
   is still the one before it: the configuration a rule started from. *)
let on_event t (pl : P.t) (e : P.event) =
  let before = t.platform in
  t.platform <- pl;
  match e with
  | P.Step (name, l) ->
    let i = index t name in
    (* D19: the active instances, for the next activate *)
    let after = pl.agents.(i).config in
    if after.active != before.agents.(i).config.active then
      Eval.set_live after.world (List.length after.active);
    Tracer.step t.tr ~agent:name ~before:before.agents.(i).config ~after:pl.agents.(i).config l
  | P.Delivered { receiver; _ } ->
    Tracer.host t.tr ~agent:receiver pl.agents.(index t receiver).config
  | P.Undeliverable { sender; receiver; message } ->
    Tracer.undeliverable t.tr ~sender ~receiver message

(* ---------------------------------------------------------- create *)

let create ?(hooks = reference_hooks) env opts specs =
  let w = match opts.trace with Some oc -> Trace.to_channel oc | None -> Trace.nowhere () in
  let on_body agent = function
    | Eval.Log s -> opts.on_log agent s
    | Eval.Error (kind, at, msg) -> opts.on_error kind at msg
    | _ -> () in
  let t = { env; opts; hooks; platform = P.create []; steps = 0;
            rand = Option.map (fun s -> Random.State.make [| s |]) opts.seed;
            tr = Tracer.create w ~on_body; sends = program_sends env } in
  Tracer.header t.tr env opts.params ~seed:opts.seed (List.map (fun (n, ty, _) -> (n, ty)) specs);
  let created = List.map (fun (name, ty, args) ->
      let (a, behs) = Eval.create_agent env ~name ~atype:ty ~args ~fuel:opts.fuel in
      Tracer.created t.tr ~agent:name ~agent_type:ty args behs a;
      Eval.set_live a (List.length behs);   (* D19 *)
      (* the bodies' Ran records (the effects of each handler) are for the
         trace's lines only *)
      if not (Trace.writes w) then a.record_ran <- false;
      (name, M.init opts.params ~world:a behs)) specs in
  t.platform <- P.create created;
  (* Messages sent by on create, once every agent exists. *)
  Array.iter (fun (ag : P.agent) ->
      let (_, out) = Eval.Bodies.take_outbox ag.config.world in
      List.iter (fun (receiver, m) ->
          let (pl, ev) = P.deliver opts.params t.platform ~sender:ag.name ~receiver m in
          on_event t pl ev) out) t.platform.agents;
  t

(* ------------------------------------------------------------ host *)

let with_agent t agent k =
  match find t agent with
  | None -> Error (Printf.sprintf "there is no agent %s" agent)
  | Some i -> k i t.platform.agents.(i).config

let set_config t i c =
  let agents = Array.copy t.platform.agents in
  agents.(i) <- { (agents.(i)) with config = c };
  t.platform <- { P.agents }

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
      | Ok c ->
        set_config t i c;
        Tracer.host t.tr ~agent c;
        Ok ())

let message t ~agent ~perf content =
  with_agent t agent (fun _ _ ->
      let (pl, ev) = P.deliver t.opts.params t.platform ~sender:"host" ~receiver:agent
          { Eval.perf; content; sender = "host" } in
      on_event t pl ev;
      Ok ())

(* ------------------------------------------------------------- run *)

(* The most rules the derived rule Dispatch can take from [c]: Dequeue, a
   Handle or Skip for each percept handler of each active instance, and
   EndDispatch; in a dispatch under way, one for each handler still to do
   and EndDispatch. *)
let dispatch_bound (c : M.t) =
  match c.phase, c.cur with
  | Mc.Handle_phase, Some d -> List.length d.todo + 1
  | _ -> List.fold_left (fun n (a : Eval.beh Mc.instance) -> n + Eval.Bodies.percept_handlers a.beh) 2 c.active

(* Without a trace, nothing sees the configurations inside a percept's
   dispatch: the derived rule Dispatch of the fast engine takes it in one
   call, its rules counted as steps, and the platform sees one step (its
   bodies' logs and errors in order, their messages delivered after it,
   before any other agent runs). It is taken only when the steps left
   cover every rule it may take, so --max-steps stops at the same rule.
   With a trace, the same when no body of the program sends a message
   (D33): each rule's line is written as the engine reports the rule's
   label; otherwise every rule is a step of its own (its messages are
   delivered, with their lines, right after it). Either way the steps are
   counted here, and the platform keeps no list of them (D29; tests
   "run: the same without a trace", "run: a traced dispatch = rule by
   rule (D33)"). *)
let iterate t i =
  let left = t.opts.max_steps - t.steps in
  if left > 0 then begin
    (* D29: without a trace, a percept's dispatch is the engine's one-call
       Dispatch; a defective implementation (hooks) takes its own rules.
       D33: with a trace too, when no body of the program sends a message:
       each rule's line is written as the engine reports its label. *)
    let writes = Trace.writes (Tracer.writer t.tr) in
    let derived = (not writes || not t.sends) && t.hooks == reference_hooks in
    let taken = ref 0 in
    let agent = t.platform.agents.(i).name in
    let step p c =
      let room = left - !taken in
      if room <= 0 then []
      else match
          if not (derived && room >= dispatch_bound c) then None
          else if writes then
            E.dispatch p c ~observe:(fun l ->
                incr taken;
                (* D33 holds only while nothing is sent: a body that sent
                   would be a broken invariant, not a reordered trace *)
                if c.Mc.world.Eval.outbox <> [] then
                  Semantics.Fault.crash "Runtime: a message sent in a dispatch traced in one call (D33)";
                match l with
                | Mc.End_dispatch _ -> ()   (* the platform's step: written by on_event *)
                | _ -> Tracer.inside t.tr ~agent ~start:c l)
          else
            (* unobserved (the engine's plans by kind of percept): a
               dispatch takes exactly [dispatch_bound c] rules, one
               Handle or Skip per handler of its snapshot between
               Dequeue and EndDispatch *)
            match E.dispatch p c with
            | Some _ as r -> taken := !taken + dispatch_bound c; r
            | None -> None with
        | Some c' -> [ (c'.Mc.last, c') ]
        | None -> (match t.hooks.step p c with [] -> [] | r -> incr taken; r) in
    let (pl, _) = P.iteration ~max_steps:left ~on_event:(on_event t) ~step ~keep:false t.opts.params t.platform i in
    t.platform <- pl;
    t.steps <- t.steps + !taken
  end

(* D20: rounds end as soon as every agent is idle (nothing can change until
   the host acts again: an idle round would only draw a seeded order) or the
   step limit is reached, or a round takes no step (it changed nothing, nor
   would the next); so [n] may be any count. *)
let run_rounds t n =
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
   iteration goes on from there at its next turn. *)
let run_rules t n =
  let rec go k =
    if k > 0 && t.steps < t.opts.max_steps then
      let rec first i =
        if i >= Array.length t.platform.agents then None
        else if M.is_idle t.platform.agents.(i).config then first (i + 1) else Some i in
      match first 0 with
      | None -> ()
      | Some i ->
        let (pl, evs) = P.iteration ~max_steps:1 ~on_event:(on_event t) ~step:t.hooks.step t.opts.params t.platform i in
        t.platform <- pl;
        let n = List.length (List.filter (function P.Step _ -> true | _ -> false) evs) in
        t.steps <- t.steps + n;
        if n > 0 then go (k - 1) in
  go n

let run_until_idle t = run_rounds t max_int

let finish t =
  Array.iter (fun (ag : P.agent) ->
      let a = ag.config.world in
      Eval.destroy_agent a;
      Tracer.destroyed t.tr ~agent:ag.name a) t.platform.agents;
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
