type t =
  | Int of int
  | Str of string
  | Bool of bool
  | Seq of t list
  | Set of t list
  | Rec of (string * t) list
  | Fn of (t * t) list

let rec compare a b = match a, b with
  | Int x, Int y -> Stdlib.compare x y
  | Str x, Str y -> Stdlib.compare x y
  | Bool x, Bool y -> Stdlib.compare x y
  | Seq x, Seq y | Set x, Set y -> List.compare compare x y
  | Rec x, Rec y -> List.compare (fun (f, v) (g, w) ->
      let c = Stdlib.compare f g in if c <> 0 then c else compare v w) x y
  | Fn x, Fn y -> List.compare (fun (k, v) (l, w) ->
      let c = compare k l in if c <> 0 then c else compare v w) x y
  | _ ->
    let tag = function Int _ -> 0 | Str _ -> 1 | Bool _ -> 2 | Seq _ -> 3
                     | Set _ -> 4 | Rec _ -> 5 | Fn _ -> 6 in
    Stdlib.compare (tag a) (tag b)

(* [List.map] in a loop: a long sequence does not grow the stack (the
   nesting, which does, is bounded by [parse]). *)
let map f l = List.rev (List.rev_map f l)

let rec canon = function
  | (Int _ | Str _ | Bool _) as v -> v
  | Seq l -> Seq (map canon l)
  | Set l -> Set (List.sort_uniq compare (map canon l))
  | Rec fs -> Rec (List.sort (fun (f, _) (g, _) -> Stdlib.compare f g)
                     (map (fun (f, v) -> (f, canon v)) fs))
  | Fn kvs -> Fn (List.sort (fun (k, _) (l, _) -> compare k l)
                    (map (fun (k, v) -> (canon k, canon v)) kvs))

let set l = Set (List.sort_uniq compare l)
let record fs = Rec (List.sort (fun (f, _) (g, _) -> Stdlib.compare f g) fs)

(* TLA+ string escapes, as TLC reads and prints them: the only six its
   lexer knows (a quote, a backslash, line feed, tab, carriage return, form
   feed), each a backslash and the letter of this table. The writer
   ([string_literal]) and the reader ([parse]) both use it. *)
let escapes = [ ('"', '"'); ('\\', '\\'); ('\n', 'n'); ('\t', 't'); ('\r', 'r'); ('\012', 'f') ]

let string_literal s =
  let b = Buffer.create (String.length s + 2) in
  Buffer.add_char b '"';
  String.iter (fun c ->
      match List.assoc_opt c escapes with
      | Some letter -> Buffer.add_char b '\\'; Buffer.add_char b letter
      | None when c = '`' || c >= '\128' ->
        invalid_arg (Printf.sprintf "Tla.string_literal: TLC cannot read %C in a string" c)
      | None -> Buffer.add_char b c) s;
  Buffer.add_char b '"';
  Buffer.contents b

let unescape letter =
  List.find_map (fun (c, l) -> if l = letter then Some c else None) escapes

let to_string v =
  let b = Buffer.create 128 in
  let rec go = function
    | Int i -> Buffer.add_string b (string_of_int i)
    | Str s -> Buffer.add_string b (string_literal s)
    | Bool x -> Buffer.add_string b (if x then "TRUE" else "FALSE")
    | Seq l -> Buffer.add_string b "<<"; list l; Buffer.add_string b ">>"
    | Set l -> Buffer.add_char b '{'; list l; Buffer.add_char b '}'
    | Rec fs ->
      Buffer.add_char b '[';
      List.iteri (fun i (f, v) ->
          if i > 0 then Buffer.add_string b ", ";
          Buffer.add_string b f; Buffer.add_string b " |-> "; go v) fs;
      Buffer.add_char b ']'
    | Fn [] -> Buffer.add_string b "<<>>"
    | Fn kvs ->
      Buffer.add_char b '(';
      List.iteri (fun i (k, v) ->
          if i > 0 then Buffer.add_string b " @@ ";
          go k; Buffer.add_string b " :> "; go v) kvs;
      Buffer.add_char b ')'
  and list l = List.iteri (fun i v -> if i > 0 then Buffer.add_string b ", "; go v) l in
  go v;
  Buffer.contents b

exception Parse_error of string

let max_depth = 1000

