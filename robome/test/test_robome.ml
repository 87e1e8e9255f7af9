(* Tests of the simulated RoboMe: kinematics against closed-form motion,
   the sound channel's latency, the robot's reaction to commands, contact
   and falls, and the geometry of its sensors. *)

open Robome

let eps = 1e-9
let close ?(tol = 1e-6) msg a b = Alcotest.(check (float tol)) msg a b
let p0 = Params.noiseless Params.default
let pose x y th = { Kinematics.x; y; theta = th }
let empty_world ?(length = 20.) ?(width = 10.) ?(cubes = []) ?(dropoffs = []) () =
  World.make ~length ~width ~cubes ~dropoffs ()
let cube ?(yaw = 0.) ?(size = 0.2) id x y =
  { World.id; cx = x; cy = y; size; yaw; faces = [| id ^ "-E"; id ^ "-N"; id ^ "-W"; id ^ "-S" |] }

(* ------------------------------------------------------------ kinematics *)

let test_straight () =
  let q = Kinematics.integrate (pose 1. 2. (Float.pi /. 6.)) ~v:0.5 ~omega:0. ~dt:4. in
  close "x" (1. +. 2. *. cos (Float.pi /. 6.)) q.x;
  close "y" (2. +. 2. *. sin (Float.pi /. 6.)) q.y;
  close "theta" (Float.pi /. 6.) q.theta

let test_arc_quarter () =
  (* radius 1 m, quarter circle to the left from the origin heading +x *)
  let q = Kinematics.integrate (pose 0. 0. 0.) ~v:1. ~omega:1. ~dt:(Float.pi /. 2.) in
  close "x" 1. q.x; close "y" 1. q.y; close "theta" (Float.pi /. 2.) q.theta

let test_full_circle () =
  let q = Kinematics.integrate (pose 3. 4. 1.) ~v:0.2 ~omega:(-0.4) ~dt:(2. *. Float.pi /. 0.4) in
  close "x" 3. q.x; close "y" 4. q.y; close "theta" 1. q.theta

let test_spin () =
  let q = Kinematics.integrate (pose 3. 4. 0.) ~v:0. ~omega:(Params.deg 60.) ~dt:1.5 in
  close "x" 3. q.x; close "y" 4. q.y; close "theta" (Float.pi /. 2.) q.theta

