(* Names are short and few per table: the length and five of the bytes (the
   first two, the middle one, the last two) are enough to spread them, and
   cost the same for every name. Collisions only lengthen a probe. *)
let hash (s : string) =
  let n = String.length s in
  if n = 0 then 0
  else
    let h = (n * 0x2f)
            lxor (Char.code (String.unsafe_get s 0) * 0x3b1)
            lxor (Char.code (String.unsafe_get s (n - 1)) * 0x1d9f)
            lxor (Char.code (String.unsafe_get s (n lsr 1)) * 0x9e37) in
    let h = if n > 2 then
        h lxor (Char.code (String.unsafe_get s 1) * 0x5bd1e9)
        lxor (Char.code (String.unsafe_get s (n - 2)) * 0x1b873593)
      else h in
    (h lxor (h lsr 17)) land max_int

(* An empty slot holds [free], a string no caller can have (compared by
   address). [vals] is empty until the first binding gives a filler. *)
let free = String.init 1 (fun _ -> '\000')

type 'a t = { mutable keys : string array; mutable vals : 'a array; mutable size : int }

let rec pow2 n k = if k >= n then k else pow2 n (2 * k)
let create n = { keys = Array.make (pow2 (2 * n) 8) free; vals = [||]; size = 0 }
let length t = t.size

(* The slot of [k], or the free slot where it would go. *)
let slot t k =
  let mask = Array.length t.keys - 1 in
  let rec probe i =
    let x = Array.unsafe_get t.keys i in
    if x == k || x == free || String.equal x k then i else probe ((i + 1) land mask) in
  probe (hash k land mask)

let find_opt t k =
  let i = slot t k in
  if Array.unsafe_get t.keys i == free then None else Some (Array.unsafe_get t.vals i)

let find t k =
  let i = slot t k in
  if Array.unsafe_get t.keys i == free then raise Not_found else Array.unsafe_get t.vals i

let mem t k = Array.unsafe_get t.keys (slot t k) != free

let rec replace t k v =
  if Array.length t.vals = 0 then t.vals <- Array.make (Array.length t.keys) v;
  let i = slot t k in
  if t.keys.(i) != free then t.vals.(i) <- v
  else if 2 * (t.size + 1) > Array.length t.keys then begin
    let keys = t.keys and vals = t.vals in
    t.keys <- Array.make (2 * Array.length keys) free;
    t.vals <- Array.make (2 * Array.length keys) v;
    t.size <- 0;
    Array.iteri (fun j x -> if x != free then replace t x vals.(j)) keys;
    replace t k v
  end else begin
    t.keys.(i) <- k; t.vals.(i) <- v; t.size <- t.size + 1
  end

let iter f t = Array.iteri (fun i k -> if k != free then f k t.vals.(i)) t.keys
