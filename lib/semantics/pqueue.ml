(* The priority queue of percepts, as PerceptPriority.tla states it: a set
   of entries; Dequeue takes one of the highest priority, and under the
   stable policy the one of smallest seq (R3b). Here the set is kept in that
   very order: a map whose keys are (priority, seq), greater priority first,
   then smaller seq. The first binding is what R3b takes. *)

type 'p entry = { p : 'p; prio : int; seq : int }

(* R3b's order on the keys: the higher priority first; among equal
   priorities, the smaller seq. *)
module Key = struct
  type t = int * int
  let compare (k1, s1) (k2, s2) = if k1 <> k2 then Int.compare k2 k1 else Int.compare s1 s2
end

module Keys = Map.Make (Key)

(* Outside the flood abstraction every entry has a seq of its own, so each
   key holds one entry; under it (every seq 0) one key may hold several
   entries, kept in the order they came. *)
type 'p t = { entries : 'p entry list Keys.t; size : int }

let key e = (e.prio, e.seq)

let empty = { entries = Keys.empty; size = 0 }
let is_empty q = q.size = 0
let size q = q.size

(* Enqueue(Q, e). *)
let insert e q =
  let add = function None -> Some [ e ] | Some l -> Some (l @ [ e ]) in
  { entries = Keys.update (key e) add q.entries; size = q.size + 1 }

let mem e q =
  match Keys.find_opt (key e) q.entries with
  | Some l -> List.mem e l
  | None -> false

(* DequeueMax(Q, e): the queue without one occurrence of e. A key that
   holds one entry holds e itself (seqs are distinct); only under the flood
   abstraction are the entries of a key compared. *)
let remove e q =
  let rec drop = function
    | [] -> None
    | x :: rest -> if x = e then Some rest else Option.map (fun r -> x :: r) (drop rest) in
  match Keys.find_opt (key e) q.entries with
  | None -> q
  | Some [ _ ] -> { entries = Keys.remove (key e) q.entries; size = q.size - 1 }
  | Some l ->
    match drop l with
    | None -> q
    | Some [] -> { entries = Keys.remove (key e) q.entries; size = q.size - 1 }
    | Some l' -> { entries = Keys.add (key e) l' q.entries; size = q.size - 1 }

(* The first entry in R3b's order. *)
let top q =
  match Keys.min_binding_opt q.entries with
  | Some (_, e :: _) -> Some e
  | Some (_, []) | None -> None

let pop q = match top q with Some e -> Some (e, remove e q) | None -> None

(* Candidates(Q, TiePolicy): under Stable, the entries of the first key
   (one, unless seqs repeat); under Unstable, every entry of the highest
   priority. *)
let candidates ~stable q =
  match Keys.min_binding_opt q.entries with
  | None -> []
  | Some ((k, _), first) ->
    if stable then first
    else
      Keys.to_seq q.entries
      |> Seq.filter (fun ((k', _), _) -> k' = k)
      |> Seq.flat_map (fun (_, l) -> List.to_seq l)
      |> List.of_seq

(* Every entry, in dequeue order; entries of one key (the flood
   abstraction) by [compare] on the percept, so that the list does not
   depend on the order they came in. *)
let to_sorted_list q =
  Keys.fold (fun _ l acc -> List.rev_append (List.sort compare l) acc) q.entries []
  |> List.rev

let fold f acc q = Keys.fold (fun _ l acc -> List.fold_left f acc l) q.entries acc
