type 'p entry = { p : 'p; prio : int; seq : int }

(* A pairing heap: a root and its sub-heaps. *)
type 'p heap = Empty | Node of 'p entry * 'p heap list

type 'p t = { heap : 'p heap; size : int }

(* [before a b]: a leaves the queue before b. *)
let before a b = a.prio > b.prio || (a.prio = b.prio && a.seq < b.seq)

let meld h1 h2 = match h1, h2 with
  | Empty, h | h, Empty -> h
  | Node (a, ka), Node (b, kb) ->
    if before b a then Node (b, h1 :: kb) else Node (a, h2 :: ka)

(* Two-pass pairing, written with an explicit accumulator so that a long
   list of sub-heaps (after 10^7 inserts) cannot overflow the stack. *)
let merge_pairs hs =
  let rec pairs acc = function
    | [] -> acc
    | [h] -> h :: acc
    | a :: b :: rest -> pairs (meld a b :: acc) rest in
  List.fold_left meld Empty (pairs [] hs)

let empty = { heap = Empty; size = 0 }
let is_empty q = q.size = 0
let size q = q.size
let insert e q = { heap = meld (Node (e, [])) q.heap; size = q.size + 1 }
let top q = match q.heap with Node (e, _) -> Some e | Empty -> None

let pop q = match q.heap with
  | Empty -> None
  | Node (e, subs) -> Some (e, { heap = merge_pairs subs; size = q.size - 1 })

let rec iter_heap f = function
  | Empty -> ()
  | Node (e, subs) -> f e; List.iter (iter_heap f) subs

let iter f q = iter_heap f q.heap

let to_sorted_list q =
  let l = ref [] in
  iter (fun e -> l := e :: !l) q;
  List.sort (fun a b ->
      if before a b then -1 else if before b a then 1 else compare a.p b.p) !l

let mem e q =
  let found = ref false in
  iter (fun x -> if x = e then found := true) q;
  !found

let candidates ~stable q =
  match top q with
  | None -> []
  | Some t ->
    (* Pop while the entries tie with the top. *)
    let same e = e.prio = t.prio && (not stable || e.seq = t.seq) in
    let rec go acc q = match pop q with
      | Some (e, q') when same e -> go (e :: acc) q'
      | _ -> List.rev acc in
    go [] q

let remove e q =
  (* Pop until e is found, then put the others back. Entries ahead of e are
     those before it in the order, so this costs the rank of e. *)
  let rec go popped q = match pop q with
    | None -> List.fold_left (fun q x -> insert x q) q popped
    | Some (x, q') when x = e -> List.fold_left (fun q x -> insert x q) q' popped
    | Some (x, q') -> go (x :: popped) q' in
  go [] q
