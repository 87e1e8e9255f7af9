let nearest_ahead r =
  let p = Robot.params r and q = Robot.pose r in
  let nb = Array.length p.proximity_bands in
  let max = p.proximity_bands.(nb - 1) in
  let fx = q.x +. p.body_radius *. cos q.theta and fy = q.y +. p.body_radius *. sin q.theta in
  let best = ref infinity in
  for i = -2 to 2 do
    let a = q.theta +. float_of_int i *. p.proximity_half_angle /. 2. in
    let d = World.ray_distance (Robot.world r) fx fy a ~max in
    if d < !best then best := d
  done;
  if !best = infinity then None else Some !best

let proximity_band (p : Params.t) = function
  | None -> None
  | Some d -> Array.fold_right (fun b acc -> if d <= b then Some b else acc) p.proximity_bands None

let edge_ahead r =
  let p = Robot.params r and q = Robot.pose r in
  let d = p.body_radius +. p.edge_lookahead in
  World.over_dropoff (Robot.world r) (q.x +. d *. cos q.theta) (q.y +. d *. sin q.theta)

let gaussian = Robot.gaussian

let uwb st ~sigma r =
  let q = Robot.pose r in
  let nx = gaussian st and ny = gaussian st in
  (q.x +. sigma *. nx, q.y +. sigma *. ny)

type sighting = { cube : int; face : int; text : string; distance : float }

let readable r =
  if Robot.fallen r then []
  else begin
    let p = Robot.params r and q = Robot.pose r and w = Robot.world r in
    let pitch = Robot.head_pitch r in
    let cam = { World.px = q.x; py = q.y } in
    let out = ref [] in
    (* loops over the indices, the faces' centres and normals and the cubes'
       sides computed once by World.make (D35) *)
    for ci = 0 to Array.length w.cubes - 1 do
      let c = w.cubes.(ci) in
      let dcx = c.cx -. q.x and dcy = c.cy -. q.y in
      let reach = p.qr_range_factor *. c.size *. p.qr_fraction +. c.size in
      if dcx *. dcx +. dcy *. dcy <= reach *. reach then
        for fi = 0 to Array.length c.faces - 1 do
          let text = c.faces.(fi) in
          if text <> "" then begin
            let f = World.face_centre_of w ci fi and n = World.face_normal_of w ci fi in
            let dx = f.px -. q.x and dy = f.py -. q.y in
            let d = sqrt (dx *. dx +. dy *. dy) in
            let qr_side = c.size *. p.qr_fraction in
            let bearing = Kinematics.normalise (atan2 dy dx -. q.theta) in
            let elevation = atan2 (c.size /. 2. -. p.camera_height) d in
            (* the face looks at the camera: cos of the angle between its
               normal and the direction from the face to the camera *)
            let facing = if d = 0. then -1. else (-.dx *. n.px -. dy *. n.py) /. d in
            let sight = { World.a = cam; b = f } in
            if d >= p.camera_min_range && d <= p.qr_range_factor *. qr_side
               && Float.abs bearing <= p.camera_hfov /. 2.
               && Float.abs (elevation -. pitch) <= p.camera_vfov /. 2.
               && facing >= cos p.qr_max_view_angle
               && not (World.segment_crosses_wall w sight)
               && not (World.sight_blocked w sight ~except:ci)
            then out := { cube = ci; face = fi; text; distance = d } :: !out
          end
        done
    done;
    List.rev !out
  end
