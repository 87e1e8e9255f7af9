type 'a t = { front : 'a list; back : 'a list; len : int }

let empty = { front = []; back = []; len = 0 }
let is_empty q = q.len = 0
let length q = q.len
let push x q = { q with back = x :: q.back; len = q.len + 1 }

let norm q = match q.front with
  | [] when q.back <> [] -> { q with front = List.rev q.back; back = [] }
  | _ -> q

let peek q = match (norm q).front with x :: _ -> Some x | [] -> None

let pop q =
  let q = norm q in
  match q.front with
  | x :: rest -> Some (x, { q with front = rest; len = q.len - 1 })
  | [] -> None

(* Tail-recursive: queues hold millions of entries under a flood. *)
let to_list q = List.rev_append (List.rev q.front) (List.rev q.back)
let of_list l = { front = l; back = []; len = List.length l }

let partition f q =
  let (yes, no) = List.partition f (to_list q) in
  (yes, of_list no)

let remove_first f q =
  let rec go acc = function
    | [] -> None
    | x :: rest when f x -> Some (x, List.rev_append acc rest)
    | x :: rest -> go (x :: acc) rest in
  match go [] (to_list q) with
  | Some (x, l) -> Some (x, of_list l)
  | None -> None

let exists f q = List.exists f q.front || List.exists f q.back
let fold f acc q = List.fold_left f (List.fold_left f acc q.front) (List.rev q.back)
