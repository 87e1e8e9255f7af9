open Explore
module Mc = Semantics.Machine

let percepts = [ "falling"; "obstacle"; "position"; "qrCodeRead" ]   (* sorted, as Model numbers them *)

let index (p : Agent.percept) =
  let n = Agent.percept_name p in
  let rec go i = function
    | [] -> Semantics.Fault.crash "Trace_check: percept %s is not one of the model's" n
    | x :: r -> if x = n then i else go (i + 1) r in
  go 0 percepts

let str s = Tla.Str s

let model_constants (loop : Agent.loop) (log : Reference_controller.label list) =
  let notifies = List.length (List.filter (function Mc.Notify _ | Mc.Notify_with _ -> true | _ -> false) log) in
  let overrides = List.sort_uniq compare (List.filter_map (function Mc.Notify_with e -> Some e.prio | _ -> None) log) in
  let handler p = Agent_loop.handler ~accepts:[ str p ] ~effects:[] in
  Agent_loop.constants {
    variant = Mc.string_of_variant loop.variant;
    tie_policy = "Stable";
    budget = loop.budget;
    percepts;
    default_priority = [ ("falling", 10); ("obstacle", 8); ("qrCodeRead", 4); ("position", 2) ];
    overrides;
    objects = []; messages = [];
    max_notify = notifies; max_put = 0; max_send = 0;
    flood = false;
    o2a_capacity = (match loop.o2a_capacity with Some c -> c | None -> max 1 notifies);
    behaviours = [ "HandlePercepts" ];
    kind = (fun _ -> "cyclic");
    has_action = (fun _ -> false);
    action_effects = (fun _ -> Tla.Seq []);
    percept_handlers = (fun _ -> Tla.Seq (List.map handler [ "falling"; "obstacle"; "qrCodeRead"; "position" ]));
    message_handlers = (fun _ -> Tla.Seq []);
    initial = [ "HandlePercepts" ];
    max_active = 1;
    inversion_bound = 0 }

let entry (e : Agent.percept Mc.entry) : int Mc.entry = { p = index e.p; prio = e.prio; seq = e.seq }

let abstract (l : Reference_controller.label) : (int, int, int) Mc.label option =
  match l with
  | Init -> Some Init
  | Notify e -> Some (Notify (entry e))
  | Notify_with e -> Some (Notify_with (entry e))
  | Transfer n -> Some (Transfer n)
  | Transfer_one e -> Some (Transfer_one (entry e))
  | Transfer_end -> Some Transfer_end
  | Dequeue e -> Some (Dequeue (entry e))
  | Handle { id; h; p; seq } -> Some (Handle { id; h; p = index p; seq })
  | Skip { id; h } -> Some (Skip { id; h })
  | End_dispatch d -> Some (End_dispatch d)
  | Behaviour_step { id; msg = None } -> Some (Behaviour_step { id; msg = None })
  | Next_iteration -> Some Next_iteration
  | Idle -> Some Idle
  | Behaviour_step { msg = Some _; _ } | Put _ | Send _ | Transfer_spin _ -> None

let replay (m : Model.t) log =
  let init = Model.M.init m.params ~world:() (List.map (fun i -> m.behaviours.(i)) m.initial) in
  let rec go c acc i = function
    | [] -> Ok (List.rev acc)
    | l :: rest ->
      match abstract l with
      | None -> Error (Printf.sprintf "step %d: %s has no abstract counterpart" i (Mc.action_name l))
      | Some a ->
        let next = match a with
          | Notify e -> Some (Model.M.notify m.params c e.p e.prio)
          | Notify_with e -> Some (Model.M.notify_with m.params c e.p e.prio)
          | _ -> List.assoc_opt a (Model.M.step m.params c) in
        match next with
        | Some c' when c'.last = a -> go c' (Project.state m c' :: acc) (i + 1) rest
        | _ -> Error (Printf.sprintf "step %d: the spec's machine cannot take %s here" i (Mc.action_name l)) in
  go init [ Project.state m init ] 1 log

let counter = ref 0

let check ?dir loop log =
  let dir = match dir with
    | Some d -> d
    | None ->
      incr counter;
      let d = Filename.concat (Filename.get_temp_dir_name ())
          (Printf.sprintf "jsref-sim-%d-%d" (Unix.getpid ()) !counter) in
      (try Unix.mkdir d 0o700 with Unix.Unix_error (Unix.EEXIST, _, _) -> ());
      d in
  let path = Random_model.write ~dir ~name:"MCRoboMeRun" (model_constants loop log) in
  let m = Model.load path in
  match replay m log with
  | Error e -> Error e
  | Ok states ->
    match Conformance.validate_runs m [ states ] with
    | Ok _ -> Ok (List.length states)
    | Error e -> Error e
