type side = Explorer_only | Tlc_only

type difference =
  | Initial of side * Tla.t
  | State of side * Tla.t
  | Transition of side * Tla.t * string * Tla.t

type report = {
  ocaml_view : string -> string option;
  explorer_states : int;
  tlc_states : int;
  explorer_transitions : int;
  tlc_transitions : int;
  differences : difference list;
  witness : (string * Tla.t) list;
}

module SS = Set.Make (String)
module ES = Set.Make (struct type t = string * string * string let compare = compare end)

(* A graph over canonical state strings, with BFS paths. *)
type g = {
  names : string array;                  (* canonical string of each node *)
  values : Tla.t array;
  init : int list;
  out : (string * int) list array;
}

let bfs_path g target =
  let n = Array.length g.names in
  let pred = Array.make n None and seen = Array.make n false in
  let q = Queue.create () in
  List.iter (fun i -> seen.(i) <- true; Queue.push i q) g.init;
  while not (Queue.is_empty q) do
    let i = Queue.pop q in
    List.iter (fun (l, j) -> if not seen.(j) then (seen.(j) <- true; pred.(j) <- Some (i, l); Queue.push j q))
      g.out.(i)
  done;
  let rec back i acc = match pred.(i) with
    | None -> ("Init", g.values.(i)) :: acc
    | Some (p, l) -> back p ((l, g.values.(i)) :: acc) in
  if seen.(target) then Some (back target []) else None

let of_explorer (x : Explorer.graph) =
  let values = Array.map (Project.state x.model) x.states in
  let names = Array.map Tla.to_string values in
  let out = Array.make (Array.length names) [] in
  Array.iter (fun (a, l, b) -> out.(a) <- (l, b) :: out.(a)) x.edges;
  { names; values; init = x.initial; out = Array.map List.rev out }

let of_dot (d : Dot.graph) =
  let index = Hashtbl.create 1024 in
  let nodes = Array.of_list d.nodes in
  Array.iteri (fun i (id, _) -> Hashtbl.replace index id i) nodes;
  let values = Array.map snd nodes in
  let names = Array.map Tla.to_string values in
  let out = Array.make (Array.length nodes) [] in
  List.iter (fun (a, l, b) ->
      match Hashtbl.find_opt index a, Hashtbl.find_opt index b with
      | Some i, Some j -> out.(i) <- (l, j) :: out.(i)
      | _ -> failwith "Compare: an edge of the DOT graph names an unknown node") d.edges;
  { names; values; init = List.filter_map (Hashtbl.find_opt index) d.initial;
    out = Array.map List.rev out }

let states g = Array.fold_left (fun s n -> SS.add n s) SS.empty g.names
let edges g =
  let s = ref ES.empty in
  Array.iteri (fun i out -> List.iter (fun (l, j) -> s := ES.add (g.names.(i), l, g.names.(j)) !s) out) g.out;
  !s
let inits g = List.fold_left (fun s i -> SS.add g.names.(i) s) SS.empty g.init

