(* The events file: one JSON object per line. *)

type t =
  | Notify of { agent : string; percept : Value.t; default : int; priority : int option }
  | Put of { agent : string; obj : Value.t }
  | Message of { agent : string; perf : string; content : Value.t }
  | Run of int
  | Run_idle

let parse_line env ~agents ~file line : (t option, (int * string) list) result =
  let errors = ref [] in
  let bad col msg = errors := (col, msg) :: !errors; None in
  let line = String.trim line in
  let r =
    if line = "" || line.[0] = '#' then None
    else match Yojson.Safe.from_string line with
      | exception Yojson.Json_error m ->
        bad 1 ("not a JSON object: " ^ String.concat " " (String.split_on_char '\n' m))
      | `Assoc fields ->
        let get f = List.assoc_opt f fields in
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
                     | Some (`Int k) when k >= 0 -> Some (Notify { agent = a; percept = v; default; priority = Some k })
                     | Some _ -> bad 1 "\"priority\" is a natural number (R2a)")
                  | exception (Eval.Trap (at, m) | Eval.Link (at, m)) -> bad at.left.column m)))
         | None, Some (`String o), None, None ->
           (* the object is read before the agent, as the messages' order has always been *)
           let e = expr "the object" o in
           (match agent (), e with
            | Some (a, _), Some e -> Option.map (fun v -> Put { agent = a; obj = v }) (value e)
            | _ -> None)
         | None, None, Some (`String c), None ->
           let perf = match get "performative" with Some (`String p) -> p | _ -> "inform" in
           let e = expr "the content" c in
           (match agent (), e with
            | Some (a, _), Some e -> Option.map (fun v -> Message { agent = a; perf; content = v }) (value e)
            | _ -> None)
         | None, None, None, Some (`Int k) when k >= 0 -> Some (Run k)
         | None, None, None, Some (`String "idle") -> Some Run_idle
         | _ -> bad 1 "expected one of \"notify\", \"put\", \"message\" (with \"agent\") or \"run\" (a number or \"idle\")")
      | _ -> bad 1 "each line is a JSON object" in
  match !errors with
  | [] -> Ok r
  | es -> Error (List.rev es)

(* ------------------------------------------------- the quick path (issue 17) *)

(* Most lines of a long events file are one notify of a percept literal,
   such as {"agent":"a","notify":"position(1, 2)"}. [quick_notify] reads
   such a line by hand, without a JSON tree and without the program grammar,
   into the very expression [Syntax.Parse.expr] would build, and evaluates it
   with [Eval.percept_value] as [parse_line] does. It only takes a strict
   subset of what the full path takes: the two fields "agent" and "notify"
   once each, no other field, printable ASCII, no JSON escape but those of
   a quote and a backslash, and a percept made of names, calls, integer, decimal, text (no
   escapes) and boolean literals. Any other line, and any line that would be
   an error, is [None]: it goes the full way, which reports it. The test
   "events: quick path = full path" holds the two equal. *)

exception Not_quick

let quick_expr s : Syntax.Ast.expr =
  let open Syntax.Ast in
  let n = String.length s in
  let pos = ref 0 in
  let peek () = if !pos < n then s.[!pos] else '\000' in
  let spaces () = while !pos < n && s.[!pos] = ' ' do incr pos done in
  let mk it = { Syntax.Source.it; at = Syntax.Source.no_region } in
  let is_digit c = c >= '0' && c <= '9' in
  let is_alpha c = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c = '_' in
  let digits () =
    let start = !pos in
    while is_digit (peek ()) do incr pos done;
    if !pos = start then raise Not_quick in
  (* the lexer's INT and REAL: digit+ ('.' digit+)? (e [+-]? digit+)? *)
  let number () =
    let start = !pos in
    digits ();
    let real = ref false in
    if peek () = '.' then (incr pos; digits (); real := true);
    if peek () = 'e' || peek () = 'E' then begin
      incr pos;
      if peek () = '+' || peek () = '-' then incr pos;
      digits (); real := true
    end;
    if is_alpha (peek ()) || peek () = '.' then raise Not_quick;
    let text = String.sub s start (!pos - start) in
    if !real then Lit (Real text)
    else match int_of_string_opt text with
      | Some i -> Lit (Int i)
      | None -> raise Not_quick in
  let rec expr () =
    match peek () with
    | '-' -> incr pos; if not (is_digit (peek ())) then raise Not_quick; mk (Unop (Neg, mk (number ())))
    | c when is_digit c -> mk (number ())
    | '"' ->
      incr pos;
      let start = !pos in
      while !pos < n && s.[!pos] <> '"' && s.[!pos] <> '\\' do incr pos done;
      if peek () <> '"' then raise Not_quick;
      let t = String.sub s start (!pos - start) in
      incr pos;
      mk (Lit (Text t))
    | c when is_alpha c ->
      let start = !pos in
      while is_alpha (peek ()) || is_digit (peek ()) do incr pos done;
      let id = String.sub s start (!pos - start) in
      (match id with
       | "true" -> mk (Lit (Bool true))
       | "false" -> mk (Lit (Bool false))
       | _ when Syntax.Lexer.keyword_of_string id <> None -> raise Not_quick
       | _ ->
         if peek () = '(' then begin
           incr pos;
           let rec args acc =
             spaces ();
             let a = expr () in
             spaces ();
             match peek () with
             | ',' -> incr pos; args (a :: acc)
             | ')' -> incr pos; List.rev (a :: acc)
             | _ -> raise Not_quick in
           let a = args [] in
           mk (Call (mk id, a))
         end else mk (Name id))
    | _ -> raise Not_quick in
  let e = expr () in
  if !pos <> n then raise Not_quick;
  e

(* A JSON string of printable ASCII at [!pos] in [line], whose only escapes
   are those of a quote and a backslash. *)
let quick_string line pos =
  let n = String.length line in
  if !pos >= n || line.[!pos] <> '"' then raise Not_quick;
  incr pos;
  let start = !pos in
  let plain = ref true in
  let rec go () =
    if !pos >= n then raise Not_quick;
    match line.[!pos] with
    | '"' -> ()
    | '\\' ->
      plain := false;
      if !pos + 1 < n && (line.[!pos + 1] = '"' || line.[!pos + 1] = '\\') then (pos := !pos + 2; go ())
      else raise Not_quick
    | c when c >= ' ' && c <= '~' -> incr pos; go ()
    | _ -> raise Not_quick in
  go ();
  let raw = String.sub line start (!pos - start) in
  incr pos;
  if !plain then raw
  else begin
    let b = Buffer.create (String.length raw) in
    let i = ref 0 in
    while !i < String.length raw do
      if raw.[!i] = '\\' then incr i;
      Buffer.add_char b raw.[!i];
      incr i
    done;
    Buffer.contents b
  end

let quick_notify env ~agents line =
  match
    let n = String.length line in
    let pos = ref 0 in
    let spaces () = while !pos < n && line.[!pos] = ' ' do incr pos done in
    let expect c = spaces (); if !pos < n && line.[!pos] = c then incr pos else raise Not_quick in
    let agent = ref None and percept = ref None in
    let field () =
      spaces ();
      let key = quick_string line pos in
      expect ':';
      spaces ();
      let v = quick_string line pos in
      match key with
      | "agent" when !agent = None -> agent := Some v
      | "notify" when !percept = None -> percept := Some v
      | _ -> raise Not_quick in
    if n = 0 || line.[0] <> '{' then raise Not_quick;
    incr pos;
    field ();
    expect ',';
    field ();
    expect '}';
    if !pos <> n then raise Not_quick;
    match !agent, !percept with
    | Some a, Some p ->
      (match List.assoc_opt a agents with
       | None -> raise Not_quick
       | Some ty ->
         let (v, default) = Eval.percept_value env ~agent_type:ty (quick_expr p) in
         Notify { agent = a; percept = v; default; priority = None })
    | _ -> raise Not_quick
  with
  | e -> Some e
  | exception (Not_quick | Eval.Trap _ | Eval.Link _) -> None

let parse_line_full = parse_line

let parse_line env ~agents ~file line =
  match quick_notify env ~agents line with
  | Some e -> Ok (Some e)
  | None -> parse_line_full env ~agents ~file line

(* Every line of the file, one at a time, with its number. *)
let fold_lines path f init =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      let rec go acc n =
        match input_line ic with
        | exception End_of_file -> acc
        | l -> match f acc n l with
          | `Continue acc -> go acc (n + 1)
          | `Stop acc -> acc in
      go init 1)

let check env ~agents path ~report =
  fold_lines path (fun count n line ->
      match parse_line env ~agents ~file:path line with
      | Ok _ -> `Continue count
      | Error es ->
        List.iter (fun (col, m) -> report ~line:n ~col m) es;
        `Continue (count + List.length es)) 0

let iter env ~agents path ~report f =
  fold_lines path (fun ok n line ->
      match parse_line env ~agents ~file:path line with
      | Ok None -> `Continue ok
      | Ok (Some e) -> f e; `Continue ok
      | Error es ->
        List.iter (fun (col, m) -> report ~line:n ~col m) es;
        `Stop false) true

