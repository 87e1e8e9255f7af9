type 'p entry = { p : 'p; prio : int; seq : int }

(* A bucket queue. Percept priorities are few (one per percept type, plus the
   ones hosts pass to notifyEvent), so the queue keeps one FIFO bucket per
   priority present, in a map, and the highest bucket apart. Within a bucket
   the entries are in seq order: seqs grow with every notify and the transfer
   moves percepts in notify order, so an insert almost always goes at the back
   ([last] tells); the rare other insert is placed by a scan. *)

(* The buckets below the highest, by priority: an AVL tree on int keys
   (Stdlib's Map reaches its comparison through a closure on every node, which
   cost more than the rest of an insert). Only what the queue needs. *)
module Prio_map = struct
  type 'a t = Leaf | Node of { l : 'a t; k : int; v : 'a; r : 'a t; h : int }

  let empty = Leaf
  let height = function Leaf -> 0 | Node n -> n.h
  let node l k v r =
    let hl = height l and hr = height r in
    Node { l; k; v; r; h = (if hl >= hr then hl + 1 else hr + 1) }

  let bal l k v r =
    let hl = height l and hr = height r in
    if hl > hr + 1 then
      match l with
      | Node { l = ll; k = lk; v = lv; r = lr; _ } when height ll >= height lr -> node ll lk lv (node lr k v r)
      | Node { l = ll; k = lk; v = lv; r = Node lr; _ } ->
        node (node ll lk lv lr.l) lr.k lr.v (node lr.r k v r)
      | _ -> node l k v r
    else if hr > hl + 1 then
      match r with
      | Node { l = rl; k = rk; v = rv; r = rr; _ } when height rr >= height rl -> node (node l k v rl) rk rv rr
      | Node { l = Node rl; k = rk; v = rv; r = rr; _ } ->
        node (node l k v rl.l) rl.k rl.v (node rl.r rk rv rr)
      | _ -> node l k v r
    else node l k v r

  let rec find_opt x = function
    | Leaf -> None
    | Node n -> if x = n.k then Some n.v else find_opt x (if x < n.k then n.l else n.r)

  (* [add x v m] binds x to v; [update x f m] binds x to [f] of its binding. *)
  let rec update x f = function
    | Leaf -> Node { l = Leaf; k = x; v = f None; r = Leaf; h = 1 }
    | Node n ->
      if x = n.k then Node { n with v = f (Some n.v) }
      else if x < n.k then bal (update x f n.l) n.k n.v n.r
      else bal n.l n.k n.v (update x f n.r)

  let add x v m = update x (fun _ -> v) m

  let rec remove_max = function
    | Leaf -> Leaf
    | Node { l; r = Leaf; _ } -> l
    | Node n -> bal n.l n.k n.v (remove_max n.r)

  let rec max_binding_opt = function
    | Leaf -> None
    | Node { k; v; r = Leaf; _ } -> Some (k, v)
    | Node n -> max_binding_opt n.r

  let rec remove x = function
    | Leaf -> Leaf
    | Node n ->
      if x < n.k then bal (remove x n.l) n.k n.v n.r
      else if x > n.k then bal n.l n.k n.v (remove x n.r)
      else match n.l, n.r with
        | Leaf, r -> r
        | l, Leaf -> l
        | l, r -> (match max_binding_opt l with
            | Some (k, v) -> bal (remove_max l) k v r
            | None -> r)

  let rec iter f = function
    | Leaf -> ()
    | Node n -> iter f n.l; f n.k n.v; iter f n.r
end

type 'p bucket = { q : 'p entry Fqueue.t; last : int (* the largest seq in q *) }

(* The highest bucket is kept in the queue's own record (its entries and
   their largest seq), so that a pop builds one record, not two. *)
type 'p t = {
  hi : int;                      (* the highest priority present *)
  top : 'p entry Fqueue.t;       (* its entries; empty only if size = 0 *)
  top_last : int;                (* the largest seq in top *)
  rest : 'p bucket Prio_map.t;   (* the other priorities (all below hi), non-empty *)
  size : int;
}

let single e = { q = Fqueue.push e Fqueue.empty; last = e.seq }

