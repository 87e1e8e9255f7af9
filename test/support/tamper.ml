(* Tampered traces: tamper.mli. The lines are handled as JSON values, since
   most tamperings make lines that no Trace.event can stand for. *)

type t = { name : string;
           apply : Random.State.t -> string list -> string list option }

type j = Yojson.Safe.t

let get k (j : j) = match j with `Assoc f -> List.assoc_opt k f | _ -> None
let str k j = match get k j with Some (`String s) -> s | _ -> ""
let int k j = match get k j with Some (`Int i) -> i | _ -> 0
let has k j = get k j <> None

let set k v (j : j) : j =
  match j with
  | `Assoc f when List.mem_assoc k f -> `Assoc (List.map (fun (k', x) -> if k' = k then (k', v) else (k', x)) f)
  | `Assoc f -> `Assoc (f @ [ (k, v) ])
  | j -> j

let remove k (j : j) : j = match j with `Assoc f -> `Assoc (List.remove_assoc k f) | j -> j

let event j = str "event" j
let agent j = str "agent" j

(* A trace: the header and the events, in file order. *)
type trace = { header : j; events : j list }

let load lines =
  match List.map Yojson.Safe.from_string (List.filter (fun l -> String.trim l <> "") lines) with
  | header :: events -> Some { header; events }
  | [] -> None
  | exception Yojson.Json_error _ -> None

let renumber es = List.mapi (fun i e -> set "step" (`Int (i + 1)) e) es
let out header events = Some (Yojson.Safe.to_string header :: List.map Yojson.Safe.to_string events)

let pick rng = function [] -> None | l -> Some (List.nth l (Random.State.int rng (List.length l)))

let indexed es = List.mapi (fun i e -> (i, e)) es
let nth es i = List.nth es i

let header_agents h = match get "agents" h with
  | Some (`List l) -> List.map (fun a -> (str "name" a, str "type" a)) l
  | _ -> []

(* Every agent of the header was destroyed: the run ended (D14). *)
let complete t =
  List.for_all (fun (n, _) -> List.exists (fun e -> event e = "destroy" && agent e = n) t.events) (header_agents t.header)

let is_body e = List.mem (event e) [ "log"; "invoke"; "send"; "activate"; "deactivate"; "error" ]

(* [lines] -> the header edited by [f]. *)
let header name f = { name; apply = fun rng lines ->
    match load lines with
    | None -> None
    | Some t -> Option.bind (f rng t.header) (fun h -> out h t.events) }

(* One event among those [p] accepts, edited by [f]. *)
let edit name p f = { name; apply = fun rng lines ->
    match load lines with
    | None -> None
    | Some t ->
      let cands = List.filter (fun (i, e) -> p t i e) (indexed t.events) in
      Option.bind (pick rng cands) (fun (i, e) ->
          Option.bind (f rng t e) (fun e' ->
              out t.header (List.mapi (fun k x -> if k = i then e' else x) t.events))) }

(* The events rearranged by [f] (which picks where), renumbered. *)
let rearrange name f = { name; apply = fun rng lines ->
    match load lines with
    | None -> None
    | Some t -> Option.bind (f rng t) (fun es -> out t.header (renumber es)) }

let move_before es ~from ~to_ =
  let x = nth es from in
  let rest = List.filteri (fun k _ -> k <> from) es in
  List.concat (List.mapi (fun k e -> if k = to_ then [ x; e ] else [ e ]) rest)

let insert_after es i x = List.concat (List.mapi (fun k e -> if k = i then [ e; x ] else [ e ]) es)
let drop es i = List.filteri (fun k _ -> k <> i) es

let is ev = fun _ _ e -> event e = ev
let changed s = s ^ "X"

(* Another percept: one this agent was notified with another literal, else a
   made-up one. *)
let other_percept rng t e =
  let p = str "percept" e in
  let others = List.sort_uniq compare (List.filter_map (fun x ->
      if event x = "notify" && agent x = agent e && str "percept" x <> p then Some (str "percept" x) else None) t.events) in
  match pick rng others with Some q -> q | None -> "other(" ^ p ^ ")"

let from_agent _ _ e = event e = "deliver" && str "from" e <> "host"

let agent_message e = match get "message" e with Some (`Assoc _ as m) when has "performative" m -> Some m | _ -> None

