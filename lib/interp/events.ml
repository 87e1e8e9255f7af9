(* The events file: one JSON object per line. *)

type t =
  | Notify of { agent : string; percept : Value.t; default : int; priority : int option }
  | Put of { agent : string; obj : Value.t }
  | Message of { agent : string; perf : string; content : Value.t; during_step : bool }
  | Run of int
  | Run_rules of int
  | Run_idle

(* The fields each action of a line takes (docs/trace-format.md, "Events
   files"): the first field of this table the line has is its action. A
   line with two actions is refused by the match below. *)
let fields_of = [
  "notify", [ "agent"; "notify"; "priority" ];
  "put", [ "agent"; "put" ];
  "message", [ "agent"; "message"; "performative"; "during" ];
  "run", [ "run" ];
]

let parse_line env ~agents ~file line : (t option, (int * string) list) result =
  let errors = ref [] in
  let bad col msg = errors := (col, msg) :: !errors; None in
  let line = String.trim line in
  let r =
    if line = "" || line.[0] = '#' then None
    else match Json_read.of_string line with
      | Error e -> bad e.column ("not JSON: " ^ e.message)
      | Ok (`Assoc fields) ->
        let get f = List.assoc_opt f fields in
        (* the column of a field's name in the line, for an error at that field *)
        let col_of f =
          let key = "\"" ^ f ^ "\"" in
          let n = String.length line and k = String.length key in
          let rec go i = if i + k > n then 1 else if String.sub line i k = key then i + 1 else go (i + 1) in
          go 0 in
        let agent () = match get "agent" with
          | Some (`String a) ->
            (match List.assoc_opt a agents with
             | Some ty -> Some (a, ty)
             | None -> bad 1 (Printf.sprintf "there is no agent %s" a))
          | _ -> bad 1 "this line needs an \"agent\"" in
        let expr what s = match Syntax.Parse.expr ~file s with
          | e -> Some e
          | exception Syntax.Diag.Failed d -> bad d.at.left.column (what ^ ": " ^ d.message) in
        let value e = match Eval.literal_value env e with
          | v -> Some v
          | exception (Eval.Trap (at, m) | Eval.Link (at, m)) -> bad at.left.column m in
        (* each action takes its own fields, and no other (a misspelt
           "priorty" would otherwise be ignored): the table [fields_of] *)
        let action = List.find_opt (fun (a, _) -> get a <> None) fields_of in
        (match action with
         | Some (a, allowed) ->
           List.iter (fun (f, _) ->
               if not (List.mem f allowed) && List.exists (fun (b, _) -> b = f) fields_of = false then
                 ignore (bad (col_of f) (Printf.sprintf "a %S line has no field %S (its fields: %s)" a
                                          (Json_read.printable f) (String.concat ", " allowed)))) fields
         | None -> ());
        if !errors <> [] then None else
        (match get "notify", get "put", get "message", get "run" with
         | Some (`String p), None, None, None ->
           (match agent () with
            | None -> None
            | Some (a, ty) ->
              (match expr "the percept" p with
               | None -> None
               | Some e ->
                 (match Eval.percept_value env ~agent_type:ty e with
                  | (v, default) ->
                    (match get "priority" with
                     | None -> Some (Notify { agent = a; percept = v; default; priority = None })
                     | Some (`Int k) when k >= 0 && k <= 0x7FFF_FFFF ->
                       Some (Notify { agent = a; percept = v; default; priority = Some k })
                     | Some (`Int _ | `Intlit _) ->
                       (* integers are Java's int (D8) *)
                       bad (col_of "priority") "\"priority\" is a natural number of 32 bits (R2a, D8): 0 to 2147483647"
                     | Some _ -> bad (col_of "priority") "\"priority\" is a natural number (R2a)")
                  | exception (Eval.Trap (at, m) | Eval.Link (at, m)) -> bad at.left.column m)))
         | None, Some (`String o), None, None ->
           (* the object is read before the agent, as the messages' order has always been *)
           let e = expr "the object" o in
           (match agent (), e with
            | Some (a, _), Some e -> Option.map (fun v -> Put { agent = a; obj = v }) (value e)
            | _ -> None)
         | None, None, Some (`String c), None ->
           let perf = match get "performative" with
             | None -> Some "inform"
             | Some (`String p) when List.mem p Typing.performatives -> Some p
             | Some _ ->
               bad (col_of "performative")
                 ("\"performative\" is one of the FIPA performatives the language knows: "
                  ^ String.concat ", " Typing.performatives) in
           let e = expr "the content" c in
           (* D42: "during": "step", the message arrives during the agent's
              next behaviour step (R5d) *)
           let during = match get "during" with
             | None -> Some false
             | Some (`String "step") -> Some true
             | Some _ -> bad (col_of "during") "\"during\" is \"step\": the message arrives during the agent's next behaviour step (D42)" in
           (match agent (), e with
            | Some (a, _), Some e ->
              (match value e, perf, during with
               | Some v, Some perf, Some during_step -> Some (Message { agent = a; perf; content = v; during_step })
               | _ -> None)
            | _ -> None)
         | None, None, None, Some (`Int k) when k >= 0 -> Some (Run k)
         | None, None, None, Some (`String "idle") -> Some Run_idle
         | None, None, None, Some (`Assoc [ ("rules", `Int k) ]) when k >= 0 -> Some (Run_rules k)
         | None, None, None, Some (`Assoc _) -> bad 1 "\"run\": {\"rules\": N} takes one field, a natural number"

         | _ -> bad 1 "expected one of \"notify\", \"put\", \"message\" (with \"agent\") or \"run\" (a number, \"idle\" or {\"rules\": N})")
      | Ok _ -> bad 1 "each line is a JSON object" in
  match !errors with
  | [] -> Ok r
  | es -> Error (List.rev es)

(* ------------------------------------------------------ the quick path (D30) *)

(* Most lines of a long events file are one notify of a percept literal,
   such as {"agent":"a","notify":"position(1, 2)"}. [quick_notify] reads
   such a line by hand, without a JSON tree and without the program grammar,
   into the very expression [Syntax.Parse.expr] would build, and evaluates it
   with [Eval.percept_value] as [parse_line] does. It only takes a strict
   subset of what the full path takes: the two fields "agent" and "notify"
   once each, no other field, printable ASCII, no JSON escape but those of
   a quote and a backslash, and a percept made of schema names, calls, integer, decimal, text (no
   escapes) and boolean literals. Any other line, and any line that would be
   an error, is [None]: it goes the full way, which reports it. The test
   "events: quick path = full path" holds the two equal. *)

exception Not_quick

(* The readers below take the text and a position and answer the position
   after what they read; they allocate only what they return. *)

let is_digit c = c >= '0' && c <= '9'
let is_alpha c = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c = '_'
let at s i = if i < String.length s then String.unsafe_get s i else '\000'

let rec spaces s i = if at s i = ' ' then spaces s (i + 1) else i
let rec digits_from s i = if is_digit (at s i) then digits_from s (i + 1) else i
let digits s i = let j = digits_from s i in if j = i then raise Not_quick else j
(* The characters of an identifier after its first: letters, digits, '_'
   (a table: this runs for every byte of every schema name read) *)
let ident_chars = String.init 256 (fun k -> let c = Char.chr k in if is_alpha c || is_digit c then '\001' else '\000')
let rec ident_end s i =
  if i < String.length s && String.unsafe_get ident_chars (Char.code (String.unsafe_get s i)) = '\001'
  then ident_end s (i + 1) else i
(* The end of a text literal's characters: printable ASCII up to a
   backslash (in the JSON line, the text's closing quote is one). *)
let rec text_end s i = match at s i with
  | '"' | '\\' -> i
  | c when c >= ' ' && c <= '~' -> text_end s (i + 1)
  | _ -> raise Not_quick

let mk it = { Syntax.Source.it; at = Syntax.Source.no_region }

(* The lexer's INT and REAL: digit+ ('.' digit+)? (e [+-]? digit+)?. *)
let number s i : Syntax.Ast.expr' * int =
  let j = digits s i in
  let (j, real) = if at s j = '.' then (digits s (j + 1), true) else (j, false) in
  let (j, real) =
    match at s j with
    | 'e' | 'E' ->
      let k = match at s (j + 1) with '+' | '-' -> j + 2 | _ -> j + 1 in
      (digits s k, true)
    | _ -> (j, real) in
  if is_alpha (at s j) || at s j = '.' then raise Not_quick;
  if real then (Lit (Real (String.sub s i (j - i))), j)
  else if j - i <= 18 then begin
    (* at most 18 digits: the value fits, as int_of_string reads it *)
    let n = ref 0 in
    for k = i to j - 1 do n := !n * 10 + (Char.code (String.unsafe_get s k) - 48) done;
    (Lit (Int !n), j)
  end else match int_of_string_opt (String.sub s i (j - i)) with
    | Some n -> (Lit (Int n), j)
    | None -> raise Not_quick

(* Does [s] hold [w] from [i] on? *)
let rec holds_from s i w k =
  let n = String.length w in
  if k + 8 <= n then
    (* eight bytes at a time; the last eight of a word of eight or more
       bytes at once (they may overlap those already compared) *)
    (String.get_int64_ne s (i + k) : int64) = String.get_int64_ne w k
    && (k + 8 = n || (if k + 16 > n then String.get_int64_ne s (i + n - 8) = String.get_int64_ne w (n - 8)
                      else holds_from s i w (k + 8)))
  else k >= n || (String.unsafe_get s (i + k) = String.unsafe_get w k && holds_from s i w (k + 1))
let holds s i w = i + String.length w <= String.length s && holds_from s i w 0

(* A word of at most eight bytes as the eight bytes that start with it and
   the mask of its own, for [holds_packed]. *)
let pack w =
  let b = Bytes.make 8 '\000' and m = Bytes.make 8 '\000' in
  let n = min 8 (String.length w) in
  Bytes.blit_string w 0 b 0 n;
  Bytes.fill m 0 n '\255';
  (Bytes.get_int64_ne b 0, Bytes.get_int64_ne m 0)

(* [holds s i w] for a word of at most eight bytes packed as [p]: one
   comparison where eight bytes of [s] are left from [i]. *)
let holds_packed s i w ((v, m) : int64 * int64) =
  if i + 8 <= String.length s then Int64.logand (String.get_int64_ne s i) m = v
  else holds s i w

(* The program's schema names (never keywords: the program declared them as
   identifiers; checked all the same), for the last type environment seen. *)
let schema_names : (Typing.Tenv.t * string array) option ref = ref None

(* The schema name spelled by [s] from [i] to [j], found without copying it
   (the name itself is answered: the lexer's copy). *)
let schema_name env s i j =
  let names = match !schema_names with
    | Some (e, a) when e == env -> a
    | _ ->
      let a = Array.of_list (List.filter_map (fun (sc : Typing.Tenv.schema) ->
          if Syntax.Lexer.keyword_of_string sc.s_name = None then Some sc.s_name else None)
          (Typing.Tenv.schemas env)) in
      schema_names := Some (env, a); a in
  let len = j - i in
  let rec find k =
    if k >= Array.length names then raise Not_quick
    else let n = names.(k) in
      if String.length n = len && holds s i n then n else find (k + 1) in
  find 0

let rec quick_expr_at env s i : Syntax.Ast.expr * int =
  let open Syntax.Ast in
  match at s i with
  | '-' -> if not (is_digit (at s (i + 1))) then raise Not_quick;
    let (e, j) = number s (i + 1) in (mk (Unop (Neg, mk e)), j)
  | c when is_digit c -> let (e, j) = number s i in (mk e, j)
  | '\\' ->
    (* a text literal: its quotes are escaped in the JSON string *)
    if at s (i + 1) <> '"' then raise Not_quick;
    let j = text_end s (i + 2) in
    if at s j <> '\\' || at s (j + 1) <> '"' then raise Not_quick;
    (mk (Lit (Text (String.sub s (i + 2) (j - i - 2)))), j + 2)
  | c when is_alpha c ->
    let j = ident_end s i in
    if j - i = 4 && holds s i "true" then (mk (Lit (Bool true)), j)
    else if j - i = 5 && holds s i "false" then (mk (Lit (Bool false)), j)
    else
    let id = schema_name env s i j in
    (match id with
     | _ when at s j = '(' ->
       let (args, j) = quick_args env s (j + 1) [] in
       (mk (Call (mk id, args)), j)
     | _ -> (mk (Name id), j))
  | _ -> raise Not_quick

and quick_args env s i acc =
  let (a, j) = quick_expr_at env s (spaces s i) in
  let j = spaces s j in
  match at s j with
  | ',' -> quick_args env s (j + 1) (a :: acc)
  | ')' -> (List.rev (a :: acc), j + 1)
  | _ -> raise Not_quick

(* The percept of the JSON string that starts at [i] (its opening quote),
   read where it stands in the line, as Syntax.Parse.expr reads the
   string's text, for the few forms above (the only names taken are the
   program's schemas; the only JSON escapes met are the quotes of text
   literals); and the position after the string. *)
let quick_expr env s i =
  if at s i <> '"' then raise Not_quick;
  let (e, j) = quick_expr_at env s (i + 1) in
  if at s j <> '"' then raise Not_quick;
  (e, j + 1)

(* The end of a JSON string of printable ASCII whose only escapes are those
   of a quote and a backslash, and whether it has one. *)
let rec string_end s i escaped =
  match at s i with
  | '"' -> (i, escaped)
  | '\\' -> (match at s (i + 1) with
      | '"' | '\\' -> string_end s (i + 2) true
      | _ -> raise Not_quick)
  | c when c >= ' ' && c <= '~' -> string_end s (i + 1) escaped
  | _ -> raise Not_quick

(* A key at [i] (spaces allowed before it and around the colon): [`Agent]
   or [`Notify], and the position of its value. *)
let agent_key = pack "\"agent\"" and notify_key = pack "\"notify\""

let quick_key s i =
  let i = spaces s i in
  let (key, j) =
    (* the letter after the quote tells which key it may be *)
    match at s (i + 1) with
    | 'a' when holds_packed s i "\"agent\"" agent_key -> (`Agent, i + 7)
    | 'n' when holds_packed s i "\"notify\"" notify_key -> (`Notify, i + 8)
    | _ -> raise Not_quick in
  let j = spaces s j in
  if at s j <> ':' then raise Not_quick;
  (key, spaces s (j + 1))

(* The agent named by the JSON string at [i] (no escapes), found without
   copying the name, and the position after it (and its spaces). *)
let quick_agent s i agents =
  if at s i <> '"' then raise Not_quick;
  let (j, escaped) = string_end s (i + 1) false in
  if escaped then raise Not_quick;
  let len = j - i - 1 in
  let rec find = function
    | ((n, _) as a) :: rest -> if String.length n = len && holds s (i + 1) n then a else find rest
    | [] -> raise Not_quick in
  (find agents, spaces s (j + 1))

(* [Eval.percept_value]: the value of the literal, checked to be a percept
   of a type the agent type sees, and that type's default priority. The
   check's answer is remembered for the agent types and percept types met
   (by address: the type names are the program's own strings), for the last
   type environment seen; a literal of a type not met yet goes through
   [Eval.percept_value] itself. *)
let percept_checks : (Typing.Tenv.t * (string * string * int) list ref) option ref = ref None

let quick_percept_value env agent_type e =
  let known = match !percept_checks with
    | Some (en, l) when en == env -> l
    | _ -> let l = ref [] in percept_checks := Some (env, l); l in
  let v = Eval.literal_value env e in
  let rec find = function
    | [] -> None
    | (ty, name, prio) :: rest ->
      if ty == agent_type && (match v with Value.Schema s -> s.sname == name | _ -> false)
      then Some prio else find rest in
  match find !known with
  | Some prio -> (v, prio)
  | None ->
    let (v, prio) = Eval.percept_value env ~agent_type e in
    (match v with
     | Value.Schema s when List.length !known < 64 -> known := (agent_type, s.sname, prio) :: !known
     | _ -> ());
    (v, prio)

(* The commonest percepts, built without an expression: a schema name
   alone, or a call whose slots are integers and texts, each given as an
   integer literal without sign, decimal point or exponent, or a text
   literal (no escapes). The value is the one [Eval.literal_value] gives
   for the expression [quick_expr_at] reads (integer slots take integers as
   they are, text slots texts). Anything else, and an integer out of the
   32-bit range, is [Not_quick] here: [quick_notify] then reads the
   expression. *)
type slot_kind = Int_slot | Text_slot

(* For the last type environment seen: each schema whose name is not a
   keyword, and the kinds of its slots ([None]: a slot of another type). *)
let direct_schemas :
  (Typing.Tenv.t * (Typing.Tenv.schema * slot_kind array option * (int64 * int64)) array) option ref = ref None

(* The schema whose name is at [i] (not followed by a letter, digit or
   '_': a name that begins another, [pos] and [position], does not hide
   it), and the position after the name. *)
let direct_schema env s i =
  let table = match !direct_schemas with
    | Some (e, a) when e == env -> a
    | _ ->
      let kind (_, ty) = match Typing.Types.repr ty with
        | Typing.Types.Integer -> Some Int_slot
        | Typing.Types.Text -> Some Text_slot
        | _ -> None in
      let a = Array.of_list (List.filter_map (fun (sc : Typing.Tenv.schema) ->
          if Syntax.Lexer.keyword_of_string sc.s_name <> None then None
          else
            let kinds = List.map kind sc.s_slots in
            Some (sc, (if List.mem None kinds then None else Some (Array.of_list (List.map Option.get kinds))),
                  pack sc.s_name))
          (Typing.Tenv.schemas env)) in
      direct_schemas := Some (env, a); a in
  let rec find k =
    if k >= Array.length table then raise Not_quick
    else let ((sc : Typing.Tenv.schema), kinds, packed) = table.(k) in
      let len = String.length sc.s_name in
      if (if len <= 8 then holds_packed s i sc.s_name packed else holds s i sc.s_name)
      && not (i + len < String.length s && String.unsafe_get ident_chars (Char.code (String.unsafe_get s (i + len))) = '\001')
      then (sc, kinds, i + len) else find (k + 1) in
  find 0

let direct_slot kind s i : Value.t * int =
  match kind with
  | Int_slot ->
    let j = digits s i in
    (match at s j with '.' | 'e' | 'E' -> raise Not_quick | c when is_alpha c -> raise Not_quick | _ -> ());
    if j - i > 10 then raise Not_quick;
    let n = ref 0 in
    for k = i to j - 1 do n := !n * 10 + (Char.code (String.unsafe_get s k) - 48) done;
    if !n > 0x7FFF_FFFF then raise Not_quick;
    (Value.Int !n, j)
  | Text_slot ->
    if at s i <> '\\' || at s (i + 1) <> '"' then raise Not_quick;
    let j = text_end s (i + 2) in
    if at s j <> '\\' || at s (j + 1) <> '"' then raise Not_quick;
    (Value.Text (String.sub s (i + 2) (j - i - 2)), j + 2)

(* The percept of the JSON string at [i] and the position after it, as
   [quick_expr] then [Eval.literal_value] would give them. *)
let direct_value env s i : Value.t * int =
  if at s i <> '"' then raise Not_quick;
  let i = i + 1 in
  if not (is_alpha (at s i)) then raise Not_quick;
  let (sc, kinds, j) = direct_schema env s i in
  let (v, j) =
    match kinds, sc.s_slots with
    | _, [] when at s j <> '(' -> (Value.Schema { sname = sc.s_name; slots = [||] }, j)
    | Some kinds, (_ :: _ as slots) when at s j = '(' ->
      (* the slots, last first *)
      let rec args k slots i acc =
        match slots with
        | (name, _) :: rest ->
          let (v, i) = direct_slot kinds.(k) s (spaces s i) in
          let acc = (name, ref v) :: acc in
          let i = spaces s i in
          (match at s i, rest with
           | ',', _ :: _ -> args (k + 1) rest (i + 1) acc
           | ')', [] -> (acc, i + 1)
           | _ -> raise Not_quick)
        | [] -> raise Not_quick in
      let (vals, j) = args 0 slots (j + 1) [] in
      let vals = match vals with
        | [ a ] -> [| a |]
        | [ b; a ] -> [| a; b |]
        | [ c; b; a ] -> [| a; b; c |]
        | l -> Array.of_list (List.rev l) in
      (Value.Schema { sname = sc.s_name; slots = vals }, j)
    | _ -> raise Not_quick in
  if at s j <> '"' then raise Not_quick;
  (v, j + 1)

(* [quick_percept_value] for a value built directly: its default priority
   when the check of its type for this agent type is remembered. *)
let direct_percept env agent_type (v : Value.t) =
  match !percept_checks, v with
  | Some (en, l), Value.Schema sv when en == env ->
    let rec find = function
      | [] -> raise Not_quick
      | (ty, name, prio) :: rest -> if ty == agent_type && sv.sname == name then prio else find rest in
    find !l
  | _ -> raise Not_quick

(* The percept at [i]: built directly when it can be, else through its
   expression. *)
let quick_percept env ty s i =
  match
    let (v, j) = direct_value env s i in
    (v, direct_percept env ty v, j)
  with
  | r -> r
  | exception Not_quick ->
    let (e, j) = quick_expr env s i in
    let (v, default) = quick_percept_value env ty e in
    (v, default, j)

let quick_notify env ~agents line =
  match
    if at line 0 <> '{' then raise Not_quick;
    let (k1, i) = quick_key line 1 in
    let (name, v, default, i) = match k1 with
      | `Agent ->
        let ((name, ty), i) = quick_agent line i agents in
        if at line i <> ',' then raise Not_quick;
        let (k2, i) = quick_key line (i + 1) in
        if k2 <> `Notify then raise Not_quick;
        let (v, default, i) = quick_percept env ty line i in
        (name, v, default, spaces line i)
      | `Notify ->
        (* the agent comes after the percept: the percept's text is read
           first, its value once the agent type is known *)
        let j = match quick_expr env line i with (_, j) -> j in
        let j = spaces line j in
        if at line j <> ',' then raise Not_quick;
        let (k2, j) = quick_key line (j + 1) in
        if k2 <> `Agent then raise Not_quick;
        let ((name, ty), j) = quick_agent line j agents in
        let (v, default, _) = quick_percept env ty line i in
        (name, v, default, j) in
    if at line i <> '}' || i + 1 <> String.length line then raise Not_quick;
    Notify { agent = name; percept = v; default; priority = None }
  with
  | e -> Some e
  | exception (Not_quick | Eval.Trap _ | Eval.Link _) -> None

let parse_line_full = parse_line

let parse_line env ~agents ~file line =
  match quick_notify env ~agents line with
  | Some e -> Ok (Some e)
  | None -> parse_line_full env ~agents ~file line

(* The line of an event, as [parse_line] reads it back (a generated events
   file: the bench, tests). *)
let to_line = function
  | Notify { agent; percept; default = _; priority } ->
    Yojson.Safe.to_string (`Assoc ([ "agent", `String agent; "notify", `String (Value.to_literal percept) ]
                                    @ (match priority with Some k -> [ "priority", `Int k ] | None -> [])))
  | Put { agent; obj } -> Yojson.Safe.to_string (`Assoc [ "agent", `String agent; "put", `String (Value.to_literal obj) ])
  | Message { agent; perf; content; during_step } ->
    Yojson.Safe.to_string (`Assoc ([ "agent", `String agent; "message", `String (Value.to_literal content);
                                     "performative", `String perf ]
                                   @ (if during_step then [ "during", `String "step" ] else [])))
  | Run k -> Yojson.Safe.to_string (`Assoc [ "run", `Int k ])
  | Run_idle -> Yojson.Safe.to_string (`Assoc [ "run", `String "idle" ])
  | Run_rules k -> Yojson.Safe.to_string (`Assoc [ "run", `Assoc [ "rules", `Int k ] ])

(* ------------------------------------------------------- reading the file *)

(* The longest line, and the most bytes, an events file may have (README,
   "Limits"): a line longer than this is an error at it and is never held
   in memory; a file longer than that is an error, and is not read past it
   (an endless pipe, /dev/zero). *)
let max_line = 16 * 1024 * 1024
let max_bytes = 1024 * 1024 * 1024

(* Every line of the channel, with its number from 1: the lines
   [input_line] reads (split at each newline, the last one with or without
   its own, a carriage return kept), [None] for one longer than
   [max_line] (not kept: the rest of it is skipped). The channel is read
   64 kB at a time and each byte is looked at once: a line held over from
   one block to the next is added to, never moved (linear in the file).
   [`Stop] ends the reading; so does [max_bytes] read: then [over] is
   called with the line number. *)
let fold_channel ic ~over f init =
  let chunk = Bytes.create 65536 in
  let pending = Buffer.create 256 in
  let long = ref false in   (* the line being read is past max_line *)
  let total = ref 0 in
  (* the first newline in [chunk] from [i] to [stop], or -1 *)
  let rec newline i stop =
    if i + 8 <= stop then begin
      let x = Int64.logxor (Bytes.get_int64_ne chunk i) 0x0A0A0A0A0A0A0A0AL in
      if Int64.logand (Int64.sub x 0x0101010101010101L) (Int64.logand (Int64.lognot x) 0x8080808080808080L) = 0L
      then newline (i + 8) stop
      else newline_byte i stop
    end else newline_byte i stop
  and newline_byte i stop =
    if i >= stop then -1 else if Bytes.unsafe_get chunk i = '\n' then i else newline_byte (i + 1) stop in
  (* the bytes [from, upto) of the chunk join the line being read *)
  let add from upto =
    if not !long then begin
      if Buffer.length pending + (upto - from) > max_line then begin long := true; Buffer.reset pending end
      else Buffer.add_subbytes pending chunk from (upto - from)
    end in
  let line_done () =
    let l = if !long then None else Some (Buffer.contents pending) in
    Buffer.clear pending; long := false; l in
  let rec go acc n =
    match input ic chunk 0 65536 with
    | 0 ->
      if Buffer.length pending > 0 || !long then
        (match f acc n (line_done ()) with `Continue acc | `Stop acc -> acc)
      else acc
    | k ->
      total := !total + k;
      if !total > max_bytes then (over n; acc)
      else lines acc n 0 k
  and lines acc n from k =
    match newline from k with
    | -1 -> add from k; go acc n
    | i ->
      let l =
        if Buffer.length pending = 0 && not !long then
          (if i - from > max_line then None else Some (Bytes.sub_string chunk from (i - from)))
        else (add from i; line_done ()) in
      match f acc n l with
      | `Continue acc -> lines acc (n + 1) (i + 1) k
      | `Stop acc -> acc in
  go init 1

let fold_lines path f init =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      fold_channel ic ~over:(fun _ -> raise (Sys_error (Printf.sprintf "%s: longer than %d bytes" path max_bytes)))
        f init)

(* The lines kept for the run: the good event lines' text, each with its
   newline, in blocks of 1 MB (a longer line in a block of its own), so
   that memory is about the size of these lines and nothing is copied
   twice. *)
type file = {
  env : Typing.Tenv.t;
  agents : (string * string) list;
  name : string;
  mutable blocks : Bytes.t list;   (* in order; each dropped once applied *)
  lines : int;
}

let block_size = 1 lsl 20

let read env ~agents path ~report =
  let problems = ref 0 in
  let blocks = ref [] and current = ref (Bytes.create 0) and used = ref 0 and count = ref 0 in
  let keep l =
    let k = String.length l + 1 in
    if !used + k > Bytes.length !current then begin
      if !used > 0 then blocks := Bytes.sub !current 0 !used :: !blocks;
      current := Bytes.create (max block_size k); used := 0
    end;
    Bytes.blit_string l 0 !current !used (k - 1);
    Bytes.set !current (!used + k - 1) '\n';
    used := !used + k;
    incr count in
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      fold_channel ic
        ~over:(fun n ->
            incr problems;
            report ~line:n ~col:1
              (Printf.sprintf "the events file is longer than %d bytes (1 GiB): it is not read further" max_bytes))
        (fun () n l ->
           (match l with
            | None ->
              incr problems;
              report ~line:n ~col:1 (Printf.sprintf "a line longer than %d bytes (16 MB)" max_line)
            | Some l ->
              match parse_line env ~agents ~file:path l with
              | Ok None -> ()
              | Ok (Some _) -> if !problems = 0 then keep l
              | Error es ->
                List.iter (fun (col, m) -> report ~line:n ~col m) es;
                problems := !problems + List.length es);
           `Continue ()) ());
  if !problems > 0 then Error !problems
  else begin
    if !used > 0 then blocks := Bytes.sub !current 0 !used :: !blocks;
    Ok { env; agents; name = path; blocks = List.rev !blocks; lines = !count }
  end

let length f = f.lines

let rec iter f apply =
  match f.blocks with
  | [] -> ()
  | b :: rest ->
      f.blocks <- rest;
      let n = Bytes.length b in
      let rec go i =
        if i < n then begin
          let j = Bytes.index_from b i '\n' in
          (match parse_line f.env ~agents:f.agents ~file:f.name (Bytes.sub_string b i (j - i)) with
           | Ok (Some e) -> apply e
           | Ok None | Error _ -> Semantics.Fault.crash "Events.iter: a line checked good reads differently");
          go (j + 1)
        end in
      go 0;
      iter f apply

(* Writing: the host's actions as written in a file (generators of test
   inputs, the fuzz campaign: fuzz/). *)
type source =
  | Notify_text of { agent : string; percept : string; priority : int option }
  | Put_text of { agent : string; obj : string }
  | Message_text of { agent : string; perf : string option; content : string; during_step : bool }
  | Run_rounds of int
  | Run_until_idle
  | Run_single_rules of int

let source_to_line = function
  | Notify_text { agent; percept; priority } ->
    Yojson.Safe.to_string (`Assoc ([("agent", `String agent); ("notify", `String percept)]
                                   @ (match priority with Some k -> [("priority", `Int k)] | None -> [])))
  | Put_text { agent; obj } -> Yojson.Safe.to_string (`Assoc [("agent", `String agent); ("put", `String obj)])
  | Message_text { agent; perf; content; during_step } ->
    Yojson.Safe.to_string (`Assoc ([("agent", `String agent); ("message", `String content)]
                                   @ (match perf with Some p -> [("performative", `String p)] | None -> [])
                                   @ (if during_step then [("during", `String "step")] else [])))
  | Run_rounds k -> Yojson.Safe.to_string (`Assoc [("run", `Int k)])
  | Run_until_idle -> Yojson.Safe.to_string (`Assoc [("run", `String "idle")])
  | Run_single_rules k -> Yojson.Safe.to_string (`Assoc [("run", `Assoc [("rules", `Int k)])])
