open Semantics

type world = {
  host : Agent.host;
  current : float * float;
  map : ((float * float) * string) list;   (* insertion order of keys *)
}

let invoke w name =
  match Robome.Host.call w.host name with
  | Ok () -> ()
  | Error _ -> ()   (* R7: recorded by an interpreter; the names here all exist *)

module Bodies = struct
  type percept = Agent.percept
  type message = unit
  type obj = unit
  type beh = unit     (* HandlePercepts, the only behaviour *)
  type nonrec world = world
  type bindings = unit

  let cyclic () = true
  let has_action () = false
  let percept_handlers () = 4
  let message_handlers () = 0

  let applies h (p : Agent.percept) = match h, p with
    | 1, Falling | 2, Obstacle | 3, Qr_code_read _ | 4, Position _ -> true
    | _ -> false

  let percept_applicable w ~id:_ () h p = (w, if applies h p then Some () else None)

  let run_percept_handler w ~id:_ ~active:_ () h (p : Agent.percept) () =
    match h, p with
    | 1, Falling ->
      invoke w "callStop"; invoke w "callMoveBackward"; invoke w "callHeadTiltDown"; (w, [])
    | 2, Obstacle ->
      invoke w "callStop"; invoke w "callTurnLeft"; invoke w "callMoveForward"; (w, [])
    | 3, Qr_code_read text ->
      let key = w.current in
      let map =
        if List.mem_assoc key w.map then List.map (fun (k, v) -> if k = key then (k, text) else (k, v)) w.map
        else w.map @ [ (key, text) ] in
      ({ w with map }, [])
    | 4, Position (x, y) -> ({ w with current = (x, y) }, [])
    | _ -> (w, [])

  let run_action w ~id:_ ~active:_ () = (w, [])
  let message_accepted w ~id:_ () _ () = (w, None)
  let run_message_handler w ~id:_ ~active:_ () _ () () = (w, [])
  let take_outbox w = (w, [])

  (* the fast engine's pre-test: handler h takes one percept kind *)
  let percept_may_apply _ () h p = applies h p

  (* the pre-test's answer depends on the percept's constructor only *)
  let percept_kind : Agent.percept -> int = function
    | Falling -> 0 | Obstacle -> 1 | Qr_code_read _ -> 2 | Position _ -> 3

  let percept_handle w ~id ~active b h p = Engine.handle_in_two percept_applicable run_percept_handler w ~id ~active b h p
end

module E = Engine.Make (Bodies)
module M = Machine.Make (Bodies)

type label = (Agent.percept, unit, unit) Machine.label

type t = {
  params : Machine.params;
  mutable c : M.t;
  mutable logging : bool;
  mutable log_rev : label list;
}

let name = "reference"

let create (loop : Agent.loop) host =
  let params = { Machine.default_params with variant = loop.variant; budget = loop.budget;
                                             o2a_capacity = loop.o2a_capacity } in
  let w = { host; current = (0., 0.); map = [] } in
  invoke w "startListening";
  let c = M.init params ~world:w [ () ] in
  invoke w "callMoveForward";
  { params; c; logging = false; log_rev = [] }

let enable_log t = t.logging <- true
let log t = List.rev t.log_rev
let record t l = if t.logging then t.log_rev <- l :: t.log_rev

let notify t p ~priority =
  match M.notify_event t.params t.c p ~default:(Agent.default_priority p) ~priority with
  | Error (Machine.Negative_priority k) -> Error (Printf.sprintf "priority %d is not a natural number (R2a)" k)
  | Error Machine.O2a_full -> Error "the O2A queue is full (R2d)"
  | Ok c -> t.c <- c; record t c.last; Ok c.next_seq

let take t =
  match E.step t.params t.c with
  | [] -> None
  | (l, c) :: _ -> t.c <- c; record t l; Some l

(* one rule at a time *)
let step_one t : Agent.work option =
  match take t with
  | None -> None
  | Some l -> Some (Agent.work_of_step ~take:(fun () -> take t) ~percept:Fun.id l)

let step t : Agent.work option =
  (* a whole dispatch in one call of the derived rule when it applies (the
     same rules, labels and work as one at a time, D29); the closures only
     then *)
  if t.c.phase = Machine.Dispatch_phase then begin
    let dispatch observe =
      match E.dispatch ~observe:(fun l w -> observe l; w) t.params t.c with
      | Some c -> t.c <- c; true
      | None -> false in
    match Agent.dispatch_work ~dispatch ~record:(record t) ~percept:Fun.id with
    | Some w -> Some w
    | None -> step_one t
  end else step_one t

let world_map t = List.map (fun ((x, y), s) -> (x, y, s)) t.c.world.map
let current_position t = t.c.world.current
