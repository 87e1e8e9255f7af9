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
  mutable pose : Kinematics.pose;
  mutable motion : motion;
  mutable waiting : Command.t list;   (* motion commands heard during a manoeuvre, in order *)
  mutable head : head;
  mutable contact : bool;
  mutable tipping : bool;
  mutable fallen : bool;
  mutable hooks : (t -> unit) list;
  rng : Random.State.t;
  trig : Kinematics.trig;   (* the heading's sine and cosine, remembered *)
  free : free;              (* a place and the room about it, for [collides] *)
  k : clock;                (* the time and the odometer *)
}

(* floats only: a physics step sets them without boxing a float *)
and clock = { mutable time : float; mutable odometer : float }

(* [room] is a lower bound of the distance from (ax, ay) to every wall and
   cube ({!World.clearance}); neg_infinity when there is no such place yet.
   All floats, so that setting them allocates nothing. *)
and free = { mutable ax : float; mutable ay : float; mutable room : float }

let create ?(step = 0.01) ?(rng = Random.State.make [| 0 |]) p w pose =
  { rng; p; w; step; pose; motion = Halted; waiting = []; head = Neutral;
    contact = false; tipping = false; fallen = false; hooks = [];
    k = { time = 0.; odometer = 0. }; trig = Kinematics.trig (); free = { ax = 0.; ay = 0.; room = neg_infinity } }

let params r = r.p
let world r = r.w
let time r = r.k.time
let pose r = r.pose
let motion r = r.motion
let head r = r.head
let tipping r = r.tipping
let fallen r = r.fallen
let odometer r = r.k.odometer
let moving r = (not r.fallen) && (match r.motion with Halted -> false | Drive _ | Manoeuvre _ -> true)
let on_step r f = r.hooks <- r.hooks @ [ f ]

let head_pitch r =
  match r.head with Neutral -> 0. | Up -> r.p.head_up_angle | Down -> r.p.head_down_angle

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
                            until = r.k.time +. Params.deg (float_of_int d) /. p.angle_turn_rate } in
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

(* [World.disc_collides r.w x y rad], without computing it while the disc
   stays within the room known about the last place where the clearance was
   measured: a disc centred less than [room - rad - margin] from that place
   is more than [rad + margin] from every wall and cube, so the exact test
   would say no (D35; the robot moves 2 mm a step in a corridor 2 m
   wide, so the clearance is measured about once in a hundred steps). *)
let collides r x y rad =
  let f = r.free in
  let dx = x -. f.ax and dy = y -. f.ay in
  if sqrt (dx *. dx +. dy *. dy) < f.room -. rad -. World.margin then false
  else begin
    let room = World.clearance r.w x y in
    f.ax <- x; f.ay <- y; f.room <- room;
    if room -. rad -. World.margin > 0. then false else World.disc_collides r.w x y rad
  end
[@@inline]   (* no float boxed to call it *)

let rec run_hooks r = function [] -> () | f :: rest -> f r; run_hooks r rest

(* One physics step of length dt (the motion is constant over it). The
   speeds are those of the motion (a manoeuvre turns on the spot), the pose that of [Kinematics.integrate]
   and the contact test that of [World.disc_collides], each computed without
   allocating a tuple or calling sin and cos again for the same heading
   (D35); the same floats bit for bit. The leading point is the point
   of the body that leads the motion: its front, or its back when the robot
   backs. *)
let physics_step r dt events =
  let v = match r.motion with Drive d -> d.v | Halted | Manoeuvre _ -> 0. in
  let omega = match r.motion with Drive d -> d.omega | Manoeuvre m -> m.omega | Halted -> 0. in
  let q = Kinematics.integrate_cached r.trig r.pose ~v ~omega ~dt in
  let rad = r.p.body_radius in
  let blocked = (v <> 0.) && collides r q.x q.y rad in
  let q = if blocked then { r.pose with theta = q.theta } else q in
  if blocked then begin
    if not r.contact then events := Collision q :: !events;
    r.contact <- true
  end else begin
    (* the contact ends once the body is clear by a centimetre *)
    if r.contact && not (World.disc_collides r.w q.x q.y (rad +. 0.01)) then r.contact <- false;
    r.k.odometer <- r.k.odometer +. Float.abs v *. dt   (* Kinematics.arc_length, unboxed *)
  end;
  r.pose <- q;
  r.k.time <- r.k.time +. dt;
  (* a world without drop-offs (most) is not asked: no float boxed for it *)
  let edges = match r.w.dropoffs with [] -> false | _ :: _ -> true in
  if edges && World.over_dropoff r.w q.x q.y then begin
    r.fallen <- true; r.motion <- Halted; r.waiting <- [];
    events := Fall q :: !events
  end else begin
    let s = if v < 0. then -.rad else rad in
    let over = edges && (Kinematics.load r.trig q.theta;
                         World.over_dropoff r.w (q.x +. s *. r.trig.cos_a) (q.y +. s *. r.trig.sin_a)) in
    if over && not r.tipping then (r.tipping <- true; events := Tipping_start q :: !events)
    else if (not over) && r.tipping && v <> 0. then (r.tipping <- false; events := Tipping_end q :: !events)
  end;
  run_hooks r r.hooks
[@@inline]   (* once a step: no float boxed to call it *)

(* Float.min (the same float for every input but two nans), written here to
   be inlined: no float boxed to call it *)
let fmin (x : float) y =
  if x < y then x
  else if y < x then y
  else if x <> x then x
  else if y <> y then y
  else if 1. /. x < 0. then x   (* -0. before 0. *)
  else y
[@@inline]

let rec advance_to r t events =
  if r.k.time < t then begin
    if not (moving r) then r.k.time <- t
    else begin
      let limit = match r.motion with Manoeuvre { until; _ } -> fmin t until | _ -> t in
      let dt = fmin r.step (limit -. r.k.time) in
      if dt > 0. then physics_step r dt events;
      (match r.motion with
       | Manoeuvre { until; _ } when r.k.time >= until -. 1e-12 -> r.k.time <- Float.max r.k.time until; end_manoeuvre r
       | _ -> ());
      advance_to r t events
    end
  end

let advance r t =
  if not (r.k.time < t) then []
  else if not (moving r) then (r.k.time <- t; [])
  else begin
    let events = ref [] in
    advance_to r t events;
    List.rev !events
  end
