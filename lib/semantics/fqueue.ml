(* Okasaki's batched queue, with the invariant "front is empty only if the
   whole queue is": the front element is then always the head of [front], so
   [peek] costs nothing and [pop] reverses [back] only when [front] runs out. *)
type 'a t = { front : 'a list; back : 'a list; len : int }

let empty = { front = []; back = []; len = 0 }
let is_empty q = q.len = 0
let length q = q.len

(* Re-establish the invariant after front may have become empty. *)
let check front back len =
  match front with
  | [] -> { front = List.rev back; back = []; len }
  | _ -> { front; back; len }

let push x q = match q.front with
  | [] -> { front = [ x ]; back = []; len = 1 }
  | _ -> { q with back = x :: q.back; len = q.len + 1 }

let peek q = match q.front with x :: _ -> Some x | [] -> None

let pop q = match q.front with
  | x :: rest -> Some (x, check rest q.back (q.len - 1))
  | [] -> None

let first q = match q.front with x :: _ -> x | [] -> invalid_arg "Fqueue.first: empty queue"

let drop q = match q.front with
  | _ :: rest -> check rest q.back (q.len - 1)
  | [] -> q

(* Tail-recursive: queues hold millions of entries under a flood. *)
let to_list q = match q.back with
  | [] -> q.front
  | back -> List.rev_append (List.rev q.front) (List.rev back)

let of_list l = { front = l; back = []; len = List.length l }
let of_list_length l n = { front = l; back = []; len = n }

let append l q = match l with
  | [] -> q
  | _ when q.len = 0 -> of_list l
  | _ -> { q with back = List.rev_append l q.back; len = q.len + List.length l }

let partition f q =
  let (yes, no) = List.partition f (to_list q) in
  (yes, of_list no)

let remove_first f q =
  (* Scan the front, then the back in order; stop at the first match. *)
  let rec go acc = function
    | [] -> None
    | x :: rest when f x -> Some (x, List.rev_append acc rest)
    | x :: rest -> go (x :: acc) rest in
  match go [] q.front with
  | Some (x, front) -> Some (x, check front q.back (q.len - 1))
  | None ->
    match go [] (List.rev q.back) with
    | Some (x, back_in_order) -> Some (x, check q.front (List.rev back_in_order) (q.len - 1))
    | None -> None

let exists f q = List.exists f q.front || List.exists f q.back
let fold_newest f acc q =
  List.fold_left f (List.fold_left f acc q.back) (List.rev q.front)

let fold f acc q = List.fold_left f (List.fold_left f acc q.front) (List.rev q.back)
