(* The interpreter's percepts as ints: schema values of integer and boolean
   slots packed, everything else boxed. See percept_codec.mli. *)

module V = Interp_eval.Value

type percept = V.t

(* A kind of packed percept: the schema name and slot names as the first
   percept of the kind spelled them, and which slots are booleans. *)
type kind = { sname : string; names : string array; bools : bool array; ktag : int }

type t = {
  mutable kinds : kind array;
  mutable n : int;
  mutable hot : kind;          (* the kind last found: asked first *)
}

(* Kind 0 is "boxed"; packed kinds are 1 .. max_kinds. *)
let max_kinds = 2047
let boxed_tag = Packed.make_tag ~kind:0 ~width:0 ~boxed:true

let none = { sname = ""; names = [||]; bools = [||]; ktag = -1 }
let create () = { kinds = [||]; n = 0; hot = none }
let kinds c = c.n

(* Names are interned by the lexer: usually the same string. *)
let same (x : string) y = x == y || String.equal x y

(* The slots of [s] are those of kind [k]: the same names, an [Int] where
   [k] has an integer, a [Bool] where it has a boolean. *)
let rec fits_slots (k : kind) (s : V.schema_v) i =
  i < 0
  || (let (name, v) = Array.unsafe_get s.slots i in
      same k.names.(i) name
      && (match !v with V.Int _ -> not k.bools.(i) | V.Bool _ -> k.bools.(i) | _ -> false)
      && fits_slots k s (i - 1))

let rec simple_slots (s : V.schema_v) i =
  i < 0 || (match !(snd s.slots.(i)) with V.Int _ | V.Bool _ -> simple_slots s (i - 1) | _ -> false)

let add c (s : V.schema_v) =
  let k = { sname = s.sname; names = Array.map fst s.slots;
            bools = Array.map (fun (_, v) -> match !v with V.Bool _ -> true | _ -> false) s.slots;
            ktag = Packed.make_tag ~kind:(c.n + 1) ~width:(Array.length s.slots) ~boxed:false } in
  if c.n = Array.length c.kinds then
    c.kinds <- Array.init (max 4 (2 * c.n)) (fun i -> if i < c.n then c.kinds.(i) else k);
  c.kinds.(c.n) <- k;
  c.n <- c.n + 1;
  k.ktag

let fits (k : kind) (s : V.schema_v) last = Array.length k.names = last + 1 && fits_slots k s last

(* The kind of [s] among the kinds from [i] on: by the schema name's
   address (the lexer interns names)... *)
let rec by_address c (s : V.schema_v) last i =
  if i >= c.n then -1
  else
    let k = Array.unsafe_get c.kinds i in
    if k.sname == s.sname && fits k s last then begin c.hot <- k; k.ktag end
    else by_address c s last (i + 1)

(* ... or, for a name spelled by another string, by its text. *)
let rec by_text c (s : V.schema_v) last i =
  if i >= c.n then -1
  else
    let k = Array.unsafe_get c.kinds i in
    if String.equal k.sname s.sname && fits k s last then k.ktag else by_text c s last (i + 1)

let tag c (s : V.schema_v) =
  let last = Array.length s.slots - 1 in
  let h = c.hot in
  let t = if h.sname == s.sname && fits h s last then h.ktag else by_address c s last 0 in
  if t >= 0 then t
  else if last < 255 && simple_slots s last then
    let t = by_text c s last 0 in
    if t >= 0 then t else if c.n < max_kinds then add c s else boxed_tag
  else boxed_tag

let encode c (p : V.t) r =
  match p with
  | V.Schema s ->
    let t = tag c s in
    if t = boxed_tag then Packed.Ring.push_box r p
    else
      for i = 0 to Array.length s.slots - 1 do
        (* the kind fits: each slot an Int or a Bool *)
        Packed.Ring.push r (match !(snd s.slots.(i)) with
            | V.Int n -> n
            | V.Bool true -> 1
            | _ -> 0)
      done;
    t
  | _ -> Packed.Ring.push_box r p; boxed_tag

(* Booleans are immutable values: the two can be shared. *)
let v_true = V.Bool true and v_false = V.Bool false

let value (k : kind) i x = if k.bools.(i) then (if x <> 0 then v_true else v_false) else V.Int x

(* Slot [i] of a percept of kind [k] whose ints start at [pos]: a fresh
   cell each time (a handler may set a slot of its content). *)
let slot (k : kind) r pos i = (k.names.(i), ref (value k i (Packed.Ring.get r (pos + i))))

let read c tag r ~pos ~box =
  if tag = boxed_tag then Packed.Ring.get_box r box
  else
    let k = c.kinds.(Packed.tag_kind tag - 1) in
    let slots = match Array.length k.names with
      | 0 -> [||]
      | 1 -> [| (k.names.(0), ref (value k 0 (Packed.Ring.get r pos))) |]
      | 2 -> let a = slot k r pos 0 in [| a; slot k r pos 1 |]
      | n -> let a = Array.make n (slot k r pos 0) in for i = 1 to n - 1 do a.(i) <- slot k r pos i done; a in
    V.Schema { sname = k.sname; slots }
