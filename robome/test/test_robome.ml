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
   box or circle the disc reaches (issue 17): it must answer as the test of
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
  ]
