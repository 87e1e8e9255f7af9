open Robome

type sensors = {
  position_rate : float;
  uwb_sigma : float;
  proximity_rate : float;
  obstacle_band : float;
  obstacle_repeat : float;
  edge_detector : bool;
  camera_rate : float;
  qr_repeat : float;
  imu_rate : float;
  falling_repeat : float;
  overrides : (string * int) list;
}

type flood = {
  percept : string;
  text : string;
  rate : float;
  start_time : float;
  end_time : float;
  priority : int option;
}

type random_cubes = { count : int; size : float; min_gap : float; keep_clear : float }

type t = {
  name : string;
  description : string;
  seed : int;
  duration : float;
  length : float;
  width : float;
  walls : World.segment list;
  cubes : World.cube list;
  random_cubes : random_cubes option;
  dropoffs : World.rect list;
  start : Kinematics.pose;
  params : Params.t;
  mapping : Host.mapping;
  sensors : sensors;
  flood : flood option;
  loop : Agent.loop;
  cost : Agent.cost;
  physics_step : float;
  trajectory_step : float;
}

exception Error of string

let fail fmt = Printf.ksprintf (fun s -> raise (Error s)) fmt

(* ---------------------------------------------------------- JSON access *)

type obj = { path : string; fields : (string * Yojson.Safe.t) list }

let as_obj path allowed = function
  | `Assoc fields ->
    List.iter (fun (k, _) ->
        if not (List.mem k allowed) then
          fail "%s: unknown field %S (allowed: %s)" path k (String.concat ", " allowed)) fields;
    { path; fields }
  | _ -> fail "%s: expected an object" path

let sub o k = if o.path = "" then k else o.path ^ "." ^ k

let num path = function
  | `Int i -> float_of_int i
  | `Float f -> f
  | `Intlit s -> (try float_of_string s with _ -> fail "%s: not a number" path)
  | _ -> fail "%s: expected a number" path

let int_ path = function
  | `Int i -> i
  | _ -> fail "%s: expected an integer" path

let opt o k f = match List.assoc_opt k o.fields with None | Some `Null -> None | Some v -> Some (f (sub o k) v)
let get o k f = match opt o k f with Some v -> v | None -> fail "%s: missing field" (sub o k)
let dflt o k f d = match opt o k f with Some v -> v | None -> d

let str path = function `String s -> s | _ -> fail "%s: expected a string" path
let bool path = function `Bool b -> b | _ -> fail "%s: expected true or false" path
let list path f = function
  | `List l -> List.mapi (fun i v -> f (Printf.sprintf "%s[%d]" path i) v) l
  | _ -> fail "%s: expected a list" path

(* Every number of a scenario has a range, documented in docs/simulation.md
   ("Ranges"), checked here when the file is read: a run is then bounded in
   time and memory, and infinity (a number too large for a float) never gets in. *)
let show x =
  if Float.is_integer x && Float.abs x < 1e15 then Printf.sprintf "%.0f" x else Printf.sprintf "%g" x

(* [range lo hi]: lo <= x <= hi; [~above:true]: lo < x <= hi. *)
let range ?(above = false) lo hi path x =
  if (if above then x > lo else x >= lo) && x <= hi then x
  else if above then
    fail "%s: %s is out of range: above %s and at most %s (docs/simulation.md)" path (show x) (show lo) (show hi)
  else fail "%s: %s is out of range: from %s to %s (docs/simulation.md)" path (show x) (show lo) (show hi)

let real ?above lo hi path v = range ?above lo hi path (num path v)
let positive hi = real ~above:true 0. hi   (* 0 < x <= hi *)
let non_neg hi = real 0. hi                (* 0 <= x <= hi *)

let int_range lo hi path v =
  let i = int_ path v in
  if i >= lo && i <= hi then i
  else fail "%s: %d is out of range: from %d to %d (docs/simulation.md)" path i lo hi

(* Coordinates, and the largest corridor: 1 km by 100 m. *)
let max_length = 1000. and max_width = 100.
let coord = real (-. max_length) max_length
let angle = real (-360.) 360.

(* A priority, as an override passes it to notify (R2a): a natural number of
   Jadescript's 32-bit integers. *)
let priority = int_range 0 0x7fffffff

let point path v =
  match v with
  | `List [ a; b ] -> { World.px = coord path a; py = coord path b }
  | _ -> fail "%s: expected [x, y]" path

