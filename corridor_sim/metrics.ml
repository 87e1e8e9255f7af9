type latency = { priority : int; count : int; mean : float; p95 : float; max : float }
type cube_map = { cube : string; entries : int; error : float option }

type t = {
  duration : float;
  cubes_total : int;
  cubes_mapped : int;
  map_entries : int;
  map_error_mean : float option;
  map_error_max : float option;
  cubes : cube_map list;
  collisions : int;
  falls : int;
  near_falls : int;
  distance : float;
  coverage : float;
  latency : latency list;
  latency_max : float;
  notified : (string * int) list;
  refused : int;
  unhandled : int;
  unhandled_oldest : float;
  commands : int;
  utilisation : float;
}

let percentile sorted q =
  let n = Array.length sorted in
  if n = 0 then 0. else sorted.(min (n - 1) (int_of_float (Float.ceil (q *. float_of_int n)) - 1 |> max 0))

(* Merge [s.(lo .. mid-1)] and [s.(mid .. hi-1)], both sorted, into
   [d.(lo .. hi-1)]; on a tie the left one first (stable). *)
let merge (s : float array) lo mid hi (d : float array) =
  let i = ref lo and j = ref mid in
  for k = lo to hi - 1 do
    if !i < mid && (!j >= hi || Float.compare (Array.unsafe_get s !i) (Array.unsafe_get s !j) <= 0) then begin
      Array.unsafe_set d k (Array.unsafe_get s !i); incr i
    end else begin
      Array.unsafe_set d k (Array.unsafe_get s !j); incr j
    end
  done

