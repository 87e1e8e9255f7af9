open Robome

let escape s =
  let b = Buffer.create (String.length s) in
  String.iter (function
      | '&' -> Buffer.add_string b "&amp;" | '<' -> Buffer.add_string b "&lt;"
      | '>' -> Buffer.add_string b "&gt;" | '"' -> Buffer.add_string b "&quot;"
      | '\'' -> Buffer.add_string b "&apos;" | c -> Buffer.add_char b c) s;
  Buffer.contents b

let header b w h =
  Printf.bprintf b "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  Printf.bprintf b "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" font-family=\"sans-serif\">\n" w h w h;
  Printf.bprintf b "<rect x=\"0\" y=\"0\" width=\"%d\" height=\"%d\" fill=\"white\"/>\n" w h

let text b ?(size = 11) ?(anchor = "start") ?(fill = "black") x y s =
  Printf.bprintf b "<text x=\"%.1f\" y=\"%.1f\" font-size=\"%d\" text-anchor=\"%s\" fill=\"%s\">%s</text>\n"
    x y size anchor fill (escape s)

(* Keep at most n elements, evenly spread, first and last included. *)
let thin n l =
  let a = Array.of_list l in
  let len = Array.length a in
  if len <= n then l
  else List.init n (fun i -> a.(i * (len - 1) / (n - 1)))

let fmt_opt = function Some x -> Printf.sprintf "%.2f m" x | None -> "-"

(* ----------------------------------------------------------------- map *)

