(* The one reader of JSON (json_read.mli): strict, iterative, bounded in
   depth. *)

let max_depth = 1000

type error = { line : int; column : int; message : string }

exception Bad of int * string   (* the offset, the message *)

let bad i fmt = Printf.ksprintf (fun m -> raise (Bad (i, m))) fmt

let printable s =
  let s = if String.length s > 200 then String.sub s 0 200 ^ "..." else s in
  String.map (fun c -> if c < ' ' || c > '~' then '?' else c) s

(* The arrays and objects not yet closed, innermost first: the elements
   (or fields) read so far, last first; an object also holds the key of
   the value being read, and its keys, in a table once it has many. *)
type frame =
  | Arr of Yojson.Safe.t list
  | Obj of obj
and obj = {
  fields : (string * Yojson.Safe.t) list;
  key : string;
  count : int;
  table : (string, unit) Hashtbl.t option;
}

let is_ws c = c = ' ' || c = '\n' || c = '\r' || c = '\t'

(* The UTF-8 bytes of a code point. *)
let add_utf8 b cp =
  if cp < 0x80 then Buffer.add_char b (Char.unsafe_chr cp)
  else if cp < 0x800 then begin
    Buffer.add_char b (Char.unsafe_chr (0xC0 lor (cp lsr 6)));
    Buffer.add_char b (Char.unsafe_chr (0x80 lor (cp land 0x3F)))
  end else if cp < 0x10000 then begin
    Buffer.add_char b (Char.unsafe_chr (0xE0 lor (cp lsr 12)));
    Buffer.add_char b (Char.unsafe_chr (0x80 lor ((cp lsr 6) land 0x3F)));
    Buffer.add_char b (Char.unsafe_chr (0x80 lor (cp land 0x3F)))
  end else begin
    Buffer.add_char b (Char.unsafe_chr (0xF0 lor (cp lsr 18)));
    Buffer.add_char b (Char.unsafe_chr (0x80 lor ((cp lsr 12) land 0x3F)));
    Buffer.add_char b (Char.unsafe_chr (0x80 lor ((cp lsr 6) land 0x3F)));
    Buffer.add_char b (Char.unsafe_chr (0x80 lor (cp land 0x3F)))
  end

(* The length of the well-formed UTF-8 sequence that starts at [i] (its
   first byte at least 0x80), or 0 (Unicode, table 3-7). *)
let utf8_length s i n =
  let byte k = if i + k < n then Char.code (String.unsafe_get s (i + k)) else -1 in
  let cont k = let c = byte k in c >= 0x80 && c <= 0xBF in
  let b = byte 0 in
  if b >= 0xC2 && b <= 0xDF then (if cont 1 then 2 else 0)
  else if b >= 0xE0 && b <= 0xEF then
    let lo = if b = 0xE0 then 0xA0 else 0x80 and hi = if b = 0xED then 0x9F else 0xBF in
    let b1 = byte 1 in
    if b1 >= lo && b1 <= hi && cont 2 then 3 else 0
  else if b >= 0xF0 && b <= 0xF4 then
    let lo = if b = 0xF0 then 0x90 else 0x80 and hi = if b = 0xF4 then 0x8F else 0xBF in
    let b1 = byte 1 in
    if b1 >= lo && b1 <= hi && cont 2 && cont 3 then 4 else 0
  else 0

let hex s i n =
  if i + 4 > n then bad i "a \\u escape needs four hexadecimal digits";
  let v = ref 0 in
  for k = i to i + 3 do
    let d = match String.unsafe_get s k with
      | '0' .. '9' as c -> Char.code c - 48
      | 'a' .. 'f' as c -> Char.code c - 87
      | 'A' .. 'F' as c -> Char.code c - 55
      | _ -> bad k "a \\u escape needs four hexadecimal digits" in
    v := !v * 16 + d
  done;
  !v

(* The string whose opening quote is at [i - 1]: its text and the offset
   after its closing quote. Copied at once when it has no escape. *)