(* [e] after every entry of seq <= e.seq: stable among equal seqs (which only
   the flood abstraction's seq 0 produces). *)
let bucket_add e b =
  if e.seq >= b.last then { q = Fqueue.push e b.q; last = e.seq }
  else
    let rec place = function
      | x :: rest when x.seq <= e.seq -> x :: place rest
      | l -> e :: l in
    { b with q = Fqueue.of_list (place (Fqueue.to_list b.q)) }

let empty = { hi = min_int; top = Fqueue.empty; top_last = min_int; rest = Prio_map.empty; size = 0 }
let top_bucket q = { q = q.top; last = q.top_last }
let is_empty q = q.size = 0
let size q = q.size

(* The queue with [n] more entries, whose bucket of priority [prio] becomes
   [f] of the one there now ([None]: there is none). *)
let place prio f n q =
  let size = q.size + n in
  if q.size = 0 then let b = f None in { hi = prio; top = b.q; top_last = b.last; rest = Prio_map.empty; size }
  else if prio = q.hi then let b = f (Some (top_bucket q)) in { q with top = b.q; top_last = b.last; size }
  else if prio > q.hi then
    let b = f None in
    { hi = prio; top = b.q; top_last = b.last; rest = Prio_map.add q.hi (top_bucket q) q.rest; size }
  else { q with rest = Prio_map.update prio f q.rest; size }

let insert e q = place e.prio (function None -> single e | Some b -> bucket_add e b) 1 q

(* [append l q]: [l] holds entries of one priority in seq order. When they
   all come after the entries of that priority in [q] (the transfer's case)
   the run goes at the back of its bucket in one piece; otherwise entry by
   entry. *)
let append l q = match l with
  | [] -> q
  | e0 :: _ ->
    let rec walk n = function [ e ] -> (n + 1, e.seq) | _ :: r -> walk (n + 1) r | [] -> (n, min_int) in
    let (n, last) = walk 0 l in
    place e0.prio (function
        | None -> { q = Fqueue.of_list l; last }
        | Some b when b.last < e0.seq -> { q = Fqueue.append l b.q; last }
        | Some b -> List.fold_left (fun b e -> bucket_add e b) b l) n q

let insert_newest_first feed q =
  (* One run per priority, consed as the entries come (newest first), so that
     each run ends oldest first; the last run used is kept at hand, as
     consecutive entries often share a priority. The first run stays out of
     the map until an entry of another priority comes (a transfer of one
     percept, or of one priority, builds no map). *)
  let runs = ref Prio_map.empty and cur_prio = ref min_int and cur = ref (ref [])
  and only = ref true in
  feed (fun e ->
      if e.prio = !cur_prio then !cur := e :: !(!cur)
      else if !cur_prio = min_int then begin cur := ref [ e ]; cur_prio := e.prio end
      else begin
        if !only then begin runs := Prio_map.add !cur_prio !cur !runs; only := false end;
        let r = match Prio_map.find_opt e.prio !runs with
          | Some r -> r
          | None -> let r = ref [] in runs := Prio_map.add e.prio r !runs; r in
        r := e :: !r; cur_prio := e.prio; cur := r
      end);
  if !only then append !(!cur) q
  else begin
    let q = ref q in
    Prio_map.iter (fun _ r -> q := append !r !q) !runs;
    !q
  end

let of_runs runs =
  let rec go q = function
    | [] -> q
    | (prio, (_ :: _ as entries), n, last) :: rest ->
      let b = { q = Fqueue.of_list_length entries n; last } in
      go (place prio (function None -> b | Some _ -> invalid_arg "Pqueue.of_runs: a priority twice") n q) rest
    | (_, [], _, _) :: rest -> go q rest in
  go empty runs

(* The queue whose top bucket's entries became [top] (its largest seq is
   unchanged): the next bucket moves up if [top] is empty. *)
let with_top q top size =
  if not (Fqueue.is_empty top) then { q with top; size }
  else match Prio_map.max_binding_opt q.rest with
    | None -> empty
    | Some (hi, b) -> { hi; top = b.q; top_last = b.last; rest = Prio_map.remove_max q.rest; size }

let top q = Fqueue.peek q.top

let pop q = match Fqueue.pop q.top with
  | None -> None
  | Some (e, rest) -> Some (e, with_top q rest (q.size - 1))

let first q = Fqueue.first q.top

let drop_first q = if q.size = 0 then q else with_top q (Fqueue.drop q.top) (q.size - 1)

let iter f q =
  if q.size > 0 then begin
    Fqueue.fold (fun () e -> f e) () q.top;
    Prio_map.iter (fun _ b -> Fqueue.fold (fun () e -> f e) () b.q) q.rest
  end

let before a b = a.prio > b.prio || (a.prio = b.prio && a.seq < b.seq)

let runs q =
  if q.size = 0 then []
  else begin
    (* the map's priorities in ascending order, consed: descending *)
    let rest = ref [] in
    Prio_map.iter (fun _ b -> rest := Fqueue.to_list b.q :: !rest) q.rest;
    Fqueue.to_list q.top :: !rest
  end

let to_sorted_list q =
  let l = ref [] in
  iter (fun e -> l := e :: !l) q;
  List.sort (fun a b ->
      if before a b then -1 else if before b a then 1 else compare a.p b.p) !l

let bucket_of e q =
  if q.size = 0 then None
  else if e.prio = q.hi then Some (top_bucket q)
  else Prio_map.find_opt e.prio q.rest

let mem e q = match bucket_of e q with
  | Some b -> Fqueue.exists (fun x -> x = e) b.q
  | None -> false

let candidates ~stable q =
  if q.size = 0 then []
  else
    let all = Fqueue.to_list q.top in
    if not stable then all
    else
      let s = (List.hd all).seq in
      let rec same = function x :: rest when x.seq = s -> x :: same rest | _ -> [] in
      same all

let remove e q = match bucket_of e q with
  | None -> q
  | Some b ->
    match Fqueue.remove_first (fun x -> x = e) b.q with
    | None -> q
    | Some (_, rest) ->
      let b = { b with q = rest } in
      if e.prio = q.hi then with_top q rest (q.size - 1)
      else if Fqueue.is_empty rest then { q with rest = Prio_map.remove e.prio q.rest; size = q.size - 1 }
      else { q with rest = Prio_map.add e.prio b q.rest; size = q.size - 1 }
