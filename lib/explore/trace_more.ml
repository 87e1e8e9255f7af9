(* Checks of a trace beyond Trace_check: bodies against their effects,
   percept literals (trace_more.mli). *)

exception Bad of string

let max_depth = 1000

(* The literal [s] as a value the interpreter writes (Value.to_literal):
   its head's name and number of slots when it is a schema value. *)
let literal_arity s =
  let n = String.length s in
  let fail i fmt = Printf.ksprintf (fun m -> raise (Bad (Printf.sprintf "%s (at byte %d)" m (i + 1)))) fmt in
  let is_name_start c = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c = '_' in
  let is_name c = is_name_start c || (c >= '0' && c <= '9') in
  let rec skip i = if i < n && s.[i] = ' ' then skip (i + 1) else i in
  let looking i t = i + String.length t <= n && String.sub s i (String.length t) = t in
  let name i = let j = ref i in while !j < n && is_name s.[!j] do incr j done; (String.sub s i (!j - i), !j) in
  let rec value depth i =
    if depth > max_depth then fail i "values nested more than %d deep" max_depth;
    let i = skip i in
    if i >= n then fail i "a value expected, found the end";
    match s.[i] with
    | '"' ->
      let rec str j =
        if j >= n then fail i "a text that is not closed"
        else match s.[j] with
          | '"' -> j + 1
          | '\\' -> if j + 1 < n then str (j + 2) else fail j "a text that is not closed"
          | c when Char.code c < 0x20 -> fail j "a control character in a text"
          | _ -> str (j + 1) in
      (None, str (i + 1))
    | '[' -> (None, items depth (i + 1) ']' (fun d j -> snd (value d j)))
    | '{' -> (None, items depth (i + 1) '}' (fun d j ->
        let j = skip (snd (value d j)) in
        if j < n && s.[j] = ':' then snd (value d (j + 1)) else fail j "':' expected in a map"))
    | '-' | '0' .. '9' ->
      if looking i "-Infinity" then (None, i + 9) else begin
        let j = ref (if s.[i] = '-' then i + 1 else i) in
        let digits = !j in
        while !j < n && (match s.[!j] with '0' .. '9' | '.' | 'e' | 'E' -> true
                                          | '+' | '-' -> (s.[!j - 1] = 'e' || s.[!j - 1] = 'E') | _ -> false) do incr j done;
        if !j = digits || not (s.[digits] >= '0' && s.[digits] <= '9') then fail i "a number expected";
        (None, !j)
      end
    | '<' ->
      let (c, j) = name (i + 1) in
      let j = ref j in
      while !j < n && (is_name s.[!j] || s.[!j] = '.' || s.[!j] = '$') do incr j done;
      if c = "" || !j >= n || s.[!j] <> '>' then fail i "a host object <Class> expected";
      (None, !j + 1)
    | c when is_name_start c ->
      let (x, j) = name i in
      if List.mem x [ "true"; "false"; "nothing"; "NaN"; "Infinity" ] then (None, j)
      else if x = "agent" && j < n && s.[j] = ' ' then (None, snd (name (j + 1)))
      else if x = "behaviour" && looking j " #" then
        (None, snd (value depth (j + 2)))
      else if j < n && s.[j] = '(' then begin
        let count = ref 0 in
        let j = items depth (j + 1) ')' (fun d k -> incr count; snd (value d k)) in
        (Some (x, !count), j)
      end else (Some (x, 0), j)
    | c -> fail i "unexpected character %C" c
  (* the items of a list, map or schema value up to [close] *)
  and items depth i close one =
    let i = skip i in
    if i < n && s.[i] = close then i + 1
    else
      let rec go i =
        let i = skip (one (depth + 1) i) in
        if i < n && s.[i] = ',' then go (i + 1)
        else if i < n && s.[i] = close then i + 1
        else fail i "',' or '%c' expected" close in
      go i in
  match value 0 0 with
  | (Some (x, k), j) when skip j = n -> Ok (x, k)
  | (Some _, j) -> Error (Printf.sprintf "text after the value (at byte %d)" (j + 1))
  | (None, _) -> Error "not a percept (a percept type's name, with its slots' values in parentheses)"
  | exception Bad m -> Error m

let show_effect = function
  | Trace.Activated b -> "activate " ^ b
  | Trace.Deactivated -> "deactivate"

let show_effects = function
  | [] -> "none"
  | l -> String.concat ", " (List.map show_effect l)

let check (h : Trace.header) lines =
  (* per agent: the effects its running step declared (the orders
     allowed) and the effects its body events showed, with the step's line *)
  let open_steps : (string, int * Trace.effect list list * Trace.effect list) Hashtbl.t = Hashtbl.create 8 in
  (* R5e, R6: a step's messages leave when the step ends. Per agent, the
     line of its running step (its last line that is not a body line); the
     messages sent and not yet delivered, in the order they must arrive
     (In_flight: per receiver, R5e, and container of the senders, D47),
     each with the sender and the line of the step that sent it; per agent,
     the line at which a message of its running step was delivered, after
     which that step can write nothing more. *)
  let step_line : (string, int) Hashtbl.t = Hashtbl.create 8 in
  let in_flight : int In_flight.t = In_flight.create h in
  let left : (string, int * string) Hashtbl.t = Hashtbl.create 8 in
  let names = Hashtbl.create 16 in
  List.iter (fun (a, _) -> Hashtbl.replace names a ()) h.agents;

  let body_line n agent what =
    match Hashtbl.find_opt left agent with
    | Some (at, receiver) ->
      raise (Bad (Printf.sprintf "%d\000a %s of %s's step, but line %d delivered to %s a message that step sent: \
                                  a step's messages leave when it ends (R5e, R6)" n what agent at receiver))
    | None -> () in
  let arity : (string, int * int) Hashtbl.t = Hashtbl.create 8 in
  let close agent =
    match Hashtbl.find_opt open_steps agent with
    | None -> ()
    | Some (at, allowed, seen) ->
      Hashtbl.remove open_steps agent;
      let seen = List.rev seen in
      if not (List.mem seen allowed) then
        raise (Bad (Printf.sprintf "%d\000the body of this step had the effects [%s], but the step says [%s]"
                      at (show_effects seen) (show_effects (List.hd allowed)))) in
  let percept n p =
    match literal_arity p with
    | Error m -> raise (Bad (Printf.sprintf "%d\000the percept %s does not parse: %s" n
                               (Json_read.printable p) m))
    | Ok (ty, k) ->
      match Hashtbl.find_opt arity ty with
      | None -> Hashtbl.replace arity ty (k, n)
      | Some (k0, n0) when k0 <> k ->
        raise (Bad (Printf.sprintf "%d\000the percept %s has %d slots, but at line %d %s had %d"
                      n (Json_read.printable p) k n0 ty k0))
      | Some _ -> () in
  match
    List.iter (fun (n, (l : Trace.line)) ->
        (match l.event with
         | Trace.Body { body; _ } ->
           body_line n l.agent (Trace.event_name l.event);
           (match body with
            | Trace.Send { receivers; _ } ->
              let at = Option.value (Hashtbl.find_opt step_line l.agent) ~default:0 in
              List.iter (fun r -> if Hashtbl.mem names r then In_flight.push in_flight ~receiver:r ~sender:l.agent at) receivers
            | _ -> ())
         | Trace.Deliver { message = { from; _ }; _ } when Hashtbl.mem names from ->
           (match In_flight.take in_flight ~receiver:l.agent ~sender:from with
            | Some (sender, at) when sender = from && Hashtbl.find_opt step_line sender = Some at ->
              if not (Hashtbl.mem left sender) then Hashtbl.replace left sender (n, l.agent)
            | _ -> ())
         | _ -> ());
        (match l.event with
         | Trace.Body _ -> ()
         | _ -> Hashtbl.replace step_line l.agent n; Hashtbl.remove left l.agent);
        match l.event with
        | Trace.Body { body = Trace.Activate b; _ } ->
          (match Hashtbl.find_opt open_steps l.agent with
           | Some (at, allowed, seen) -> Hashtbl.replace open_steps l.agent (at, allowed, Trace.Activated b :: seen)
           | None -> ())
        | Trace.Body { body = Trace.Deactivate _; _ } ->
          (match Hashtbl.find_opt open_steps l.agent with
           | Some (at, allowed, seen) -> Hashtbl.replace open_steps l.agent (at, allowed, Trace.Deactivated :: seen)
           | None -> ())
        | Trace.Body _ -> ()
        | ev ->
          close l.agent;
          (match ev with
           | Trace.Handle { effects; _ } -> Hashtbl.replace open_steps l.agent (n, [ effects ], [])
           | Trace.Behaviour_step { action_effects; handler; _ } ->
             let a = Option.value action_effects ~default:[] and h = match handler with Some (_, e) -> e | None -> [] in
             Hashtbl.replace open_steps l.agent (n, [ a @ h; h @ a ], [])
           | Trace.Notify { entry; _ } -> percept n entry.percept
           | Trace.Refused { percept = p; _ } -> percept n p
           | _ -> ())) lines;
    (* the last step of each agent *)
    Hashtbl.iter (fun a _ -> close a) (Hashtbl.copy open_steps)
  with
  | () -> Ok ()
  | exception Bad m ->
    match String.index_opt m '\000' with
    | Some i -> Error (int_of_string (String.sub m 0 i), String.sub m (i + 1) (String.length m - i - 1))
    | None -> Error (1, m)