let read_string s i n =
  let rec plain j =
    if j >= n then bad (i - 1) "a string that is not closed"
    else match String.unsafe_get s j with
      | '"' -> (String.sub s i (j - i), j + 1)
      | '\\' ->
        let b = Buffer.create (j - i + 16) in
        Buffer.add_substring b s i (j - i);
        escaped b j
      | c when c < ' ' -> bad j "a control character (byte %d) inside a string: JSON writes it as an escape" (Char.code c)
      | c when c < '\x80' -> plain (j + 1)
      | _ ->
        let k = utf8_length s j n in
        if k = 0 then bad j "byte %d is not valid UTF-8" (j + 1);
        plain (j + k)
  and escaped b j =
    (* [j]: a backslash *)
    if j + 1 >= n then bad j "a string that is not closed";
    match String.unsafe_get s (j + 1) with
    | '"' -> Buffer.add_char b '"'; rest b (j + 2)
    | '\\' -> Buffer.add_char b '\\'; rest b (j + 2)
    | '/' -> Buffer.add_char b '/'; rest b (j + 2)
    | 'b' -> Buffer.add_char b '\b'; rest b (j + 2)
    | 'f' -> Buffer.add_char b '\012'; rest b (j + 2)
    | 'n' -> Buffer.add_char b '\n'; rest b (j + 2)
    | 'r' -> Buffer.add_char b '\r'; rest b (j + 2)
    | 't' -> Buffer.add_char b '\t'; rest b (j + 2)
    | 'u' ->
      let u = hex s (j + 2) n in
      if u >= 0xD800 && u <= 0xDBFF then begin
        (* the first half of a surrogate pair: the second must follow *)
        if j + 7 < n && String.unsafe_get s (j + 6) = '\\' && String.unsafe_get s (j + 7) = 'u' then begin
          let v = hex s (j + 8) n in
          if v >= 0xDC00 && v <= 0xDFFF then begin
            add_utf8 b (0x10000 + ((u - 0xD800) lsl 10) + (v - 0xDC00));
            rest b (j + 12)
          end else bad j "a \\u escape of a lone surrogate (\\u%04X) is not a character" u
        end else bad j "a \\u escape of a lone surrogate (\\u%04X) is not a character" u
      end else if u >= 0xDC00 && u <= 0xDFFF then
        bad j "a \\u escape of a lone surrogate (\\u%04X) is not a character" u
      else begin add_utf8 b u; rest b (j + 6) end
    | c -> bad j "\\%s is not a JSON escape" (printable (String.make 1 c))
  and rest b j =
    if j >= n then bad (i - 1) "a string that is not closed"
    else match String.unsafe_get s j with
      | '"' -> (Buffer.contents b, j + 1)
      | '\\' -> escaped b j
      | c when c < ' ' -> bad j "a control character (byte %d) inside a string: JSON writes it as an escape" (Char.code c)
      | c when c < '\x80' -> Buffer.add_char b c; rest b (j + 1)
      | _ ->
        let k = utf8_length s j n in
        if k = 0 then bad j "byte %d is not valid UTF-8" (j + 1);
        Buffer.add_substring b s j k;
        rest b (j + k) in
  plain i

let is_digit c = c >= '0' && c <= '9'