let map (r : Sim.result) (mt : Metrics.t) =
  let w = r.world in
  let scale = Float.min 90. (1100. /. w.length) in
  let ml = 40. and mtop = 60. in
  let wpx = int_of_float (2. *. ml +. w.length *. scale) in
  let hpx = int_of_float (mtop +. w.width *. scale +. 90.) in
  let sx x = ml +. x *. scale and sy y = mtop +. (w.width -. y) *. scale in
  let b = Buffer.create 65536 in
  header b wpx hpx;
  text b ~size:14 ml 20. (Printf.sprintf "%s - seed %d - agent %s - %.0f s" r.scenario.name r.seed r.agent_name r.end_time);
  text b ml 40. (Printf.sprintf "cubes mapped %d/%d, map error mean %s, collisions %d, falls %d, distance %.1f m, coverage %.0f%%"
                   mt.cubes_mapped mt.cubes_total (fmt_opt mt.map_error_mean) mt.collisions mt.falls mt.distance
                   (100. *. mt.coverage));
  (* floor *)
  Printf.bprintf b "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#f4f4f0\" stroke=\"black\" stroke-width=\"2\"/>\n"
    (sx 0.) (sy w.width) (w.length *. scale) (w.width *. scale);
  (* metre ticks *)
  for i = 0 to int_of_float w.length do
    let x = sx (float_of_int i) in
    Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#999\" stroke-width=\"1\"/>\n" x (sy 0.) x (sy 0. +. 5.);
    text b ~size:9 ~anchor:"middle" ~fill:"#666" x (sy 0. +. 15.) (Printf.sprintf "%d m" i)
  done;
  List.iter (fun (d : World.rect) ->
      Printf.bprintf b "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#d9534f\" fill-opacity=\"0.35\" stroke=\"#d9534f\"/>\n"
        (sx d.x_min) (sy d.y_max) ((d.x_max -. d.x_min) *. scale) ((d.y_max -. d.y_min) *. scale);
      text b ~size:10 ~anchor:"middle" ~fill:"#a02020" (sx ((d.x_min +. d.x_max) /. 2.)) (sy ((d.y_min +. d.y_max) /. 2.)) "drop-off")
    w.dropoffs;
  (match w.walls with
   | _ :: _ :: _ :: _ :: extra ->
     List.iter (fun (s : World.segment) ->
         Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"black\" stroke-width=\"4\"/>\n"
           (sx s.a.px) (sy s.a.py) (sx s.b.px) (sy s.b.py)) extra
   | _ -> ());
  (* cubes and their faces *)
  Array.iter (fun (c : World.cube) ->
      let pts = List.map (fun (s : World.segment) -> Printf.sprintf "%.1f,%.1f" (sx s.a.px) (sy s.a.py)) (World.cube_segments c) in
      Printf.bprintf b "<polygon points=\"%s\" fill=\"#8fb3d9\" stroke=\"#2b4c7e\" stroke-width=\"1.5\"/>\n" (String.concat " " pts);
      text b ~size:10 ~anchor:"middle" ~fill:"#2b4c7e" (sx c.cx) (sy c.cy +. 4.) c.id;
      Array.iteri (fun i t ->
          if t <> "" then begin
            let f = World.face_centre c i and n = World.face_normal c i in
            let off = 0.16 in
            text b ~size:8 ~anchor:"middle" ~fill:"#333" (sx (f.px +. off *. n.px)) (sy (f.py +. off *. n.py) +. 3.) t
          end) c.faces) w.cubes;
  (* trajectory *)
  let traj = thin 5000 r.trajectory in
  Printf.bprintf b "<polyline fill=\"none\" stroke=\"#1f5fbf\" stroke-width=\"1.5\" stroke-opacity=\"0.8\" points=\"%s\"/>\n"
    (String.concat " " (List.map (fun (_, (q : Kinematics.pose)) -> Printf.sprintf "%.1f,%.1f" (sx q.x) (sy q.y)) traj));
  let s0 = r.scenario.start in
  Printf.bprintf b "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"#2ca02c\"/>\n" (sx s0.x) (sy s0.y);
  Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#2ca02c\" stroke-width=\"2\"/>\n"
    (sx s0.x) (sy s0.y) (sx (s0.x +. 0.3 *. cos s0.theta)) (sy (s0.y +. 0.3 *. sin s0.theta));
  let q = r.final_pose in
  Printf.bprintf b "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"black\"/>\n" (sx q.x) (sy q.y);
  (* the agent's map *)
  List.iter (fun (x, y, _) ->
      Printf.bprintf b "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\" fill=\"#ff7f0e\" fill-opacity=\"0.7\"/>\n" (sx x) (sy y))
    r.world_map;
  Array.iter (fun (c : World.cube) ->
      let mine = List.filter (fun (_, _, t) -> t <> "" && Array.mem t c.faces) r.world_map in
      let n = List.length mine in
      if n > 0 then begin
        let mx = List.fold_left (fun a (x, _, _) -> a +. x) 0. mine /. float_of_int n
        and my = List.fold_left (fun a (_, y, _) -> a +. y) 0. mine /. float_of_int n in
        Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ff7f0e\" stroke-width=\"1.2\" stroke-dasharray=\"4,3\"/>\n"
          (sx mx) (sy my) (sx c.cx) (sy c.cy);
        let x = sx mx and y = sy my in
        Printf.bprintf b "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"#ff7f0e\" stroke=\"#a0500a\"/>\n"
          x (y -. 6.) (x +. 6.) y x (y +. 6.) (x -. 6.) y;
        text b ~size:9 ~fill:"#a0500a" (x +. 7.) (y -. 5.) (Printf.sprintf "%s (%d)" c.id n)
      end) w.cubes;
  List.iter (fun (_, (q : Kinematics.pose)) ->
      let x = sx q.x and y = sy q.y in
      Printf.bprintf b "<path d=\"M %.1f %.1f L %.1f %.1f M %.1f %.1f L %.1f %.1f\" stroke=\"#d62728\" stroke-width=\"2.5\"/>\n"
        (x -. 5.) (y -. 5.) (x +. 5.) (y +. 5.) (x -. 5.) (y +. 5.) (x +. 5.) (y -. 5.)) r.collisions;
  List.iter (fun (_, (q : Kinematics.pose)) ->
      Printf.bprintf b "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"9\" fill=\"none\" stroke=\"#d62728\" stroke-width=\"3\"/>\n" (sx q.x) (sy q.y);
      text b ~size:10 ~fill:"#d62728" (sx q.x +. 11.) (sy q.y) "fall") r.falls;
  (* legend *)
  let ly = mtop +. w.width *. scale +. 40. in
  let item x colour label shape =
    (match shape with
     | `Line -> Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/>\n" x (ly -. 4.) (x +. 16.) (ly -. 4.) colour
     | `Dot -> Printf.bprintf b "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n" (x +. 8.) (ly -. 4.) colour
     | `Box -> Printf.bprintf b "<rect x=\"%.1f\" y=\"%.1f\" width=\"12\" height=\"12\" fill=\"%s\"/>\n" (x +. 2.) (ly -. 10.) colour);
    text b ~size:10 (x +. 20.) ly label in
  item ml "#1f5fbf" "trajectory" `Line;
  item (ml +. 110.) "#2ca02c" "start" `Dot;
  item (ml +. 170.) "black" "end" `Dot;
  item (ml +. 220.) "#8fb3d9" "cube (QR text per face)" `Box;
  item (ml +. 390.) "#ff7f0e" "worldMap entry / mean per cube" `Dot;
  item (ml +. 600.) "#d62728" "collision / fall" `Dot;
  item (ml +. 720.) "#d9534f" "drop-off" `Box;
  Buffer.add_string b "</svg>\n";
  Buffer.contents b

(* ------------------------------------------------------------ timeline *)

let prio_colour = function
  | 10 -> "#d62728" | 8 -> "#ff7f0e" | 4 -> "#2ca02c" | 2 -> "#1f77b4" | _ -> "#9467bd"

let kind_colour = function
  | "transfer" -> "#7f7f7f" | "dispatch" -> "#1f77b4" | "step" -> "#2ca02c" | _ -> "#c7c7c7"

let timeline ?window (r : Sim.result) (mt : Metrics.t) =
  let window = match window with Some w -> Float.min w r.end_time | None -> Float.min 10. r.end_time in
  let window = if window <= 0. then 1. else window in
  let prios =
    List.sort_uniq (fun a b -> compare b a)
      ([ 10; 8; 4; 2 ] @ List.map (fun (l : Metrics.latency) -> l.priority) mt.latency
       @ List.sort_uniq compare (List.rev_map (fun (p : Sim.pending) -> p.p_priority) r.pending)) in
  let wpx = 1100 and left = 90. and right = 30. in
  let plot_w = float_of_int wpx -. left -. right in
  let row_h = 28. and top1 = 60. in
  let rows = 1 + List.length prios in
  let h1 = float_of_int rows *. row_h in
  let top2 = top1 +. h1 +. 80. and h2 = 260. in
  let hpx = int_of_float (top2 +. h2 +. 70.) in
  let b = Buffer.create 65536 in
  header b wpx hpx;
  text b ~size:14 left 20. (Printf.sprintf "Percept handling - %s - seed %d - agent %s" r.scenario.name r.seed r.agent_name);
  text b left 40. (Printf.sprintf "first %.1f s: agent work and each percept from notification (o) to dispatch (*)" window);
  let tx t = left +. t /. window *. plot_w in
  (* axis *)
  let axis_y = top1 +. h1 in
  Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"black\"/>\n" left axis_y (left +. plot_w) axis_y;
  let ticks = 10 in
  for i = 0 to ticks do
    let t = window *. float_of_int i /. float_of_int ticks in
    Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n" (tx t) top1 (tx t) axis_y;
    text b ~size:9 ~anchor:"middle" (tx t) (axis_y +. 14.) (Printf.sprintf "%.2f s" t)
  done;
  (* agent row *)
  text b ~size:10 ~anchor:"end" (left -. 6.) (top1 +. row_h /. 2. +. 4.) "agent";
  List.iter (fun (w : Sim.busy) ->
      if w.b_start < window then begin
        let x0 = tx w.b_start and x1 = tx (Float.min window w.b_end) in
        Printf.bprintf b "<rect x=\"%.2f\" y=\"%.1f\" width=\"%.2f\" height=\"%.1f\" fill=\"%s\"/>\n"
          x0 (top1 +. 6.) (Float.max 0.6 (x1 -. x0)) (row_h -. 12.) (kind_colour w.b_kind)
      end) (thin 20000 r.busy);
  (* one row per priority *)
  List.iteri (fun i prio ->
      let y = top1 +. float_of_int (i + 1) *. row_h +. row_h /. 2. in
      text b ~size:10 ~anchor:"end" (left -. 6.) (y +. 4.) (Printf.sprintf "priority %d" prio);
      Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#eee\"/>\n" left y (left +. plot_w) y;
      let col = prio_colour prio in
      let hs = List.filter (fun (h : Sim.handled) -> h.priority = prio && h.notified < window) (Lazy.force r.handled) in
      List.iter (fun (h : Sim.handled) ->
          let x0 = tx h.notified and x1 = tx (Float.min window h.dispatched) in
          Printf.bprintf b "<line x1=\"%.2f\" y1=\"%.1f\" x2=\"%.2f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/>\n" x0 y x1 y col;
          Printf.bprintf b "<circle cx=\"%.2f\" cy=\"%.1f\" r=\"2.5\" fill=\"white\" stroke=\"%s\"/>\n" x0 y col;
          if h.dispatched <= window then
            Printf.bprintf b "<circle cx=\"%.2f\" cy=\"%.1f\" r=\"2\" fill=\"%s\"/>\n" x1 y col) (thin 1500 hs);
      let ps = List.filter (fun (p : Sim.pending) -> p.p_priority = prio && p.p_notified < window) r.pending in
      List.iter (fun (p : Sim.pending) ->
          Printf.bprintf b "<line x1=\"%.2f\" y1=\"%.1f\" x2=\"%.2f\" y2=\"%.1f\" stroke=\"#d62728\" stroke-width=\"1\" stroke-opacity=\"0.5\"/>\n"
            (tx p.p_notified) (y +. 4.) (tx window) (y +. 4.)) (thin 300 ps))
    prios;
  (* latency over the whole run *)
  text b ~size:12 left (top2 -. 30.) (Printf.sprintf "latency (notification to dispatch) over the whole run, log scale; max %.3f ms"
                                        (1000. *. mt.latency_max));
  let lat_min = 1e-4 in
  let worst_pending = List.fold_left (fun m (p : Sim.pending) -> Float.max m (r.end_time -. p.p_notified)) 0. r.pending in
  let lat_max_v = Float.max 1e-2 (Float.max mt.latency_max worst_pending) in
  let decades = int_of_float (Float.ceil (log10 (lat_max_v /. lat_min))) in
  let ly l = top2 +. h2 -. (log10 (Float.max lat_min l /. lat_min) /. float_of_int decades) *. h2 in
  let t2 t = left +. t /. r.end_time *. plot_w in
  Printf.bprintf b "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"black\"/>\n" left top2 plot_w h2;
  for d = 0 to decades do
    let l = lat_min *. (10. ** float_of_int d) in
    Printf.bprintf b "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n" left (ly l) (left +. plot_w) (ly l);
    let lab = if l < 1. then Printf.sprintf "%g ms" (l *. 1000.) else Printf.sprintf "%g s" l in
    text b ~size:9 ~anchor:"end" (left -. 4.) (ly l +. 3.) lab
  done;
  for i = 0 to ticks do
    let t = r.end_time *. float_of_int i /. float_of_int ticks in
    text b ~size:9 ~anchor:"middle" (t2 t) (top2 +. h2 +. 14.) (Printf.sprintf "%.0f s" t)
  done;
  let bins = 600 in
  List.iter (fun prio ->
      let worst = Array.make bins neg_infinity and at = Array.make bins 0. in
      List.iter (fun (h : Sim.handled) ->
          if h.priority = prio then begin
            let k = min (bins - 1) (int_of_float (h.notified /. r.end_time *. float_of_int bins)) in
            let l = h.dispatched -. h.notified in
            if l > worst.(k) then (worst.(k) <- l; at.(k) <- h.notified)
          end) (Lazy.force r.handled);
      Array.iteri (fun k l ->
          if l > neg_infinity then
            Printf.bprintf b "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"2\" fill=\"%s\"/>\n" (t2 at.(k)) (ly l) (prio_colour prio)) worst)
    prios;
  List.iter (fun (p : Sim.pending) ->
      let x = t2 p.p_notified and y = ly (r.end_time -. p.p_notified) in
      Printf.bprintf b "<path d=\"M %.2f %.2f L %.2f %.2f L %.2f %.2f Z\" fill=\"#d62728\" fill-opacity=\"0.6\"/>\n"
        (x -. 3.) (y +. 2.) (x +. 3.) (y +. 2.) x (y -. 4.)) (thin 400 r.pending);
  (* legend *)
  let ly0 = top2 +. h2 +. 40. in
  let x = ref left in
  List.iter (fun prio ->
      Printf.bprintf b "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n" (!x +. 4.) (ly0 -. 4.) (prio_colour prio);
      text b ~size:10 (!x +. 12.) ly0 (Printf.sprintf "priority %d" prio);
      x := !x +. 90.) prios;
  List.iter (fun (k, lab) ->
      Printf.bprintf b "<rect x=\"%.1f\" y=\"%.1f\" width=\"10\" height=\"10\" fill=\"%s\"/>\n" !x (ly0 -. 9.) (kind_colour k);
      text b ~size:10 (!x +. 14.) ly0 lab; x := !x +. 100.)
    [ ("transfer", "transfer"); ("dispatch", "dispatch"); ("step", "behaviour step"); ("loop", "loop") ];
  Printf.bprintf b "<path d=\"M %.1f %.1f L %.1f %.1f L %.1f %.1f Z\" fill=\"#d62728\"/>\n" !x (ly0 +. 1.) (!x +. 8.) (ly0 +. 1.) (!x +. 4.) (ly0 -. 8.);
  text b ~size:10 (!x +. 12.) ly0 "never dispatched (lower bound)";
  Buffer.add_string b "</svg>\n";
  Buffer.contents b
