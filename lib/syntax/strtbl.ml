(* Names are short and few per table: the length and five of the bytes (the
   first two, the middle one, the last two) are enough to spread them, and
   cost the same for every name. Collisions only lengthen a bucket. *)
let hash (s : string) =
  let n = String.length s in
  if n = 0 then 0
  else
    let b i = Char.code (String.unsafe_get s i) in
    let h = (n * 0x2f) lxor (b 0 * 0x3b1) lxor (b (n - 1) * 0x1d9f) lxor (b (n / 2) * 0x9e37) in
    let h = if n > 2 then h lxor (b 1 * 0x5bd1e9) lxor (b (n - 2) * 0x1b873593) else h in
    h land max_int

include Hashtbl.Make (struct
    type t = string
    let equal (a : string) b = a == b || String.equal a b
    let hash = hash
  end)