(* The number at [i]: its value and the offset after it. *)
let read_number s i n =
  let at k = if k < n then String.unsafe_get s k else '\000' in
  let j = if at i = '-' then i + 1 else i in
  let rec digits k = if is_digit (at k) then digits (k + 1) else k in
  let j =
    if at j = '0' then begin
      if is_digit (at (j + 1)) then bad j "a number does not start with 0 (but 0 itself, or 0.5)";
      j + 1
    end else if is_digit (at j) then digits j
    else bad i "a number needs a digit here" in
  let (j, frac) =
    if at j = '.' then
      (if not (is_digit (at (j + 1))) then bad j "a number needs a digit after its point";
       (digits (j + 1), true))
    else (j, false) in
  let (j, expo) =
    match at j with
    | 'e' | 'E' ->
      let k = match at (j + 1) with '+' | '-' -> j + 2 | _ -> j + 1 in
      if not (is_digit (at k)) then bad j "a number needs a digit in its exponent";
      (digits k, true)
    | _ -> (j, false) in
  let text = String.sub s i (j - i) in
  let v : Yojson.Safe.t =
    if frac || expo then `Float (float_of_string text)
    else match int_of_string_opt text with
      | Some k -> `Int k
      | None -> `Intlit text in
  (v, j)

let word s i n w v =
  let k = String.length w in
  if i + k <= n && String.sub s i k = w then (v, i + k)
  else bad i "not JSON here (a value is an object, an array, a string, a number, true, false or null)"

let parse ~max_depth s =
  let n = String.length s in
  let rec ws i = if i < n && is_ws (String.unsafe_get s i) then ws (i + 1) else i in
  let char_at i = if i < n then String.unsafe_get s i else '\000' in
  let describe i =
    if i >= n then "the end of the text"
    else match String.unsafe_get s i with
      | c when c >= ' ' && c <= '~' -> Printf.sprintf "%C" c
      | c -> Printf.sprintf "byte %d" (Char.code c) in
  (* an object's key at [i] (after white space): the key and the offset
     after its colon *)
  let key i =
    let i = ws i in
    if char_at i <> '"' then bad i "an object's key is a string, not %s" (describe i);
    let (k, j) = read_string s (i + 1) n in
    let j = ws j in
    if char_at j <> ':' then bad j "a colon after an object's key, not %s" (describe j);
    (k, j + 1) in
  let add_key i (o : obj) k =
    (* [o] holds [o.key] and its fields; [k] is the next key *)
    let table = match o.table with
      | Some t -> Hashtbl.replace t o.key (); Some t
      | None when o.count >= 16 ->
        let t = Hashtbl.create 64 in
        Hashtbl.replace t o.key ();
        List.iter (fun (f, _) -> Hashtbl.replace t f ()) o.fields;
        Some t
      | None -> None in
    let seen = match table with
      | Some t -> Hashtbl.mem t k
      | None -> k = o.key || List.exists (fun (f, _) -> f = k) o.fields in
    if seen then bad i "the key %S is in this object twice" (printable k);
    table in
  (* [value i stack depth]: a value starts at [i] *)
  let rec value i stack depth =
    let i = ws i in
    match char_at i with
    | '[' ->
      if depth >= max_depth then bad i "arrays and objects nested more than %d deep" max_depth;
      let j = ws (i + 1) in
      if char_at j = ']' then complete (`List []) (j + 1) stack depth
      else value j (Arr [] :: stack) (depth + 1)
    | '{' ->
      if depth >= max_depth then bad i "arrays and objects nested more than %d deep" max_depth;
      let j = ws (i + 1) in
      if char_at j = '}' then complete (`Assoc []) (j + 1) stack depth
      else begin
        let (k, j) = key j in
        value j (Obj { fields = []; key = k; count = 0; table = None } :: stack) (depth + 1)
      end
    | '"' -> let (t, j) = read_string s (i + 1) n in complete (`String t) j stack depth
    | '-' | '0' .. '9' -> let (v, j) = read_number s i n in complete v j stack depth
    | 't' -> let (v, j) = word s i n "true" (`Bool true) in complete v j stack depth
    | 'f' -> let (v, j) = word s i n "false" (`Bool false) in complete v j stack depth
    | 'n' -> let (v, j) = word s i n "null" `Null in complete v j stack depth
    | _ when i >= n -> bad i "the text ends where a value is expected"
    | _ -> bad i "not JSON here: %s (a value is an object, an array, a string, a number, true, false or null)"
             (describe i)
  (* the value [v] ends before [i] *)
  and complete v i stack depth =
    match stack with
    | [] ->
      let j = ws i in
      if j < n then bad j "%s after the end of the value" (describe j);
      v
    | Arr l :: rest ->
      let j = ws i in
      (match char_at j with
       | ',' -> value (j + 1) (Arr (v :: l) :: rest) depth
       | ']' -> complete (`List (List.rev (v :: l))) (j + 1) rest (depth - 1)
       | _ -> bad j "a comma or ] in an array, not %s" (describe j))
    | Obj o :: rest ->
      let j = ws i in
      (match char_at j with
       | ',' ->
         let (k, after) = key (j + 1) in
         let table = add_key (ws (j + 1)) o k in
         value after (Obj { fields = (o.key, v) :: o.fields; key = k; count = o.count + 1; table } :: rest) depth
       | '}' -> complete (`Assoc (List.rev ((o.key, v) :: o.fields))) (j + 1) rest (depth - 1)
       | _ -> bad j "a comma or } in an object, not %s" (describe j)) in
  value 0 [] 0

(* Line and column (from 1, in bytes) of offset [i]. *)
let locate s i =
  let i = min i (String.length s) in
  let line = ref 1 and start = ref 0 in
  for k = 0 to i - 1 do
    if String.unsafe_get s k = '\n' then begin incr line; start := k + 1 end
  done;
  (!line, i - !start + 1)

let of_string ?(max_depth = max_depth) s =
  match parse ~max_depth s with
  | v -> Ok v
  | exception Bad (i, message) ->
    let (line, column) = locate s i in
    Error { line; column; message }

let of_file ~max_bytes path =
  let ic = open_in_bin path in
  let text = Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      let b = Buffer.create 4096 and chunk = Bytes.create 65536 in
      let rec go () =
        if Buffer.length b > max_bytes then None
        else match input ic chunk 0 65536 with
          | 0 -> Some (Buffer.contents b)
          | k -> Buffer.add_subbytes b chunk 0 k; go () in
      go ()) in
  match text with
  | None -> Error { line = 1; column = 1; message = Printf.sprintf "the file is longer than %d bytes" max_bytes }
  | Some t -> of_string t

let to_string e = Printf.sprintf "%d:%d: %s" e.line e.column e.message
