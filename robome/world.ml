type point = { px : float; py : float }
type segment = { a : point; b : point }

type cube = {
  id : string;
  cx : float;
  cy : float;
  size : float;
  yaw : float;
  faces : string array;
}

type rect = { x_min : float; y_min : float; x_max : float; y_max : float }

(* The broad phase of [disc_collides]: for wall i, its bounding box at
   [wall_box.(4i) .. (4i+3)] (x_min, y_min, x_max, y_max); for cube j, the
   radius of the circle about its centre that holds its footprint (half its
   diagonal). *)
type broad = { walls_a : segment array; wall_box : float array; cube_reach : float array;
               cube_sides : segment list array; (* cube_segments of each cube, for ray *)
               cube_cos : float array; cube_sin : float array;   (* of each cube's yaw *)
               face_c : point array array; face_n : point array array
               (* face_centre and face_normal of each face of each cube *) }

type t = {
  length : float;
  width : float;
  walls : segment list;
  cubes : cube array;
  dropoffs : rect list;
  broad : broad;
}

let pt px py = { px; py }

let broad_of walls cubes =
  let walls_a = Array.of_list walls in
  let wall_box = Array.make (4 * Array.length walls_a) 0. in
  Array.iteri (fun i s ->
      wall_box.(4 * i) <- Float.min s.a.px s.b.px;
      wall_box.(4 * i + 1) <- Float.min s.a.py s.b.py;
      wall_box.(4 * i + 2) <- Float.max s.a.px s.b.px;
      wall_box.(4 * i + 3) <- Float.max s.a.py s.b.py) walls_a;
  { walls_a; wall_box; cube_reach = Array.map (fun c -> c.size *. sqrt 2. /. 2.) cubes; cube_sides = [||];
    cube_cos = [||]; cube_sin = [||]; face_c = [||]; face_n = [||] }

(* The cube's local axes: face i has its normal at yaw + i * 90 degrees. *)
let face_normal c i =
  let a = c.yaw +. float_of_int i *. Float.pi /. 2. in
  pt (cos a) (sin a)

let face_centre c i =
  let n = face_normal c i in
  let h = c.size /. 2. in
  pt (c.cx +. h *. n.px) (c.cy +. h *. n.py)

let corners c =
  let h = c.size /. 2. in
  let co = cos c.yaw and si = sin c.yaw in
  List.map (fun (u, v) -> pt (c.cx +. u *. co -. v *. si) (c.cy +. u *. si +. v *. co))
    [ (h, h); (-.h, h); (-.h, -.h); (h, -.h) ]

let cube_segments c =
  match corners c with
  | [ p1; p2; p3; p4 ] -> [ { a = p1; b = p2 }; { a = p2; b = p3 }; { a = p3; b = p4 }; { a = p4; b = p1 } ]
  | _ -> assert false

let make ~length ~width ?(extra_walls = []) ~cubes ~dropoffs () =
  let c00 = pt 0. 0. and c10 = pt length 0. and c11 = pt length width and c01 = pt 0. width in
  let outer = [ { a = c00; b = c10 }; { a = c10; b = c11 }; { a = c11; b = c01 }; { a = c01; b = c00 } ] in
  let walls = outer @ extra_walls and cubes = Array.of_list cubes in
  { length; width; walls; cubes; dropoffs;
    broad = { (broad_of walls cubes) with
              cube_sides = Array.map cube_segments cubes;
              cube_cos = Array.map (fun c -> cos c.yaw) cubes;
              cube_sin = Array.map (fun c -> sin c.yaw) cubes;
              face_c = Array.map (fun c -> Array.mapi (fun i _ -> face_centre c i) c.faces) cubes;
              face_n = Array.map (fun c -> Array.mapi (fun i _ -> face_normal c i) c.faces) cubes } }

let face_centre_of w j i = w.broad.face_c.(j).(i)
let face_normal_of w j i = w.broad.face_n.(j).(i)

let in_rect r x y = x >= r.x_min && x <= r.x_max && y >= r.y_min && y <= r.y_max

(* a loop rather than List.exists: no closure over x and y at every physics step *)
let rec over_any rs x y = match rs with [] -> false | r :: rest -> in_rect r x y || over_any rest x y

let over_dropoff w x y = over_any w.dropoffs x y

(* Coordinates of a point in the cube's frame. *)
let local c x y =
  let dx = x -. c.cx and dy = y -. c.cy in
  let co = cos c.yaw and si = sin c.yaw in
  (dx *. co +. dy *. si, -.dx *. si +. dy *. co)

let in_cube c x y =
  let (u, v) = local c x y in
  let h = c.size /. 2. in
  Float.abs u <= h && Float.abs v <= h

let disc_hits_cube c x y r =
  let (u, v) = local c x y in
  let h = c.size /. 2. in
  let cu = Float.max (-.h) (Float.min h u) and cv = Float.max (-.h) (Float.min h v) in
  let du = u -. cu and dv = v -. cv in
  du *. du +. dv *. dv < r *. r

let dist_point_segment x y s =
  let vx = s.b.px -. s.a.px and vy = s.b.py -. s.a.py in
  let wx = x -. s.a.px and wy = y -. s.a.py in
  let l2 = vx *. vx +. vy *. vy in
  let t = if l2 = 0. then 0. else Float.max 0. (Float.min 1. ((wx *. vx +. wy *. vy) /. l2)) in
  let dx = wx -. t *. vx and dy = wy -. t *. vy in
  sqrt (dx *. dx +. dy *. dy)

(* The exact tests (the distance to a wall below r, the disc over a cube's
   footprint) run only on the walls and cubes the disc may reach: a wall
   whose bounding box is farther than r along x or y, a cube whose centre is
   farther than r plus half its diagonal, is at least that far from the disc's
   centre, so the exact test would say no. A margin of a micrometre keeps
   that true of the computed distances too (their rounding errors are some
   1e-15 m): the answer is the same as testing everything, bit for bit. *)
let margin = 1e-6

let disc_collides w x y r =
  let b = w.broad in
  let reach = r +. margin in
  let hit = ref false and i = ref 0 in
  let n = Array.length b.walls_a in
  while not !hit && !i < n do
    let k = 4 * !i in
    if x > Array.unsafe_get b.wall_box k -. reach && x < Array.unsafe_get b.wall_box (k + 2) +. reach
       && y > Array.unsafe_get b.wall_box (k + 1) -. reach && y < Array.unsafe_get b.wall_box (k + 3) +. reach
       && dist_point_segment x y (Array.unsafe_get b.walls_a !i) < r
    then hit := true;
    incr i
  done;
  let j = ref 0 and m = Array.length w.cubes in
  while not !hit && !j < m do
    let c = Array.unsafe_get w.cubes !j in
    let dx = x -. c.cx and dy = y -. c.cy and d = reach +. Array.unsafe_get b.cube_reach !j in
    if dx *. dx +. dy *. dy < d *. d && disc_hits_cube c x y r then hit := true;
    incr j
  done;
  !hit

(* A lower bound of the distance from (x, y) to every wall and cube: the
   exact distance to each wall, and to each cube the distance to its centre
   less half its diagonal. *)
let clearance w x y =
  let b = w.broad in
  let d = ref infinity in
  for i = 0 to Array.length b.walls_a - 1 do
    let e = dist_point_segment x y (Array.unsafe_get b.walls_a i) in
    if e < !d then d := e
  done;
  for j = 0 to Array.length w.cubes - 1 do
    let c = Array.unsafe_get w.cubes j in
    let dx = x -. c.cx and dy = y -. c.cy in
    let e = sqrt (dx *. dx +. dy *. dy) -. Array.unsafe_get b.cube_reach j in
    if e < !d then d := e
  done;
  !d

(* Intersection of the ray (o + t d, t >= 0) with a segment: the t, if any. *)
let ray_segment ox oy dx dy s =
  let ex = s.b.px -. s.a.px and ey = s.b.py -. s.a.py in
  let den = dx *. ey -. dy *. ex in
  if Float.abs den < 1e-12 then None
  else
    let ax = s.a.px -. ox and ay = s.a.py -. oy in
    let t = (ax *. ey -. ay *. ex) /. den in
    let u = (ax *. dy -. ay *. dx) /. den in
    if t >= 0. && u >= 0. && u <= 1. then Some t else None

let ray w x y angle ~max =
  let dx = cos angle and dy = sin angle in
  let best = ref None in
  let consider s =
    match ray_segment x y dx dy s with
    | Some t when t <= max -> (match !best with Some b when b <= t -> () | _ -> best := Some t)
    | _ -> () in
  List.iter consider w.walls;
  Array.iteri (fun j c ->
      (* cheap reject: the cube is farther than max plus its half diagonal *)
      let ddx = c.cx -. x and ddy = c.cy -. y in
      let reach = max +. c.size in
      if ddx *. ddx +. ddy *. ddy <= reach *. reach then List.iter consider w.broad.cube_sides.(j))
    w.cubes;
  !best

(* The earlier of [best] and the hit of the ray on [s] if it is at most
   [max]: the test of [ray_segment], without an option. *)
let closer ox oy dx dy s max best =
  let ex = s.b.px -. s.a.px and ey = s.b.py -. s.a.py in
  let den = dx *. ey -. dy *. ex in
  if Float.abs den < 1e-12 then best
  else begin
    let ax = s.a.px -. ox and ay = s.a.py -. oy in
    let t = (ax *. ey -. ay *. ex) /. den in
    let u = (ax *. dy -. ay *. dx) /. den in
    if t >= 0. && u >= 0. && u <= 1. && t <= max && t < best then t else best
  end [@@inline]

let rec closer_in ox oy dx dy sides max best =
  match sides with
  | [] -> best
  | s :: rest -> closer_in ox oy dx dy rest max (closer ox oy dx dy s max best)

let ray_distance w x y angle ~max =
  let dx = cos angle and dy = sin angle in
  let b = w.broad in
  let best = ref infinity in
  for i = 0 to Array.length b.walls_a - 1 do
    best := closer x y dx dy (Array.unsafe_get b.walls_a i) max !best
  done;
  for j = 0 to Array.length w.cubes - 1 do
    let c = Array.unsafe_get w.cubes j in
    let ddx = c.cx -. x and ddy = c.cy -. y in
    let reach = max +. c.size in
    if ddx *. ddx +. ddy *. ddy <= reach *. reach then
      best := closer_in x y dx dy (Array.unsafe_get b.cube_sides j) max !best
  done;
  !best

let orient p q r = (q.px -. p.px) *. (r.py -. p.py) -. (q.py -. p.py) *. (r.px -. p.px)

let segments_cross s1 s2 =
  let d1 = orient s2.a s2.b s1.a and d2 = orient s2.a s2.b s1.b in
  let d3 = orient s1.a s1.b s2.a and d4 = orient s1.a s1.b s2.b in
  ((d1 > 0. && d2 < 0.) || (d1 < 0. && d2 > 0.)) && ((d3 > 0. && d4 < 0.) || (d3 < 0. && d4 > 0.))

let segment_hits_cube s c =
  in_cube c s.a.px s.a.py || in_cube c s.b.px s.b.py
  || List.exists (segments_cross s) (cube_segments c)

let segment_crosses_wall w s =
  match w.walls with
  | _ :: _ :: _ :: _ :: extra -> List.exists (segments_cross s) extra
  | _ -> false

(* [in_cube c x y] for cube [j] = c, with the cosine and sine of its yaw
   computed once ([local]'s formulas) *)
let in_cube_at b j c x y =
  let dx = x -. c.cx and dy = y -. c.cy in
  let co = Array.unsafe_get b.cube_cos j and si = Array.unsafe_get b.cube_sin j in
  let u = dx *. co +. dy *. si and v = -.dx *. si +. dy *. co in
  let h = c.size /. 2. in
  Float.abs u <= h && Float.abs v <= h

let rec crosses_any s = function [] -> false | side :: rest -> segments_cross s side || crosses_any s rest

let sight_blocked w s ~except =
  let b = w.broad in
  let rec go j =
    j < Array.length w.cubes
    && ((j <> except
         && (let c = Array.unsafe_get w.cubes j in
             in_cube_at b j c s.a.px s.a.py || in_cube_at b j c s.b.px s.b.py
             || crosses_any s (Array.unsafe_get b.cube_sides j)))
        || go (j + 1)) in
  go 0
