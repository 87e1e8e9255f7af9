(* Growable circular buffers of ints and of boxed values; see ring.mli. *)

type 'b t = {
  mutable ints : int array;     (* length a power of two *)
  mutable head : int;
  mutable len : int;
  mutable bx : 'b array;        (* [||] or a power of two *)
  mutable bhead : int;
  mutable blen : int;
}

let small = 16

let create () = { ints = Array.make small 0; head = 0; len = 0; bx = [||]; bhead = 0; blen = 0 }

let length r = r.len
let boxes r = r.blen
let is_empty r = r.len = 0 && r.blen = 0

let grow r =
  let n = Array.length r.ints in
  let a = Array.make (2 * n) 0 in
  for i = 0 to r.len - 1 do a.(i) <- r.ints.((r.head + i) land (n - 1)) done;
  r.ints <- a;
  r.head <- 0

let[@inline] push r x =
  if r.len = Array.length r.ints then grow r;
  r.ints.((r.head + r.len) land (Array.length r.ints - 1)) <- x;
  r.len <- r.len + 1

let[@inline] get r i = Array.unsafe_get r.ints ((r.head + i) land (Array.length r.ints - 1))

let[@inline] drop r n =
  r.head <- (r.head + n) land (Array.length r.ints - 1);
  r.len <- r.len - n

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
    if Array.length r.ints > large then begin r.ints <- Array.make small 0; r.head <- 0 end;
    if Array.length r.bx > large then begin r.bx <- [||]; r.bhead <- 0 end
  end

let capacity_words r =
  (* each array: its elements and a header word; the record: 6 + 1 *)
  Array.length r.ints + 1 + (if Array.length r.bx = 0 then 0 else Array.length r.bx + 1) + 7