(* A natural merge sort on a float array: the runs already in order (a
   run's latencies come in some forty of them) are found first,
   then merged two by two, from one array into the other, until one is left.
   [bounds.(0 .. runs)] holds where each run starts, and n. *)
let sort_floats (a : float array) =
  let n = Array.length a in
  if n > 1 then begin
    let bounds = ref (Array.make (n + 1) 0) and runs = ref 0 in
    for i = 1 to n - 1 do
      if Float.compare (Array.unsafe_get a (i - 1)) (Array.unsafe_get a i) > 0 then begin
        incr runs; !bounds.(!runs) <- i
      end
    done;
    incr runs; !bounds.(!runs) <- n;
    let src = ref a and dst = ref (Array.make n 0.) and spare = ref (Array.make (n + 1) 0) in
    while !runs > 1 do
      let b = !bounds and nb = !spare and s = !src and d = !dst in
      let k = ref 0 and m = ref 0 in
      (* runs 2k and 2k+1 into one; an odd last run is copied *)
      while !k < !runs do
        let lo = b.(!k) in
        let mid = b.(!k + 1) in
        let hi = if !k + 2 <= !runs then b.(!k + 2) else mid in
        merge s lo mid hi d;
        nb.(!m) <- lo;
        incr m;
        k := !k + 2
      done;
      nb.(!m) <- n;
      runs := !m;
      spare := b; bounds := nb;
      src := d; dst := s
    done;
    if !src != a then Array.blit !src 0 a 0 n
  end

(* Loops over the dispatched percepts without a closure (they
   are some 15,000 in a run). *)
let rec mem_int (x : int) = function [] -> false | y :: rest -> x = y || mem_int x rest

(* The priorities present, and per priority the latencies in dispatch
   order, read from the run's columns (Sim.dispatch_log): no record, no
   closure, no boxed float per dispatch. *)
let priorities (l : Sim.dispatch_log) =
  let acc = ref [] in
  for i = 0 to l.d_n - 1 do
    let p = Array.unsafe_get l.d_priority i in
    if not (mem_int p !acc) then acc := p :: !acc
  done;
  !acc

let count_prio prio (l : Sim.dispatch_log) =
  let n = ref 0 in
  for i = 0 to l.d_n - 1 do if Array.unsafe_get l.d_priority i = prio then incr n done;
  !n

let fill_prio prio (a : float array) (l : Sim.dispatch_log) =
  let k = ref 0 in
  for i = 0 to l.d_n - 1 do
    if Array.unsafe_get l.d_priority i = prio then begin
      Array.unsafe_set a !k (Array.unsafe_get l.d_dispatched i -. Array.unsafe_get l.d_notified i);
      incr k
    end
  done

(* the sum from the first to the last, as Array.fold_left ( +. ) 0. *)
let sum (a : float array) =
  let s = ref 0. in
  for i = 0 to Array.length a - 1 do s := !s +. Array.unsafe_get a i done;
  !s

let of_result (r : Sim.result) =
  let cubes = Array.to_list r.world.cubes |> List.map (fun (c : Robome.World.cube) ->
      let mine = List.filter (fun (_, _, s) -> s <> "" && Array.mem s c.faces) r.world_map in
      let n = List.length mine in
      let error =
        if n = 0 then None
        else
          let sx = List.fold_left (fun a (x, _, _) -> a +. x) 0. mine
          and sy = List.fold_left (fun a (_, y, _) -> a +. y) 0. mine in
          let mx = sx /. float_of_int n and my = sy /. float_of_int n in
          Some (Float.hypot (mx -. c.cx) (my -. c.cy)) in
      { cube = c.id; entries = n; error }) in
  let errors = List.filter_map (fun c -> c.error) cubes in
  let prios = List.sort (fun a b -> Int.compare b a) (priorities r.dispatches) in
  let latency = List.map (fun prio ->
      let n = count_prio prio r.dispatches in
      let a = Array.make n 0. in
      fill_prio prio a r.dispatches;
      (* sorted, for the mean is summed in increasing order (D35: the
         order of Array.stable_sort Float.compare, without boxing a float
         per comparison) *)
      sort_floats a;
      { priority = prio; count = n;
        mean = sum a /. float_of_int (max 1 n);
        p95 = percentile a 0.95; max = (if n = 0 then 0. else a.(n - 1)) }) prios in
  let falls = List.length r.falls in
  { duration = r.end_time;
    cubes_total = Array.length r.world.cubes;
    cubes_mapped = List.length errors;
    map_entries = List.length r.world_map;
    map_error_mean = (match errors with [] -> None
                                       | l -> Some (List.fold_left ( +. ) 0. l /. float_of_int (List.length l)));
    map_error_max = (match errors with [] -> None | l -> Some (List.fold_left Float.max 0. l));
    cubes;
    collisions = List.length r.collisions;
    falls;
    near_falls = max 0 (List.length r.tippings - falls);
    distance = r.odometer;
    coverage = r.coverage;
    latency;
    latency_max = List.fold_left (fun m (l : latency) -> Float.max m l.max) 0. latency;
    notified = r.notified;
    refused = r.refused;
    unhandled = List.length r.pending;
    unhandled_oldest = List.fold_left (fun m (p : Sim.pending) -> Float.max m (r.end_time -. p.p_notified)) 0. r.pending;
    commands = List.length r.commands;
    utilisation = (if r.end_time > 0. then r.busy_total /. r.end_time else 0.) }

let lat prio m = match List.find_opt (fun l -> l.priority = prio) m.latency with
  | Some l -> l.max | None -> nan

let opt = function Some x -> x | None -> nan

let summary_fields = [
  ("cubes mapped", fun m -> float_of_int m.cubes_mapped);
  ("map error mean (m)", fun m -> opt m.map_error_mean);
  ("map error max (m)", fun m -> opt m.map_error_max);
  ("collisions", fun m -> float_of_int m.collisions);
  ("falls", fun m -> float_of_int m.falls);
  ("near falls", fun m -> float_of_int m.near_falls);
  ("distance (m)", fun m -> m.distance);
  ("coverage", fun m -> m.coverage);
  ("latency max p10 (ms)", fun m -> 1000. *. lat 10 m);
  ("latency max p8 (ms)", fun m -> 1000. *. lat 8 m);
  ("latency max p4 (ms)", fun m -> 1000. *. lat 4 m);
  ("latency max p2 (ms)", fun m -> 1000. *. lat 2 m);
  ("latency max (ms)", fun m -> 1000. *. m.latency_max);
  ("unhandled", fun m -> float_of_int m.unhandled);
  ("agent utilisation", fun m -> m.utilisation);
]
