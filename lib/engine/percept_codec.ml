(* The interpreter's percepts as ints: schema values of integer and boolean
   slots packed, everything else boxed. See percept_codec.mli. *)

module V = Interp_eval.Value

type percept = V.t

(* A kind of packed percept: the schema name and slot names as the first
   percept of the kind spelled them, and which slots are booleans. *)
type kind = { sname : string; names : string array; bools : bool array }

type t = { mutable kinds : kind array; mutable n : int }

let max_kinds = 4096

let create () = { kinds = [||]; n = 0 }
let kinds c = c.n

(* Names are interned by the lexer: usually the same string. *)
let same (x : string) y = x == y || String.equal x y

let rec simple_slots (s : V.schema_v) i =
  i >= Array.length s.slots
  || (match !(snd s.slots.(i)) with V.Int _ | V.Bool _ -> simple_slots s (i + 1) | _ -> false)

let rec fits_slots (k : kind) (s : V.schema_v) i =
  i >= Array.length s.slots
  || (same k.names.(i) (fst s.slots.(i))
      && (match !(snd s.slots.(i)) with V.Bool _ -> k.bools.(i) | _ -> not k.bools.(i))
      && fits_slots k s (i + 1))

let fits (k : kind) (s : V.schema_v) =
  same k.sname s.sname && Array.length k.names = Array.length s.slots && fits_slots k s 0

let tag c (p : V.t) =
  match p with
  | V.Schema s when simple_slots s 0 ->
    let rec find i = if i >= c.n then -1 else if fits c.kinds.(i) s then i + 1 else find (i + 1) in
    (match find 0 with
     | -1 when c.n >= max_kinds -> 0
     | -1 ->
       let k = { sname = s.sname; names = Array.map fst s.slots;
                 bools = Array.map (fun (_, v) -> match !v with V.Bool _ -> true | _ -> false) s.slots } in
       if c.n = Array.length c.kinds then
         c.kinds <- Array.init (max 4 (2 * c.n)) (fun i -> if i < c.n then c.kinds.(i) else k);
       c.kinds.(c.n) <- k;
       c.n <- c.n + 1;
       c.n
     | i -> i)
  | _ -> 0

let width c tag = if tag = 0 then 0 else Array.length c.kinds.(tag - 1).names
let boxed _ tag = tag = 0

let write _ tag (p : V.t) r =
  if tag = 0 then Ring.push_box r p
  else match p with
    | V.Schema s ->
      for i = 0 to Array.length s.slots - 1 do
        Ring.push r (match !(snd s.slots.(i)) with
            | V.Int n -> n
            | V.Bool b -> if b then 1 else 0
            | _ -> invalid_arg "Percept_codec.write: not the tag's kind")
      done
    | _ -> invalid_arg "Percept_codec.write: not the tag's kind"

(* Booleans are immutable values: the two can be shared. *)
let v_true = V.Bool true and v_false = V.Bool false

let read c tag r ~pos ~box =
  if tag = 0 then Ring.get_box r box
  else
    let k = c.kinds.(tag - 1) in
    let n = Array.length k.names in
    if n = 0 then V.Schema { sname = k.sname; slots = [||] }
    else
      let slot i =
        let x = Ring.get r (pos + i) in
        (k.names.(i), ref (if k.bools.(i) then (if x <> 0 then v_true else v_false) else V.Int x)) in
      let slots = Array.make n (slot 0) in
      for i = 1 to n - 1 do slots.(i) <- slot i done;
      V.Schema { sname = k.sname; slots }
