(* The packed agent: the engine's agent loop with its waiting percepts as
   ints in rings (Ring), beside the reference rules of
   lib/semantics/machine.ml. See packed.mli for the layout; every function
   here computes what a rule of the reference computes, and test/fastpath
   holds [to_config] equal to the reference after every step. *)

open Semantics.Machine
module Pqueue = Semantics.Pqueue
module Fqueue = Semantics.Fqueue

(* First-in first-out rings of ints in chunks, with a side ring of boxed
   values; see packed.mli. Here, in the same unit as the agent, so that its
   loops inline them. *)
module Ring = struct
  module A = Bigarray.Array1

  (* The ints live outside the OCaml heap: the collector neither copies
     nor scans them (a flood's millions of waiting percepts cost it
     nothing to mark). *)
  type ints = (int, Bigarray.int_elt, Bigarray.c_layout) A.t

  let make_ints n : ints = A.create Bigarray.int Bigarray.c_layout n

  (* A chunk's place in a ring's array of chunks when it holds none. *)
  let no_chunk = make_ints 0

  (* Chunks of [csize] ints (a power of two), shared by the rings of one
     agent: a chunk a ring has emptied is taken by the next ring to grow,
     so that a Transfer moves a flood's O2A chunks to its buckets. At most
     [max_free] wait here; more are left to the collector. *)
  type pool = {
    shift : int;
    bshift : int;                 (* box chunks: a 64th of the size, at least 2 *)
    csize : int;
    free : ints array;
    mutable nfree : int;
    mutable made : int;           (* chunks made so far *)
  }

  let default_chunk = 1 lsl 16
  let max_free = 8

  let pool ?(chunk = default_chunk) () =
    if chunk < 1 || chunk land (chunk - 1) <> 0 then invalid_arg "Packed.Ring.pool";
    let rec log2 k = if k = 1 then 0 else 1 + log2 (k lsr 1) in
    { shift = log2 chunk; bshift = max 1 (log2 chunk - 6); csize = chunk; free = Array.make max_free no_chunk; nfree = 0; made = 0 }

  let free_chunks p = p.nfree
  let pool_offheap_words p = p.nfree * p.csize
  let made p = p.made

  let take p =
    if p.nfree = 0 then begin p.made <- p.made + 1; make_ints p.csize end
    else begin
      p.nfree <- p.nfree - 1;
      let c = p.free.(p.nfree) in
      p.free.(p.nfree) <- no_chunk;
      c
    end

  let give p c = if p.nfree < max_free then begin p.free.(p.nfree) <- c; p.nfree <- p.nfree + 1 end

  type 'b t = {
    pool : pool;
    shift : int;                  (* the pool's, here to save a load *)
    cmask : int;                  (* its chunk size - 1 *)
    mutable ch : ints array;      (* the chunks [ch.(c0)] .. [ch.(c0 + nch - 1)] *)
    mutable c0 : int;
    mutable nch : int;
    mutable head : int;           (* the front int: place [head] of chunk [c0] *)
    mutable len : int;
    mutable front : ints;         (* [ch.(c0)] *)
    mutable tail : ints;          (* the chunk of the back int *)
    mutable tpos : int;
      (* the place after the back int in [tail]; the chunk size when there
         is no room there (or no chunk): the next push takes a chunk *)
    bshift : int;                 (* box chunks of [bmask + 1] values *)
    bmask : int;
    mutable bch : 'b array array; (* the box chunks [bch.(b0)] .. [bch.(b0 + nb - 1)] *)
    mutable b0 : int;
    mutable nb : int;
    mutable bhead : int;          (* the front box: place [bhead] of chunk [b0] *)
    mutable blen : int;
    mutable btail : int;          (* the place after the back box in the last chunk; [bmask + 1] when full or none *)
  }

  let create ?pool:p () =
    let p = match p with Some p -> p | None -> pool () in
    { pool = p; shift = p.shift; cmask = p.csize - 1; ch = [||]; c0 = 0; nch = 0; head = 0; len = 0;
      front = no_chunk; tail = no_chunk; tpos = p.csize;
      bshift = p.bshift; bmask = (1 lsl p.bshift) - 1; bch = [||]; b0 = 0; nb = 0; bhead = 0; blen = 0;
      btail = 1 lsl p.bshift }

  let length r = r.len
  let chunk_mask r = r.cmask
  let boxes r = r.blen
  let is_empty r = r.len = 0 && r.blen = 0
  let chunks r = r.nch

  (* One more chunk at the back, from the pool: the array of chunks is
     slid to its start, or doubled (it holds a few hundred at most). *)
  let add_chunk r =
    if r.c0 + r.nch = Array.length r.ch then begin
      if r.c0 > 0 then begin
        Array.blit r.ch r.c0 r.ch 0 r.nch;
        Array.fill r.ch r.nch r.c0 no_chunk
      end else begin
        let a = Array.make (max 4 (2 * r.nch)) no_chunk in
        Array.blit r.ch 0 a 0 r.nch;
        r.ch <- a
      end;
      r.c0 <- 0
    end;
    let c = take r.pool in
    r.ch.(r.c0 + r.nch) <- c;
    if r.nch = 0 then r.front <- c;
    r.nch <- r.nch + 1;
    r.tail <- c;
    r.tpos <- 0

  let[@inline] push r x =
    if r.tpos > r.cmask then add_chunk r;
    A.unsafe_set r.tail r.tpos x;
    r.tpos <- r.tpos + 1;
    r.len <- r.len + 1

  (* The [i]th int's chunk and place, beyond the front chunk. *)
  let get_far r a = A.unsafe_get (Array.unsafe_get r.ch (r.c0 + a lsr r.shift)) (a land r.cmask)

  let[@inline] get r i =
    let a = r.head + i in
    if a <= r.cmask then A.unsafe_get r.front a else get_far r a

  let[@inline] set r i x =
    let a = r.head + i in
    A.unsafe_set (Array.unsafe_get r.ch (r.c0 + a lsr r.shift)) (a land r.cmask) x

  (* The ring empty: its first chunk (if any) used again from its start,
     the others back to the pool. *)
  let restart r =
    for i = r.c0 + 1 to r.c0 + r.nch - 1 do give r.pool r.ch.(i); r.ch.(i) <- no_chunk done;
    r.head <- 0;
    if r.nch > 0 then begin r.nch <- 1; r.tail <- r.front; r.tpos <- 0 end
    else begin r.c0 <- 0; r.tail <- no_chunk; r.tpos <- r.cmask + 1 end

  (* The front chunks read to their end go back to the pool (the ring is
     not empty: its back int is in a later chunk). *)
  let release_front r =
    while r.head > r.cmask do
      give r.pool r.ch.(r.c0);
      r.ch.(r.c0) <- no_chunk;
      r.c0 <- r.c0 + 1;
      r.nch <- r.nch - 1;
      r.head <- r.head - r.cmask - 1
    done;
    r.front <- r.ch.(r.c0)

  let[@inline] drop r n =
    r.head <- r.head + n;
    r.len <- r.len - n;
    if r.len = 0 then restart r
    else if r.head > r.cmask then release_front r

  (* The boxed values, in chunks too (ordinary arrays, a 64th of an int
     chunk's length: 1,024 by default): a chunk is made with its first
     value as the filler of its other places, and left to the collector
     once read to its end. *)
  let add_box_chunk r v =
    if r.b0 + r.nb = Array.length r.bch then begin
      if r.b0 > 0 then begin
        Array.blit r.bch r.b0 r.bch 0 r.nb;
        Array.fill r.bch r.nb r.b0 [||]
      end else begin
        let a = Array.make (max 4 (2 * r.nb)) [||] in
        Array.blit r.bch 0 a 0 r.nb;
        r.bch <- a
      end;
      r.b0 <- 0
    end;
    r.bch.(r.b0 + r.nb) <- Array.make (r.bmask + 1) v;
    r.nb <- r.nb + 1;
    r.btail <- 0

  let push_box r v =
    if r.btail > r.bmask then add_box_chunk r v;
    r.bch.(r.b0 + r.nb - 1).(r.btail) <- v;
    r.btail <- r.btail + 1;
    r.blen <- r.blen + 1

  let get_box r j =
    let a = r.bhead + j in
    r.bch.(r.b0 + a lsr r.bshift).(a land r.bmask)

  (* The value leaving stays in its chunk until the chunk leaves (at most
     a chunk's worth of values kept so). *)
  let drop_box r =
    r.bhead <- r.bhead + 1;
    r.blen <- r.blen - 1;
    if r.bhead > r.bmask then begin
      r.bch.(r.b0) <- [||];
      r.b0 <- r.b0 + 1;
      r.nb <- r.nb - 1;
      r.bhead <- 0;
      if r.nb = 0 then begin r.b0 <- 0; r.btail <- r.bmask + 1 end
    end

  let shrink r =
    if r.len = 0 && r.blen = 0 then begin
      for i = r.c0 to r.c0 + r.nch - 1 do give r.pool r.ch.(i); r.ch.(i) <- no_chunk done;
      r.c0 <- 0; r.nch <- 0; r.head <- 0;
      r.front <- no_chunk; r.tail <- no_chunk; r.tpos <- r.cmask + 1;
      for i = r.b0 to r.b0 + r.nb - 1 do r.bch.(i) <- [||] done;
      r.b0 <- 0; r.nb <- 0; r.bhead <- 0; r.btail <- r.bmask + 1
    end

  (* The record (19 fields and a header), the array of chunks, each
     chunk's bigarray block (a custom block of 6 words with its header),
     the array of box chunks and the box chunks. *)
  let heap_words r =
    20 + (if Array.length r.ch = 0 then 0 else Array.length r.ch + 1) + 7 * r.nch
    + (if Array.length r.bch = 0 then 0 else Array.length r.bch + 1) + r.nb * (r.bmask + 2)
  let offheap_words r = r.nch lsl r.shift
end

module type CODEC = sig
  type percept
  type t
  val create : unit -> t
  val encode : t -> percept -> percept Ring.t -> int
  val read : t -> int -> percept Ring.t -> pos:int -> box:int -> percept
  val encode_one : t -> percept -> int
  val read_int : t -> int -> int -> percept
end

(* A tag: [kind] (10 bits), [width] (8 bits), [boxes] (2 bits). *)
let make_tag ~kind ~width ~boxes =
  if kind < 0 || kind >= 1024 || width < 0 || width > 255 || boxes < 0 || boxes > 3 then
    invalid_arg "Packed.make_tag";
  (kind lsl 10) lor (width lsl 2) lor boxes
(* A percept that travels as it is, in the ring's side ring of boxes. *)
let boxed_tag = make_tag ~kind:0 ~width:0 ~boxes:1

let tag_kind tag = tag lsr 10
let tag_width tag = (tag lsr 2) land 255
let tag_boxes tag = tag land 3

(* A record's header, in one of two forms told apart by bit 0 (D39):
   - long (bit 0 clear): [x] (the record's seq: counts of notifies fit
     in the 42 bits left) and the tag; the record's ints and boxes follow;
   - a word (bit 0 set): the whole record in one int, for a kind of one
     int slot or of none, and no box (width 1 or 0), numbered 1 to 15:
     the kind (bits 1-4), [x] (bits 5-30: the seq less the bucket's
     [base]), the slot's int (bits 31-62: a 32-bit integer, D8; 0 for no
     slot). *)
let tag_bits = 20
let tag_mask = (1 lsl tag_bits) - 1
let long x tag = (x lsl (tag_bits + 1)) lor (tag lsl 1)

let word_kinds = 15
let word_x_bits = 26
let word_x_limit = 1 lsl word_x_bits
let min32 = - (1 lsl 31) and max32 = (1 lsl 31) - 1

let[@inline] is_word h = h land 1 = 1
let[@inline] word ~v ~kind ~x = (v lsl 31) lor (x lsl 5) lor (kind lsl 1) lor 1
let[@inline] word_v h = h asr 31
let[@inline] word_x h = (h lsr 5) land (word_x_limit - 1)
let[@inline] word_kind h = (h lsr 1) land word_kinds

(* A tag that a word can stand for: width 1 or 0, no box, kind 1 to 15. *)
let[@inline] word_tag tag = (tag land 1023 = 4 || tag land 1023 = 0) && tag >= 1024 && tag < (word_kinds + 1) lsl 10

(* Of either form: the header's [x], its tag, the record's ints (header
   included) and boxes. *)
let[@inline] x_of h = if is_word h then word_x h else h asr (tag_bits + 1)
(* A word's tag is given width 1 (its kind may have none: the codec's
   read_int knows its kind). *)
let[@inline] tag_of h = if is_word h then (word_kind h lsl 10) lor 4 else (h lsr 1) land tag_mask
let[@inline] ints_of h = if is_word h then 1 else 1 + tag_width ((h lsr 1) land tag_mask)
let[@inline] boxes_of h = if is_word h then 0 else (h lsr 1) land 3

module Make (B : Fast.BODIES) (C : CODEC with type percept = B.percept) = struct
  module F = Fast.Make (B)
  module M = F.M

  (* One priority's waiting percepts, oldest first (R3b, stable ties):
     first those Transfer moved to the priority queue ([tn] records, the
     front [tpos] ints and [tbox] boxes), then those still in O2A, in the
     order they were notified. A Transfer moves none: it counts them all
     as the priority queue's. *)
  type bucket = {
    bprio : int;
    ring : B.percept Ring.t;
    mutable base : int;   (* the seq of the first record pushed since it was empty: a word's seq is [base + x] *)
    mutable nrec : int;   (* records *)
    mutable tn : int;     (* of which the priority queue's, at the front *)
    mutable tpos : int;   (* their ints *)
    mutable tbox : int;   (* their boxes *)
  }

  type t = {
    p : params;
    can_pack : bool;                   (* [packable p] *)
    mutable is_packed : bool;
    pack_above : int;
      (* plain (the configuration's own queues, as [Fast]) while fewer than
         this many wait in O2A and the priority queue: they die young, and
         packing them would only cost; packed from there until none wait
         (a backlog the collector would otherwise promote and mark) *)
    mutable c : M.t;
      (* packed: [c.o2a] holds the objects only (R2c), [c.pq] is empty *)
    codec : C.t;
    pool : Ring.pool;                  (* the chunks of its rings *)
    x_limit : int;                     (* a word's [x] is below it *)
    mutable o2a_n : int;               (* records in O2A (at the backs of the buckets) *)
    mutable after : int Fqueue.t;
      (* beside each object of [c.o2a], in order: [next_seq] when it was
         put (it stands after the percept of that seq, before the next) *)
    mutable buckets : bucket array;    (* highest priority first *)
    mutable pq_n : int;                (* records in the buckets *)
    by_prio : bucket array;
      (* the bucket of each priority below [small_prios], or [no_bucket] *)
    mutable top : int;                 (* the buckets before it are empty *)
    mutable pend : int;
      (* notifies not yet written into [c]: [c.next_seq] is short of them,
         [c.phase] may still be Idle, [c.last] is to be the last one's label:
         its percept (the record at [pend_at] of the bucket of
         [pend_prio], its boxes from the [pend_box]th: decoded then, no
         write barrier per notify; nothing is popped before), its
         priority, whether it was NotifyWith *)
    mutable pend_at : int;
    mutable pend_box : int;
    mutable pend_prio : int;
    mutable pend_with : bool;
    plain_runs : B.percept entry list array;
    plain_lens : int array;
    mutable plain_mask : int;
    mutable plain_big : B.percept entry list;
    mutable pq_runs : B.percept entry list list;
    mutable pq_runs_n : int;
      (* plain: the priority queue's entries when a Transfer took them as
         they waited (highest priority first, each run oldest first, R3b),
         [pq_runs_n] of them; [c.pq] is then empty. Written into [c.pq]
         before anything but a run of dispatches reads it ({!sync}). *)
      (* plain (and packable): the [pend] notifies' entries, not yet in
         [c.o2a] (as O2A items), by priority: those of priority [k] below
         {!plain_small} in [plain_runs.(k)], newest first, [plain_lens.(k)]
         of them, bit [k] of [plain_mask] set when there are some; the
         others in [plain_big], newest first. A Transfer that takes them
         as they wait has them in their buckets already. *)
  }

  let packable p =
    (p.variant = Reference || p.variant = Budgeted) && p.tie = Stable && not p.flood && not p.ghosts

  (* The percept of the record of header [h] at [pos] in [ring], its boxes
     from the [box]th. *)
  let[@inline] percept_at t ring h ~pos ~box =
    if is_word h then C.read_int t.codec (tag_of h) (word_v h)
    else C.read t.codec (tag_of h) ring ~pos:(pos + 1) ~box

  (* Priorities below this one find their bucket in [by_prio], at once. *)
  let small_prios = 64
  let no_bucket = { bprio = min_int; ring = Ring.create (); base = 0; nrec = 0; tn = 0; tpos = 0; tbox = 0 }

  (* The bucket of priority [prio] found in [buckets], or made in its place
     (priorities descending). *)
  let find_or_add t prio =
    let bs = t.buckets in
    let n = Array.length bs in
    let rec find i = if i < n && bs.(i).bprio > prio then find (i + 1) else i in
    let i = find 0 in
    if i < n && bs.(i).bprio = prio then bs.(i)
    else begin
      let b = { bprio = prio; ring = Ring.create ~pool:t.pool (); base = 0; nrec = 0; tn = 0; tpos = 0; tbox = 0 } in
      t.buckets <- Array.init (n + 1) (fun j -> if j < i then bs.(j) else if j = i then b else bs.(j - 1));
      t.top <- 0;
      if prio >= 0 && prio < small_prios then t.by_prio.(prio) <- b;
      b
    end

  let bucket_for t prio =
    if prio >= 0 && prio < small_prios then
      let b = Array.unsafe_get t.by_prio prio in
      if b.bprio = prio then b else find_or_add t prio
    else find_or_add t prio

  (* Priorities below this one wait in [plain_runs] (a bit of [plain_mask] each). *)
  let plain_small = 62

  (* The plain notifies waiting, taken: newest first. *)
  let take_plain t =
    if t.plain_mask = 0 && t.plain_big = [] then [] else
    let all = ref t.plain_big in
    t.plain_big <- [];
    for k = 0 to plain_small - 1 do
      if t.plain_mask land (1 lsl k) <> 0 then begin
        all := List.rev_append t.plain_runs.(k) !all;
        t.plain_runs.(k) <- []; t.plain_lens.(k) <- 0
      end
    done;
    t.plain_mask <- 0;
    List.sort (fun (a : B.percept entry) b -> compare b.seq a.seq) !all

  (* The notifies not yet written into [c], written: what the reference's
     Notify does to the configuration's fields other than O2A (next_seq, an
     idle agent woken, last), once for a run of notifies. *)
  let settle_runs t =
    if t.pq_runs <> [] then begin
      let pq = List.fold_left (List.fold_left (fun q e -> Pqueue.insert e q)) t.c.pq t.pq_runs in
      t.c <- { t.c with pq };
      t.pq_runs <- []; t.pq_runs_n <- 0
    end

  let sync t =
    settle_runs t;
    if t.pend > 0 then begin
      let c = t.c in
      let seq = c.next_seq + t.pend in
      let (o2a, e) = match take_plain t with
        | (e :: _) as items -> (Fqueue.append (List.rev_map (fun e -> O_percept e) items) c.o2a, e)
        | _ ->
          let r = (bucket_for t t.pend_prio).ring in
          let h = Ring.get r t.pend_at in
          (c.o2a, { p = percept_at t r h ~pos:t.pend_at ~box:t.pend_box; prio = t.pend_prio; seq }) in
      t.c <- { c with next_seq = seq; o2a;
                      phase = (if c.phase = Idle_phase then Transfer_phase else c.phase);
                      last = (if t.pend_with then Notify_with e else Notify e) };
      t.pend <- 0
    end

  let params t = t.p
  let packed t = t.is_packed
  let phase t = sync t; t.c.phase
  let last t = sync t; t.c.last
  let world t = t.c.world

  (* ---------------------------------------------------------- buckets *)

  (* The highest bucket holding some of the priority queue's records; there
     is one when [pq_n > 0]. The scan starts at [top]: the buckets before
     it hold none. *)
  let rec first_non_empty t (bs : bucket array) i =
    if bs.(i).tn > 0 then begin t.top <- i; bs.(i) end
    else first_non_empty t bs (i + 1)

  let top_bucket t = first_non_empty t t.buckets t.top

  (* The seq of a bucket's record of header [h]. *)
  let[@inline] seq_in b h = if is_word h then b.base + word_x h else x_of h

  (* A bucket's record of header [h] at [pos], its boxes from the [box]th,
     decoded into its entry (not removed). *)
  let[@inline] entry_at t b h ~pos ~box = { p = percept_at t b.ring h ~pos ~box; prio = b.bprio; seq = seq_in b h }

  let front_entry t b = entry_at t b (Ring.get b.ring 0) ~pos:0 ~box:0

  (* Dequeue's pops (R3b), the highest bucket's oldest record first: a
     reader takes the records in place, bucket by bucket, and drops what it
     has read from its bucket's front once ([settle]): when the bucket's
     records of the priority queue are all taken, when a chunk has been
     read (it goes back to the pool), or when the caller is done. Nothing
     else may read or change the buckets before [settle]. *)
  type reader = { mutable rb : bucket; mutable pos : int; mutable box : int; mutable taken : int }

  let reader t = { rb = top_bucket t; pos = 0; box = 0; taken = 0 }

  let settle t r =
    let b = r.rb in
    Ring.drop b.ring r.pos;
    for _ = 1 to r.box do Ring.drop_box b.ring done;
    Ring.shrink b.ring;
    b.nrec <- b.nrec - r.taken; b.tn <- b.tn - r.taken;
    b.tpos <- b.tpos - r.pos; b.tbox <- b.tbox - r.box;
    t.pq_n <- t.pq_n - r.taken;
    r.pos <- 0; r.box <- 0; r.taken <- 0

  (* The next record, decoded; there is one when [pq_n] exceeds what the
     reader has taken. *)
  let read_next t r =
    if r.taken = r.rb.tn then begin settle t r; r.rb <- top_bucket t end;
    let b = r.rb in
    let h = Ring.get b.ring r.pos in
    let e = entry_at t b h ~pos:r.pos ~box:r.box in
    r.pos <- r.pos + ints_of h;
    r.box <- r.box + boxes_of h;
    r.taken <- r.taken + 1;
    if r.pos > Ring.chunk_mask b.ring then settle t r;
    e

  (* One pop: a reader of one record. *)
  let pop t =
    let r = reader t in
    let e = read_next t r in
    settle t r;
    e

  (* ------------------------------------------------ packing, projecting *)

  let empty_state ~pack_above ~pool ~x_limit p c =
    { p; can_pack = packable p; is_packed = false; pack_above; c; codec = C.create (); pool; x_limit;
      o2a_n = 0; after = Fqueue.empty;
      buckets = [||]; pq_n = 0; by_prio = Array.make small_prios no_bucket; top = 0;
      pend = 0; pend_at = 0; pend_box = 0; pend_prio = 0; pend_with = false;
      plain_runs = Array.make plain_small []; plain_lens = Array.make plain_small 0; plain_mask = 0; plain_big = [];
      pq_runs = []; pq_runs_n = 0 }

  (* A record pushed onto [ring]: a word, when the codec answers the
     percept's tag and int ([encode_one]), the tag is one a word stands
     for, and [wx] (the word's [x]) is small
     enough; else its long header ([x] = [lx]), then what the codec
     writes. *)
  let[@inline] push_record t ring ~wx ~lx percept =
    let o = if wx >= 0 && wx < t.x_limit then C.encode_one t.codec percept else 0 in
    let tag = o land tag_mask and v = o asr tag_bits in
    if o <> 0 && word_tag tag && v >= min32 && v <= max32 then Ring.push ring (word ~v ~kind:(tag_kind tag) ~x:wx)
    else begin
      let at = Ring.length ring in
      Ring.push ring 0;
      let tag = C.encode t.codec percept ring in
      Ring.set ring at (long lx tag)
    end

  (* An entry at the back of its priority's bucket; its bucket. *)
  let push_bucket t (e : B.percept entry) =
    let b = bucket_for t e.prio in
    if Ring.length b.ring = 0 then b.base <- e.seq;
    push_record t b.ring ~wx:(e.seq - b.base) ~lx:e.seq e.p;
    b.nrec <- b.nrec + 1;
    b

  (* A percept of O2A; of the priority queue (after any of O2A there is none). *)
  let push_o2a t (e : B.percept entry) =
    ignore (push_bucket t e);
    t.o2a_n <- t.o2a_n + 1

  let push_pq t (e : B.percept entry) =
    let b = push_bucket t e in
    b.tn <- b.nrec; b.tpos <- Ring.length b.ring; b.tbox <- Ring.boxes b.ring;
    t.pq_n <- t.pq_n + 1

  (* Packing what waits in [t.c] (plain until now; the rings are empty). *)
  let pack_now t =
    let c = t.c in
    (* the percepts in O2A are the last notified: their seqs run to next_seq *)
    let items = Fqueue.to_list c.o2a in
    let percepts = List.filter_map (function O_percept e -> Some e | O_object _ -> None) items in
    let first = c.next_seq - List.length percepts + 1 in
    List.iteri (fun i (e : B.percept entry) ->
        if e.seq <> first + i then invalid_arg "Packed.of_config: O2A's seqs are not the last notified")
      percepts;
    (* the rings are empty: the priority queue's percepts first, at the
       fronts of the buckets (seqs below O2A's), then O2A's *)
    Array.iter (fun b -> b.nrec <- 0; b.tn <- 0; b.tpos <- 0; b.tbox <- 0) t.buckets;
    List.iter (push_pq t) (Pqueue.to_sorted_list c.pq);
    let seen = ref (first - 1) and objects = ref [] and after = ref [] in
    List.iter (function
        | O_percept e -> push_o2a t e; seen := e.seq
        | O_object _ as o -> objects := o :: !objects; after := !seen :: !after) items;
    t.after <- Fqueue.of_list (List.rev !after);
    (* the buckets outlive a plain interval, [top] with them: a record may
       now wait in a bucket before it *)
    t.top <- 0;
    t.c <- { c with o2a = Fqueue.of_list (List.rev !objects); pq = Pqueue.empty };
    t.is_packed <- true

  (* Plain, at most this many wait; packed, at least. *)
  let backlog (c : M.t) = Fqueue.length c.o2a + Pqueue.size c.pq

  let maybe_pack t =
    if t.can_pack && not t.is_packed && backlog t.c + t.pend >= t.pack_above then begin
      sync t; pack_now t end

  (* Nothing waits any more: plain again. The
     configuration is then the plain one: its O2A holds the objects, its
     priority queue is empty ([after] is rewritten by the next [pack_now]). *)
  let maybe_unpack t =
    if t.is_packed && t.pack_above > 0 && t.o2a_n = 0 && t.pq_n = 0 then
      t.is_packed <- false

  let default_pack_above = 4096

  let of_config ?(pack_above = default_pack_above) ?(chunk = Ring.default_chunk) ?(word_x_limit = word_x_limit) p (c : M.t) =
    if word_x_limit < 0 || word_x_limit > 1 lsl word_x_bits then invalid_arg "Packed.of_config: word_x_limit";
    let t = empty_state ~pack_above ~pool:(Ring.pool ~chunk ()) ~x_limit:word_x_limit p c in
    maybe_pack t;
    t

  (* The records of a ring, decoded in order: [header -> percept -> 'a]. *)
  let decode_all t ring n f =
    let pos = ref 0 and box = ref 0 in
    List.init n (fun _ ->
        let h = Ring.get ring !pos in
        let x = f h (percept_at t ring h ~pos:!pos ~box:!box) in
        pos := !pos + ints_of h;
        box := !box + boxes_of h;
        x)

  let to_config t : M.t =
    sync t;
    if not t.is_packed then t.c
    else begin
      let c = t.c in
      (* each bucket: the priority queue's records, then O2A's *)
      let pq = ref Pqueue.empty and in_o2a = ref [] in
      Array.iter (fun b ->
          List.iteri (fun i e -> if i < b.tn then pq := Pqueue.insert e !pq else in_o2a := e :: !in_o2a)
            (decode_all t b.ring b.nrec (fun h p -> { p; prio = b.bprio; seq = seq_in b h })))
        t.buckets;
      let percepts = List.sort (fun (a : B.percept entry) b -> compare a.seq b.seq) !in_o2a in
      (* objects go before the first percept notified after them *)
      let rec merge (ps : B.percept entry list) objs = match ps, objs with
        | e :: ps', (a, o) :: objs' ->
          if a < e.seq then o :: merge ps objs' else O_percept e :: merge ps' objs
        | _, [] -> List.map (fun e -> O_percept e) ps
        | [], _ -> List.map snd objs in
      let objs = List.combine (Fqueue.to_list t.after) (Fqueue.to_list c.o2a) in
      { c with o2a = Fqueue.of_list (merge percepts objs); pq = !pq }
    end

  let waiting t =
    sync t;
    if t.is_packed then t.o2a_n + t.pq_n
    else Fqueue.fold (fun n x -> match x with O_percept _ -> n + 1 | O_object _ -> n) 0 t.c.o2a
         + Pqueue.size t.c.pq

  let ring_ints t = Array.fold_left (fun n b -> n + Ring.length b.ring) 0 t.buckets
  let chunks_made t = Ring.made t.pool

  let offheap_words t =
    Array.fold_left (fun n b -> n + Ring.offheap_words b.ring)
      (Ring.pool_offheap_words t.pool) t.buckets

  (* -------------------------------------------------------- host rules *)

  (* R2d: the percepts in O2A and the objects. *)
  let o2a_has_room t =
    if not t.is_packed then
      (match t.p.o2a_capacity with None -> true | Some _ -> sync t; M.o2a_has_room t.p t.c)
    else match t.p.o2a_capacity with
      | None -> true
      | Some cap -> t.o2a_n + Fqueue.length t.c.o2a < cap

  (* NotifyEffect: as the reference's, the percept into O2A (its record at
     the back of its priority's bucket); the
     rest of the configuration is written by [sync] before anything reads
     it (a host's run of notifies copies no configuration). *)
  let notify_effect t percept prio ~with_ =
    let b = bucket_for t prio and seq = t.c.next_seq + t.pend + 1 in
    let r = b.ring in
    if Ring.length r = 0 then b.base <- seq;
    t.pend_at <- Ring.length r;
    t.pend_box <- Ring.boxes r;
    push_record t r ~wx:(seq - b.base) ~lx:seq percept;
    b.nrec <- b.nrec + 1;
    t.o2a_n <- t.o2a_n + 1;
    t.pend <- t.pend + 1;
    t.pend_prio <- prio;
    t.pend_with <- with_

  (* The same, plain: the O2A item is made now (its seq is known) and
     waits in [plain_pend] until [sync] appends the run to [c.o2a]; the
     label is the last item's. Only where packing could be: the reference's
     NotifyEffect there neither merges seqs (flood) nor keeps waits
     (ghosts). *)
  let notify_plain t percept prio ~with_ =
    let e = { p = percept; prio; seq = t.c.next_seq + t.pend + 1 } in
    if prio < plain_small then begin
      Array.unsafe_set t.plain_runs prio (e :: Array.unsafe_get t.plain_runs prio);
      Array.unsafe_set t.plain_lens prio (Array.unsafe_get t.plain_lens prio + 1);
      t.plain_mask <- t.plain_mask lor (1 lsl prio)
    end else t.plain_big <- e :: t.plain_big;
    t.pend <- t.pend + 1;
    t.pend_with <- with_

  (* [maybe_pack] after a plain notify (packable, not packed) *)
  let[@inline] pack_if_due t =
    if Fqueue.length t.c.o2a + Pqueue.size t.c.pq + t.pq_runs_n + t.pend >= t.pack_above then begin sync t; pack_now t end

  let notify t percept prio =
    if t.is_packed then notify_effect t percept prio ~with_:false
    else if t.can_pack then begin notify_plain t percept prio ~with_:false; pack_if_due t end
    else t.c <- M.notify t.p t.c percept prio

  let notify_with t percept prio =
    if t.is_packed then notify_effect t percept prio ~with_:true
    else if t.can_pack then begin notify_plain t percept prio ~with_:true; pack_if_due t end
    else t.c <- M.notify_with t.p t.c percept prio

  let notify_event t percept ~default ~priority =
    match priority with
    | Some k when k < 0 -> Error (Negative_priority k)                      (* R2a *)
    | _ when not (o2a_has_room t) -> Error O2a_full                          (* R2d *)
    | None -> notify t percept default; Ok ()
    | Some k -> notify_with t percept k; Ok ()

  let put t o =
    sync t;
    if t.is_packed then t.after <- Fqueue.push t.c.next_seq t.after;
    t.c <- M.put t.p t.c o

  let send t m = sync t; t.c <- M.send t.p t.c m

  (* -------------------------------------------------------- agent rules *)

  (* Transfer (R3a): O2A's records, each at the back of its priority's
     bucket, become the priority queue's; the objects stay. *)
  let transfer t =
    let n = t.o2a_n in
    (* O2A's records are in their buckets already, behind the priority
       queue's: they become the priority queue's *)
    Array.iter (fun b -> b.tn <- b.nrec; b.tpos <- Ring.length b.ring; b.tbox <- Ring.boxes b.ring) t.buckets;
    t.o2a_n <- 0;
    t.pq_n <- t.pq_n + n;
    t.top <- 0;
    let l = Transfer n in
    t.c <- { t.c with phase = Dispatch_phase; dispatched = 0; last = l };
    l

  (* DispatchOver, with the buckets for the priority queue. *)
  let dispatch_over t = t.pq_n = 0 || M.budget_spent t.p t.c

  (* The configuration a rule other than Transfer and Dequeue sees: those
     rules ask of O2A and of the priority queue only whether they hold a
     percept (IdleCondition, DispatchOver), so O2A gets its first percept
     beside the objects and the priority queue its top; they change
     neither (packed mode has no Native or Printed variant, no ghosts). *)
  let view t : M.t =
    let c = t.c in
    let o2a =
      if t.o2a_n = 0 then c.o2a
      else begin
        (* O2A's oldest percept: the least seq behind a bucket's front part *)
        let best = ref no_bucket and best_seq = ref max_int in
        Array.iter (fun b ->
            if b.nrec > b.tn then begin
              let s = seq_in b (Ring.get b.ring b.tpos) in
              if s < !best_seq then begin best := b; best_seq := s end
            end) t.buckets;
        let b = !best in
        Fqueue.push (O_percept (entry_at t b (Ring.get b.ring b.tpos) ~pos:b.tpos ~box:b.tbox)) c.o2a
      end in
    let pq = if t.pq_n = 0 then Pqueue.empty else Pqueue.insert (front_entry t (top_bucket t)) Pqueue.empty in
    { c with o2a; pq }

  (* Plain, a run of notifies waiting with nothing before it in O2A, and
     Transfer the next rule (the agent in Transfer or Idle): what [sync]
     writes but O2A, then Transfer of the run as it waits, newest first. *)
  let transfer_plain_run t =
    if (t.plain_mask <> 0 || t.plain_big <> []) && Fqueue.is_empty t.c.o2a
       && (t.c.phase = Transfer_phase || t.c.phase = Idle_phase) then begin
      settle_runs t;
      let c = t.c and n = t.pend in
      t.pend <- 0;
      let pq =
        if Pqueue.is_empty c.pq && t.plain_big = [] && t.p.variant = Reference then begin
          (* each priority's run, oldest first, waits as it is, the highest
             priority's first, for a run of dispatches *)
          let runs = ref [] in
          for k = 0 to plain_small - 1 do
            if t.plain_mask land (1 lsl k) <> 0 then begin
              runs := List.rev t.plain_runs.(k) :: !runs;
              t.plain_runs.(k) <- []; t.plain_lens.(k) <- 0
            end
          done;
          t.plain_mask <- 0;
          t.pq_runs <- !runs; t.pq_runs_n <- n;
          Pqueue.empty
        end else List.fold_left (fun q e -> Pqueue.insert e q) c.pq (take_plain t) in
      let (l, c) = F.transfer_into { c with next_seq = c.next_seq + n; phase = Transfer_phase } pq n in
      t.c <- c;
      Some l
    end else None

  let step t =
    match if t.is_packed then None else transfer_plain_run t with
    | Some _ as l -> l
    | None ->
    sync t;
    if not t.is_packed then
      match F.step t.p t.c with
      | [] -> None
      | (l, c) :: _ -> t.c <- c; Some l
    else
      match t.c.phase with
      | Transfer_phase -> Some (transfer t)
      | Dispatch_phase when not (dispatch_over t) ->
        let (l, c) = F.dequeue_entry t.p t.c (pop t) ~pq:Pqueue.empty in
        t.c <- c; maybe_unpack t; Some l
      | _ ->
        match F.step t.p (view t) with
        | [] -> None
        | (l, c) :: _ -> t.c <- { c with o2a = t.c.o2a; pq = Pqueue.empty }; Some l

  (* Notifies waiting and the agent in Transfer or Idle: Transfer is next,
     no dispatch is enabled (nothing is written yet: [step] may take the
     run as it waits). *)
  let transfer_next t = t.pend > 0 && (t.c.phase = Transfer_phase || t.c.phase = Idle_phase)

  let dispatch_synced ?observe t =
    sync t;
    if not t.is_packed then
      match F.dispatch ?observe t.p t.c with
      | Some c -> t.c <- c; true
      | None -> false
    else
      match t.c.phase with
      | Handle_phase ->
        (* the rest of a dispatch: the priority queue is not read *)
        (match F.dispatch ?observe t.p t.c with
         | Some c -> t.c <- c; true
         | None -> false)
      | Dispatch_phase when not (dispatch_over t) ->
        t.c <- F.dispatch_entry ?observe t.p t.c (pop t) ~pq:Pqueue.empty; maybe_unpack t; true
      | _ -> false

  let dispatch ?observe t = if transfer_next t then false else dispatch_synced ?observe t

  let dispatch_run_synced ~max t =
    if t.pq_runs <> [] && max = max_int && t.pend = 0 && t.c.phase = Dispatch_phase && t.c.cur = None
       && not t.p.ghosts then begin
      (* the runs a Transfer left, dispatched as they are: the variant is
         Reference, so they all go *)
      let runs = t.pq_runs in
      t.pq_runs <- []; t.pq_runs_n <- 0;
      let (c, n) = F.dispatch_lists t.p t.c runs in
      t.c <- c;
      n
    end else begin
    sync t;
    if not t.is_packed then begin
      if max = max_int then
        match F.dispatch_run t.p t.c with
        | Some (c, n) -> t.c <- c; n
        | None -> 0
      else begin
        let n = ref 0 in
        while !n < max && dispatch t do incr n done;
        !n
      end
    end else if t.c.phase = Dispatch_phase && t.c.cur = None && not (dispatch_over t) then begin
      (* the percepts popped from the buckets one by one, as long as
         Dequeue would be enabled: some wait, the budget is not spent *)
      let left = if t.p.variant = Budgeted then min max (t.p.budget - t.c.dispatched) else max in
      (* one reader for the run: a dispatch adds nothing to the queue, and
         nothing else reads it meanwhile *)
      let r = reader t in
      let (c, n) = F.dispatch_from t.p t.c (min left t.pq_n) (fun () -> read_next t r) in
      settle t r;
      t.c <- c;
      maybe_unpack t;
      n
    end else 0
    end

  let dispatch_run ?(max = max_int) t = if transfer_next t then 0 else dispatch_run_synced ~max t
end
