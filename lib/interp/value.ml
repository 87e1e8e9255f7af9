module Int_table = struct
  type 'a bucket = Nil | Cons of { key : int; mutable data : 'a; next : 'a bucket }
  type 'a t = { mutable places : 'a bucket array; mutable size : int }

  let create n =
    let rec pow k = if k >= n then k else pow (2 * k) in
    { places = Array.make (pow 8) Nil; size = 0 }

  let[@inline] index t k = k land (Array.length t.places - 1)

  let rec find_or k d = function
    | Nil -> d
    | Cons c -> if c.key = k then c.data else find_or k d c.next

  (* the first of its place's keys asked at once (a key is mostly alone there) *)
  let[@inline] find_default t k d =
    match Array.unsafe_get t.places (index t k) with
    | Cons c when c.key = k -> c.data
    | b -> find_or k d b

  (* Twice as many places once there are twice as many keys as places. *)
  let grow t =
    let old = t.places in
    let places = Array.make (2 * Array.length old) Nil in
    let n = Array.length places - 1 in
    let rec move = function
      | Nil -> ()
      | Cons c -> move c.next; let i = c.key land n in places.(i) <- Cons { c with next = places.(i) } in
    Array.iter move old;
    t.places <- places

  let rec set_in k v = function
    | Nil -> false
    | Cons c -> if c.key = k then (c.data <- v; true) else set_in k v c.next

  let replace t k v =
    let i = index t k in
    if not (set_in k v t.places.(i)) then begin
      t.places.(i) <- Cons { key = k; data = v; next = t.places.(i) };
      t.size <- t.size + 1;
      if t.size > 2 * Array.length t.places then grow t
    end
end

type t =
  | Bool of bool
  | Int of int
  | Float of float
  | Double of float
  | Text of string
  | Aid of string
  | List of list_v
  | Map of map_v
  | Schema of schema_v
  | Native of native
  | Agent_ref of string
  | Behaviour_ref of int
  | Unit

and list_v = { mutable items : t array; mutable len : int }
and map_v = { table : (t * t ref) list Int_table.t; mutable order : (t * t ref) list; mutable size : int }
and schema_v = { sname : string; slots : (string * t ref) array }
and native = { nid : int; cls : string; methods : (string * (t list -> t)) list }

let int32 n = Int (Int32.to_int (Int32.of_int n))
let float32 x = Int32.float_of_bits (Int32.bits_of_float x)

let list_items l = Array.to_list (Array.sub l.items 0 l.len)
let list_of l = let a = Array.of_list l in List { items = a; len = Array.length a }

let tag = function
  | Bool _ -> 0 | Int _ | Float _ | Double _ -> 1 | Text _ -> 2 | Aid _ -> 3
  | List _ -> 4 | Map _ -> 5 | Schema _ -> 6 | Native _ -> 7 | Agent_ref _ -> 8
  | Behaviour_ref _ -> 9 | Unit -> 10

let num = function Int i -> float_of_int i | Float f | Double f -> f | _ -> nan

(* D37: one comparison of two values, or one hash of a value, visits at
   most [max_visits] values: each call of [cmp] or [hsh] below is a visit,
   each time a shared part is reached again, so a value built by sharing
   (a list of two copies of a list of two copies of ...) cannot make an
   operator run for ever. Past the bound, [Too_large]; the evaluator turns
   it into an exhaustion error at the operator. *)
exception Too_large

let max_visits = 10_000_000
let visits = ref 0

let visit () =
  incr visits;
  if !visits > max_visits then raise Too_large

let rec cmp a b =
  visit ();
  if a == b then 0 else
  match a, b with
  | Bool x, Bool y -> Stdlib.compare x y
  | Int x, Int y -> Stdlib.compare x y
  | (Int _ | Float _ | Double _), (Int _ | Float _ | Double _) -> Stdlib.compare (num a) (num b)
  | Text x, Text y | Aid x, Aid y | Agent_ref x, Agent_ref y -> Stdlib.compare x y
  | List x, List y -> List.compare cmp (list_items x) (list_items y)
  | Map x, Map y ->
    List.compare (fun (k1, v1) (k2, v2) -> let c = cmp k1 k2 in if c <> 0 then c else cmp v1 v2)
      (map_bindings x) (map_bindings y)
  | Schema x, Schema y ->
    let c = Stdlib.compare x.sname y.sname in
    if c <> 0 then c
    else List.compare (fun (_, u) (_, v) -> cmp !u !v) (Array.to_list x.slots) (Array.to_list y.slots)
  | Native x, Native y -> Stdlib.compare x.nid y.nid
  | Behaviour_ref x, Behaviour_ref y -> Stdlib.compare x y
  | Unit, Unit -> 0
  | _ -> Stdlib.compare (tag a) (tag b)

(* the bindings in insertion order, without a look-up *)
and map_bindings m = List.rev_map (fun (k, r) -> (k, !r)) m.order

and hsh v =
  visit ();
  match v with
  | Bool b -> if b then 1 else 0
  | Int i -> i
  | Float f | Double f ->
    (* an integral value hashes as the integer it equals (1 = 1.0) *)
    if Float.is_integer f && Float.abs f < 4e18 then int_of_float f else Hashtbl.hash f
  | Text s | Aid s | Agent_ref s -> Hashtbl.hash s
  | List l -> List.fold_left (fun h x -> (h * 31) + hsh x) 7 (list_items l)
  | Map m -> List.fold_left (fun h (k, x) -> (h * 31) + (hsh k * 17) + hsh x) 11 (map_bindings m)
  | Schema s -> Array.fold_left (fun h (_, x) -> (h * 31) + hsh !x) (Hashtbl.hash s.sname) s.slots
  | Native n -> n.nid
  | Behaviour_ref i -> i
  | Unit -> 0

(* Each comparison and each hash starts with a budget of its own (D37). *)
let compare a b = visits := 0; cmp a b
let equal a b = compare a b = 0
let hash v = visits := 0; hsh v

(* A look-up: one hash of the key, then one comparison with each key of the
   same hash. *)
(* An integer key is its own hash and equals another integer key exactly
   when the two are the same number: what [hash] and [equal] answer, after
   one and two visits, far below the bound. *)
let[@inline] key_hash k = match k with Int i -> i land max_int | _ -> hash k land max_int
let[@inline] same_key k k' = match k, k' with Int i, Int j -> i = j | _ -> equal k k'

let rec find_key k = function
  | [] -> None
  | (k', v) :: rest -> if same_key k k' then Some !v else find_key k rest

let map_find m k = find_key k (Int_table.find_default m.table (key_hash k) [])

let map_empty () = Map { table = Int_table.create 8; order = []; size = 0 }

(* [true] when [k] had an entry in [bucket], now bound to [v] *)
let rec set_in_bucket k v = function
  | [] -> false
  | (k', r) :: rest -> if same_key k k' then begin r := v; true end else set_in_bucket k v rest

let map_set m k v =
  let h = key_hash k in
  let bucket = Int_table.find_default m.table h [] in
  let found = match bucket with
    | (k', r) :: _ when same_key k k' -> r := v; true
    | _ -> set_in_bucket k v bucket in
  if not found then begin
    let r = ref v in
    Int_table.replace m.table h ((k, r) :: bucket);
    m.order <- (k, r) :: m.order;
    m.size <- m.size + 1
  end

(* Java's Double.toString / Float.toString: the shortest digits that read
   back as the same value; plain notation for 10^-3 <= |x| < 10^7, otherwise
   d.dddE[-]n; always a digit after the point. *)
let java_text ~single f =
  if Float.is_nan f then "NaN"
  else if f = Float.infinity then "Infinity"
  else if f = Float.neg_infinity then "-Infinity"
  else if f = 0. then (if 1. /. f < 0. then "-0.0" else "0.0")
  else begin
    let same s = let g = float_of_string s in if single then float32 g = f else g = f in
    let rec digits p = let s = Printf.sprintf "%.*e" p f in if p >= 17 || same s then s else digits (p + 1) in
    let e = digits 0 in
    (* e is like "-1.2345e+07": split the mantissa digits and the exponent *)
    let neg = e.[0] = '-' in
    let e = if neg then String.sub e 1 (String.length e - 1) else e in
    let k = String.index e 'e' in
    let mant = String.concat "" (String.split_on_char '.' (String.sub e 0 k)) in
    let exp = int_of_string (String.sub e (k + 1) (String.length e - k - 1)) in
    let mant = (* drop trailing zeros, keep one digit *)
      let n = ref (String.length mant) in
      while !n > 1 && mant.[!n - 1] = '0' do decr n done;
      String.sub mant 0 !n in
    let a = Float.abs f in
    let body =
      if a >= 1e-3 && a < 1e7 then
        if exp >= 0 then
          let ip = if String.length mant > exp + 1 then String.sub mant 0 (exp + 1)
            else mant ^ String.make (exp + 1 - String.length mant) '0' in
          let fp = if String.length mant > exp + 1 then String.sub mant (exp + 1) (String.length mant - exp - 1) else "0" in
          ip ^ "." ^ fp
        else "0." ^ String.make (- exp - 1) '0' ^ mant
      else
        let fp = if String.length mant > 1 then String.sub mant 1 (String.length mant - 1) else "0" in
        String.sub mant 0 1 ^ "." ^ fp ^ "E" ^ string_of_int exp in
    (if neg then "-" else "") ^ body
  end

let float_text f = java_text ~single:false f
let float32_text f = java_text ~single:true f

(* A value's text, written into a buffer: integers by a digit loop, no
   intermediate strings for lists, maps and schema values (the trace
   writes a percept's text on its notify, dequeue and handle lines). *)
let int_digits = Bytes.create 20

let add_int b i =
  if i >= 0 && i < 10 then Buffer.add_char b (Char.unsafe_chr (48 + i))
  else if i >= 0 then begin
    (* the digits from the last, at the end of [int_digits] *)
    let rec put n j =
      Bytes.unsafe_set int_digits j (Char.unsafe_chr (48 + n mod 10));
      if n >= 10 then put (n / 10) (j - 1) else j in
    let first = put i 19 in
    Buffer.add_subbytes b int_digits first (20 - first)
  end else Buffer.add_string b (string_of_int i)

let rec add_show b ~quote v = match v with
  | Bool x -> Buffer.add_string b (if x then "true" else "false")
  | Int i -> add_int b i
  | Float f -> Buffer.add_string b (float32_text f)
  | Double f -> Buffer.add_string b (float_text f)
  | Text s -> Buffer.add_string b (if quote then Syntax.Print.text_literal s else s)
  | Aid a -> Buffer.add_string b "aid("; Buffer.add_string b (Syntax.Print.text_literal a); Buffer.add_char b ')'
  | List l ->
    Buffer.add_char b '[';
    for i = 0 to l.len - 1 do
      if i > 0 then Buffer.add_string b ", ";
      add_show b ~quote:true l.items.(i)
    done;
    Buffer.add_char b ']'
  | Map m ->
    Buffer.add_char b '{';
    List.iteri (fun i (k, x) ->
        if i > 0 then Buffer.add_string b ", ";
        add_show b ~quote:true k; Buffer.add_string b ": "; add_show b ~quote:true x) (map_bindings m);
    Buffer.add_char b '}'
  | Schema s when Array.length s.slots = 0 -> Buffer.add_string b s.sname
  | Schema s ->
    Buffer.add_string b s.sname;
    Buffer.add_char b '(';
    for i = 0 to Array.length s.slots - 1 do
      if i > 0 then Buffer.add_string b ", ";
      add_show b ~quote:true !(snd (Array.unsafe_get s.slots i))
    done;
    Buffer.add_char b ')'
  | Native n -> Buffer.add_char b '<'; Buffer.add_string b n.cls; Buffer.add_char b '>'
  | Agent_ref a -> Buffer.add_string b "agent "; Buffer.add_string b a
  | Behaviour_ref i -> Buffer.add_string b "behaviour #"; add_int b i
  | Unit -> Buffer.add_string b "nothing"

(* one buffer, reused: [add_show] never comes back here *)
let show_buffer = Buffer.create 64

let show ~quote v = match v with
  | Schema s when Array.length s.slots = 0 -> s.sname
  | Text s when not quote -> s
  | _ ->
    Buffer.clear show_buffer;
    add_show show_buffer ~quote v;
    let text = Buffer.contents show_buffer in
    if Buffer.length show_buffer > 65536 then Buffer.reset show_buffer;   (* give a big one back *)
    text

let to_text v = show ~quote:false v
let to_literal v = show ~quote:true v

(* D21: is [show ~quote v] at most [limit] bytes long? Counted as [show]
   builds it, and given up as soon as the count passes the limit, so the
   answer costs at most about [limit] steps even when a map holds the same
   big value many times. *)
exception Over

let printed_within ~quote limit v =
  let n = ref 0 in
  let add k = n := !n + k; if !n > limit then raise Over in
  let rec go ~quote v = match v with
    | List l ->
      add 2; List.iteri (fun i x -> if i > 0 then add 2; go ~quote:true x) (list_items l)
    | Map m ->
      add 2;
      List.iteri (fun i (k, x) -> if i > 0 then add 2; go ~quote:true k; add 2; go ~quote:true x) (map_bindings m)
    | Schema s when Array.length s.slots > 0 ->
      add (String.length s.sname + 2);
      Array.iteri (fun i (_, x) -> if i > 0 then add 2; go ~quote:true !x) s.slots
    | Text t when not quote -> add (String.length t)
    | v -> add (String.length (show ~quote v)) in
  match go ~quote v with () -> true | exception Over -> false

let type_name = function
  | Bool _ -> "boolean" | Int _ -> "integer" | Float _ -> "float" | Double _ -> "double"
  | Text _ -> "text" | Aid _ -> "aid" | List _ -> "list" | Map _ -> "map"
  | Schema s -> s.sname | Native _ -> "any" | Agent_ref _ -> "agent"
  | Behaviour_ref _ -> "behaviour" | Unit -> "nothing"
