module P = Semantics.Platform.Make (Eval.Bodies)
module M = P.M
module E = Engine.Fast.Make (Engine.Interp_bodies)
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

type t = {
  env : T.t;
  opts : options;
  mutable platform : P.t;
  mutable steps : int;           (* agent steps so far *)
  rand : Random.State.t option;
  tr : Tracer.t;
}

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
    Tracer.step t.tr ~agent:name ~before:before.agents.(i).config ~after:pl.agents.(i).config l
  | P.Delivered { receiver; _ } ->
    Tracer.host t.tr ~agent:receiver pl.agents.(index t receiver).config
  | P.Undeliverable { sender; receiver; message } ->
    Tracer.undeliverable t.tr ~sender ~receiver message

(* ---------------------------------------------------------- create *)

let create env opts specs =
  let w = match opts.trace with Some oc -> Trace.to_channel oc | None -> Trace.nowhere () in
  let on_body agent = function
    | Eval.Log s -> opts.on_log agent s
    | Eval.Error (kind, at, msg) -> opts.on_error kind at msg
    | _ -> () in
  let t = { env; opts; platform = P.create []; steps = 0;
            rand = Option.map (fun s -> Random.State.make [| s |]) opts.seed;
            tr = Tracer.create w ~on_body } in
  Tracer.header t.tr env opts.params ~seed:opts.seed (List.map (fun (n, ty, _) -> (n, ty)) specs);
  let created = List.map (fun (name, ty, args) ->
      let (a, behs) = Eval.create_agent env ~name ~atype:ty ~args ~fuel:opts.fuel in
      Tracer.created t.tr ~agent:name ~agent_type:ty args behs a;
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
      match M.notify_event t.opts.params c v ~default ~priority with
      | Error (Mc.Negative_priority k) -> Error (Printf.sprintf "priority %d is negative (R2a)" k)
      | Error Mc.O2a_full ->
        Tracer.refused t.tr ~agent v;
        Error "the O2A queue is full (R2d)"
      | Ok c -> set_config t i c; Tracer.host t.tr ~agent c; Ok ())

let put t ~agent v =
  with_agent t agent (fun i c ->
      if not (M.o2a_has_room t.opts.params c) then Error "the O2A queue is full (R2d)"
      else begin
        let c = M.put t.opts.params c v in
        set_config t i c;
        Tracer.host t.tr ~agent c;
        Ok ()
      end)

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
   With a trace, every rule is a step of its own. Either way the steps are
   counted here, and the platform keeps no list of them (issue 17; test
   "run: the same without a trace"). *)
let iterate t i =
  let left = t.opts.max_steps - t.steps in
  if left > 0 then begin
    let derived = not (Trace.writes (Tracer.writer t.tr)) in
    let taken = ref 0 in
    let count _ = incr taken in
    let step p c =
      let room = left - !taken in
      if room <= 0 then []
      else match if derived && room >= dispatch_bound c then E.dispatch ~observe:count p c else None with
        | Some c' -> [ (c'.Mc.last, c') ]
        | None -> (match E.step p c with [] -> [] | r -> incr taken; r) in
    let (pl, _) = P.iteration ~max_steps:left ~on_event:(on_event t) ~step ~keep:false t.opts.params t.platform i in
    t.platform <- pl;
    t.steps <- t.steps + !taken
  end

let run_rounds t n =
  for _ = 1 to n do
    List.iter (fun i -> if not (M.is_idle t.platform.agents.(i).config) then iterate t i) (P.round t.rand t.platform)
  done

let run_until_idle t =
  let rec go () =
    if t.steps < t.opts.max_steps && not (P.all_idle t.platform) then begin
      run_rounds t 1; go ()
    end in
  go ()

let finish t =
  Array.iter (fun (ag : P.agent) ->
      let a = ag.config.world in
      Eval.destroy_agent a;
      Tracer.destroyed t.tr ~agent:ag.name a) t.platform.agents;
  match t.opts.trace with Some oc -> flush oc | None -> ()

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