(* A QCheck property as an alcotest case, with a fixed seed. *)
let qtest ?(count = 300) name gen prop =
  Alcotest.test_case name `Quick (fun () ->
      QCheck.Test.check_exn ~rand:(Random.State.make [| 42 |]) (QCheck.Test.make ~count ~name gen prop))

let gen_motion =
  QCheck.(quad (float_range (-0.3) 0.3) (float_range (-2.) 2.) (float_range 0. 5.) (float_range 0. 5.))

let prop_composition =
  qtest "integrating dt1 then dt2 = integrating dt1 + dt2" gen_motion (fun (v, omega, d1, d2) ->
      let s = pose 0.5 (-1.) 0.3 in
      let a = Kinematics.integrate (Kinematics.integrate s ~v ~omega ~dt:d1) ~v ~omega ~dt:d2 in
      let b = Kinematics.integrate s ~v ~omega ~dt:(d1 +. d2) in
      Float.abs (a.x -. b.x) < 1e-6 && Float.abs (a.y -. b.y) < 1e-6
      && Float.abs (Kinematics.normalise (a.theta -. b.theta)) < 1e-6)

let prop_arc_radius =
  qtest "an arc stays on its circle" gen_motion (fun (v, omega, d1, _) ->
      QCheck.assume (Float.abs omega > 0.05);
      let s = pose 0. 0. 0. in
      let q = Kinematics.integrate s ~v ~omega ~dt:d1 in
      (* centre of the circle: (0, v/omega) *)
      let r = v /. omega in
      Float.abs (Float.hypot q.x (q.y -. r) -. Float.abs r) < 1e-6)

let prop_normalise =
  qtest "normalise lands in (-pi, pi] and keeps the angle" QCheck.(float_range (-100.) 100.) (fun a ->
      let n = Kinematics.normalise a in
      n > -.Float.pi -. eps && n <= Float.pi +. eps
      && Float.abs (sin n -. sin a) < 1e-9 && Float.abs (cos n -. cos a) < 1e-9)

(* ----------------------------------------------------------- sound queue *)

let test_sound_latency () =
  let q = Sound_queue.create ~duration:0.1 ~gap:0.1 in
  List.iter (Sound_queue.enqueue q ~now:0.) [ Command.Stop; Turn_left (Degrees 90); Forward 3 ];
  let effects = List.init 3 (fun _ -> match Sound_queue.pop q with Some (_, _, at) -> at | None -> nan) in
  List.iter2 (close "effect") [ 0.1; 0.3; 0.5 ] effects;
  Alcotest.(check bool) "empty" true (Sound_queue.next_effect q = None);
  (* after a silence, a command only waits for its own tone *)
  Sound_queue.enqueue q ~now:2.0 Command.Head_up;
  close "after silence" 2.1 (Option.get (Sound_queue.next_effect q));
  ignore (Sound_queue.pop q);
  (* issued during the gap: waits for the gap's end *)
  Sound_queue.enqueue q ~now:2.15 Command.Head_down;
  close "during the gap" 2.3 (Option.get (Sound_queue.next_effect q))

let test_command_strings () =
  List.iter (fun c ->
      Alcotest.(check bool) (Command.to_string c) true (Command.of_string (Command.to_string c) = Some c))
    [ Command.Stop; Forward 1; Backward 5; Turn_left (Speed 2); Turn_right (Degrees 180); Head_reset ];
  Alcotest.(check bool) "level 6 invalid" false (Command.valid (Forward 6));
  Alcotest.(check bool) "45 degrees invalid" false (Command.valid (Turn_left (Degrees 45)))

(* ----------------------------------------------------------------- robot *)

let test_forward () =
  let r = Robot.create p0 (empty_world ()) (pose 1. 5. 0.) in
  Robot.apply r (Forward 3);
  ignore (Robot.advance r 10.);
  close ~tol:1e-6 "x" (1. +. 10. *. p0.forward_speeds.(2)) (Robot.pose r).x;
  close "odometer" (10. *. p0.forward_speeds.(2)) (Robot.odometer r);
  Robot.apply r Stop;
  ignore (Robot.advance r 20.);
  close ~tol:1e-6 "stopped" (1. +. 10. *. p0.forward_speeds.(2)) (Robot.pose r).x

let test_preset_turn () =
  let r = Robot.create p0 (empty_world ()) (pose 5. 5. 0.) in
  Robot.apply r (Turn_left (Degrees 90));
  (* a forward heard during the manoeuvre waits for its end *)
  ignore (Robot.advance r 0.5);
  Robot.apply r (Forward 1);
  ignore (Robot.advance r 1.5);
  close ~tol:1e-6 "heading after the turn" (Float.pi /. 2.) (Robot.pose r).theta;
  close ~tol:1e-6 "no translation during the turn" 5. (Robot.pose r).y;
  ignore (Robot.advance r 2.5);
  close ~tol:1e-6 "then forward along +y" (5. +. p0.forward_speeds.(0)) (Robot.pose r).y;
  (* stop cancels a manoeuvre *)
  Robot.apply r (Turn_right (Degrees 180));
  ignore (Robot.advance r 3.0);
  Robot.apply r Stop;
  let th = (Robot.pose r).theta in
  ignore (Robot.advance r 10.);
  close ~tol:1e-6 "stopped mid-turn" th (Robot.pose r).theta;
  close ~tol:1e-6 "turned 30 degrees right" (Float.pi /. 2. -. Params.deg 30.) th

let test_wall_contact () =
  let r = Robot.create p0 (empty_world ~length:2. ()) (pose 1. 5. 0.) in
  Robot.apply r (Forward 5);
  let evs = Robot.advance r 30. in
  let n = List.length (List.filter (function Robot.Collision _ -> true | _ -> false) evs) in
  Alcotest.(check int) "one collision" 1 n;
  let x = (Robot.pose r).x in
  Alcotest.(check bool) "stopped at the wall" true (x <= 2. -. p0.body_radius +. 1e-9 && x > 2. -. p0.body_radius -. 0.02)

let test_fall () =
  let w = empty_world ~dropoffs:[ { World.x_min = 3.; y_min = 0.; x_max = 4.; y_max = 10. } ] () in
  let r = Robot.create p0 w (pose 1. 5. 0.) in
  Robot.apply r (Forward 5);
  let evs = Robot.advance r 60. in
  (match evs with
   | [ Tipping_start a; Fall b ] ->
     close ~tol:0.02 "tipping when the front reaches the edge" (3. -. p0.body_radius) a.x;
     close ~tol:0.02 "falls when the centre does" 3. b.x
   | _ -> Alcotest.fail "expected tipping then a fall");
  Alcotest.(check bool) "fallen" true (Robot.fallen r);
  Robot.apply r (Backward 3);
  let q = Robot.pose r in
  ignore (Robot.advance r 70.);
  close "a fallen robot does not move" q.x (Robot.pose r).x

let test_saved_by_backing () =
  let w = empty_world ~dropoffs:[ { World.x_min = 3.; y_min = 0.; x_max = 4.; y_max = 10. } ] () in
  let r = Robot.create p0 w (pose 2.5 5. 0.) in
  Robot.apply r (Forward 3);
  let evs = Robot.advance r 4.5 in
  Alcotest.(check bool) "tipping" true (Robot.tipping r && List.length evs = 1);
  Robot.apply r (Backward 3);
  let evs = Robot.advance r 6. in
  Alcotest.(check bool) "tipping ends, no fall" true
    ((not (Robot.tipping r)) && (not (Robot.fallen r)) && List.exists (function Robot.Tipping_end _ -> true | _ -> false) evs)

(* --------------------------------------------------------------- sensors *)

let at ?(cubes = []) ?(head = Command.Head_reset) x y th =
  let r = Robot.create p0 (empty_world ~cubes ()) (pose x y th) in
  Robot.apply r head;
  r

let test_proximity_bands () =
  let band d =
    (* a cube whose west face is d metres in front of the body *)
    let c = cube "A" (5. +. p0.body_radius +. d +. 0.1) 5. in
    Sensors.proximity_band p0 (Sensors.nearest_ahead (at ~cubes:[ c ] 5. 5. 0.)) in
  Alcotest.(check (option (float 1e-9))) "0.15 m -> 20 cm" (Some 0.2) (band 0.15);
  Alcotest.(check (option (float 1e-9))) "0.4 m -> 50 cm" (Some 0.5) (band 0.4);
  Alcotest.(check (option (float 1e-9))) "0.8 m -> 100 cm" (Some 1.0) (band 0.8);
  Alcotest.(check (option (float 1e-9))) "1.5 m -> nothing" None (band 1.5);
  (* outside the cone: 0.5 m ahead but 0.4 m to the side *)
  let c = cube "A" 5.7 5.5 in
  Alcotest.(check bool) "outside the cone" true (Sensors.nearest_ahead (at ~cubes:[ c ] 5. 5. 0.) = None);
  (* walls count *)
  let r = at 19.5 5. 0. in
  Alcotest.(check (option (float 1e-9))) "the end wall" (Some 0.5) (Sensors.proximity_band p0 (Sensors.nearest_ahead r))

let texts r = List.map (fun (s : Sensors.sighting) -> s.text) (Sensors.readable r)

let test_camera () =
  let c = cube "A" 6. 5. in   (* its west face at 5.9 *)
  Alcotest.(check (list string)) "facing, in range" [ "A-W" ] (texts (at ~cubes:[ c ] 5. 5. 0.));
  Alcotest.(check (list string)) "too far (1.28 m max)" [] (texts (at ~cubes:[ c ] 4.5 5. 0.));
  Alcotest.(check (list string)) "behind the camera" [] (texts (at ~cubes:[ c ] 5. 5. Float.pi));
  Alcotest.(check (list string)) "outside the horizontal field" [] (texts (at ~cubes:[ c ] 5. 5. (Params.deg 40.)));
  (* from the north-west at 45 degrees: both the west and the north face are
     seen at 45 degrees, within the 60 degree limit *)
  Alcotest.(check (list string)) "two faces at 45 degrees" [ "A-N"; "A-W" ]
    (List.sort compare (texts (at ~cubes:[ c ] 5.4 5.6 (Params.deg (-45.)))));
  (* occlusion: another cube between the camera and the face *)
  let b = cube "B" 5.7 5. ~size:0.1 in
  Alcotest.(check (list string)) "seen from 1 m" [ "A-W" ] (texts (at ~cubes:[ c ] 4.9 5. 0.));
  Alcotest.(check (list string)) "hidden by B (whose own code is too small to read)" []
    (texts (at ~cubes:[ c; b ] 4.9 5. 0.));
  (* vertical field: too close with the head level, visible with it down *)
  let r = at ~cubes:[ c ] 5.5 5. 0. in
  Alcotest.(check (list string)) "below the level view" [] (texts r);
  Alcotest.(check (list string)) "head down sees it" [ "A-W" ] (texts (at ~cubes:[ c ] ~head:Head_down 5.5 5. 0.))

let test_edge () =
  let w = empty_world ~dropoffs:[ { World.x_min = 3.; y_min = 0.; x_max = 4.; y_max = 10. } ] () in
  let r = Robot.create p0 w (pose 2.86 5. 0.) in
  Alcotest.(check bool) "edge ahead" true (Sensors.edge_ahead r);
  let r = Robot.create p0 w (pose 2.8 5. Float.pi) in
  Alcotest.(check bool) "edge behind is not seen" false (Sensors.edge_ahead r)

let test_uwb () =
  let st = Random.State.make [| 42 |] in
  let r = at 5. 5. 0. in
  let n = 20_000 in
  let within = ref 0 and sx = ref 0. in
  for _ = 1 to n do
    let (x, y) = Sensors.uwb st ~sigma:0.3 r in
    sx := !sx +. x;
    if Float.hypot (x -. 5.) (y -. 5.) < 1. then incr within
  done;
  Alcotest.(check bool) "error under 1 m in > 99% of fixes" true (float_of_int !within /. float_of_int n > 0.99);
  close ~tol:0.01 "unbiased" 5. (!sx /. float_of_int n)

let test_host () =
  let got = ref [] and listening = ref 0 in
  let h = Host.make Host.default_mapping ~enqueue:(fun c -> got := c :: !got) ~start_listening:(fun () -> incr listening) in
  List.iter (fun n -> ignore (Host.call h n)) Host.method_names;
  Alcotest.(check int) "startListening" 1 !listening;
  Alcotest.(check (list string)) "commands in call order"
    [ "stop"; "forward(3)"; "backward(3)"; "turn_left(90deg)"; "turn_right(90deg)"; "head_up"; "head_down"; "head_reset" ]
    (List.rev_map Command.to_string !got);
  Alcotest.(check bool) "unknown method" true (Result.is_error (Host.call h "callDance"))

(* ------------------------------------------------ collision broad phase *)

(* World.disc_collides tests exactly only the walls and cubes whose bounding
   box or circle the disc reaches (D35): it must answer as the test of
   every wall and cube does (the formula before the broad phase, here), on
   random discs and on discs that touch a wall or a cube's corner within a
   rounding error. *)
let brute_collides (w : World.t) x y r =
  let dist_point_segment x y (s : World.segment) =
    let vx = s.b.px -. s.a.px and vy = s.b.py -. s.a.py in
    let wx = x -. s.a.px and wy = y -. s.a.py in
    let l2 = vx *. vx +. vy *. vy in
    let t = if l2 = 0. then 0. else Float.max 0. (Float.min 1. ((wx *. vx +. wy *. vy) /. l2)) in
    let dx = wx -. t *. vx and dy = wy -. t *. vy in
    sqrt (dx *. dx +. dy *. dy) in
  List.exists (fun s -> dist_point_segment x y s < r) w.walls
  || Array.exists (fun c -> World.disc_hits_cube c x y r) w.cubes

let broad_world () =
  let p x y = { World.px = x; py = y } in
  World.make ~length:10. ~width:2.
    ~extra_walls:[ { a = p 3. 0.; b = p 3. 0.8 }; { a = p 5. 2.; b = p 5.5 1.2 }; { a = p 7. 1.; b = p 7. 1. } ]
    ~cubes:[ cube "A" 2.5 0.7; cube ~yaw:0.35 "B" 4.2 1.4; cube ~yaw:(Float.pi /. 4.) ~size:0.3 "C" 6. 0.6 ]
    ~dropoffs:[] ()

let test_broad_phase_random () =
  let w = broad_world () in
  let rng = Random.State.make [| 17 |] in
  let hits = ref 0 in
  for _ = 1 to 200_000 do
    let x = Random.State.float rng 11. -. 0.5 and y = Random.State.float rng 3. -. 0.5 in
    let r = Random.State.float rng 0.4 in
    let b = brute_collides w x y r in
    if b then incr hits;
    if World.disc_collides w x y r <> b then
      Alcotest.failf "disc (%h, %h) radius %h: broad phase %b, every wall and cube %b" x y r (not b) b
  done;
  (* both answers occur *)
  Alcotest.(check bool) "some discs collide, some do not" true (!hits > 1000 && !hits < 199_000)

let test_broad_phase_touching () =
  let w = broad_world () in
  let check x y r =
    if World.disc_collides w x y r <> brute_collides w x y r then
      Alcotest.failf "disc (%h, %h) radius %h: the broad phase differs" x y r in
  let shifts = [ -1e-9; -1e-12; -1e-15; 0.; 1e-15; 1e-12; 1e-9 ] in
  let r = 0.15 in
  (* along every wall, at distance r (plus or minus a little) on both sides,
     and round its ends *)
  List.iter (fun (s : World.segment) ->
      let vx = s.b.px -. s.a.px and vy = s.b.py -. s.a.py in
      let l = Float.max 1e-9 (sqrt (vx *. vx +. vy *. vy)) in
      let nx = -. vy /. l and ny = vx /. l in
      for k = -2 to 12 do
        let t = float_of_int k /. 10. in
        let px = s.a.px +. t *. vx and py = s.a.py +. t *. vy in
        List.iter (fun d ->
            List.iter (fun side -> check (px +. side *. (r +. d) *. nx) (py +. side *. (r +. d) *. ny) r) [ 1.; -1. ];
            List.iter (fun a -> check (s.a.px +. (r +. d) *. cos a) (s.a.py +. (r +. d) *. sin a) r;
                        check (s.b.px +. (r +. d) *. cos a) (s.b.py +. (r +. d) *. sin a) r)
              [ 0.; 0.7; 1.6; 2.5; 3.14; 4.; 5.5 ]) shifts
      done) w.walls;
  (* round every cube's corners and faces *)
  Array.iter (fun (c : World.cube) ->
      List.iter (fun (seg : World.segment) ->
          List.iter (fun d ->
              List.iter (fun a -> check (seg.a.px +. (r +. d) *. cos a) (seg.a.py +. (r +. d) *. sin a) r)
                [ 0.; 0.4; 0.785398; 1.2; 2.356; 3.9; 5.5 ]) shifts) (World.cube_segments c);
      for i = 0 to 3 do
        let fc = World.face_centre c i and n = World.face_normal c i in
        List.iter (fun d -> check (fc.px +. (r +. d) *. n.px) (fc.py +. (r +. d) *. n.py) r) shifts
      done) w.cubes

(* ------------------------------------------- faster paths = the formulas *)

(* The same float, bit for bit. *)
let same_bits a b = Int64.equal (Int64.bits_of_float a) (Int64.bits_of_float b)

(* Kinematics.integrate_cached against Kinematics.integrate, bit for bit, on
   runs of steps that share one cache as the robot's do (the heading of one
   step is the next step's), with headings at zero of both signs, at +-pi
   (where normalise wraps), and straight steps between arcs. *)
let test_integrate_cached () =
  let rng = Random.State.make [| 23 |] in
  let pick l = List.nth l (Random.State.int rng (List.length l)) in
  for _ = 1 to 2_000 do
    let t = Kinematics.trig () in
    let start = pick [ 0.; -0.; Float.pi; -.Float.pi; Random.State.float rng 7. -. 3.5 ] in
    let p = ref (pose (Random.State.float rng 10.) (Random.State.float rng 2.) start) in
    for _ = 1 to 50 do
      let v = pick [ 0.; -0.; 0.3; -0.2; Random.State.float rng 1. -. 0.5 ] in
      let omega = pick [ 0.; -0.; 1e-13; 0.8; -1.5; Random.State.float rng 4. -. 2. ] in
      let dt = pick [ 0.01; 0.004; Random.State.float rng 0.02 ] in
      let a = Kinematics.integrate !p ~v ~omega ~dt and b = Kinematics.integrate_cached t !p ~v ~omega ~dt in
      if not (same_bits a.x b.x && same_bits a.y b.y && same_bits a.theta b.theta) then
        Alcotest.failf "pose (%h, %h, %h), v %h, omega %h, dt %h: (%h, %h, %h) cached, (%h, %h, %h) not"
          !p.x !p.y !p.theta v omega dt b.x b.y b.theta a.x a.y a.theta;
      (* sometimes a heading of the other zero, as a blocked step may keep *)
      p := if Random.State.int rng 10 = 0 then { a with theta = pick [ 0.; -0. ] } else a;
      if not (same_bits (Kinematics.sin_of t !p.theta) (sin !p.theta)
              && same_bits (Kinematics.cos_of t !p.theta) (cos !p.theta)) then
        Alcotest.failf "sin/cos of %h from the cache differ" !p.theta
    done
  done

(* World.clearance, as Robot uses it to skip disc_collides: a disc of radius
   r whose centre is less than clearance - r - margin from the place where
   the clearance was measured collides with nothing. Random places, and
   discs placed at the edge of that room, in the world of the broad-phase
   tests (walls inside the corridor, turned cubes, a wall of length 0). *)
let test_clearance () =
  let w = broad_world () in
  let rng = Random.State.make [| 29 |] in
  let skipped = ref 0 in
  for _ = 1 to 100_000 do
    let ax = Random.State.float rng 11. -. 0.5 and ay = Random.State.float rng 3. -. 0.5 in
    let room = World.clearance w ax ay in
    let r = Random.State.float rng 0.3 in
    let reach = room -. r -. World.margin in
    if reach > 0. then begin
      (* a point strictly inside the room, close to its edge most times *)
      let a = Random.State.float rng (2. *. Float.pi) in
      let d = reach *. (if Random.State.bool rng then 1. -. Random.State.float rng 1e-6 else Random.State.float rng 1.) in
      let x = ax +. d *. cos a and y = ay +. d *. sin a in
      if sqrt ((x -. ax) *. (x -. ax) +. (y -. ay) *. (y -. ay)) < reach then begin
        incr skipped;
        if brute_collides w x y r then
          Alcotest.failf "room %h at (%h, %h): the disc (%h, %h) radius %h collides" room ax ay x y r
      end
    end
  done;
  Alcotest.(check bool) "many discs skipped" true (!skipped > 10_000)

(* The robot's run against the formulas its fast physics step replaced:
   after every step, the pose is Kinematics.integrate of the last one, or
   that pose turned only when World.disc_collides says the end overlaps (the
   wheels spin). Drives with drift (every step an arc) into the walls and
   cubes of the broad-phase world, bit for bit. *)
let test_robot_as_formulas () =
  let w = broad_world () in
  let p = { Params.default with speed_noise = 0.1; drift = 0.3 } in
  let blocked = ref 0 and steps = ref 0 in
  List.iter (fun (seed, x, y, th) ->
      let r = Robot.create ~rng:(Random.State.make [| seed |]) p w (pose x y th) in
      let last = ref (Robot.pose r) and last_t = ref 0. and target = ref 0. in
      Robot.on_step r (fun r ->
          let (v, omega) = match Robot.motion r with
            | Drive { v; omega } -> (v, omega) | Manoeuvre { omega; _ } -> (0., omega) | Halted -> (0., 0.) in
          (* the step Robot.advance takes: the physics step, or what is left *)
          let dt = Float.min 0.01 (!target -. !last_t) in
          let q = Kinematics.integrate !last ~v ~omega ~dt in
          let hit = v <> 0. && World.disc_collides w q.x q.y p.body_radius in
          let expected = if hit then { !last with theta = q.theta } else q in
          let got = Robot.pose r in
          incr steps; if hit then incr blocked;
          if not (same_bits got.x expected.x && same_bits got.y expected.y && same_bits got.theta expected.theta) then
            Alcotest.failf "seed %d, t = %h: (%h, %h, %h), the formulas (%h, %h, %h)" seed (Robot.time r)
              got.x got.y got.theta expected.x expected.y expected.theta;
          last := got; last_t := Robot.time r);
      List.iteri (fun i c ->
          Robot.apply r c;
          (* a step shorter than the physics step now and then *)
          target := float_of_int (i + 1) *. 6. +. 0.0037;
          ignore (Robot.advance r !target))
        [ Command.Forward 3; Command.Backward 2; Command.Forward 3; Command.Turn_left (Command.Speed 1);
          Command.Forward 3; Command.Backward 3; Command.Forward 2 ])
    [ (1, 1., 1., 0.3); (2, 2.5, 1.6, -0.4); (3, 5.6, 0.4, 2.9); (4, 9.2, 1.7, 0.) ];
  Alcotest.(check bool) (Printf.sprintf "blocked steps (%d of %d)" !blocked !steps) true (!blocked > 100)

let test_ray_distance () =
  let w = broad_world () in
  let rng = Random.State.make [| 31 |] in
  let hits = ref 0 in
  for _ = 1 to 100_000 do
    let x = Random.State.float rng 10. and y = Random.State.float rng 2. in
    let a = Random.State.float rng 7. -. 3.5 and max = Random.State.float rng 3. in
    let d = World.ray_distance w x y a ~max in
    match World.ray w x y a ~max with
    | Some e -> incr hits; if not (same_bits d e) then Alcotest.failf "ray (%h, %h, %h) max %h: %h, not %h" x y a max d e
    | None -> if d <> infinity then Alcotest.failf "ray (%h, %h, %h) max %h: %h, not none" x y a max d
  done;
  Alcotest.(check bool) "many hits" true (!hits > 10_000)

let test_sight_blocked () =
  let w = broad_world () in
  let rng = Random.State.make [| 37 |] in
  let blocked = ref 0 in
  let pt () = { World.px = Random.State.float rng 8. +. 1.; py = Random.State.float rng 2. } in
  (* a point inside a cube's footprint *)
  let inside () =
    let c = w.cubes.(Random.State.int rng (Array.length w.cubes)) in
    let u = (Random.State.float rng 0.9 -. 0.45) *. c.size and v = (Random.State.float rng 0.9 -. 0.45) *. c.size in
    { World.px = c.cx +. u *. cos c.yaw -. v *. sin c.yaw; py = c.cy +. u *. sin c.yaw +. v *. cos c.yaw } in
  for _ = 1 to 100_000 do
    (* ends anywhere, inside a cube, or at a cube's face centre as the
       camera's are *)
    let j = Random.State.int rng (Array.length w.cubes) in
    let b = match Random.State.int rng 3 with
      | 0 -> pt () | 1 -> inside () | _ -> World.face_centre w.cubes.(j) (Random.State.int rng 4) in
    let a = if Random.State.int rng 4 = 0 then inside () else pt () in
    (* sometimes both ends in the same cube: no side crossed *)
    let a = if Random.State.int rng 8 = 0 then { World.px = b.px +. 0.001; py = b.py } else a in
    let s = { World.a; b } in
    let expected = Array.exists (fun (o : World.cube) -> o != w.cubes.(j) && World.segment_hits_cube s o) w.cubes in
    if expected then incr blocked;
    if World.sight_blocked w s ~except:j <> expected then
      Alcotest.failf "segment (%h, %h)-(%h, %h) but cube %d: %b" s.a.px s.a.py s.b.px s.b.py j (not expected)
  done;
  Array.iteri (fun j (c : World.cube) ->
      for i = 0 to 3 do
        let f = World.face_centre c i and f' = World.face_centre_of w j i in
        let n = World.face_normal c i and n' = World.face_normal_of w j i in
        if not (same_bits f.px f'.px && same_bits f.py f'.py && same_bits n.px n'.px && same_bits n.py n'.py) then
          Alcotest.failf "face %d of cube %d computed once differs" i j
      done) w.cubes;
  Alcotest.(check bool) "many blocked" true (!blocked > 5_000)

let () =
  Alcotest.run "robome" [
    ("kinematics", [
        Alcotest.test_case "straight line" `Quick test_straight;
        Alcotest.test_case "quarter arc" `Quick test_arc_quarter;
        Alcotest.test_case "full circle" `Quick test_full_circle;
        Alcotest.test_case "turn on the spot" `Quick test_spin;
        prop_composition; prop_arc_radius; prop_normalise ]);
    ("commands", [
        Alcotest.test_case "sound channel latency" `Quick test_sound_latency;
        Alcotest.test_case "names and validity" `Quick test_command_strings;
        Alcotest.test_case "host object" `Quick test_host ]);
    ("robot", [
        Alcotest.test_case "forward and stop" `Quick test_forward;
        Alcotest.test_case "preset turn, waiting and stop" `Quick test_preset_turn;
        Alcotest.test_case "wall contact" `Quick test_wall_contact;
        Alcotest.test_case "tipping and falling" `Quick test_fall;
        Alcotest.test_case "backing off the edge" `Quick test_saved_by_backing ]);
    ("sensors", [
        Alcotest.test_case "proximity bands and cone" `Quick test_proximity_bands;
        Alcotest.test_case "camera: range, fields of view, facing, occlusion" `Quick test_camera;
        Alcotest.test_case "edge detector" `Quick test_edge;
        Alcotest.test_case "UWB error" `Quick test_uwb ]);
    ("broad phase", [
        Alcotest.test_case "random discs: as testing every wall and cube" `Quick test_broad_phase_random;
        Alcotest.test_case "touching discs: as testing every wall and cube" `Quick test_broad_phase_touching ]);
    ("faster paths", [
        Alcotest.test_case "integrate with sin/cos remembered = integrate, bit for bit" `Quick test_integrate_cached;
        Alcotest.test_case "discs within the clearance collide with nothing" `Quick test_clearance;
        Alcotest.test_case "the robot's steps = integrate and disc_collides, bit for bit" `Quick test_robot_as_formulas;
        Alcotest.test_case "ray_distance = ray" `Quick test_ray_distance;
        Alcotest.test_case "sight_blocked and the faces computed once = the formulas" `Quick test_sight_blocked ]);
  ]
