(* A binary min-heap kept in three parallel arrays: the times unboxed in a
   float array, the scheduling numbers in an int array, the events in an
   array of their own. Nothing is allocated per event once the arrays are
   large enough (issue 17: a record per event, moved to the major heap with
   its array, was a tenth of a simulation's time with the collector). *)

type 'a t = {
  mutable times : float array;
  mutable seqs : int array;
  mutable vs : 'a array;
  mutable n : int;
  mutable next : int;
}

let create () = { times = [||]; seqs = [||]; vs = [||]; n = 0; next = 0 }
let is_empty q = q.n = 0
let size q = q.n

(* [i] before [j]: earlier, or as early and scheduled first *)
let before q ti si j =
  let tj = Array.unsafe_get q.times j in
  ti < tj || (ti = tj && si < Array.unsafe_get q.seqs j)

let grow q v =
  let cap = max 16 (2 * q.n) in
  let times = Array.make cap 0. and seqs = Array.make cap 0 and vs = Array.make cap v in
  Array.blit q.times 0 times 0 q.n;
  Array.blit q.seqs 0 seqs 0 q.n;
  Array.blit q.vs 0 vs 0 q.n;
  q.times <- times; q.seqs <- seqs; q.vs <- vs

(* Put (t, s, v) in the hole at [i], moving parents down while it is
   before them. *)
let rec sift_up q i t s v =
  let parent = (i - 1) / 2 in
  if i > 0 && before q t s parent then begin
    Array.unsafe_set q.times i (Array.unsafe_get q.times parent);
    Array.unsafe_set q.seqs i (Array.unsafe_get q.seqs parent);
    Array.unsafe_set q.vs i (Array.unsafe_get q.vs parent);
    sift_up q parent t s v
  end else begin
    Array.unsafe_set q.times i t; Array.unsafe_set q.seqs i s; Array.unsafe_set q.vs i v
  end

let add q time v =
  if q.n = Array.length q.times then grow q v;
  let s = q.next in
  q.next <- s + 1;
  let i = q.n in
  q.n <- i + 1;
  sift_up q i time s v

(* Put (t, s, v) in the hole at [i], moving the earlier child up while it
   is before it. *)
let rec sift_down q i t s v =
  let l = 2 * i + 1 in
  if l >= q.n then begin
    Array.unsafe_set q.times i t; Array.unsafe_set q.seqs i s; Array.unsafe_set q.vs i v
  end else begin
    let r = l + 1 in
    let c = if r < q.n && before q (Array.unsafe_get q.times r) (Array.unsafe_get q.seqs r) l then r else l in
    (* the sequence numbers differ: [c] is before (t, s) unless (t, s) is before [c] *)
    if not (before q t s c) then begin
      Array.unsafe_set q.times i (Array.unsafe_get q.times c);
      Array.unsafe_set q.seqs i (Array.unsafe_get q.seqs c);
      Array.unsafe_set q.vs i (Array.unsafe_get q.vs c);
      sift_down q c t s v
    end else begin
      Array.unsafe_set q.times i t; Array.unsafe_set q.seqs i s; Array.unsafe_set q.vs i v
    end
  end

let take q =
  if q.n = 0 then invalid_arg "Event_queue.take: empty";
  let top = Array.unsafe_get q.vs 0 in
  let last = q.n - 1 in
  q.n <- last;
  if last > 0 then
    sift_down q 0 (Array.unsafe_get q.times last) (Array.unsafe_get q.seqs last) (Array.unsafe_get q.vs last);
  top

let next_time q = if q.n = 0 then infinity else Array.unsafe_get q.times 0

let pop q =
  if q.n = 0 then None
  else begin
    let t = q.times.(0) in
    let v = take q in
    Some (t, v)
  end

let peek_time q = if q.n = 0 then None else Some q.times.(0)