let all = [
  (* --- the header *)
  header "header: version 99" (fun _ h -> Some (set "version" (`Int 99) h));
  header "header: version as a text" (fun _ h -> Some (set "version" (`String "1") h));
  header "header: no version" (fun _ h -> Some (remove "version" h));
  header "header: unknown variant" (fun _ h -> Some (set "variant" (`String "quantum") h));
  header "header: unknown tie policy" (fun _ h -> Some (set "tie_policy" (`String "fifo") h));
  header "header: agent type other than its create's" (fun rng h ->
      match get "agents" h with
      | Some (`List l) when l <> [] ->
        let k = Random.State.int rng (List.length l) in
        Some (set "agents" (`List (List.mapi (fun i a -> if i = k then set "type" (`String (changed (str "type" a))) a else a) l)) h)
      | _ -> None);
  header "header: an agent twice" (fun _ h ->
      match get "agents" h with
      | Some (`List (a :: rest)) -> Some (set "agents" (`List (a :: rest @ [ a ])) h)
      | _ -> None);
  header "header: capacity 0" (fun _ h -> Some (set "o2a_capacity" (`Int 0) h));
  header "header: budget 0" (fun _ h -> Some (set "budget" (`Int 0) h));
  { name = "header: a default priority changed"; apply = fun rng lines ->
        (* a type notified with its default (action Notify): the header's
           default no longer matches *)
        match load lines with
        | None -> None
        | Some t ->
          let ty p = match String.index_opt p '(' with Some i -> String.sub p 0 i | None -> p in
          let types = List.sort_uniq compare (List.filter_map (fun e ->
              if event e = "notify" && str "action" e = "Notify" then Some (ty (str "percept" e)) else None) t.events) in
          Option.bind (pick rng types) (fun p ->
              match get "program" t.header with
              | Some prog ->
                (match get "percepts" prog with
                 | Some (`Assoc ps) ->
                   let ps = List.map (fun (n, v) -> match v with `Int k when n = p -> (n, `Int (k + 1)) | _ -> (n, v)) ps in
                   out (set "program" (set "percepts" (`Assoc ps) prog) t.header) t.events
                 | _ -> None)
              | None -> None) };
  header "header: unknown field" (fun _ h -> Some (set "colour" (`String "blue") h));
  (* --- literals *)
  edit "dequeue: another percept than notified" (is "dequeue") (fun rng t e -> Some (set "percept" (`String (other_percept rng t e)) e));
  edit "dequeue: another priority than notified" (is "dequeue") (fun _ _ e -> Some (set "priority" (`Int (int "priority" e + 1)) e));
  edit "dequeue: a seq never notified" (is "dequeue") (fun _ _ e -> Some (set "seq" (`Int (int "seq" e + 1000)) e));
  edit "transfer_one: another percept than notified" (is "transfer_one") (fun rng t e -> Some (set "percept" (`String (other_percept rng t e)) e));
  edit "handle: another percept than dequeued" (is "handle") (fun rng t e -> Some (set "percept" (`String (other_percept rng t e)) e));
  edit "handle: another seq than dequeued" (is "handle") (fun _ _ e -> Some (set "seq" (`Int (int "seq" e + 1000)) e));
  edit "deliver: another content than sent" from_agent (fun _ _ e -> Some (set "content" (`String (changed (str "content" e))) e));
  edit "deliver: another performative than sent" from_agent (fun _ _ e ->
      Some (set "performative" (`String (if str "performative" e = "inform" then "request" else "inform")) e));
  edit "deliver: another sender" from_agent (fun rng t e ->
      Option.map (fun (n, _) -> set "from" (`String n) e)
        (pick rng (List.filter (fun (n, _) -> n <> str "from" e) (header_agents t.header))));
  edit "deliver: wrong seq" (is "deliver") (fun _ _ e -> Some (set "seq" (`Int (int "seq" e + 1)) e));
  edit "behaviour step: another message than delivered" (fun _ _ e -> event e = "behaviour_step" && agent_message e <> None)
    (fun _ _ e -> Option.map (fun m -> set "message" (set "content" (`String (changed (str "content" m))) m) e) (agent_message e));
  edit "behaviour step: a message seq never delivered" (fun _ _ e -> event e = "behaviour_step" && agent_message e <> None)
    (fun _ t e ->
       (* a seq above every one delivered to this agent (seq + 1000 could be
          a later message with the same content, taken out of order: a fault
          only TLC sees) *)
       let top = List.fold_left (fun acc f ->
           if event f = "deliver" && agent f = agent e then max acc (int "seq" f) else acc) 0 t.events in
       Option.map (fun m -> set "message" (set "seq" (`Int (top + 1000)) m) e) (agent_message e));
  edit "notify: wrong seq" (is "notify") (fun _ _ e -> Some (set "seq" (`Int (int "seq" e + 1)) e));
  edit "notify: not the default priority" (fun _ _ e -> event e = "notify" && str "action" e = "Notify")
    (fun _ _ e -> Some (set "priority" (`Int (int "priority" e + 1)) e));
  edit "put: wrong index" (is "put") (fun _ _ e -> Some (set "index" (`Int (int "index" e + 1)) e));
  (* --- messages across agents *)
  rearrange "deliver: before its send" (fun rng t ->
      if not (complete t) then None else
      let cands = List.filter_map (fun (i, e) ->
          if not (from_agent t i e) then None
          else
            let sends = List.filter (fun (k, s) ->
                k < i && event s = "send" && agent s = str "from" e && str "content" s = str "content" e
                && (match get "to" s with Some (`List l) -> List.mem (`String (agent e)) l | _ -> false))
                (indexed t.events) in
            (* the send this delivery matches: the (d+1)-th such send, d the
               same deliveries before it (the same content may be sent twice
               in one step: moving before the second would stay valid) *)
            let d = List.length (List.filter (fun (k, f) ->
                k < i && event f = "deliver" && agent f = agent e && str "from" f = str "from" e
                && str "content" f = str "content" e) (indexed t.events)) in
            match List.nth_opt sends d with Some (k, _) -> Some (i, k) | None -> None) (indexed t.events) in
      Option.map (fun (i, k) -> move_before t.events ~from:i ~to_:k) (pick rng cands));
  (* R5e, R6 revised: a step's messages leave when the step ends: the
     delivery moved to right after its send, before a later line of the
     sender's same step *)
  rearrange "deliver: before its sender's step ended" (fun rng t ->
      if not (complete t) then None else
      let es = indexed t.events in
      let cands = List.filter_map (fun (i, e) ->
          if not (from_agent t i e) then None
          else
            let sends = List.filter (fun (k, s) ->
                k < i && event s = "send" && agent s = str "from" e && str "content" s = str "content" e
                && (match get "to" s with Some (`List l) -> List.mem (`String (agent e)) l | _ -> false)) es in
            let d = List.length (List.filter (fun (k, f) ->
                k < i && event f = "deliver" && agent f = agent e && str "from" f = str "from" e
                && str "content" f = str "content" e) es) in
            match List.nth_opt sends d with
            | Some (k, s) ->
              (* the sender's next line after the send: a line of the same step *)
              (match List.find_opt (fun (j, x) -> j > k && agent x = agent s) es with
               | Some (j, x) when j < i && is_body x -> Some (i, k + 1)
               | _ -> None)
            | None -> None) es in
      Option.map (fun (i, k) -> move_before t.events ~from:i ~to_:k) (pick rng cands));
  rearrange "deliver: before its receiver exists" (fun rng t ->
      let cands = List.filter_map (fun (i, e) ->
          if event e <> "deliver" then None
          else match List.find_opt (fun (_, c) -> event c = "create" && agent c = agent e) (indexed t.events) with
            | Some (k, _) when k < i -> Some (i, k)
            | _ -> None) (indexed t.events) in
      Option.map (fun (i, k) -> move_before t.events ~from:i ~to_:k) (pick rng cands));
  (* R5d revised: a delivery during a step only in the window of that step *)
  edit "SendInStep: outside the window" (fun t i e ->
      event e = "deliver" && str "action" e = "Send"
      && (match List.rev (List.filter (fun (k, x) -> k < i && agent x = agent e) (indexed t.events)) with
          | (_, x) :: _ -> List.mem (event x) [ "transfer"; "idle"; "next_iteration"; "dequeue"; "end_dispatch"; "discard" ]
          | [] -> false))
    (fun _ _ e -> Some (set "action" (`String "SendInStep") e));
  (* R5e revised, D43: ams's failure names the receiver that was not found *)
  edit "failure from ams: another content" (fun _ _ e -> event e = "deliver" && str "from" e = "ams")
    (fun _ _ e -> Some (set "content" (`String "aid(\"someone else\")") e));
  edit "undeliverable: to an agent that exists" (is "undeliverable") (fun rng t e ->
      Option.map (fun (n, _) -> set "to" (`String n) e) (pick rng (header_agents t.header)));
  rearrange "send: dropped" (fun rng t ->
      if not (complete t) then None else
      let names = List.map fst (header_agents t.header) in
      let cands = List.filter (fun (_, e) ->
          event e = "send" && str "action" e <> "destroy"
          && (match get "to" e with Some (`List l) -> List.exists (function `String r -> List.mem r names | _ -> false) l | _ -> false))
          (indexed t.events) in
      Option.map (fun (i, _) -> drop t.events i) (pick rng cands));
  rearrange "deliver: dropped" (fun rng t ->
      if not (complete t) then None
      else Option.map (fun (i, _) -> drop t.events i) (pick rng (List.filter (fun (i, e) -> from_agent t i e) (indexed t.events))));
  (* --- agents *)
  edit "an agent not in the header" (fun _ _ _ -> true) (fun _ _ e -> Some (set "agent" (`String "intruder") e));
  rearrange "a step after destroy" (fun rng t ->
      let cands = List.filter (fun (_, e) -> event e = "destroy") (indexed t.events) in
      Option.map (fun (i, e) ->
          insert_after t.events i (`Assoc [ "step", `Int 0; "agent", `String (agent e); "event", `String "next_iteration";
                                           "action", `String "NextIteration" ])) (pick rng cands));
  rearrange "destroy: before the agent's last step" (fun rng t ->
      let cands = List.filter_map (fun (i, e) ->
          if event e <> "destroy" then None
          else match List.rev (List.filter (fun (k, x) -> k < i && agent x = agent e && not (is_body x) && event x <> "create")
                                 (indexed t.events)) with
            | (k, _) :: _ -> Some (i, k)
            | [] -> None) (indexed t.events) in
      Option.map (fun (i, k) -> move_before t.events ~from:i ~to_:k) (pick rng cands));
  edit "create: another type than the header's" (is "create") (fun _ _ e -> Some (set "type" (`String (changed (str "type" e))) e));
  rearrange "create: dropped" (fun rng t ->
      Option.map (fun (i, _) -> drop t.events i) (pick rng (List.filter (fun (_, e) -> event e = "create") (indexed t.events))));
  (* --- the O2A queue (R2d) *)
  rearrange "refused notify: the queue has room or no bound" (fun rng t ->
      let p = match get "program" t.header with
        | Some prog -> (match get "percepts" prog with Some (`Assoc ((p, _) :: _)) -> p | _ -> "p")
        | None -> "p" in
      Option.map (fun (i, e) ->
          insert_after t.events i (`Assoc [ "step", `Int 0; "agent", `String (agent e); "event", `String "refused";
                                           "action", `Null; "percept", `String p; "reason", `String "the O2A queue is full (R2d)" ]))
        (pick rng (List.filter (fun (_, e) -> event e = "create") (indexed t.events))));
  rearrange "refused put: the queue has room or no bound" (fun rng t ->
      Option.map (fun (i, e) ->
          insert_after t.events i (`Assoc [ "step", `Int 0; "agent", `String (agent e); "event", `String "refused";
                                           "action", `Null; "object", `String "42"; "reason", `String "the O2A queue is full (R2d)" ]))
        (pick rng (List.filter (fun (_, e) -> event e = "create") (indexed t.events))));
  (* --- the format *)
  edit "an unknown event" (fun _ _ _ -> true) (fun _ _ e -> Some (set "event" (`String "teleport") e));
  edit "an unknown field" (fun _ _ _ -> true) (fun _ _ e -> Some (set "colour" (`String "blue") e));
  edit "a field missing" (fun _ _ e -> has "seq" e) (fun _ _ e -> Some (remove "seq" e));
  edit "moved: \"zero\"" (is "transfer") (fun _ _ e -> Some (set "moved" (`String "zero") e));
  edit "moved: 1e30" (is "transfer") (fun _ _ e -> Some (set "moved" (`Float 1e30) e));
  edit "seq: a text" (fun _ _ e -> has "seq" e) (fun _ _ e -> Some (set "seq" (`String (string_of_int (int "seq" e))) e));
  edit "priority: huge" (fun _ _ e -> has "priority" e) (fun _ _ e -> Some (set "priority" (`Int 4611686018427387903) e));
  edit "priority: negative" (fun _ _ e -> has "priority" e) (fun _ _ e -> Some (set "priority" (`Int (-1)) e));
  edit "action: another" (fun _ _ _ -> true) (fun _ _ e ->
      Some (set "action" (`String (if str "action" e = "Handle" then "Skip" else "Handle")) e));
  { name = "invalid UTF-8 in a text"; apply = fun rng lines ->
        let cands = List.filteri (fun i _ -> i > 0) (List.mapi (fun i l -> (i, l)) lines) in
        Option.bind (pick rng cands) (fun (i, l) ->
            (* inside the line's last text: just before its closing quote *)
            match String.rindex_opt l '"' with
            | Some q -> Some (List.mapi (fun k x -> if k = i then String.sub l 0 q ^ "\xff" ^ String.sub l q (String.length l - q) else x) lines)
            | None -> None) };
  { name = "a line cut short"; apply = fun rng lines ->
        let cands = List.filteri (fun i _ -> i > 0) (List.mapi (fun i l -> (i, l)) lines) in
        Option.map (fun (i, l) ->
            List.mapi (fun k x -> if k = i then String.sub l 0 (String.length l / 2) else x) lines) (pick rng cands) };
  (* --- steps *)
  (* two neighbours' step numbers exchanged, the lines left in place *)
  { name = "steps: decreasing"; apply = fun rng lines ->
        match load lines with
        | None -> None
        | Some t ->
          let n = List.length t.events in
          if n < 2 then None else
            let i = Random.State.int rng (n - 1) in
            out t.header (List.mapi (fun k e ->
                if k = i then set "step" (`Int (i + 2)) e
                else if k = i + 1 then set "step" (`Int (i + 1)) e else e) (renumber t.events)) };
  rearrange "loop steps of one agent swapped" (fun rng t ->
      let loop e = match get "action" e with
        | Some (`String a) -> not (is_body e) && not (List.mem a [ "Notify"; "NotifyWith"; "Put"; "Send"; "Init" ])
        | _ -> false in
      let es = Array.of_list t.events in
      let cands = List.filter (fun i ->
          i + 1 < Array.length es && loop es.(i) && loop es.(i + 1) && agent es.(i) = agent es.(i + 1)
          && event es.(i) <> event es.(i + 1)) (List.init (Array.length es) Fun.id) in
      Option.map (fun i -> move_before t.events ~from:(i + 1) ~to_:i) (pick rng cands));
  rearrange "a line duplicated" (fun rng t ->
      let dup e = List.mem (event e) [ "notify"; "put"; "deliver"; "dequeue"; "end_dispatch"; "discard"; "create"; "destroy"; "transfer_one" ]
                  || (event e = "behaviour_step" && agent_message e <> None) in
      Option.map (fun (i, e) -> insert_after t.events i e) (pick rng (List.filter (fun (_, e) -> dup e) (indexed t.events))));
  rearrange "dequeue: dropped" (fun rng t ->
      (* only a dequeue whose dispatch follows it: a run cut by --max-steps
         right after a dequeue is still valid without it *)
      let evs = indexed t.events in
      let dispatch_follows i e =
        match List.find_opt (fun (k, f) -> k > i && agent f = agent e) evs with
        | Some (_, f) -> List.mem (event f) [ "handle"; "skip"; "end_dispatch" ]
        | None -> false in
      Option.map (fun (i, _) -> drop t.events i)
        (pick rng (List.filter (fun (i, e) -> event e = "dequeue" && dispatch_follows i e) evs)));
]

let tlc_only = [ "loop steps of one agent swapped" ]
