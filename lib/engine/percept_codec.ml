(* The interpreter's percepts as ints: schema values of integer, boolean
   and text slots packed (texts as boxes), everything else boxed whole. See
   percept_codec.mli. *)

module V = Interp_eval.Value

type percept = V.t

(* How a slot is written: an int ([Int], or [Bool] as 0 or 1), or its
   value as a box ([Text], an immutable value: the box is the value). *)
let s_int = 0 and s_bool = 1 and s_text = 2

(* A kind of packed percept: the schema name and slot names as the first
   percept of the kind spelled them, and how each slot is written. *)
type kind = { sname : string; names : string array; how : int array; ktag : int }

type t = {
  mutable kinds : kind array;
  mutable n : int;
  mutable hot : int;
    (* the index in [kinds] of the kind last found, asked first (an int:
       writing it costs no write barrier) *)
}

(* Kind 0 is "boxed whole"; packed kinds are 1 .. max_kinds. *)
let max_kinds = 1023
let max_texts = 3
let boxed_tag = Packed.boxed_tag

let none = { sname = ""; names = [||]; how = [||]; ktag = -1 }
let create () = { kinds = [| none |]; n = 0; hot = 0 }
let kinds c = c.n

let how_of = function
  | V.Int _ -> s_int | V.Bool _ -> s_bool | V.Text _ -> s_text | _ -> -1

(* The slots of [s] are those of kind [k]: the same names, each value of
   the slot's sort. *)
let rec fits_slots (k : kind) (s : V.schema_v) i =
  i < 0
  || (let (name, v) = Array.unsafe_get s.slots i in
      (k.names.(i) == name || String.equal k.names.(i) name)
      && how_of !v = k.how.(i)
      && fits_slots k s (i - 1))

let fits (k : kind) (s : V.schema_v) last = Array.length k.names = last + 1 && fits_slots k s last

(* Every slot an Int, a Bool or a Text: how many Texts; -1 otherwise. *)
let rec texts (s : V.schema_v) i acc =
  if i < 0 then acc
  else match !(snd s.slots.(i)) with
    | V.Int _ | V.Bool _ -> texts s (i - 1) acc
    | V.Text _ -> texts s (i - 1) (acc + 1)
    | _ -> -1

let add c (s : V.schema_v) ~texts =
  let k = { sname = s.sname; names = Array.map fst s.slots;
            how = Array.map (fun (_, v) -> how_of !v) s.slots;
            ktag = Packed.make_tag ~kind:(c.n + 1) ~width:(Array.length s.slots - texts) ~boxes:texts } in
  if c.n = Array.length c.kinds then
    c.kinds <- Array.init (max 4 (2 * c.n)) (fun i -> if i < c.n then c.kinds.(i) else k);
  c.kinds.(c.n) <- k;
  c.n <- c.n + 1;
  k.ktag

(* The kind of [s] among [left] kinds from the [i]th on, round (after
   the last, the first): by the schema name's address (the lexer interns
   names)... *)
let rec by_address c (s : V.schema_v) last i left =
  if left = 0 then -1
  else
    let i = if i >= c.n then 0 else i in
    let k = Array.unsafe_get c.kinds i in
    if k.sname == s.sname && fits k s last then begin c.hot <- i; k.ktag end
    else by_address c s last (i + 1) (left - 1)

(* ... or, for a name spelled by another string, by its text. *)
let rec by_text c (s : V.schema_v) last i =
  if i >= c.n then -1
  else
    let k = Array.unsafe_get c.kinds i in
    if String.equal k.sname s.sname && fits k s last then k.ktag else by_text c s last (i + 1)

let tag c (s : V.schema_v) =
  let last = Array.length s.slots - 1 in
  let h = Array.unsafe_get c.kinds c.hot in
  let t = if h.sname == s.sname && fits h s last then h.ktag else by_address c s last (c.hot + 1) c.n in
  if t >= 0 then t
  else
    let n = texts s last 0 in
    if n < 0 || n > max_texts || last + 1 - n > 255 then boxed_tag
    else
      let t = by_text c s last 0 in
      if t >= 0 then t else if c.n < max_kinds then add c s ~texts:n else boxed_tag

let min32 = - (1 lsl 31) and max32 = (1 lsl 31) - 1

(* The tag of a schema of the one slot [name], written as [how]: the kind
   found by the addresses of the names (what [tag] finds first, without
   asking how each slot is written: here it is known), else [tag]'s
   answer. *)