let parse_prefix s start =
  let n = String.length s in
  let fail i msg = raise (Parse_error (Printf.sprintf "at offset %d: %s" i msg)) in
  let rec ws i = if i < n && (s.[i] = ' ' || s.[i] = '\n' || s.[i] = '\t' || s.[i] = '\r') then ws (i + 1) else i in
  let expect i lit =
    let i = ws i in
    let l = String.length lit in
    if i + l <= n && String.sub s i l = lit then i + l
    else fail i (Printf.sprintf "expected %S" lit) in
  let looking i lit =
    let i = ws i in
    let l = String.length lit in
    i + l <= n && String.sub s i l = lit in
  let ident i =
    let j = ref i in
    while !j < n && (match s.[!j] with 'a'..'z' | 'A'..'Z' | '0'..'9' | '_' -> true | _ -> false) do incr j done;
    if !j = i then fail i "expected a name";
    (String.sub s i (!j - i), !j) in
  (* [depth]: the sequences, sets, records and functions around [i]; at
     most [max_depth] (a model's constants nest a few deep) *)
  let rec value depth i =
    let i = ws i in
    if i >= n then fail i "unexpected end";
    let nested i = if depth >= max_depth then fail i (Printf.sprintf "values nested more than %d deep" max_depth) in
    let value = value (depth + 1) and elements = elements (depth + 1) in
    match s.[i] with
    | '"' ->
      let b = Buffer.create 16 in
      let rec str j =
        if j >= n then fail j "unterminated string"
        else match s.[j] with
          | '"' -> j + 1
          | '\\' when j + 1 < n ->
            (match unescape s.[j + 1] with
             | Some c -> Buffer.add_char b c
             | None -> fail j (Printf.sprintf "unknown string escape \\%c" s.[j + 1]));
            str (j + 2)
          | c -> Buffer.add_char b c; str (j + 1) in
      let j = str (i + 1) in
      (Str (Buffer.contents b), j)
    | '-' | '0'..'9' ->
      let j = ref (i + 1) in
      while !j < n && s.[!j] >= '0' && s.[!j] <= '9' do incr j done;
      (match int_of_string_opt (String.sub s i (!j - i)) with
       | Some k -> (Int k, !j)
       | None -> fail i "bad number")
    | '<' ->
      nested i;
      let i = expect i "<<" in
      if looking i ">>" then (Seq [], expect i ">>")
      else let (l, i) = elements i ">>" in (Seq l, i)
    | '{' ->
      nested i;
      let i = expect i "{" in
      if looking i "}" then (Set [], expect i "}")
      else let (l, i) = elements i "}" in (Set l, i)
    | '[' ->
      nested i;
      let i = expect i "[" in
      let rec fields acc i =
        let (f, i) = ident (ws i) in
        let i = expect i "|->" in
        let (v, i) = value i in
        if looking i "," then fields ((f, v) :: acc) (expect i ",")
        else (List.rev ((f, v) :: acc), expect i "]") in
      let (fs, i) = fields [] i in
      (Rec fs, i)
    | '(' ->
      nested i;
      let i = expect i "(" in
      let rec pairs acc i =
        let (k, i) = value i in
        let i = expect i ":>" in
        let (v, i) = value i in
        if looking i "@@" then pairs ((k, v) :: acc) (expect i "@@")
        else (List.rev ((k, v) :: acc), expect i ")") in
      let (kvs, i) = pairs [] i in
      (Fn kvs, i)
    | 'T' when looking i "TRUE" -> (Bool true, expect i "TRUE")
    | 'F' when looking i "FALSE" -> (Bool false, expect i "FALSE")
    | _ -> fail i "unexpected character"
  (* the elements of a sequence or set, in a loop (a long one does not
     grow the stack) *)
  and elements depth i close =
    let rec go acc i =
      let (v, i) = value depth i in
      if looking i "," then go (v :: acc) (expect i ",")
      else (List.rev (v :: acc), expect i close) in
    go [] i in
  let (v, i) = value 0 start in
  (canon v, i)

let parse s =
  let (v, i) = parse_prefix s 0 in
  let rec ws i = if i < String.length s && String.contains " \n\t\r" s.[i] then ws (i + 1) else i in
  if ws i <> String.length s then raise (Parse_error (Printf.sprintf "trailing text at offset %d" i));
  v

let bad what v = invalid_arg (Printf.sprintf "Tla.%s: %s" what (to_string v))

let field f = function
  | Rec fs as v -> (match List.assoc_opt f fs with Some x -> x | None -> bad ("field " ^ f) v)
  | v -> bad ("field " ^ f) v
let to_int = function Int i -> i | v -> bad "to_int" v
let to_str = function Str s -> s | v -> bad "to_str" v
let to_bool = function Bool b -> b | v -> bad "to_bool" v
let to_list = function Seq l | Set l -> l | Fn [] -> [] | v -> bad "to_list" v
