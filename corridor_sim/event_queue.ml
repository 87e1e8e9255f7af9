(* A binary min-heap of (time, scheduling number, slot), in three parallel
   arrays of unboxed floats and ints; the events themselves stay in their
   slot of [vals] from [add] to [take] and never move. So sifting moves
   floats and ints only, and nothing is allocated per event once the arrays
   are large enough (a record per event, moved to the major heap
   with its array, was a tenth of a simulation's time with the collector). *)

type 'a t = {
  mutable times : float array;
  mutable seqs : int array;
  mutable slots : int array;
  mutable vals : 'a array;      (* by slot *)
  mutable free : int array;     (* the free slots: free.(0 .. nfree-1) *)
  mutable nfree : int;
  mutable n : int;
  mutable next : int;
}

let create () = { times = [||]; seqs = [||]; slots = [||]; vals = [||]; free = [||]; nfree = 0; n = 0; next = 0 }
let is_empty q = q.n = 0
let size q = q.n

let grow q v =
  let cap = max 16 (2 * q.n) in
  let times = Array.make cap 0. and seqs = Array.make cap 0 and slots = Array.make cap 0
  and vals = Array.make cap v and free = Array.make cap 0 in
  Array.blit q.times 0 times 0 q.n;
  Array.blit q.seqs 0 seqs 0 q.n;
  Array.blit q.slots 0 slots 0 q.n;
  Array.blit q.vals 0 vals 0 q.n;
  (* every slot is in use when the queue is full: the new ones are free *)
  for k = 0 to cap - q.n - 1 do free.(k) <- cap - 1 - k done;
  q.times <- times; q.seqs <- seqs; q.slots <- slots; q.vals <- vals; q.free <- free;
  q.nfree <- cap - q.n

let add q time v =
  if q.n = Array.length q.times then grow q v;
  q.nfree <- q.nfree - 1;
  let slot = Array.unsafe_get q.free q.nfree in
  Array.unsafe_set q.vals slot v;
  let s = q.next in
  q.next <- s + 1;
  let times = q.times and seqs = q.seqs and slots = q.slots in
  (* the hole goes up while (time, s) is before its parent *)
  let i = ref q.n in
  q.n <- q.n + 1;
  let continue = ref true in
  while !continue && !i > 0 do
    let parent = (!i - 1) / 2 in
    let tp = Array.unsafe_get times parent in
    if time < tp || (time = tp && s < Array.unsafe_get seqs parent) then begin
      Array.unsafe_set times !i tp;
      Array.unsafe_set seqs !i (Array.unsafe_get seqs parent);
      Array.unsafe_set slots !i (Array.unsafe_get slots parent);
      i := parent
    end else continue := false
  done;
  Array.unsafe_set times !i time; Array.unsafe_set seqs !i s; Array.unsafe_set slots !i slot

let take q =
  if q.n = 0 then invalid_arg "Event_queue.take: empty";
  let times = q.times and seqs = q.seqs and slots = q.slots in
  let top = Array.unsafe_get slots 0 in
  let v = Array.unsafe_get q.vals top in
  Array.unsafe_set q.free q.nfree top;
  q.nfree <- q.nfree + 1;
  let last = q.n - 1 in
  q.n <- last;
  if last > 0 then begin
    (* the last entry goes down from the root while a child is before it *)
    let t = Array.unsafe_get times last and s = Array.unsafe_get seqs last
    and sl = Array.unsafe_get slots last in
    let i = ref 0 and continue = ref true in
    while !continue do
      let l = 2 * !i + 1 in
      if l >= last then continue := false
      else begin
        let r = l + 1 in
        let c =
          if r < last then begin
            let tl = Array.unsafe_get times l and tr = Array.unsafe_get times r in
            if tr < tl || (tr = tl && Array.unsafe_get seqs r < Array.unsafe_get seqs l) then r else l
          end else l in
        let tc = Array.unsafe_get times c in
        if tc < t || (tc = t && Array.unsafe_get seqs c < s) then begin
          Array.unsafe_set times !i tc;
          Array.unsafe_set seqs !i (Array.unsafe_get seqs c);
          Array.unsafe_set slots !i (Array.unsafe_get slots c);
          i := c
        end else continue := false
      end
    done;
    Array.unsafe_set times !i t; Array.unsafe_set seqs !i s; Array.unsafe_set slots !i sl
  end;
  v

let next_time q = if q.n = 0 then infinity else Array.unsafe_get q.times 0

let pop q =
  if q.n = 0 then None
  else begin
    let t = q.times.(0) in
    let v = take q in
    Some (t, v)
  end

let peek_time q = if q.n = 0 then None else Some q.times.(0)