let rec one_by_address c sname name how i left =
  if left = 0 then -1
  else
    let i = if i >= c.n then 0 else i in
    let k = Array.unsafe_get c.kinds i in
    if k.sname == sname && Array.length k.how = 1 && k.names.(0) == name && k.how.(0) = how
    then begin c.hot <- i; k.ktag end
    else one_by_address c sname name how (i + 1) (left - 1)

let tag_one c (s : V.schema_v) name how =
  let h = Array.unsafe_get c.kinds c.hot in
  if h.sname == s.sname && Array.length h.how = 1 && h.names.(0) == name && h.how.(0) = how then h.ktag
  else
    (* from the kind after the hot one, round: percepts often come in a
       round of kinds, the next after the last *)
    let t = one_by_address c s.sname name how (c.hot + 1) c.n in
    if t >= 0 then t else tag c s

let encode c (p : V.t) r =
  match p with
  | V.Schema s ->
    let t = match s.slots with
      | [| (name, v) |] ->
        (match !v with
         | V.Int _ -> tag_one c s name s_int
         | V.Bool _ -> tag_one c s name s_bool
         | V.Text _ -> tag_one c s name s_text
         | _ -> tag c s)
      | _ -> tag c s in
    if t = boxed_tag then Packed.Ring.push_box r p
    else
      for i = 0 to Array.length s.slots - 1 do
        (* the kind fits: each slot an Int, a Bool or a Text *)
        match !(snd s.slots.(i)) with
        | V.Int n -> Packed.Ring.push r n
        | V.Bool b -> Packed.Ring.push r (if b then 1 else 0)
        | v -> Packed.Ring.push_box r v
      done;
    t
  | _ -> Packed.Ring.push_box r p; boxed_tag

(* The tag and int of a percept of one 32-bit int slot (D8), or the tag of
   one of no slot, for a word (D39); 0 for any other. *)
let encode_one c (p : V.t) =
  match p with
  | V.Schema ({ slots = [| (name, v) |]; _ } as s) ->
    (match !v with
     | V.Int n when n >= min32 && n <= max32 ->
       let t = tag_one c s name s_int in
       if t = boxed_tag then 0 else (n lsl 20) lor t
     | V.Bool b ->
       let t = tag_one c s name s_bool in
       if t = boxed_tag then 0 else ((if b then 1 else 0) lsl 20) lor t
     | _ -> 0)
  | V.Schema ({ slots = [||]; _ } as s) ->
    (* no slot: the kind alone (D39) *)
    let t = tag c s in
    if t = boxed_tag then 0 else t
  | _ -> 0

(* Booleans are immutable values: the two can be shared. *)
let v_true = V.Bool true and v_false = V.Bool false

(* Slot [i] of kind [k], its int the [pos]th of [r] or its box the [box]th:
   a fresh cell each time (a handler may set a slot of its content). *)
let slot (k : kind) r i ~pos ~box =
  let h = k.how.(i) in
  (k.names.(i),
   ref (if h = s_int then V.Int (Packed.Ring.get r pos)
        else if h = s_bool then (if Packed.Ring.get r pos <> 0 then v_true else v_false)
        else Packed.Ring.get_box r box))

let read c tag r ~pos ~box =
  if tag = boxed_tag then Packed.Ring.get_box r box
  else
    let k = c.kinds.(Packed.tag_kind tag - 1) in
    let n = Array.length k.names in
    if n = 0 then V.Schema { sname = k.sname; slots = [||] }
    else if n = 1 then V.Schema { sname = k.sname; slots = [| slot k r 0 ~pos ~box |] }
    else begin
      let a = Array.make n (slot k r 0 ~pos ~box) in
      let pos = ref (if k.how.(0) = s_text then pos else pos + 1)
      and box = ref (if k.how.(0) = s_text then box + 1 else box) in
      for i = 1 to n - 1 do
        a.(i) <- slot k r i ~pos:!pos ~box:!box;
        if k.how.(i) = s_text then incr box else incr pos
      done;
      V.Schema { sname = k.sname; slots = a }
    end

(* A kind of one int slot (a word of the packed agent, D39): the slot's
   int given. *)
let read_int c tag v =
  let k = c.kinds.(Packed.tag_kind tag - 1) in
  if Array.length k.how = 0 then V.Schema { sname = k.sname; slots = [||] }
  else
    let x = if k.how.(0) = s_int then V.Int v else if v <> 0 then v_true else v_false in
    V.Schema { sname = k.sname; slots = [| (k.names.(0), ref x) |] }
