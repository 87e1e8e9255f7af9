open Robome

type handled = {
  seq : int;
  percept : Agent.percept;
  priority : int;
  source : string;
  notified : float;
  dispatched : float;
  handlers : int;
}

(* The dispatched percepts in columns, recorded as the run goes:
   the ints and floats in arrays of their own, so that a dispatch boxes
   nothing and leaves the collector nothing to move (a record, two boxed
   floats, a percept and a list cell per dispatch were a tenth of a run, all
   moved to the major heap). [handled] is made from it when asked. *)
type dispatch_log = {
  mutable d_n : int;
  mutable d_seq : int array;
  mutable d_priority : int array;
  mutable d_handlers : int array;
  mutable d_notified : float array;
  mutable d_dispatched : float array;
  mutable d_kind : int array;          (* 0 falling, 1 obstacle, 2 qrCodeRead, 3 position *)
  mutable d_x : float array;           (* a position's *)
  mutable d_y : float array;
  mutable d_text : string array;       (* a QR code's text *)
  mutable d_source : string array;
}

let log_create cap =
  { d_n = 0; d_seq = Array.make cap 0; d_priority = Array.make cap 0; d_handlers = Array.make cap 0;
    d_notified = Array.make cap 0.; d_dispatched = Array.make cap 0.; d_kind = Array.make cap 0;
    d_x = Array.make cap 0.; d_y = Array.make cap 0.; d_text = Array.make cap ""; d_source = Array.make cap "" }

let log_grow l =
  let cap = 2 * Array.length l.d_seq in
  let ints a = let b = Array.make cap 0 in Array.blit a 0 b 0 l.d_n; b
  and floats a = let b = Array.make cap 0. in Array.blit a 0 b 0 l.d_n; b
  and texts a = let b = Array.make cap "" in Array.blit a 0 b 0 l.d_n; b in
  l.d_seq <- ints l.d_seq; l.d_priority <- ints l.d_priority; l.d_handlers <- ints l.d_handlers;
  l.d_notified <- floats l.d_notified; l.d_dispatched <- floats l.d_dispatched; l.d_kind <- ints l.d_kind;
  l.d_x <- floats l.d_x; l.d_y <- floats l.d_y; l.d_text <- texts l.d_text; l.d_source <- texts l.d_source

(* One more dispatch, at the end of the columns. *)
let[@inline] log_add l ~seq ~priority ~handlers ~notified ~dispatched ~source (percept : Agent.percept) =
  if l.d_n = Array.length l.d_seq then log_grow l;
  let i = l.d_n in
  l.d_n <- i + 1;
  Array.unsafe_set l.d_seq i seq;
  Array.unsafe_set l.d_priority i priority;
  Array.unsafe_set l.d_handlers i handlers;
  Array.unsafe_set l.d_notified i notified;
  Array.unsafe_set l.d_dispatched i dispatched;
  Array.unsafe_set l.d_source i source;
  match percept with
  | Falling -> Array.unsafe_set l.d_kind i 0
  | Obstacle -> Array.unsafe_set l.d_kind i 1
  | Qr_code_read text -> Array.unsafe_set l.d_kind i 2; Array.unsafe_set l.d_text i text
  | Position (x, y) -> Array.unsafe_set l.d_kind i 3; Array.unsafe_set l.d_x i x; Array.unsafe_set l.d_y i y

(* the [i]th dispatch as a record *)
let log_get l i : handled =
  let percept : Agent.percept = match l.d_kind.(i) with
    | 0 -> Falling | 1 -> Obstacle | 2 -> Qr_code_read l.d_text.(i)
    | _ -> Position (l.d_x.(i), l.d_y.(i)) in
  { seq = l.d_seq.(i); percept; priority = l.d_priority.(i); source = l.d_source.(i);
    notified = l.d_notified.(i); dispatched = l.d_dispatched.(i); handlers = l.d_handlers.(i) }

let handled_of_log l =
  let rec go i acc = if i < 0 then acc else go (i - 1) (log_get l i :: acc) in
  go (l.d_n - 1) []

type pending = { p_seq : int; p_percept : Agent.percept; p_priority : int; p_notified : float }
type busy = { b_start : float; b_end : float; b_kind : string }

type result = {
  scenario : Scenario.t;
  seed : int;
  agent_name : string;
  world : World.t;
  end_time : float;
  final_pose : Kinematics.pose;
  trajectory : (float * Kinematics.pose) list;
  collisions : (float * Kinematics.pose) list;
  falls : (float * Kinematics.pose) list;
  tippings : (float * Kinematics.pose) list;
  notified : (string * int) list;
  refused : int;
  handled : handled list Lazy.t;
  dispatches : dispatch_log;
  pending : pending list;
  world_map : (float * float * string) list;
  commands : (float * float * Command.t) list;
  busy : busy list;
  busy_total : float;
  odometer : float;
  coverage : float;
  events : int;
  trace : string;
}

let coverage_cell = 0.2

type clock = {
  mutable now : float;
  mutable last_traj : float;     (* time of the last trajectory point *)
  mutable agent_free : float;    (* when the agent's current unit of work ends *)
  mutable busy_total : float;
  mutable last_alert : float;    (* the last obstacle alert *)
  mutable last_falling : float;  (* the last falling percept *)
}

type source = Uwb | Proximity | Camera | Imu | Flood

type ev =
  | Sample of source * int               (* the k-th sample of a periodic source *)
  | Deliver of Agent.percept * string    (* a reading reaching the phone late *)
  | Sound
  | Agent_work

(* The percepts notified and not yet dispatched, by sequence number: a hash
   table on ints hashed and compared as ints (the generic table
   called the polymorphic hash and compare twice a percept). Only [fold]
   sees its order, and the pending percepts are sorted by number after. *)
module Seq_table = Hashtbl.Make (struct
    type t = int
    let equal (a : int) b = a = b
    let hash (k : int) = k land max_int
  end)

(* ------------------------------------------------------------ coverage *)

type grid = { nx : int; ny : int; free : bool array; seen : bool array;
              mutable box : int * int * int * int;   (* the cells the last [mark] looked at *)
              mutable box_seen : bool }              (* all of them seen after it *)

let make_grid (w : World.t) =
  let nx = max 1 (int_of_float (Float.ceil (w.length /. coverage_cell)))
  and ny = max 1 (int_of_float (Float.ceil (w.width /. coverage_cell))) in
  let free = Array.init (nx * ny) (fun k ->
      let i = k mod nx and j = k / nx in
      let x = (float_of_int i +. 0.5) *. coverage_cell and y = (float_of_int j +. 0.5) *. coverage_cell in
      not (World.over_dropoff w x y || Array.exists (fun c -> World.in_cube c x y) w.cubes)) in
  { nx; ny; free; seen = Array.make (nx * ny) false; box = (-1, -1, -1, -1); box_seen = false }

(* on ints: Stdlib's max and min are polymorphic, some 90 instructions a call *)
let imax (a : int) b = if a >= b then a else b
let imin (a : int) b = if a <= b then a else b

let mark g x y r =
  let i0 = imax 0 (int_of_float ((x -. r) /. coverage_cell))
  and i1 = imin (g.nx - 1) (int_of_float ((x +. r) /. coverage_cell))
  and j0 = imax 0 (int_of_float ((y -. r) /. coverage_cell))
  and j1 = imin (g.ny - 1) (int_of_float ((y +. r) /. coverage_cell)) in
  (* a cell already seen stays seen: only the others are measured
     (the robot moves 2 mm a step, so nearly every cell under it is seen);
     and when the cells are those of the last call, all seen, nothing is *)
  let (a0, a1, b0, b1) = g.box in
  if not (g.box_seen && i0 = a0 && i1 = a1 && j0 = b0 && j1 = b1) then begin
    let all = ref true in
    for i = i0 to i1 do
      for j = j0 to j1 do
        if not (Array.unsafe_get g.seen (j * g.nx + i)) then begin
          let cx = Float.max (float_of_int i *. coverage_cell) (Float.min (float_of_int (i + 1) *. coverage_cell) x)
          and cy = Float.max (float_of_int j *. coverage_cell) (Float.min (float_of_int (j + 1) *. coverage_cell) y) in
          if (cx -. x) *. (cx -. x) +. (cy -. y) *. (cy -. y) < r *. r then g.seen.(j * g.nx + i) <- true
          else all := false
        end
      done
    done;
    g.box <- (i0, i1, j0, j1);
    g.box_seen <- !all
  end
[@@inline]   (* no float boxed to call it at every physics step *)

let coverage g =
  let free = ref 0 and seen = ref 0 in
  Array.iteri (fun k f -> if f then (incr free; if g.seen.(k) then incr seen)) g.free;
  if !free = 0 then 0. else float_of_int !seen /. float_of_int !free

(* ---------------------------------------------------------------- run *)

module Make (A : Agent.AGENT) = struct
  let run ?(trace = false) ?(timeline_window = 20.) ?(on_create = fun _ -> ()) (sc : Scenario.t) ~seed =
    let world = Scenario.world sc ~seed in
    let p = sc.params and s = sc.sensors in
    let robot = Robot.create ~step:sc.physics_step ~rng:(Random.State.make [| seed; 3 |]) p world sc.start in
    let sound = Sound_queue.create ~duration:p.sound_duration ~gap:p.sound_gap in
    let agenda : ev Event_queue.t = Event_queue.create () in
    let rng_uwb = Random.State.make [| seed; 1 |] and rng_flood = Random.State.make [| seed; 2 |] in
    let buf = Buffer.create (if trace then 65536 else 16) in
    (* without a trace, nothing is formatted (formatting the
       numbers of every event was a fifth of the run) *)
    let tr fmt =
      if trace then Printf.ksprintf (fun l -> Buffer.add_string buf l; Buffer.add_char buf '\n') fmt
      else Printf.ifprintf () fmt in
    (* the floats that change as the run goes, in one record of floats only:
       setting them allocates nothing ([ref]s of floats box a
       float at every assignment) *)
    let clk = { now = 0.; last_traj = 0.; agent_free = 0.; busy_total = 0.; last_alert = neg_infinity;
              last_falling = neg_infinity } in
    (* records *)
    let trajectory = ref [ (0., sc.start) ] in
    let collisions = ref [] and falls = ref [] and tippings = ref [] in
    let counts = Array.make 4 0 and refused = ref 0 in
    (* room for a run's position fixes at once (they are most of the
       dispatches): no copy as it grows *)
    let log = log_create (1024 + int_of_float (Float.min 1e6 (sc.duration *. s.position_rate))) and commands = ref [] and busy = ref [] in
    let outstanding : (Agent.percept * int * string * float) Seq_table.t = Seq_table.create 1024 in
    let events = ref 0 in
    let grid = make_grid world in
    mark grid sc.start.x sc.start.y p.body_radius;
    Robot.on_step robot (fun r ->
        let q = Robot.pose r in
        mark grid q.x q.y p.body_radius;
        let t = Robot.time r in
        if t -. clk.last_traj >= sc.trajectory_step then (trajectory := (t, q) :: !trajectory; clk.last_traj <- t));
    (* the sound channel *)
    let sound_scheduled = ref false in
    let schedule_sound () =
      if not !sound_scheduled then
        match Sound_queue.next_effect sound with
        | Some at -> Event_queue.add agenda at Sound; sound_scheduled := true
        | None -> () in
    (* the host object *)
    let pending_cmds = ref [] and invokes = ref 0 in
    let listening = ref false in
    let start_sources () =
      let start src rate = if rate > 0. then Event_queue.add agenda clk.now (Sample (src, 0)) in
      start Uwb s.position_rate; start Proximity s.proximity_rate; start Camera s.camera_rate;
      start Imu s.imu_rate;
      match sc.flood with
      | Some f -> Event_queue.add agenda (Float.max clk.now f.start_time) (Sample (Flood, 0))
      | None -> () in
    let host = Host.make sc.mapping
        ~enqueue:(fun c -> incr invokes; pending_cmds := c :: !pending_cmds)
        ~start_listening:(fun () ->
            incr invokes;
            if not !listening then (listening := true; tr "%.6f startListening" clk.now; start_sources ())) in
    let issue_commands at =
      (match !pending_cmds with
       | [] -> ()
       | cmds ->
         List.iter (fun c ->
             Sound_queue.enqueue sound ~now:at c;
             if trace then tr "%.6f issue %s" at (Command.to_string c)) (List.rev cmds);
         pending_cmds := []);
      schedule_sound () in
    (* the agent *)
    let agent = A.create sc.loop host in
    on_create agent;
    issue_commands 0.;
    invokes := 0;
    let agent_scheduled = ref false and agent_next = ref false in
    let wake () =
      if not !agent_scheduled then begin
        agent_scheduled := true;
        Event_queue.add agenda (Float.max clk.now clk.agent_free) Agent_work
      end in
    wake ();   (* the first iteration runs HandlePercepts' first step (R5g) *)
    let override name = List.assoc_opt name s.overrides in
    let notify ?priority (pc : Agent.percept) src =
      let name = Agent.percept_name pc in
      let priority = match priority with Some _ -> priority | None -> override name in
      match A.notify agent pc ~priority with
      | Ok seq ->
        let k = match pc with Falling -> 0 | Obstacle -> 1 | Qr_code_read _ -> 2 | Position _ -> 3 in
        counts.(k) <- counts.(k) + 1;
        let prio = match priority with Some k -> k | None -> Agent.default_priority pc in
        Seq_table.replace outstanding seq (pc, prio, src, clk.now);
        if trace then tr "%.6f notify seq=%d %s prio=%d src=%s" clk.now seq (Agent.percept_to_string pc) prio src;
        wake ()
      | Error e ->
        incr refused;
        if trace then tr "%.6f refused %s src=%s: %s" clk.now (Agent.percept_to_string pc) src e in
    (* sensor state *)
    let alert_on = ref false in
    let last_qr : (string, float) Hashtbl.t = Hashtbl.create 16 in
    let fell_unreported = ref false in
    let period = function
      | Uwb -> 1. /. s.position_rate | Proximity -> 1. /. s.proximity_rate
      | Camera -> 1. /. s.camera_rate | Imu -> 1. /. s.imu_rate
      | Flood -> (match sc.flood with Some f -> 1. /. f.rate | None -> infinity) in
    let base = function
      | Flood -> (match sc.flood with Some f -> Float.max 0. f.start_time | None -> 0.)
      | _ -> 0. in
    let sample src k =
      (match src with
       | Uwb ->
         let (x, y) = Sensors.uwb rng_uwb ~sigma:s.uwb_sigma robot in
         notify (Position (x, y)) "uwb"
       | Proximity ->
         let band = Sensors.proximity_band p (Sensors.nearest_ahead robot) in
         let near = match band with Some b -> b <= s.obstacle_band +. 1e-9 | None -> false in
         let edge = s.edge_detector && Sensors.edge_ahead robot in
         let on = near || edge in
         if on && ((not !alert_on) || clk.now -. clk.last_alert >= s.obstacle_repeat -. 1e-9) then begin
           clk.last_alert <- clk.now;
           Event_queue.add agenda (clk.now +. p.alert_latency)
             (Deliver (Obstacle, if near then "proximity" else "edge"))
         end;
         alert_on := on
       | Camera ->
         List.iter (fun (sg : Sensors.sighting) ->
             let fresh = match Hashtbl.find_opt last_qr sg.text with
               | None -> true | Some t -> clk.now -. t >= s.qr_repeat -. 1e-9 in
             if fresh then begin
               Hashtbl.replace last_qr sg.text clk.now;
               Event_queue.add agenda (clk.now +. p.camera_latency) (Deliver (Qr_code_read sg.text, "camera"))
             end) (Sensors.readable robot)
       | Imu ->
         if (Robot.tipping robot || !fell_unreported)
         && clk.now -. clk.last_falling >= s.falling_repeat -. 1e-9 then begin
           clk.last_falling <- clk.now; fell_unreported := false;
           notify Falling "imu"
         end
       | Flood ->
         (match sc.flood with
          | None -> ()
          | Some f ->
            let pc : Agent.percept = match f.percept with
              | "falling" -> Falling | "obstacle" -> Obstacle
              | "qrCodeRead" -> Qr_code_read f.text
              | _ -> let (x, y) = Sensors.uwb rng_flood ~sigma:s.uwb_sigma robot in Position (x, y) in
            notify ?priority:f.priority pc "flood"));
      let next = base src +. float_of_int (k + 1) *. period src in
      let stop = match src with Flood -> (match sc.flood with Some f -> f.end_time | None -> 0.) | _ -> infinity in
      if next < stop then Event_queue.add agenda next (Sample (src, k + 1)) in
    let work_kind : Agent.work -> string = function
      | Transfer _ -> "transfer" | Dispatch _ -> "dispatch" | Behaviour_step -> "step" | Loop _ -> "loop" in
    let agent_work () =
      (* written only when not empty already: [pending_cmds] lives in the
         major heap, where every write is a [caml_modify] *)
      (match !pending_cmds with [] -> () | _ -> pending_cmds := []);
      invokes := 0;
      match A.step agent with
      | None -> agent_scheduled := false; if trace then tr "%.6f idle" clk.now
      | Some w ->
        let cost = Agent.cost_of sc.cost w ~invokes:!invokes in
        let t_end = clk.now +. cost in
        (match w with
         | Dispatch d ->
           let (pc, prio, src, t0) = match Seq_table.find_opt outstanding d.seq with
             | Some x -> x | None -> (d.percept, d.priority, "?", clk.now) in
           Seq_table.remove outstanding d.seq;
           ignore pc;
           log_add log ~seq:d.seq ~priority:prio ~handlers:d.handlers_run ~notified:t0 ~dispatched:clk.now
             ~source:src d.percept;
           if trace then
             tr "%.6f dispatch seq=%d %s prio=%d latency=%.6f handlers=%d" clk.now d.seq
               (Agent.percept_to_string d.percept) prio (clk.now -. t0) d.handlers_run
         | Transfer { moved; _ } -> if trace && moved > 0 then tr "%.6f transfer moved=%d" clk.now moved
         | Behaviour_step -> if trace then tr "%.6f behaviour-step" clk.now
         | Loop _ -> ());
        clk.busy_total <- clk.busy_total +. cost;
        if clk.now < timeline_window then busy := { b_start = clk.now; b_end = t_end; b_kind = work_kind w } :: !busy;
        issue_commands t_end;
        clk.agent_free <- t_end;
        (* The next unit of work starts at t_end. When the agenda has nothing
           before or at t_end (an event already there at t_end was scheduled
           first, so it would go first), its event would be the next taken:
           the loop then runs it at once instead (two thirds of the
           events are agent work). The same events in the same order; only
           the agenda's numbering of later events is one lower, which keeps
           their order. *)
        if t_end <= sc.duration && Event_queue.next_time agenda > t_end then agent_next := true
        else Event_queue.add agenda t_end Agent_work in
    let robot_events evs =
      List.iter (fun (e : Robot.event) ->
          let t = Robot.time robot in
          match e with
          | Collision q -> collisions := (t, q) :: !collisions; tr "%.6f collision x=%.4f y=%.4f" t q.x q.y
          | Tipping_start q -> tippings := (t, q) :: !tippings; tr "%.6f tipping x=%.4f y=%.4f" t q.x q.y
          | Tipping_end _ -> tr "%.6f tipping-end" t
          | Fall q -> falls := (t, q) :: !falls; fell_unreported := true; tr "%.6f fall x=%.4f y=%.4f" t q.x q.y)
        evs in
    let rec loop () =
      let t = Event_queue.next_time agenda in
      if (not (Event_queue.is_empty agenda)) && t <= sc.duration then begin
        let ev = Event_queue.take agenda in
        incr events;
        (* most events find nothing happened to the robot: no closure then *)
        (match Robot.advance robot t with [] -> () | evs -> robot_events evs);
        clk.now <- t;
        (match ev with
         | Sample (src, k) -> sample src k
         | Deliver (pc, src) -> notify pc src
         | Sound ->
           sound_scheduled := false;
           (match Sound_queue.pop sound with
            | Some (c, issued, _) ->
              Robot.apply robot c;
              commands := (issued, t, c) :: !commands;
              if trace then tr "%.6f play %s" t (Command.to_string c)
            | None -> ());
           schedule_sound ()
         | Agent_work -> agent_work ());
        (* the agent's units of work that follow at once, as events taken *)
        while !agent_next do
          agent_next := false;
          let t = clk.agent_free in
          incr events;
          (match Robot.advance robot t with [] -> () | evs -> robot_events evs);
          clk.now <- t;
          agent_work ()
        done;
        loop ()
      end in
    loop ();
    robot_events (Robot.advance robot sc.duration);
    clk.now <- sc.duration;
    let pending =
      Seq_table.fold (fun seq (pc, prio, _, t0) acc -> { p_seq = seq; p_percept = pc; p_priority = prio; p_notified = t0 } :: acc)
        outstanding []
      |> List.sort (fun a b -> compare a.p_seq b.p_seq) in
    let q = Robot.pose robot in
    trajectory := (sc.duration, q) :: !trajectory;
    tr "%.6f end x=%.4f y=%.4f theta=%.4f" sc.duration q.x q.y q.theta;
    let result = {
      scenario = sc; seed; agent_name = A.name; world; end_time = sc.duration; final_pose = q;
      trajectory = List.rev !trajectory; collisions = List.rev !collisions; falls = List.rev !falls;
      tippings = List.rev !tippings;
      notified = [ ("falling", counts.(0)); ("obstacle", counts.(1)); ("qrCodeRead", counts.(2));
                   ("position", counts.(3)) ];
      refused = !refused; handled = lazy (handled_of_log log); dispatches = log; pending;
      world_map = A.world_map agent; commands = List.rev !commands; busy = List.rev !busy;
      busy_total = clk.busy_total; odometer = Robot.odometer robot; coverage = coverage grid;
      events = !events; trace = Buffer.contents buf } in
    (result, agent)
end

let run ?trace ?timeline_window (module A : Agent.AGENT) sc ~seed =
  let module S = Make (A) in
  fst (S.run ?trace ?timeline_window sc ~seed)
