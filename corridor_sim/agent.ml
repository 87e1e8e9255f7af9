type percept =
  | Falling
  | Obstacle
  | Qr_code_read of string
  | Position of float * float

let default_priority = function Falling -> 10 | Obstacle -> 8 | Qr_code_read _ -> 4 | Position _ -> 2

let percept_name = function
  | Falling -> "falling" | Obstacle -> "obstacle" | Qr_code_read _ -> "qrCodeRead"
  | Position _ -> "position"

let percept_to_string = function
  | Falling -> "falling"
  | Obstacle -> "obstacle"
  | Qr_code_read s -> "qrCodeRead(" ^ Syntax.Print.text_literal s ^ ")"   (* a Jadescript literal *)
  | Position (x, y) -> Printf.sprintf "position(%.3f, %.3f)" x y

type host = Robome.Host.t

type work =
  | Transfer of { moved : int; o2a_calls : int }
  | Dispatch of { percept : percept; priority : int; seq : int; handlers_run : int }
  | Behaviour_step
  | Loop of { o2a_calls : int }

type cost = {
  o2a_call : float;
  transfer_per_percept : float;
  dispatch : float;
  handler : float;
  invoke : float;
  behaviour_step : float;
  iteration : float;
}

let default_cost = {
  o2a_call = 0.0002;
  transfer_per_percept = 0.00001;
  dispatch = 0.00005;
  handler = 0.0001;
  invoke = 0.00005;
  behaviour_step = 0.0001;
  iteration = 0.00001;
}

let cost_of c w ~invokes =
  let base = match w with
    | Transfer { moved; o2a_calls } -> float_of_int o2a_calls *. c.o2a_call +. float_of_int moved *. c.transfer_per_percept
    | Dispatch { handlers_run; _ } -> c.dispatch +. float_of_int handlers_run *. c.handler
    | Behaviour_step -> c.behaviour_step
    | Loop { o2a_calls } -> c.iteration +. float_of_int o2a_calls *. c.o2a_call in
  base +. float_of_int invokes *. c.invoke

type loop = {
  variant : Semantics.Machine.variant;
  budget : int;
  o2a_capacity : int option;
}

let default_loop = { variant = Semantics.Machine.Reference; budget = 4; o2a_capacity = None }

module type AGENT = sig
  type t
  val name : string
  val create : loop -> host -> t
  val notify : t -> percept -> priority:int option -> (int, string) result
  val step : t -> work option
  val world_map : t -> (float * float * string) list
end

let work_of_step ~take ~percept (l : (_, _, _) Semantics.Machine.label) : work =
  let open Semantics.Machine in
  match l with
  | Transfer n -> Transfer { moved = n; o2a_calls = 1 }
  | Transfer_one _ -> Transfer { moved = 1; o2a_calls = 1 }
  | Transfer_spin _ -> Transfer { moved = 0; o2a_calls = 1 }
  | Transfer_end -> Loop { o2a_calls = 1 }
  | Dequeue e ->
    let rec finish handlers =
      match take () with
      | Some (Handle _) -> finish (handlers + 1)
      | Some (Skip _) -> finish handlers
      | Some _ | None -> handlers in
    let handlers_run = finish 0 in
    Dispatch { percept = percept e.p; priority = e.prio; seq = e.seq; handlers_run }
  | Behaviour_step _ -> Behaviour_step
  | Next_iteration | Idle | Init | Notify _ | Notify_with _ | Put _ | Send _ | Handle _ | Skip _
  | End_dispatch _ -> Loop { o2a_calls = 0 }

let dispatch_work ~dispatch ~record ~percept : work option =
  let first = ref None and handlers = ref 0 in
  let observe (l : (_, _, _) Semantics.Machine.label) =
    record l;
    match l with
    | Dequeue e -> first := Some e
    | Handle _ -> incr handlers
    | _ -> () in
  if not (dispatch observe) then None
  else match !first with
    | Some e -> Some (Dispatch { percept = percept e.Semantics.Machine.p; priority = e.prio; seq = e.seq;
                                 handlers_run = !handlers })
    | None -> None
