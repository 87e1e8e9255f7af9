type head = Neutral | Up | Down

type motion =
  | Halted
  | Drive of { v : float; omega : float }
  | Manoeuvre of { omega : float; until : float }

type event =
  | Collision of Kinematics.pose
  | Tipping_start of Kinematics.pose
  | Tipping_end of Kinematics.pose
  | Fall of Kinematics.pose

type t = {
  p : Params.t;
  w : World.t;
  step : float;
  mutable time : float;
  mutable pose : Kinematics.pose;
  mutable motion : motion;
  mutable waiting : Command.t list;   (* motion commands heard during a manoeuvre, in order *)
  mutable head : head;
  mutable contact : bool;
  mutable tipping : bool;
  mutable fallen : bool;
  mutable odometer : float;
  mutable hooks : (t -> unit) list;
}

let create ?(step = 0.01) p w pose =
  { p; w; step; time = 0.; pose; motion = Halted; waiting = []; head = Neutral;
    contact = false; tipping = false; fallen = false; odometer = 0.; hooks = [] }

let params r = r.p
let world r = r.w
let time r = r.time
let pose r = r.pose
let motion r = r.motion
let head r = r.head
let tipping r = r.tipping
let fallen r = r.fallen
let odometer r = r.odometer
let moving r = (not r.fallen) && r.motion <> Halted
let on_step r f = r.hooks <- r.hooks @ [ f ]

let head_pitch r =
  match r.head with Neutral -> 0. | Up -> r.p.head_up_angle | Down -> r.p.head_down_angle

let velocity r =
  match r.motion with
  | Halted -> (0., 0.)
  | Drive { v; omega } -> (v, omega)
  | Manoeuvre { omega; _ } -> (0., omega)

(* The point of the body that leads the motion. *)
let leading_point r (q : Kinematics.pose) =
  let (v, _) = velocity r in
  let s = if v < 0. then -.r.p.body_radius else r.p.body_radius in
  (q.x +. s *. cos q.theta, q.y +. s *. sin q.theta)

let level a s = a.(s - 1)

(* Act on a motion command (never during a manoeuvre). *)
let start r (c : Command.t) =
  let p = r.p in
  match c with
  | Stop -> r.motion <- Halted
  | Forward s -> r.motion <- Drive { v = level p.forward_speeds s; omega = 0. }
  | Backward s -> r.motion <- Drive { v = -.level p.backward_speeds s; omega = 0. }
  | Turn_left (Speed s) -> r.motion <- Drive { v = 0.; omega = level p.turn_rates s }
  | Turn_right (Speed s) -> r.motion <- Drive { v = 0.; omega = -.level p.turn_rates s }
  | Turn_left (Degrees d) ->
    r.motion <- Manoeuvre { omega = p.angle_turn_rate;
                            until = r.time +. Params.deg (float_of_int d) /. p.angle_turn_rate }
  | Turn_right (Degrees d) ->
    r.motion <- Manoeuvre { omega = -.p.angle_turn_rate;
                            until = r.time +. Params.deg (float_of_int d) /. p.angle_turn_rate }
  | Head_up | Head_down | Head_reset -> ()

(* Motion commands that waited for a manoeuvre act in order, at once: the
   last one wins unless one of them starts another manoeuvre. *)
let rec resume r =
  match r.waiting with
  | [] -> ()
  | c :: rest ->
    r.waiting <- rest;
    start r c;
    (match r.motion with Manoeuvre _ -> () | _ -> resume r)

let end_manoeuvre r = r.motion <- Halted; resume r

let apply r (c : Command.t) =
  if not (Command.valid c) then invalid_arg ("Robot.apply: " ^ Command.to_string c);
  if not r.fallen then
    match c with
    | Head_up -> r.head <- Up
    | Head_down -> r.head <- Down
    | Head_reset -> r.head <- Neutral
    | Stop -> r.waiting <- []; r.motion <- Halted
    | _ ->
      (match r.motion with
       | Manoeuvre _ -> r.waiting <- r.waiting @ [ c ]
       | _ -> start r c)

(* One physics step of length dt (the motion is constant over it). *)
let physics_step r dt events =
  let (v, omega) = velocity r in
  let q = Kinematics.integrate r.pose ~v ~omega ~dt in
  let rad = r.p.body_radius in
  let blocked = (v <> 0.) && World.disc_collides r.w q.x q.y rad in
  let q = if blocked then { r.pose with theta = q.theta } else q in
  if blocked then begin
    if not r.contact then events := Collision q :: !events;
    r.contact <- true
  end else begin
    if v <> 0. then r.contact <- false;
    r.odometer <- r.odometer +. Kinematics.arc_length ~v ~dt
  end;
  r.pose <- q;
  r.time <- r.time +. dt;
  if World.over_dropoff r.w q.x q.y then begin
    r.fallen <- true; r.motion <- Halted; r.waiting <- [];
    events := Fall q :: !events
  end else begin
    let (lx, ly) = leading_point r q in
    let over = World.over_dropoff r.w lx ly in
    if over && not r.tipping then (r.tipping <- true; events := Tipping_start q :: !events)
    else if (not over) && r.tipping && v <> 0. then (r.tipping <- false; events := Tipping_end q :: !events)
  end;
  List.iter (fun f -> f r) r.hooks

let advance r t =
  let events = ref [] in
  let rec go () =
    if r.time < t then begin
      if not (moving r) then r.time <- t
      else begin
        let limit = match r.motion with Manoeuvre { until; _ } -> Float.min t until | _ -> t in
        let dt = Float.min r.step (limit -. r.time) in
        if dt > 0. then physics_step r dt events;
        (match r.motion with
         | Manoeuvre { until; _ } when r.time >= until -. 1e-12 -> r.time <- Float.max r.time until; end_manoeuvre r
         | _ -> ());
        go ()
      end
    end in
  go ();
  List.rev !events