(* ------------------------------------------------------------- sections *)

let percept_names = [ "falling"; "obstacle"; "qrCodeRead"; "position" ]

let cube path v =
  let o = as_obj path [ "id"; "x"; "y"; "size_m"; "yaw_deg"; "faces" ] v in
  let faces = get o "faces" (fun p v -> list p str v) in
  if List.length faces <> 4 then fail "%s.faces: four texts expected (+x, +y, -x, -y)" path;
  { World.id = get o "id" str; cx = get o "x" coord; cy = get o "y" coord;
    size = dflt o "size_m" (positive 10.) 0.2; yaw = Params.deg (dflt o "yaw_deg" angle 0.);
    faces = Array.of_list faces }

let rect path v =
  let o = as_obj path [ "x_min"; "y_min"; "x_max"; "y_max" ] v in
  let r = { World.x_min = get o "x_min" coord; y_min = get o "y_min" coord;
            x_max = get o "x_max" coord; y_max = get o "y_max" coord } in
  if r.x_min >= r.x_max || r.y_min >= r.y_max then fail "%s: empty rectangle" path;
  r

let wall path v =
  let o = as_obj path [ "from"; "to" ] v in
  { World.a = get o "from" point; b = get o "to" point }

let random_cubes path v =
  let o = as_obj path [ "count"; "size_m"; "min_gap_m"; "keep_clear_m" ] v in
  { count = get o "count" (int_range 0 1000); size = dflt o "size_m" (positive 10.) 0.2;
    min_gap = dflt o "min_gap_m" (non_neg 100.) 0.4;
    keep_clear = dflt o "keep_clear_m" (non_neg max_length) 1.0 }

(* The sizes that bound a run (docs/simulation.md, "Ranges"). *)
let max_duration = 3600.          (* s of simulated time *)
let max_sensor_rate = 1000.       (* Hz *)
let max_flood_rate = 20_000.      (* Hz *)
let max_flood_percepts = 1_000_000.
let max_trajectory_points = 1_000_000.
let max_items = 1000              (* walls, cubes, drop-offs *)
(* every sensor at 1000 Hz for an hour would be 14.4M samples, about 3 GB of
   trace and queues: the samples of a run are bounded as a whole (a run of
   1.44M samples measured 300 MB) *)
let max_samples = 2_000_000.

let default_sensors = {
  position_rate = 10.; uwb_sigma = 0.3; proximity_rate = 10.; obstacle_band = 0.5;
  obstacle_repeat = 1.0; edge_detector = true; camera_rate = 5.; qr_repeat = 2.0;
  imu_rate = 50.; falling_repeat = 0.5; overrides = [];
}