let graphs (x : Explorer.graph) (d : Dot.graph) =
  let a = of_explorer x and b = of_dot d in
  let index g = let h = Hashtbl.create 1024 in Array.iteri (fun i n -> Hashtbl.replace h n i) g.names; h in
  let ia = index a and ib = index b in
  let sa = states a and sb = states b and ea = edges a and eb = edges b in
  let diffs = ref [] in
  let add side g idx target d =
    let len = match bfs_path g (Hashtbl.find idx target) with Some p -> List.length p | None -> max_int in
    diffs := (len, side, d, target) :: !diffs in
  SS.iter (fun n -> if not (SS.mem n (inits b)) then add Explorer_only a ia n (Initial (Explorer_only, a.values.(Hashtbl.find ia n)))) (inits a);
  SS.iter (fun n -> if not (SS.mem n (inits a)) then add Tlc_only b ib n (Initial (Tlc_only, b.values.(Hashtbl.find ib n)))) (inits b);
  SS.iter (fun n -> if not (SS.mem n sb) then add Explorer_only a ia n (State (Explorer_only, a.values.(Hashtbl.find ia n)))) sa;
  SS.iter (fun n -> if not (SS.mem n sa) then add Tlc_only b ib n (State (Tlc_only, b.values.(Hashtbl.find ib n)))) sb;
  (* A transition counts when both its ends are common states: otherwise the
     missing state is the difference to show. *)
  ES.iter (fun (s, l, t) -> if SS.mem s sb && SS.mem t sb && not (ES.mem (s, l, t) eb) then
              add Explorer_only a ia s (Transition (Explorer_only, a.values.(Hashtbl.find ia s), l, a.values.(Hashtbl.find ia t)))) ea;
  ES.iter (fun (s, l, t) -> if SS.mem s sa && SS.mem t sa && not (ES.mem (s, l, t) ea) then
              add Tlc_only b ib s (Transition (Tlc_only, b.values.(Hashtbl.find ib s), l, b.values.(Hashtbl.find ib t)))) eb;
  let sorted = List.sort (fun (l1, _, _, _) (l2, _, _, _) -> compare l1 l2) !diffs in
  let witness = match sorted with
    | [] -> []
    | (_, side, d, target) :: _ ->
      let (g, idx) = if side = Explorer_only then (a, ia) else (b, ib) in
      let path = Option.value (bfs_path g (Hashtbl.find idx target)) ~default:[] in
      (match d with
       | Transition (_, _, l, t) -> path @ [ (l, t) ]
       | _ -> path) in
  let ocaml_view v = match Hashtbl.find_opt ia v with
    | Some i -> Some (Explorer.show x.model x.states.(i))
    | None -> None in
  { ocaml_view; explorer_states = Array.length a.names; tlc_states = Array.length b.names;
    explorer_transitions = ES.cardinal ea; tlc_transitions = ES.cardinal eb;
    differences = List.map (fun (_, _, d, _) -> d) sorted; witness }

let agree r = r.differences = []

let changed before after =
  match before, after with
  | Tla.Rec fa, Tla.Rec fb ->
    List.filter_map (fun (f, v) ->
        match List.assoc_opt f fa with
        | Some v0 when Tla.compare v0 v = 0 -> None
        | _ -> Some (Printf.sprintf "%s = %s" f (Tla.to_string v))) fb
  | _ -> [ Tla.to_string after ]

let side_name = function Explorer_only -> "only the OCaml explorer" | Tlc_only -> "only TLC"

let render r =
  let b = Buffer.create 1024 in
  Printf.bprintf b "states: explorer %d, TLC %d; transitions: explorer %d, TLC %d\n"
    r.explorer_states r.tlc_states r.explorer_transitions r.tlc_transitions;
  (match r.differences with
   | [] -> Buffer.add_string b "the two state graphs are identical\n"
   | d :: _ ->
     Printf.bprintf b "the graphs differ in %d places; the first (shortest path):\n"
       (List.length r.differences);
     (match d with
      | Initial (s, v) -> Printf.bprintf b "  an initial state that %s has:\n    %s\n" (side_name s) (Tla.to_string v)
      | State (s, v) -> Printf.bprintf b "  a state that %s reaches:\n    %s\n" (side_name s) (Tla.to_string v)
      | Transition (s, _, l, _) -> Printf.bprintf b "  a %s transition that %s takes (last step below)\n" l (side_name s));
     Buffer.add_string b "  path (TLA+: the variables each step changed; OCaml: the machine's configuration):\n";
     let prev = ref None in
     List.iteri (fun i (l, v) ->
         (match !prev with
          | None -> Printf.bprintf b "  %2d %s\n     TLA+:  %s\n" i l (Tla.to_string v)
          | Some p -> Printf.bprintf b "  %2d %s\n     TLA+:  %s\n" i l (String.concat "; " (changed p v)));
         Printf.bprintf b "     OCaml: %s\n"
           (match r.ocaml_view (Tla.to_string v) with
            | Some s -> s
            | None -> "(a state the OCaml machine does not reach)");
         prev := Some v) r.witness);
  Buffer.contents b
