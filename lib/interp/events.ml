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

(* Writing: the host's actions as written in a file (generators of test
   inputs, the fuzz campaign: fuzz/). *)
type source =
  | Notify_text of { agent : string; percept : string; priority : int option }
  | Put_text of { agent : string; obj : string }
  | Message_text of { agent : string; perf : string option; content : string }
  | Run_rounds of int
  | Run_until_idle

let to_line = function
  | Notify_text { agent; percept; priority } ->
    Yojson.Safe.to_string (`Assoc ([("agent", `String agent); ("notify", `String percept)]
                                   @ (match priority with Some k -> [("priority", `Int k)] | None -> [])))
  | Put_text { agent; obj } -> Yojson.Safe.to_string (`Assoc [("agent", `String agent); ("put", `String obj)])
  | Message_text { agent; perf; content } ->
    Yojson.Safe.to_string (`Assoc ([("agent", `String agent); ("message", `String content)]
                                   @ (match perf with Some p -> [("performative", `String p)] | None -> [])))
  | Run_rounds k -> Yojson.Safe.to_string (`Assoc [("run", `Int k)])
  | Run_until_idle -> Yojson.Safe.to_string (`Assoc [("run", `String "idle")])
