let fixed d x =
  if Float.is_nan x || Float.abs x = infinity then `Null
  else `Intlit (Printf.sprintf "%.*f" d (if x = 0. then 0. else x))

let m = fixed 3
let s = fixed 6
let opt f = function Some x -> f x | None -> `Null

let variant_name = function
  | Semantics.Machine.Reference -> "reference" | Printed -> "printed" | Budgeted -> "budgeted"
  | Native -> "native"

let to_json (r : Sim.result) (mt : Metrics.t) : Yojson.Safe.t =
  let sc = r.scenario in
  `Assoc [
    ("format", `String "jadescript-ref/sim-report/1");
    ("scenario", `String sc.name);
    ("seed", `Int r.seed);
    ("agent", `String r.agent_name);
    ("loop", `String (variant_name sc.loop.variant));
    ("duration_s", s mt.duration);
    ("metrics", `Assoc [
        ("cubes_total", `Int mt.cubes_total);
        ("cubes_mapped", `Int mt.cubes_mapped);
        ("map_entries", `Int mt.map_entries);
        ("map_error_mean_m", opt m mt.map_error_mean);
        ("map_error_max_m", opt m mt.map_error_max);
        ("collisions", `Int mt.collisions);
        ("falls", `Int mt.falls);
        ("near_falls", `Int mt.near_falls);
        ("distance_m", m mt.distance);
        ("coverage", m mt.coverage);
        ("latency_max_s", s mt.latency_max);
        ("latency", `List (List.map (fun (l : Metrics.latency) ->
             `Assoc [ ("priority", `Int l.priority); ("count", `Int l.count); ("mean_s", s l.mean);
                      ("p95_s", s l.p95); ("max_s", s l.max) ]) mt.latency));
        ("notified", `Assoc (List.map (fun (k, n) -> (k, `Int n)) mt.notified));
        ("refused", `Int mt.refused);
        ("unhandled", `Int mt.unhandled);
        ("unhandled_oldest_s", s mt.unhandled_oldest);
        ("commands", `Int mt.commands);
        ("agent_utilisation", m mt.utilisation);
      ]);
    ("cubes", `List (List.map2 (fun (c : Robome.World.cube) (cm : Metrics.cube_map) ->
         `Assoc [ ("id", `String c.id); ("x", m c.cx); ("y", m c.cy); ("size_m", m c.size);
                  ("yaw_deg", m (Robome.Params.to_deg c.yaw));
                  ("faces", `List (Array.to_list (Array.map (fun t -> `String t) c.faces)));
                  ("map_entries", `Int cm.entries); ("map_error_m", opt m cm.error) ])
         (Array.to_list r.world.cubes) mt.cubes));
    ("world_map", `List (List.map (fun (x, y, t) -> `Assoc [ ("x", m x); ("y", m y); ("text", `String t) ]) r.world_map));
    ("collisions", `List (List.map (fun (t, (q : Robome.Kinematics.pose)) ->
         `Assoc [ ("t_s", s t); ("x", m q.x); ("y", m q.y) ]) r.collisions));
    ("falls", `List (List.map (fun (t, (q : Robome.Kinematics.pose)) ->
         `Assoc [ ("t_s", s t); ("x", m q.x); ("y", m q.y) ]) r.falls));
    ("final_pose", `Assoc [ ("x", m r.final_pose.x); ("y", m r.final_pose.y);
                            ("heading_deg", m (Robome.Params.to_deg r.final_pose.theta)) ]);
    ("events", `Int r.events);
  ]

let to_string r mt = Yojson.Safe.pretty_to_string (to_json r mt) ^ "\n"
