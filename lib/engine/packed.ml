(* The packed agent: the engine's agent loop with its waiting percepts as
   ints in rings (Ring), beside the reference rules of
   lib/semantics/machine.ml. See packed.mli for the layout; every function
   here computes what a rule of the reference computes, and test/fastpath
   holds [to_config] equal to the reference after every step. *)

open Semantics.Machine
module Pqueue = Semantics.Pqueue
module Fqueue = Semantics.Fqueue

(* Growable circular buffers of ints and of boxed values; see packed.mli.
   Here, in the same unit as the agent, so that its loops inline them. *)
module Ring = struct
  module A = Bigarray.Array1

  (* The ints live outside the OCaml heap: the collector neither copies
     nor scans them (a flood's millions of waiting percepts cost it
     nothing to mark). *)
  type ints = (int, Bigarray.int_elt, Bigarray.c_layout) A.t

  type 'b t = {
    mutable ints : ints;          (* length a power of two *)
    mutable mask : int;           (* its length - 1 *)
    mutable head : int;
    mutable len : int;
    mutable bx : 'b array;        (* [||] or a power of two *)
    mutable bhead : int;
    mutable blen : int;
  }

  let small = 16

  let make_ints n : ints = A.create Bigarray.int Bigarray.c_layout n

  let create () =
    { ints = make_ints small; mask = small - 1; head = 0; len = 0; bx = [||]; bhead = 0; blen = 0 }

  let length r = r.len
  let boxes r = r.blen
  let is_empty r = r.len = 0 && r.blen = 0

  (* Twice the places, the ints copied in order to the front (in at most two
     pieces: from [head] to the end of the array, then from its start). *)
  let grow r =
    let n = r.mask + 1 in
    let a = make_ints (2 * n) in
    let first = min r.len (n - r.head) in
    A.blit (A.sub r.ints r.head first) (A.sub a 0 first);
    if first < r.len then A.blit (A.sub r.ints 0 (r.len - first)) (A.sub a first (r.len - first));
    r.ints <- a;
    r.mask <- 2 * n - 1;
    r.head <- 0

  let[@inline] push r x =
    if r.len > r.mask then grow r;
    A.unsafe_set r.ints ((r.head + r.len) land r.mask) x;
    r.len <- r.len + 1

  let[@inline] get r i = A.unsafe_get r.ints ((r.head + i) land r.mask)

  let[@inline] set r i x = A.unsafe_set r.ints ((r.head + i) land r.mask) x

  let[@inline] drop r n =
    r.head <- (r.head + n) land r.mask;
    r.len <- r.len - n

  (* [n] ints from the front of [src], after skipping [skip] of them, to
     the back of [dst]. *)
  let[@inline] move_front src dst n ~skip =
    while dst.len + n > dst.mask + 1 do grow dst done;
    let a = dst.ints and m = dst.mask and b = src.ints and ms = src.mask in
    let at = dst.head + dst.len and from = src.head + skip in
    for k = 0 to n - 1 do
      A.unsafe_set a ((at + k) land m) (A.unsafe_get b ((from + k) land ms))
    done;
    dst.len <- dst.len + n;
    src.head <- (from + n) land ms;
    src.len <- src.len - n - skip

  (* The front record of [src], a header and [w] ints, moved to the back of
     [dst] with the header [h] instead: Transfer's inner loop. *)
  let[@inline] move_record src dst h w =
    push dst h;
    move_front src dst w ~skip:1

  (* The side ring is made with its first value as the filler of its empty
     places. *)
  let grow_boxes r v =
    let n = Array.length r.bx in
    let a = Array.make (max 8 (2 * n)) v in
    for j = 0 to r.blen - 1 do a.(j) <- r.bx.((r.bhead + j) land (n - 1)) done;
    r.bx <- a;
    r.bhead <- 0

  let push_box r v =
    if r.blen = Array.length r.bx then grow_boxes r v;
    r.bx.((r.bhead + r.blen) land (Array.length r.bx - 1)) <- v;
    r.blen <- r.blen + 1

  let get_box r j = r.bx.((r.bhead + j) land (Array.length r.bx - 1))

  let drop_box r =
    let m = Array.length r.bx - 1 in
    (* the place of the value leaving gets the newest one, still in the ring
       (or the value itself when it was the last) *)
    r.bx.(r.bhead) <- r.bx.((r.bhead + r.blen - 1) land m);
    r.bhead <- (r.bhead + 1) land m;
    r.blen <- r.blen - 1

  (* Above this many places, a drained ring's array is given back. *)
  let large = 1 lsl 16

  let shrink r =
    if r.len = 0 && r.blen = 0 then begin
      if r.mask + 1 > large then begin r.ints <- make_ints small; r.mask <- small - 1; r.head <- 0 end;
      if Array.length r.bx > large then begin r.bx <- [||]; r.bhead <- 0 end
    end

  (* The record (7 fields and a header), the bigarray's block (a custom
     block of 6 words with its header), the side array. *)
  let heap_words r = 8 + 6 + (if Array.length r.bx = 0 then 0 else Array.length r.bx + 1)
  let offheap_words r = r.mask + 1
end

module type CODEC = sig
  type percept
  type t
  val create : unit -> t
  val encode : t -> percept -> percept Ring.t -> int
  val read : t -> int -> percept Ring.t -> pos:int -> box:int -> percept
end

(* A record's header: a priority (O2A ring) or a seq (bucket) and the tag,
   in one int. Priorities are Java ints and seqs count notifies: both fit
   in the 42 bits left (arithmetic shift: a negative one too). *)
let tag_bits = 20
let tag_mask = (1 lsl tag_bits) - 1
let header x tag = (x lsl tag_bits) lor tag
let high h = h asr tag_bits
let tag_of h = h land tag_mask

(* A tag: [kind] (10 bits), [width] (8 bits), [boxes] (2 bits). *)
let make_tag ~kind ~width ~boxes =
  if kind < 0 || kind >= 1024 || width < 0 || width > 255 || boxes < 0 || boxes > 3 then
    invalid_arg "Packed.make_tag";
  (kind lsl 10) lor (width lsl 2) lor boxes
(* A percept that travels as it is, in the ring's side array. *)
let boxed_tag = make_tag ~kind:0 ~width:0 ~boxes:1

let tag_kind tag = tag lsr 10
let tag_width tag = (tag lsr 2) land 255
let tag_boxes tag = tag land 3

module Make (B : Fast.BODIES) (C : CODEC with type percept = B.percept) = struct
  module F = Fast.Make (B)
  module M = F.M

  (* One priority's waiting percepts, oldest first (R3b, stable ties). *)
  type bucket = { bprio : int; ring : B.percept Ring.t }

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
    o2a : B.percept Ring.t;            (* records [prio_tag; slots...] *)
    mutable o2a_n : int;               (* records in the O2A ring *)
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
         its percept [pend_p.(0)], its priority, whether it was NotifyWith *)
    mutable pend_p : B.percept array;   (* [||] until the first notify *)
    mutable pend_prio : int;
    mutable pend_with : bool;
    mutable plain_pend : (B.percept, B.obj) o2a_item list;
      (* plain (and packable): the [pend] notifies' O2A items, newest
         first, not yet in [c.o2a] *)
  }

  let packable p =
    (p.variant = Reference || p.variant = Budgeted) && p.tie = Stable && not p.flood && not p.ghosts

  (* The notifies not yet written into [c], written: what the reference's
     Notify does to the configuration's fields other than O2A (next_seq, an
     idle agent woken, last), once for a run of notifies. *)
  let sync t =
    if t.pend > 0 then begin
      let c = t.c in
      let seq = c.next_seq + t.pend in
      let (o2a, e) = match t.plain_pend with
        | (O_percept e :: _) as items ->
          t.plain_pend <- [];
          (Fqueue.append_newest_first items t.pend c.o2a, e)
        | _ -> (c.o2a, { p = t.pend_p.(0); prio = t.pend_prio; seq }) in
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

  (* Priorities below this one find their bucket in [by_prio], at once. *)
  let small_prios = 64
  let no_bucket = { bprio = min_int; ring = Ring.create () }

  (* The bucket of priority [prio] found in [buckets], or made in its place
     (priorities descending). *)
  let find_or_add t prio =
    let bs = t.buckets in
    let n = Array.length bs in
    let rec find i = if i < n && bs.(i).bprio > prio then find (i + 1) else i in
    let i = find 0 in
    if i < n && bs.(i).bprio = prio then bs.(i)
    else begin
      let b = { bprio = prio; ring = Ring.create () } in
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

  (* The highest non-empty bucket; there is one when [pq_n > 0]. The scan
     starts at [top]: the buckets before it are empty. *)
  let rec first_non_empty t (bs : bucket array) i =
    if Ring.length bs.(i).ring > 0 then begin t.top <- i; bs.(i) end
    else first_non_empty t bs (i + 1)

  let top_bucket t = first_non_empty t t.buckets t.top

  (* The front record of a bucket, decoded into its entry (not removed). *)
  let front_entry t b =
    let h = Ring.get b.ring 0 in
    { p = C.read t.codec (tag_of h) b.ring ~pos:1 ~box:0; prio = b.bprio; seq = high h }

  (* Dequeue's pop (R3b): the highest bucket's oldest record, decoded. *)
  let pop t =
    let b = top_bucket t in
    let e = front_entry t b in
    let tag = tag_of (Ring.get b.ring 0) in
    Ring.drop b.ring (1 + tag_width tag);
    for _ = 1 to tag_boxes tag do Ring.drop_box b.ring done;
    Ring.shrink b.ring;
    t.pq_n <- t.pq_n - 1;
    e

  (* A record of [ring]: the header [h], its ints from [pos], its box (if
     any) the front one; pushed onto bucket [b] with header [h'], and
     removed from [ring]. *)
  let move ring b h' =
    let tag = tag_of h' in
    Ring.move_record ring b.ring h' (tag_width tag);
    for _ = 1 to tag_boxes tag do Ring.push_box b.ring (Ring.get_box ring 0); Ring.drop_box ring done

  (* ------------------------------------------------ packing, projecting *)

  let empty_state ~pack_above p c =
    { p; can_pack = packable p; is_packed = false; pack_above; c; codec = C.create (); o2a = Ring.create (); o2a_n = 0; after = Fqueue.empty;
      buckets = [||]; pq_n = 0; by_prio = Array.make small_prios no_bucket; top = 0;
      pend = 0; pend_p = [||]; pend_prio = 0; pend_with = false; plain_pend = [] }

  (* A record pushed onto [ring]: its header ([x], a priority or a seq, with
     the tag the codec answers), then what the codec writes. *)
  let push_record t ring x percept =
    let at = Ring.length ring in
    Ring.push ring 0;
    let tag = C.encode t.codec percept ring in
    Ring.set ring at (header x tag)

  let push_o2a t (e : B.percept entry) =
    push_record t t.o2a e.prio e.p;
    t.o2a_n <- t.o2a_n + 1

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
    let seen = ref (first - 1) and objects = ref [] and after = ref [] in
    List.iter (function
        | O_percept e -> push_o2a t e; seen := e.seq
        | O_object _ as o -> objects := o :: !objects; after := !seen :: !after) items;
    t.after <- Fqueue.of_list (List.rev !after);
    List.iter (fun (e : B.percept entry) ->
        push_record t (bucket_for t e.prio).ring e.seq e.p;
        t.pq_n <- t.pq_n + 1)
      (Pqueue.to_sorted_list c.pq);
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

  let of_config ?(pack_above = default_pack_above) p (c : M.t) =
    let t = empty_state ~pack_above p c in
    maybe_pack t;
    t

  (* The records of a ring, decoded in order: [header -> percept -> 'a]. *)
  let decode_all t ring n f =
    let pos = ref 0 and box = ref 0 in
    List.init n (fun _ ->
        let h = Ring.get ring !pos in
        let tag = tag_of h in
        let x = f h (C.read t.codec tag ring ~pos:(!pos + 1) ~box:!box) in
        pos := !pos + 1 + tag_width tag;
        box := !box + tag_boxes tag;
        x)

  let to_config t : M.t =
    sync t;
    if not t.is_packed then t.c
    else begin
      let c = t.c in
      let first = c.next_seq - t.o2a_n + 1 in
      let seq = ref (first - 1) in
      let percepts = decode_all t t.o2a t.o2a_n (fun h p ->
          incr seq; { p; prio = high h; seq = !seq }) in
      (* objects go before the first percept notified after them *)
      let rec merge (ps : B.percept entry list) objs = match ps, objs with
        | e :: ps', (a, o) :: objs' ->
          if a < e.seq then o :: merge ps objs' else O_percept e :: merge ps' objs
        | _, [] -> List.map (fun e -> O_percept e) ps
        | [], _ -> List.map snd objs in
      let objs = List.combine (Fqueue.to_list t.after) (Fqueue.to_list c.o2a) in
      let pq = Array.fold_left (fun pq b ->
          let n = ref 0 and pos = ref 0 in
          while !pos < Ring.length b.ring do
            let w = tag_width (tag_of (Ring.get b.ring !pos)) in
            pos := !pos + 1 + w; incr n
          done;
          List.fold_left (fun pq e -> Pqueue.insert e pq) pq
            (decode_all t b.ring !n (fun h p -> { p; prio = b.bprio; seq = high h })))
          Pqueue.empty t.buckets in
      { c with o2a = Fqueue.of_list (merge percepts objs); pq }
    end

  let waiting t =
    sync t;
    if t.is_packed then t.o2a_n + t.pq_n
    else Fqueue.fold (fun n x -> match x with O_percept _ -> n + 1 | O_object _ -> n) 0 t.c.o2a
         + Pqueue.size t.c.pq

  let offheap_words t =
    Array.fold_left (fun n b -> n + Ring.offheap_words b.ring) (Ring.offheap_words t.o2a) t.buckets

  (* -------------------------------------------------------- host rules *)

  (* R2d: the O2A ring's percepts and the objects. *)
  let o2a_has_room t =
    if not t.is_packed then (sync t; M.o2a_has_room t.p t.c)
    else match t.p.o2a_capacity with
      | None -> true
      | Some cap -> t.o2a_n + Fqueue.length t.c.o2a < cap

  (* NotifyEffect: as the reference's, the percept into the O2A ring; the
     rest of the configuration is written by [sync] before anything reads
     it (a host's run of notifies copies no configuration). *)
  let notify_effect t percept prio ~with_ =
    push_record t t.o2a prio percept;
    t.o2a_n <- t.o2a_n + 1;
    t.pend <- t.pend + 1;
    if Array.length t.pend_p = 0 then t.pend_p <- [| percept |] else t.pend_p.(0) <- percept;
    t.pend_prio <- prio;
    t.pend_with <- with_

  (* The same, plain: the O2A item is made now (its seq is known) and
     waits in [plain_pend] until [sync] appends the run to [c.o2a]; the
     label is the last item's. Only where packing could be: the reference's
     NotifyEffect there neither merges seqs (flood) nor keeps waits
     (ghosts). *)
  let notify_plain t percept prio ~with_ =
    let e = { p = percept; prio; seq = t.c.next_seq + t.pend + 1 } in
    t.plain_pend <- O_percept e :: t.plain_pend;
    t.pend <- t.pend + 1;
    t.pend_with <- with_

  let notify t percept prio =
    if t.is_packed then notify_effect t percept prio ~with_:false
    else if t.can_pack then begin notify_plain t percept prio ~with_:false; maybe_pack t end
    else t.c <- M.notify t.p t.c percept prio

  let notify_with t percept prio =
    if t.is_packed then notify_effect t percept prio ~with_:true
    else if t.can_pack then begin notify_plain t percept prio ~with_:true; maybe_pack t end
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

  (* Transfer (R3a): every record of the O2A ring to its priority's bucket,
     in order (so each bucket stays oldest first); the objects stay. *)
  let transfer t =
    let n = t.o2a_n in
    let first = t.c.next_seq - n + 1 in
    for i = 0 to n - 1 do
      let h = Ring.get t.o2a 0 in
      move t.o2a (bucket_for t (high h)) (header (first + i) (tag_of h))
    done;
    t.o2a_n <- 0;
    Ring.shrink t.o2a;
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
      else
        let h = Ring.get t.o2a 0 in
        let p = C.read t.codec (tag_of h) t.o2a ~pos:1 ~box:0 in
        Fqueue.push (O_percept { p; prio = high h; seq = c.next_seq - t.o2a_n + 1 }) c.o2a in
    let pq = if t.pq_n = 0 then Pqueue.empty else Pqueue.insert (front_entry t (top_bucket t)) Pqueue.empty in
    { c with o2a; pq }

  let step t =
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

  let dispatch ?observe t =
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

  let dispatch_run t =
    sync t;
    if not t.is_packed then
      match F.dispatch_run t.p t.c with
      | Some (c, n) -> t.c <- c; n
      | None -> 0
    else begin
      let n = ref 0 in
      while t.c.phase = Dispatch_phase && dispatch t do incr n done;
      !n
    end
end
