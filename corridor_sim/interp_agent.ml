module V = Interp.Value
module Mc = Semantics.Machine
module M = Interp.Runtime.P.M

let program () =
  let rec up d =
    let p = Filename.concat d "examples/robome/robome.jade" in
    if Sys.file_exists p then p
    else let u = Filename.dirname d in
      if u = d then failwith "examples/robome/robome.jade not found" else up u in
  up (Sys.getcwd ())

let load path =
  let r = match Syntax.Parse.file path with
    | r -> r
    | exception Syntax.Diag.Failed d -> failwith (Syntax.Diag.to_string d) in
  let env, diags = Typing.check [ r ] in
  if Typing.has_errors diags then
    failwith (String.concat "\n" (List.map Syntax.Diag.to_string
                                   (List.filter (fun d -> d.Syntax.Diag.severity = Syntax.Diag.Error) diags)));
  env

let value_of_percept (p : Agent.percept) =
  match p with
  | Agent.Falling -> V.Schema { sname = "falling"; slots = [||] }
  | Agent.Obstacle -> V.Schema { sname = "obstacle"; slots = [||] }
  | Agent.Qr_code_read s -> V.Schema { sname = "qrCodeRead"; slots = [| ("qrCode", ref (V.Text s)) |] }
  | Agent.Position (x, y) -> V.Schema { sname = "position"; slots = [| ("x", ref (V.Double x)); ("y", ref (V.Double y)) |] }

let num = function V.Double f | V.Float f -> f | V.Int i -> float_of_int i | _ -> nan

let percept_of_value (v : V.t) : Agent.percept =
  match v with
  | V.Schema { sname = "falling"; _ } -> Agent.Falling
  | V.Schema { sname = "obstacle"; _ } -> Agent.Obstacle
  | V.Schema { sname = "qrCodeRead"; slots } -> Agent.Qr_code_read (V.to_text !(snd slots.(0)))
  | V.Schema { sname = "position"; slots } -> Agent.Position (num !(snd slots.(0)), num !(snd slots.(1)))
  | _ -> Agent.Obstacle

let convert_entry (e : V.t Mc.entry) : Agent.percept Mc.entry =
  { Mc.p = percept_of_value e.p; prio = e.prio; seq = e.seq }

(* A label of the interpreter's machine in the simulation's terms (no
   messages or objects occur in the simulation). *)
let convert (l : (V.t, Interp.Eval.message, V.t) Mc.label) : Reference_controller.label =
  match l with
  | Mc.Init -> Mc.Init
  | Mc.Notify e -> Mc.Notify (convert_entry e)
  | Mc.Notify_with e -> Mc.Notify_with (convert_entry e)
  | Mc.Put _ -> Mc.Put ()
  | Mc.Send (_, s) -> Mc.Send ((), s)
  | Mc.Transfer n -> Mc.Transfer n
  | Mc.Transfer_one e -> Mc.Transfer_one (convert_entry e)
  | Mc.Transfer_spin _ -> Mc.Transfer_spin ()
  | Mc.Transfer_end -> Mc.Transfer_end
  | Mc.Dequeue e -> Mc.Dequeue (convert_entry e)
  | Mc.Handle { id; h; p; seq } -> Mc.Handle { id; h; p = percept_of_value p; seq }
  | Mc.Skip { id; h } -> Mc.Skip { id; h }
  | Mc.End_dispatch { seq; discarded } -> Mc.End_dispatch { seq; discarded }
  | Mc.Behaviour_step { id; msg } ->
    Mc.Behaviour_step { id; msg = (match msg with
        | None -> None
        | Some (Mc.M_percept e) -> Some (Mc.M_percept (convert_entry e))
        | Some (Mc.M_message { mseq; _ }) -> Some (Mc.M_message { m = (); mseq })) }
  | Mc.Next_iteration -> Mc.Next_iteration
  | Mc.Idle -> Mc.Idle

let make_with ?program:(path = program ()) ~record () : (module Agent.AGENT) =
  let env = load path in
  (module struct
    type t = { params : Mc.params; mutable c : M.t; rules : (module Engine.INTERP) }

    let name = "jadescript"

    let create (loop : Agent.loop) (host : Agent.host) =
      let params = { Mc.default_params with variant = loop.variant; budget = loop.budget;
                                            o2a_capacity = loop.o2a_capacity } in
      let native = V.Native {
          nid = 1; cls = "RoboMe";
          methods = List.map (fun (m, _) -> (m, fun _ ->
              match Robome.Host.call host m with
              | Ok () -> V.Unit
              | Error e -> failwith e)) host } in
      (* the simulation reads no event of the agent's (it drops them after
         each rule): no [Ran] event is made for a trace nobody writes *)
      let config = { Interp.Eval.default_config with fuel = 100_000; record_effects = false } in
      let (a, behs) = Interp.Eval.create_agent ~config env ~name:"robome" ~atype:"RoboMe" ~args:[ native ] in
      let (a, _) = Interp.Eval.take_events a in
      record Mc.Init;
      { params; c = M.init params ~world:a behs; rules = Engine.for_agent () }

    (* the configuration without the events and messages of its agent *)
    let drop_output (c : M.t) =
      match c.world.events, c.world.outbox with
      | [], [] -> c
      | _ -> { c with world = { c.world with events = []; outbox = [] } }

    let notify t p ~priority =
      match M.notify_event t.params t.c (value_of_percept p) ~default:(Agent.default_priority p) ~priority with
      | Error (Mc.Negative_priority k) -> Error (Printf.sprintf "priority %d is not a natural number (R2a)" k)
      | Error Mc.O2a_full -> Error "the O2A queue is full (R2d)"
      | Ok c -> t.c <- c; record c.last; Ok c.next_seq

    let take t =
      let module E = (val t.rules) in
      match E.step t.params t.c with
      | [] -> None
      | (l, c) :: _ ->
        t.c <- drop_output c;
        record l;
        Some l

    (* one rule at a time *)
    let step_one t : Agent.work option =
      match take t with
      | None -> None
      | Some l -> Some (Agent.work_of_step ~take:(fun () -> take t) ~percept:percept_of_value l)

    let step t : Agent.work option =
      (* a whole dispatch in one call of the derived rule when it applies (the
         same rules, labels and work as one at a time, D29); the closures only
         then *)
      if t.c.phase = Mc.Dispatch_phase then begin
        let module E = (val t.rules) in
        let dispatch observe =
          match E.dispatch ~observe:(fun l w -> observe l; w) t.params t.c with
          | Some c -> t.c <- drop_output c; true
          | None -> false in
        match Agent.dispatch_work ~dispatch ~record ~percept:percept_of_value with
        | Some w -> Some w
        | None -> step_one t
      end else step_one t

    let world_map t =
      match Interp.Eval.property t.c.world "worldMap" with
      | Some (V.Map m) ->
        List.filter_map (fun (k, v) -> match k with
            | V.Schema { sname = "position"; slots } when Array.length slots = 2 ->
              Some (num !(snd slots.(0)), num !(snd slots.(1)), V.to_text v)
            | _ -> None) (V.map_bindings m)
      | _ -> []
  end)

let make ?program () = make_with ?program ~record:(fun _ -> ()) ()

let make_logged ?program () =
  let log = ref [] in
  let record l = match l with Mc.Init -> log := [] | _ -> log := convert l :: !log in
  (make_with ?program ~record (), fun () -> List.rev !log)