let sensors path v =
  let d = default_sensors in
  let o = as_obj path [ "position_rate_hz"; "uwb_sigma_m"; "proximity_rate_hz"; "obstacle_band_m";
                        "obstacle_repeat_s"; "edge_detector"; "camera_rate_hz"; "qr_repeat_s";
                        "imu_rate_hz"; "falling_repeat_s"; "priority_overrides" ] v in
  let overrides = dflt o "priority_overrides" (fun p v ->
      match v with
      | `Assoc l -> List.map (fun (k, x) ->
          if not (List.mem k percept_names) then fail "%s: unknown percept %S" p k;
          (k, priority (p ^ "." ^ k) x)) l
      | _ -> fail "%s: expected an object" p) [] in
  let rate = positive max_sensor_rate and every = positive max_duration in
  { position_rate = dflt o "position_rate_hz" rate d.position_rate;
    uwb_sigma = dflt o "uwb_sigma_m" (non_neg 10.) d.uwb_sigma;
    proximity_rate = dflt o "proximity_rate_hz" rate d.proximity_rate;
    obstacle_band = dflt o "obstacle_band_m" (positive 10.) d.obstacle_band;
    obstacle_repeat = dflt o "obstacle_repeat_s" every d.obstacle_repeat;
    edge_detector = dflt o "edge_detector" bool d.edge_detector;
    camera_rate = dflt o "camera_rate_hz" rate d.camera_rate;
    qr_repeat = dflt o "qr_repeat_s" (non_neg max_duration) d.qr_repeat;
    imu_rate = dflt o "imu_rate_hz" rate d.imu_rate;
    falling_repeat = dflt o "falling_repeat_s" every d.falling_repeat;
    overrides }

let flood path v =
  let o = as_obj path [ "percept"; "text"; "rate_hz"; "start_s"; "end_s"; "priority" ] v in
  let percept = get o "percept" str in
  if not (List.mem percept percept_names) then fail "%s.percept: unknown percept %S" path percept;
  let f = { percept; text = dflt o "text" str "FLOOD"; rate = get o "rate_hz" (positive max_flood_rate);
            start_time = dflt o "start_s" (non_neg max_duration) 0.;
            end_time = dflt o "end_s" (non_neg max_duration) infinity;
            priority = opt o "priority" priority } in
  if f.end_time <= f.start_time then fail "%s.end_s: must be after start_s" path;
  f

let turn path v =
  match v with
  | `Int d when d = 90 || d = 180 || d = 360 -> Command.Degrees d
  | `String s when String.length s > 6 && String.sub s 0 6 = "speed:" ->
    (match int_of_string_opt (String.sub s 6 (String.length s - 6)) with
     | Some l when l >= 1 && l <= 5 -> Command.Speed l
     | _ -> fail "%s: speed level 1-5 expected" path)
  | _ -> fail "%s: 90, 180, 360 or \"speed:N\" expected" path

let level path v = let l = int_ path v in if l >= 1 && l <= 5 then l else fail "%s: level 1-5 expected" path

let host path v =
  let o = as_obj path [ "forward_level"; "backward_level"; "turn" ] v in
  let d = Host.default_mapping in
  { Host.forward_level = dflt o "forward_level" level d.forward_level;
    backward_level = dflt o "backward_level" level d.backward_level;
    turn = dflt o "turn" turn d.turn }

let robot path v =
  let d = Params.default in
  let o = as_obj path [ "body_radius_m"; "sound_duration_s"; "sound_gap_s"; "angle_turn_rate_deg_s";
                        "forward_speeds_m_s"; "camera_hfov_deg"; "qr_range_factor";
                        "speed_noise"; "drift_deg_s" ] v in
  let speeds p v = let l = list p (non_neg 10.) v in
    if List.length l <> 5 then fail "%s: five speeds expected" p; Array.of_list l in
  { d with
    body_radius = dflt o "body_radius_m" (positive 1.) d.body_radius;
    sound_duration = dflt o "sound_duration_s" (non_neg 10.) d.sound_duration;
    sound_gap = dflt o "sound_gap_s" (non_neg 10.) d.sound_gap;
    angle_turn_rate = (match opt o "angle_turn_rate_deg_s" (positive 3600.) with
        | Some r -> Params.deg r | None -> d.angle_turn_rate);
    forward_speeds = dflt o "forward_speeds_m_s" speeds d.forward_speeds;
    camera_hfov = (match opt o "camera_hfov_deg" (positive 180.) with Some a -> Params.deg a | None -> d.camera_hfov);
    qr_range_factor = dflt o "qr_range_factor" (positive 100.) d.qr_range_factor;
    speed_noise = dflt o "speed_noise" (non_neg 1.) d.speed_noise;
    drift = (match opt o "drift_deg_s" (non_neg 360.) with Some a -> Params.deg a | None -> d.drift) }

let cost path v =
  let d = Agent.default_cost in
  let o = as_obj path [ "o2a_call_s"; "transfer_per_percept_s"; "dispatch_s"; "handler_s";
                        "invoke_s"; "behaviour_step_s"; "iteration_s" ] v in
  { Agent.o2a_call = dflt o "o2a_call_s" (non_neg 10.) d.o2a_call;
    transfer_per_percept = dflt o "transfer_per_percept_s" (non_neg 10.) d.transfer_per_percept;
    dispatch = dflt o "dispatch_s" (non_neg 10.) d.dispatch;
    handler = dflt o "handler_s" (non_neg 10.) d.handler;
    invoke = dflt o "invoke_s" (non_neg 10.) d.invoke;
    behaviour_step = dflt o "behaviour_step_s" (non_neg 10.) d.behaviour_step;
    iteration = dflt o "iteration_s" (non_neg 10.) d.iteration }

let agent path v =
  let o = as_obj path [ "loop"; "budget"; "o2a_capacity"; "cost" ] v in
  let variant = dflt o "loop" (fun p v ->
      match str p v with
      | "reference" -> Semantics.Machine.Reference
      | "printed" -> Semantics.Machine.Printed
      | "budgeted" -> Semantics.Machine.Budgeted
      | s -> fail "%s: %S is not reference, printed or budgeted" p s) Semantics.Machine.Reference in
  let loop = { Agent.variant;
               budget = dflt o "budget" (int_range 1 1_000_000) 4;
               o2a_capacity = opt o "o2a_capacity" (int_range 1 100_000_000) } in
  (loop, dflt o "cost" cost Agent.default_cost)

let of_json v =
  let o = as_obj "" [ "name"; "description"; "seed"; "duration_s"; "corridor"; "cubes"; "random_cubes";
                      "dropoffs"; "start"; "robot"; "host"; "sensors"; "flood"; "agent";
                      "physics_step_s"; "trajectory_step_s" ] v in
  let corridor = get o "corridor" (fun p v -> as_obj p [ "length_m"; "width_m"; "walls" ] v) in
  let start = get o "start" (fun p v ->
      let s = as_obj p [ "x"; "y"; "heading_deg" ] v in
      { Kinematics.x = get s "x" coord; y = get s "y" coord;
        theta = Kinematics.normalise (Params.deg (dflt s "heading_deg" angle 0.)) }) in
  let (loop, cost) = dflt o "agent" agent (Agent.default_loop, Agent.default_cost) in
  let t = {
    name = get o "name" str;
    description = dflt o "description" str "";
    seed = dflt o "seed" (int_range 0 0x3fffffff) 1;
    duration = get o "duration_s" (positive max_duration);
    length = get corridor "length_m" (positive max_length);
    width = get corridor "width_m" (positive max_width);
    walls = dflt corridor "walls" (fun p v -> list p wall v) [];
    cubes = dflt o "cubes" (fun p v -> list p cube v) [];
    random_cubes = opt o "random_cubes" random_cubes;
    dropoffs = dflt o "dropoffs" (fun p v -> list p rect v) [];
    start;
    params = dflt o "robot" robot Params.default;
    mapping = dflt o "host" host Host.default_mapping;
    sensors = dflt o "sensors" sensors default_sensors;
    flood = opt o "flood" flood;
    loop; cost;
    physics_step = dflt o "physics_step_s" (real 0.001 0.1) 0.01;
    trajectory_step = dflt o "trajectory_step_s" (real 0.001 60.) 0.1;
  } in
  if t.start.x < 0. || t.start.x > t.length || t.start.y < 0. || t.start.y > t.width then
    fail "start: outside the corridor";
  List.iter (fun (field, n) ->
      if n > max_items then fail "%s: %d elements; at most %d" field n max_items)
    [ ("corridor.walls", List.length t.walls); ("cubes", List.length t.cubes);
      ("dropoffs", List.length t.dropoffs) ];
  (* the start inside a cube: the robot would begin in a collision *)
  List.iter (fun (c : World.cube) ->
      if Float.hypot (t.start.x -. c.cx) (t.start.y -. c.cy) < c.size *. sqrt 2. /. 2. +. t.params.body_radius
      then fail "start: inside cube %S (or touching it)" c.id) t.cubes;
  let s = t.sensors in
  let samples = t.duration *. (s.position_rate +. s.proximity_rate +. s.camera_rate +. s.imu_rate) in
  if samples > max_samples then
    fail "sensors: %s samples (duration_s times the sum of the four *_rate_hz); at most %s"
      (show (Float.round samples)) (show max_samples);
  if t.duration /. t.trajectory_step > max_trajectory_points then
    fail "trajectory_step_s: %s s over %s s is more than %s trajectory points" (show t.trajectory_step)
      (show t.duration) (show max_trajectory_points);
  Option.iter (fun f ->
      let n = f.rate *. (Float.min f.end_time t.duration -. f.start_time) in
      if n > max_flood_percepts then
        fail "flood: %s percepts (rate_hz times its time within duration_s); at most %s"
          (show (Float.round n)) (show max_flood_percepts)) t.flood;
  let ids = List.map (fun (c : World.cube) -> c.id) t.cubes in
  List.iteri (fun i id -> if List.mem id (List.filteri (fun j _ -> j < i) ids) then fail "cubes: duplicate id %S" id) ids;
  t

(* A scenario is a few kilobytes (at most 1,000 walls, cubes and drop-offs
   of about 100 bytes each); a longer file is not read (docs/simulation.md,
   "Ranges"). *)
let max_bytes = 1024 * 1024

let load file =
  let v = match Json_read.of_file ~max_bytes file with
    | Ok v -> v
    | Error e -> fail "%s:%d:%d: error: %s" file e.line e.column e.message
    | exception Sys_error m -> fail "cannot read the scenario: %s" m in
  of_json v

(* Random cubes: rejection sampling from a stream of their own, so that
   they do not depend on anything else the seed drives. *)
let place_random t (r : random_cubes) ~seed =
  let st = Random.State.make [| seed; 0x5eed; 7 |] in
  let placed = ref t.cubes in
  let half_diag c = c *. sqrt 2. /. 2. in
  let ok x y =
    let m = half_diag r.size +. r.min_gap in
    x >= m && x <= t.length -. m && y >= m && y <= t.width -. m
    && Float.hypot (x -. t.start.x) (y -. t.start.y) >= r.keep_clear
    && List.for_all (fun (c : World.cube) ->
        Float.hypot (x -. c.cx) (y -. c.cy) >= half_diag r.size +. half_diag c.size +. r.min_gap) !placed in
  let made = ref [] in
  let tries = ref 0 in
  let i = ref 1 in
  while !i <= r.count && !tries < 10_000 do
    incr tries;
    let x = Random.State.float st t.length and y = Random.State.float st t.width in
    let yaw = Random.State.float st (Float.pi /. 2.) in
    if ok x y then begin
      let id = Printf.sprintf "R%d" !i in
      let c = { World.id; cx = x; cy = y; size = r.size; yaw;
                faces = Array.map (fun s -> id ^ "-" ^ s) [| "E"; "N"; "W"; "S" |] } in
      placed := !placed @ [ c ]; made := !made @ [ c ]; incr i
    end
  done;
  !made

let world t ~seed =
  let extra = match t.random_cubes with None -> [] | Some r -> place_random t r ~seed in
  World.make ~length:t.length ~width:t.width ~extra_walls:t.walls ~cubes:(t.cubes @ extra)
    ~dropoffs:t.dropoffs ()

let with_position_rate t r = { t with sensors = { t.sensors with position_rate = r } }
