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
  rng : Random.State.t;
}

let create ?(step = 0.01) ?(rng = Random.State.make [| 0 |]) p w pose =
  { rng; p; w; step; time = 0.; pose; motion = Halted; waiting = []; head = Neutral;
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

let gaussian st =
  let u1 = Float.max 1e-300 (Random.State.float st 1.0) and u2 = Random.State.float st 1.0 in
  sqrt (-2. *. log u1) *. cos (2. *. Float.pi *. u2)

(* The actual speed factor and drift of one motion command. *)
let noise r =
  if r.p.speed_noise = 0. && r.p.drift = 0. then (1., 0.)
  else
    let a = gaussian r.rng in
    let b = gaussian r.rng in
    (Float.max 0. (1. +. r.p.speed_noise *. a), r.p.drift *. b)

(* Act on a motion command (never during a manoeuvre). *)
let start r (c : Command.t) =
  let p = r.p in
  let drive v omega =
    let (k, d) = noise r in
    r.motion <- Drive { v = k *. v; omega = (if v <> 0. then omega +. d else k *. omega) } in
  let manoeuvre sign d =
    let (k, _) = noise r in
    (* the firmware times the turn for the nominal rate: the angle is off by k *)
    r.motion <- Manoeuvre { omega = sign *. k *. p.angle_turn_rate;
                            until = r.time +. Params.deg (float_of_int d) /. p.angle_turn_rate } in
  match c with
  | Stop -> r.motion <- Halted
  | Forward s -> drive (level p.forward_speeds s) 0.
  | Backward s -> drive (-.level p.backward_speeds s) 0.
  | Turn_left (Speed s) -> drive 0. (level p.turn_rates s)
  | Turn_right (Speed s) -> drive 0. (-.level p.turn_rates s)
  | Turn_left (Degrees d) -> manoeuvre 1. d
  | Turn_right (Degrees d) -> manoeuvre (-1.) d
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
    (* the contact ends once the body is clear by a centimetre *)
    if r.contact && not (World.disc_collides r.w q.x q.y (rad +. 0.01)) then r.contact <- false;
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
