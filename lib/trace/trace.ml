(* The trace's events and their JSON: docs/trace-format.md. The order of the
   fields of each line is part of the format. *)

type entry = { percept : string; priority : int; seq : int }
type message = { performative : string; content : string; from : string }
type effect = Activated of string | Deactivated
type taken = Took_message of message * int | Took_percept of entry

type body =
  | Log of string
  | Invoke of { meth : string; obj : string; args : string list; result : string }
  | Send of { performative : string; content : string; receivers : string list }
  | Activate of string
  | Deactivate of int
  | Error of { at : string; message : string }

type event =
  | Create of { agent_type : string; args : string list; behaviours : string list }
  | Notify of { entry : entry; overridden : bool }
  | Refused of { percept : string; reason : string }
  | Refused_put of { obj : string; reason : string }
  | Put of { obj : string; index : int }
  | Deliver of { message : message; seq : int }
  | Undeliverable of { receiver : string; performative : string; content : string }
  | Transfer of int
  | Transfer_one of entry
  | Transfer_spin of string
  | Transfer_end
  | Dequeue of entry
  | Handle of { instance : int; behaviour : string; handler : int; percept : string; seq : int;
                effects : effect list }
  | Skip of { instance : int; behaviour : string; handler : int }
  | End_dispatch of { seq : int; discarded : bool }
  | Behaviour_step of { instance : int; behaviour : string; taken : taken option;
                        action_effects : effect list option; handler : (int * effect list) option }
  | Next_iteration
  | Idle
  | Destroy
  | Body of { action : string; body : body }

type line = { step : int; agent : string; event : event }

let event_name = function
  | Create _ -> "create" | Notify _ -> "notify" | Refused _ | Refused_put _ -> "refused" | Put _ -> "put"
  | Deliver _ -> "deliver" | Undeliverable _ -> "undeliverable" | Transfer _ -> "transfer"
  | Transfer_one _ -> "transfer_one" | Transfer_spin _ -> "transfer_spin"
  | Transfer_end -> "transfer_end" | Dequeue _ -> "dequeue" | Handle _ -> "handle"
  | Skip _ -> "skip" | End_dispatch { discarded = true; _ } -> "discard"
  | End_dispatch { discarded = false; _ } -> "end_dispatch"
  | Behaviour_step _ -> "behaviour_step" | Next_iteration -> "next_iteration" | Idle -> "idle"
  | Destroy -> "destroy"
  | Body { body; _ } ->
    (match body with
     | Log _ -> "log" | Invoke _ -> "invoke" | Send _ -> "send" | Activate _ -> "activate"
     | Deactivate _ -> "deactivate" | Error _ -> "error")

let action = function
  | Create _ -> Some "Init"
  | Notify { overridden; _ } -> Some (if overridden then "NotifyWith" else "Notify")
  | Refused _ | Refused_put _ | Undeliverable _ | Destroy -> None
  | Put _ -> Some "Put" | Deliver _ -> Some "Send" | Transfer _ -> Some "Transfer"
  | Transfer_one _ -> Some "TransferOne" | Transfer_spin _ -> Some "TransferSpin"
  | Transfer_end -> Some "TransferEnd" | Dequeue _ -> Some "Dequeue" | Handle _ -> Some "Handle"
  | Skip _ -> Some "Skip" | End_dispatch _ -> Some "EndDispatch"
  | Behaviour_step _ -> Some "BehaviourStep" | Next_iteration -> Some "NextIteration"
  | Idle -> Some "Idle"
  | Body { action; _ } -> Some action

type behaviour_info = { name : string; kind : string; has_action : bool;
                        percept_handlers : int; message_handlers : int }

type header = {
  variant : string; tie_policy : string; budget : int; o2a_capacity : int option;
  seed : int option; agents : (string * string) list;
  behaviours : behaviour_info list; percepts : (string * int) list;
}

(* ------------------------------------------------------------ encoding *)

let version = 1

let str s = `String s
let int i = `Int i
let strs l = `List (List.map str l)
let opt_int = function Some i -> `Int i | None -> `Null

let effect_to_string = function Activated b -> "activate " ^ b | Deactivated -> "deactivate"
let effects l = strs (List.map effect_to_string l)

let entry_fields e = [ "percept", str e.percept; "priority", int e.priority; "seq", int e.seq ]
let message_fields m = [ "performative", str m.performative; "content", str m.content; "from", str m.from ]

let fields = function
  | Create { agent_type; args; behaviours } ->
    [ "type", str agent_type; "args", strs args; "behaviours", strs behaviours ]
  | Notify { entry; _ } | Transfer_one entry | Dequeue entry -> entry_fields entry
  | Refused { percept; reason } -> [ "percept", str percept; "reason", str reason ]
  | Refused_put { obj; reason } -> [ "object", str obj; "reason", str reason ]
  | Put { obj; index } -> [ "object", str obj; "index", int index ]
  | Deliver { message; seq } -> message_fields message @ [ "seq", int seq ]
  | Undeliverable { receiver; performative; content } ->
    [ "to", str receiver; "performative", str performative; "content", str content ]
  | Transfer n -> [ "moved", int n ]
  | Transfer_spin o -> [ "object", str o ]
  | Transfer_end | Next_iteration | Idle | Destroy -> []
  | Handle { instance; behaviour; handler; percept; seq; effects = e } ->
    [ "instance", int instance; "behaviour", str behaviour; "handler", int handler;
      "percept", str percept; "seq", int seq; "effects", effects e ]
  | Skip { instance; behaviour; handler } ->
    [ "instance", int instance; "behaviour", str behaviour; "handler", int handler ]
  | End_dispatch { seq; _ } -> [ "seq", int seq ]
  | Behaviour_step { instance; behaviour; taken; action_effects; handler } ->
    [ "instance", int instance; "behaviour", str behaviour;
      "message", (match taken with
          | None -> `Null
          | Some (Took_message (m, seq)) -> `Assoc (message_fields m @ [ "seq", int seq ])
          | Some (Took_percept e) -> `Assoc (entry_fields e)) ]
    @ (match action_effects with Some e -> [ "action_effects", effects e ] | None -> [])
    @ (match handler with Some (h, e) -> [ "handler", int h; "effects", effects e ] | None -> [])
  | Body { body; _ } ->
    (match body with
     | Log s -> [ "text", str s ]
     | Invoke { meth; obj; args; result } ->
       [ "method", str meth; "object", str obj; "args", strs args; "result", str result ]
     | Send { performative; content; receivers } ->
       [ "performative", str performative; "content", str content; "to", strs receivers ]
     | Activate b -> [ "behaviour", str b ]
     | Deactivate id -> [ "instance", int id ]
     | Error { at; message } -> [ "at", str at; "message", str message ])

let line_to_json l =
  `Assoc ([ "step", int l.step; "agent", str l.agent; "event", str (event_name l.event);
            "action", (match action l.event with Some a -> str a | None -> `Null) ]
          @ fields l.event)

let header_to_json h =
  `Assoc [
    "trace", str "jadescript-ref"; "version", int version;
    "variant", str h.variant; "tie_policy", str h.tie_policy; "budget", int h.budget;
    "o2a_capacity", opt_int h.o2a_capacity; "seed", opt_int h.seed;
    "agents", `List (List.map (fun (n, ty) -> `Assoc [ "name", str n; "type", str ty ]) h.agents);
    "program", `Assoc [
      "behaviours", `List (List.map (fun b ->
          `Assoc [ "name", str b.name; "kind", str b.kind; "action", `Bool b.has_action;
                   "percept_handlers", int b.percept_handlers;
                   "message_handlers", int b.message_handlers ]) h.behaviours);
      "percepts", `Assoc (List.map (fun (n, k) -> (n, int k)) h.percepts) ] ]

let is_header = function
  | `Assoc f -> List.mem_assoc "trace" f
  | _ -> false

let header_version = function
  | `Assoc f when List.assoc_opt "trace" f = Some (`String "jadescript-ref") ->
    Some (Option.value (List.assoc_opt "version" f) ~default:`Null)
  | _ -> None

let is_error = function
  | `Assoc f -> List.assoc_opt "event" f = Some (`String "error")
  | _ -> false

let without_step = function
  | `Assoc f -> `Assoc (List.remove_assoc "step" f)
  | j -> j

(* ------------------------------------------------------------ decoding *)

(* Reading is strict (docs/trace-format.md, "What validate checks"): every
   field of the right JSON type, no field the format does not have, no field
   twice, integers in the language's 32-bit range, the [action] field the
   one of the event, the header of version 1 with known values. A bad value
   is never read as 0 or "" (D25: version 1 is closed). *)

exception Bad of string

let bad fmt = Printf.ksprintf (fun s -> raise (Bad s)) fmt

let int32_min = -0x8000_0000
let int32_max = 0x7fff_ffff

let describe : Yojson.Safe.t -> string = function
  | `Int _ | `Intlit _ -> "an integer" | `Float _ -> "a decimal number" | `String _ -> "a text"
  | `Bool _ -> "a boolean" | `Null -> "null" | `List _ | `Tuple _ -> "a list"
  | `Assoc _ -> "an object" | `Variant _ -> "a variant"

let field f fs = match List.assoc_opt f fs with Some v -> v | None -> bad "no field %S" f
let get_str f fs = match field f fs with `String s -> s | v -> bad "field %S is %s, not a text" f (describe v)
let int_value f = function
  | `Int i when i >= int32_min && i <= int32_max -> i
  | `Int _ | `Intlit _ -> bad "field %S is out of range (integers are 32-bit, %d to %d)" f int32_min int32_max
  | v -> bad "field %S is %s, not an integer" f (describe v)
let get_int f fs = int_value f (field f fs)
let get_nat f fs = let i = get_int f fs in if i < 0 then bad "field %S is negative (%d)" f i else i
let get_pos f fs = let i = get_int f fs in if i < 1 then bad "field %S must be at least 1 (it is %d)" f i else i
let get_bool f fs = match field f fs with `Bool b -> b | v -> bad "field %S is %s, not a boolean" f (describe v)
let get_strs f fs = match field f fs with
  | `List l -> List.map (function `String s -> s | v -> bad "field %S holds %s, not a text" f (describe v)) l
  | v -> bad "field %S is %s, not a list" f (describe v)
let get_opt_int f fs = match List.assoc_opt f fs with
  | None -> bad "no field %S" f
  | Some `Null -> None
  | Some v -> Some (int_value f v)
let get_obj f fs = match field f fs with `Assoc o -> o | v -> bad "field %S is %s, not an object" f (describe v)

(* The fields of an object are exactly [expected] (in any order), each once. *)
let exact_fields what fs expected =
  let rec dups = function
    | (k, _) :: rest -> if List.mem_assoc k rest then bad "field %S appears twice%s" k what else dups rest
    | [] -> () in
  dups fs;
  List.iter (fun (k, _) -> if not (List.mem k expected) then bad "unknown field %S%s" k what) fs

let effect_of_string s =
  match String.split_on_char ' ' s with
  | [ "deactivate" ] -> Deactivated
  | [ "activate"; b ] when b <> "" -> Activated b
  | _ -> bad "unknown effect %S" s

let get_effects f fs = List.map effect_of_string (get_strs f fs)

let entry_of fs = { percept = get_str "percept" fs; priority = get_nat "priority" fs; seq = get_pos "seq" fs }
let message_of fs = { performative = get_str "performative" fs; content = get_str "content" fs; from = get_str "from" fs }

(* The actions a body event may name: the spec's actions, and "destroy". *)
let body_actions =
  [ "Init"; "Notify"; "NotifyWith"; "Put"; "Send"; "Transfer"; "TransferOne"; "TransferSpin"; "TransferEnd";
    "Dequeue"; "Handle"; "Skip"; "EndDispatch"; "BehaviourStep"; "NextIteration"; "Idle"; "destroy" ]

let event_of name fs =
  let action = match List.assoc_opt "action" fs with
    | Some (`String a) -> a
    | Some `Null -> ""
    | Some v -> bad "field \"action\" is %s, not a text or null" (describe v)
    | None -> bad "no field \"action\"" in
  let body b =
    if not (List.mem action body_actions) then bad "a %s event happens during a step: its action %S is not one" name action;
    Body { action; body = b } in
  match name with
  | "create" -> Create { agent_type = get_str "type" fs; args = get_strs "args" fs;
                         behaviours = get_strs "behaviours" fs }
  | "notify" -> Notify { entry = entry_of fs; overridden = action = "NotifyWith" }
  | "refused" when List.mem_assoc "object" fs ->
    Refused_put { obj = get_str "object" fs; reason = get_str "reason" fs }
  | "refused" -> Refused { percept = get_str "percept" fs; reason = get_str "reason" fs }
  | "put" -> Put { obj = get_str "object" fs; index = get_pos "index" fs }
  | "deliver" -> Deliver { message = message_of fs; seq = get_pos "seq" fs }
  | "undeliverable" -> Undeliverable { receiver = get_str "to" fs; performative = get_str "performative" fs;
                                       content = get_str "content" fs }
  | "transfer" -> Transfer (get_nat "moved" fs)
  | "transfer_one" -> Transfer_one (entry_of fs)
  | "transfer_spin" -> Transfer_spin (get_str "object" fs)
  | "transfer_end" -> Transfer_end
  | "dequeue" -> Dequeue (entry_of fs)
  | "handle" -> Handle { instance = get_pos "instance" fs; behaviour = get_str "behaviour" fs;
                         handler = get_pos "handler" fs; percept = get_str "percept" fs;
                         seq = get_pos "seq" fs; effects = get_effects "effects" fs }
  | "skip" -> Skip { instance = get_pos "instance" fs; behaviour = get_str "behaviour" fs;
                     handler = get_pos "handler" fs }
  | "discard" | "end_dispatch" -> End_dispatch { seq = get_pos "seq" fs; discarded = name = "discard" }
  | "behaviour_step" ->
    let taken = match field "message" fs with
      | `Null -> None
      | `Assoc m when List.mem_assoc "performative" m ->
        exact_fields " in \"message\"" m [ "performative"; "content"; "from"; "seq" ];
        Some (Took_message (message_of m, get_pos "seq" m))
      | `Assoc m ->
        exact_fields " in \"message\"" m [ "percept"; "priority"; "seq" ];
        Some (Took_percept (entry_of m))
      | v -> bad "field \"message\" is %s, not an object or null" (describe v) in
    let handler = match List.mem_assoc "handler" fs, List.mem_assoc "effects" fs with
      | true, _ -> Some (get_pos "handler" fs, get_effects "effects" fs)
      | false, true -> bad "field \"effects\" without \"handler\""
      | false, false -> None in
    if handler <> None && taken = None then bad "a behaviour step that took no message has no handler";
    Behaviour_step {
      instance = get_pos "instance" fs; behaviour = get_str "behaviour" fs; taken;
      action_effects = (if List.mem_assoc "action_effects" fs then Some (get_effects "action_effects" fs) else None);
      handler }
  | "next_iteration" -> Next_iteration
  | "idle" -> Idle
  | "destroy" -> Destroy
  | "log" -> body (Log (get_str "text" fs))
  | "invoke" -> body (Invoke { meth = get_str "method" fs; obj = get_str "object" fs;
                               args = get_strs "args" fs; result = get_str "result" fs })
  | "send" -> body (Send { performative = get_str "performative" fs;
                           content = get_str "content" fs; receivers = get_strs "to" fs })
  | "activate" -> body (Activate (get_str "behaviour" fs))
  | "deactivate" -> body (Deactivate (get_pos "instance" fs))
  | "error" -> body (Error { at = get_str "at" fs; message = get_str "message" fs })
  | e -> bad "unknown event %S" e

let line_of_json j =
  match j with
  | `Assoc fs ->
    (try
       let step = match field "step" fs with
         | `Int i when i >= 1 -> i
         | `Int i -> bad "field \"step\" must be at least 1 (it is %d)" i
         | v -> bad "field \"step\" is %s, not an integer" (describe v) in
       let l = { step; agent = get_str "agent" fs; event = event_of (get_str "event" fs) fs } in
       exact_fields "" fs (List.map fst (match line_to_json l with `Assoc f -> f | _ -> []));
       (match action l.event, List.assoc_opt "action" fs with
        | Some a, Some (`String b) when a = b -> ()
        | None, Some `Null -> ()
        | expected, _ ->
          bad "the action of a %s event is %s" (event_name l.event)
            (match expected with Some a -> Printf.sprintf "%S" a | None -> "null"));
       Ok l
     with Bad m -> Error m)
  | v -> Error (Printf.sprintf "a trace line is a JSON object, not %s" (describe v))

let variants = [ "reference"; "printed"; "budgeted"; "native" ]
let tie_policies = [ "stable"; "unstable" ]
let kinds = [ "cyclic"; "oneshot" ]

let one_of f fs known =
  let v = get_str f fs in
  if List.mem v known then v
  else bad "unknown %s %S (known: %s)" f v (String.concat ", " known)

let header_of_json j =
  match j with
  | `Assoc fs when is_header j ->
    (try
       if get_str "trace" fs <> "jadescript-ref" then bad "not a jadescript-ref trace";
       (match List.assoc_opt "version" fs with
        | Some (`Int v) when v = version -> ()
        | Some (`Int v) -> bad "trace format version %d is not supported (this reader knows version %d)" v version
        | Some v -> bad "field \"version\" is %s, not the integer %d" (describe v) version
        | None -> bad "the header has no field \"version\" (this reader knows version %d)" version);
       exact_fields " in the header" fs
         [ "trace"; "version"; "variant"; "tie_policy"; "budget"; "o2a_capacity"; "seed"; "agents"; "program" ];
       let program = get_obj "program" fs in
       exact_fields " in \"program\"" program [ "behaviours"; "percepts" ];
       let o2a_capacity = get_opt_int "o2a_capacity" fs in
       (match o2a_capacity with
        | Some c when c < 1 -> bad "field \"o2a_capacity\" must be at least 1 or null (it is %d)" c
        | _ -> ());
       let seed = match List.assoc_opt "seed" fs with
         | Some `Null -> None | Some (`Int s) -> Some s
         | Some v -> bad "field \"seed\" is %s, not an integer or null" (describe v)
         | None -> bad "no field \"seed\"" in
       let percepts = get_obj "percepts" program in
       exact_fields " in \"percepts\"" percepts (List.map fst percepts);
       Ok { variant = one_of "variant" fs variants; tie_policy = one_of "tie_policy" fs tie_policies;
            budget = get_pos "budget" fs; o2a_capacity; seed;
            agents = (match field "agents" fs with
                | `List l -> List.map (function
                    | `Assoc a ->
                      exact_fields " in an agent" a [ "name"; "type" ];
                      (get_str "name" a, get_str "type" a)
                    | v -> bad "an agent is an object, not %s" (describe v)) l
                | v -> bad "field \"agents\" is %s, not a list" (describe v));
            behaviours = (match field "behaviours" program with
                | `List l -> List.map (function
                    | `Assoc b ->
                      exact_fields " in a behaviour" b
                        [ "name"; "kind"; "action"; "percept_handlers"; "message_handlers" ];
                      { name = get_str "name" b; kind = one_of "kind" b kinds;
                        has_action = get_bool "action" b;
                        percept_handlers = get_nat "percept_handlers" b;
                        message_handlers = get_nat "message_handlers" b }
                    | v -> bad "a behaviour is an object, not %s" (describe v)) l
                | v -> bad "field \"behaviours\" is %s, not a list" (describe v));
            percepts = List.map (fun (n, v) ->
                let k = int_value ("priority of " ^ n) v in
                if k < 0 then bad "the default priority of %s is negative (%d)" n k;
                (n, k)) percepts }
     with Bad m -> Error m)
  | _ -> Error "not a jadescript-ref trace (no header line)"

(* ---------------------------------------------- direct encoding (issue 17) *)

(* A line written straight into a buffer, byte for byte what
   [Yojson.Safe.to_string (line_to_json l)] writes: the same fields in the
   same order, strings and integers by Yojson's own writers, and no JSON
   tree in between. Create (once per agent) and any event without a case
   here go through the tree. The test "trace: direct encoding = JSON tree"
   holds the two equal over every event. *)

(* Does the string need no JSON escape (none of the characters Yojson
   escapes: a quote, a backslash, a control character, DEL)? *)
let rec plain s i =
  i >= String.length s
  || (let c = String.unsafe_get s i in
      c >= ' ' && c <> '"' && c <> '\\' && c <> '\x7F' && plain s (i + 1))

let write_string b s =
  if plain s 0 then (Buffer.add_char b '"'; Buffer.add_string b s; Buffer.add_char b '"')
  else Yojson.Safe.write_string b s

(* A natural number's decimal digits, as Yojson writes them, at once;
   other integers by Yojson. *)
let digits = Bytes.create 20

let write_int b i =
  if i > 0 then begin
    let k = ref 20 and n = ref i in
    while !n > 0 do
      decr k; Bytes.unsafe_set digits !k (Char.unsafe_chr (48 + !n mod 10)); n := !n / 10
    done;
    Buffer.add_subbytes b digits !k (20 - !k)
  end else Yojson.Safe.write_int b i

let put_str b key s = Buffer.add_string b key; write_string b s
let put_int b key i = Buffer.add_string b key; write_int b i

let put_list b key f l =
  Buffer.add_string b key;
  Buffer.add_char b '[';
  List.iteri (fun i x -> if i > 0 then Buffer.add_char b ','; f x) l;
  Buffer.add_char b ']'

let put_effects b key l = put_list b key (fun e -> write_string b (effect_to_string e)) l

(* [sep] comes before the first field: "," inside a line, "" in an object
   of its own *)
let put_entry b sep e =
  put_str b (sep ^ "\"percept\":") e.percept;
  put_int b ",\"priority\":" e.priority;
  put_int b ",\"seq\":" e.seq

let put_message b sep m =
  put_str b (sep ^ "\"performative\":") m.performative;
  put_str b ",\"content\":" m.content;
  put_str b ",\"from\":" m.from

(* The agent's name as JSON, for the last name seen (physically): a run
   writes the same few names on every line. *)
let agent_json = ref ("", "\"\"")

let line_to_buffer b l =
  let head () =
    put_int b "{\"step\":" l.step;
    Buffer.add_string b ",\"agent\":";
    (match !agent_json with
     | (a, j) when a == l.agent -> Buffer.add_string b j
     | _ ->
       let j = Buffer.create 16 in
       write_string j l.agent;
       agent_json := (l.agent, Buffer.contents j);
       Buffer.add_string b (Buffer.contents j));
    (* event names and the actions of this module need no escape *)
    Buffer.add_string b ",\"event\":\"";
    Buffer.add_string b (event_name l.event);
    (match l.event, action l.event with
     | Body _, Some a -> put_str b "\",\"action\":" a
     | _, Some a -> Buffer.add_string b "\",\"action\":\""; Buffer.add_string b a; Buffer.add_char b '"'
     | _, None -> Buffer.add_string b "\",\"action\":null") in
  match l.event with
  | Notify { entry; _ } | Transfer_one entry | Dequeue entry ->
    head (); put_entry b "," entry; Buffer.add_char b '}'
  | Refused { percept; reason } ->
    head (); put_str b ",\"percept\":" percept; put_str b ",\"reason\":" reason; Buffer.add_char b '}'
  | Put { obj; index } ->
    head (); put_str b ",\"object\":" obj; put_int b ",\"index\":" index; Buffer.add_char b '}'
  | Deliver { message; seq } ->
    head (); put_message b "," message; put_int b ",\"seq\":" seq; Buffer.add_char b '}'
  | Undeliverable { receiver; performative; content } ->
    head (); put_str b ",\"to\":" receiver; put_str b ",\"performative\":" performative;
    put_str b ",\"content\":" content; Buffer.add_char b '}'
  | Transfer n -> head (); put_int b ",\"moved\":" n; Buffer.add_char b '}'
  | Transfer_spin o -> head (); put_str b ",\"object\":" o; Buffer.add_char b '}'
  | Transfer_end | Next_iteration | Idle | Destroy -> head (); Buffer.add_char b '}'
  | Handle { instance; behaviour; handler; percept; seq; effects = e } ->
    head ();
    put_int b ",\"instance\":" instance; put_str b ",\"behaviour\":" behaviour;
    put_int b ",\"handler\":" handler; put_str b ",\"percept\":" percept;
    put_int b ",\"seq\":" seq; put_effects b ",\"effects\":" e;
    Buffer.add_char b '}'
  | Skip { instance; behaviour; handler } ->
    head ();
    put_int b ",\"instance\":" instance; put_str b ",\"behaviour\":" behaviour;
    put_int b ",\"handler\":" handler;
    Buffer.add_char b '}'
  | End_dispatch { seq; _ } -> head (); put_int b ",\"seq\":" seq; Buffer.add_char b '}'
  | Behaviour_step { instance; behaviour; taken; action_effects; handler } ->
    head ();
    put_int b ",\"instance\":" instance; put_str b ",\"behaviour\":" behaviour;
    (match taken with
     | None -> Buffer.add_string b ",\"message\":null"
     | Some (Took_message (m, seq)) ->
       Buffer.add_string b ",\"message\":{"; put_message b "" m; put_int b ",\"seq\":" seq;
       Buffer.add_char b '}'
     | Some (Took_percept e) ->
       Buffer.add_string b ",\"message\":{"; put_entry b "" e; Buffer.add_char b '}');
    (match action_effects with Some e -> put_effects b ",\"action_effects\":" e | None -> ());
    (match handler with
     | Some (h, e) -> put_int b ",\"handler\":" h; put_effects b ",\"effects\":" e
     | None -> ());
    Buffer.add_char b '}'
  | Body { body; _ } ->
    head ();
    (match body with
     | Log s -> put_str b ",\"text\":" s
     | Invoke { meth; obj; args; result } ->
       put_str b ",\"method\":" meth; put_str b ",\"object\":" obj;
       put_list b ",\"args\":" (write_string b) args; put_str b ",\"result\":" result
     | Send { performative; content; receivers } ->
       put_str b ",\"performative\":" performative; put_str b ",\"content\":" content;
       put_list b ",\"to\":" (write_string b) receivers
     | Activate beh -> put_str b ",\"behaviour\":" beh
     | Deactivate id -> put_int b ",\"instance\":" id
     | Error { at; message } -> put_str b ",\"at\":" at; put_str b ",\"message\":" message);
    Buffer.add_char b '}'
  | _ -> Yojson.Safe.to_buffer b (line_to_json l)

(* ------------------------------------------------------------- writing *)

type writer = { emit : (string -> unit) option; mutable lines : int; buf : Buffer.t;
                oc : out_channel option (* to_channel's: lines go from [buf] to it *) }

let writer emit = { emit = Some emit; lines = 0; buf = Buffer.create 256; oc = None }
let to_channel oc =
  (* buffered; flushed by the channel when its buffer fills, and when the
     program ends: normally, by [exit] (a signal handler may call it), or by
     an uncaught exception *)
  at_exit (fun () -> try flush oc with Sys_error _ -> ());
  { (writer (output_string oc)) with oc = Some oc }
let nowhere () = { emit = None; lines = 0; buf = Buffer.create 1; oc = None }

let write_header w h =
  match w.emit with
  | Some emit -> emit (Yojson.Safe.to_string (header_to_json h) ^ "\n")
  | None -> ()

let write w ~agent event =
  w.lines <- w.lines + 1;
  match w.emit with
  | Some emit ->
    Buffer.clear w.buf;
    line_to_buffer w.buf { step = w.lines; agent; event };
    Buffer.add_char w.buf '\n';
    (match w.oc with
     | Some oc -> Buffer.output_buffer oc w.buf
     | None -> emit (Buffer.contents w.buf))
  | None -> ()

let lines_written w = w.lines

let writes w = w.emit <> None

let write_with w ~agent event =
  match w.emit with
  | Some _ -> write w ~agent (event ())
  | None -> w.lines <- w.lines + 1

(* ------------------------------------------------------------- reading *)

let fold_file path f init =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
      let rec go acc n =
        match input_line ic with
        | exception End_of_file -> acc
        | l ->
          if String.trim l = "" then go acc (n + 1)
          else match Yojson.Safe.from_string l with
            | j -> go (f acc n j) (n + 1)
            | exception Yojson.Json_error m ->
              failwith (Printf.sprintf "%s:%d:1: error: not JSON: %s" path n
                          (String.concat " " (String.split_on_char '\n' m))) in
      go init 1)

exception Located of int * string


(* A trace line is far shorter than this; a longer one (a file of zeros, a
   runaway writer) is an error, not a line read into memory without end. *)
let max_line = 16 * 1024 * 1024

(* The next line, without its newline; [None] at the end of the file.
   @raise Located when longer than [max_line] *)
let bounded_line ic n =
  let b = Buffer.create 256 in
  let rec go () =
    match input_char ic with
    | '\n' -> Some (Buffer.contents b)
    | c ->
      if Buffer.length b >= max_line then
        raise (Located (n, Printf.sprintf "a line longer than %d bytes: not a trace" max_line));
      Buffer.add_char b c; go ()
    | exception End_of_file -> if Buffer.length b = 0 then None else Some (Buffer.contents b) in
  go ()

(* One printable line: control characters of a message shown as '?'. *)
let printable m =
  String.map (fun c -> if c = '\n' || c = '\t' then ' ' else if Char.code c < 0x20 || c = '\127' then '?' else c) m

let read_located path =
  let located n fmt = Printf.ksprintf (fun m -> raise (Located (n, m))) fmt in
  match
    let ic = open_in_bin path in
    Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
        let rec go h acc n =
          match bounded_line ic n with
          | None -> (h, acc)
          | Some l when String.trim l = "" -> go h acc (n + 1)
          | Some l ->
            (match Utf8.first_invalid l with
             | Some k -> located n "not JSON: byte %d is not valid UTF-8" (k + 1)
             | None -> ());
            let j = match Yojson.Safe.from_string l with
              | j -> j
              | exception Yojson.Json_error m ->
                located n "not JSON: %s" (printable m) in
            match h with
            | None ->
              (match header_of_json j with
               | Ok h -> go (Some h) acc (n + 1)
               | Error m -> located n "%s" m)
            | Some _ ->
              (match line_of_json j with
               | Ok l -> go h ((n, l) :: acc) (n + 1)
               | Error m -> located n "%s" m) in
        go None [] 1)
  with
  | (Some h, lines) -> Ok (h, List.rev lines)
  | (None, _) -> Error (1, "not a jadescript-ref trace (no header line)")
  | exception Located (n, m) -> Error (n, m)
  | exception Sys_error m -> Error (1, m)

let read_file path =
  match read_located path with
  | Ok r -> Ok r
  | Error (n, m) -> Error (Printf.sprintf "%s:%d:1: error: %s" path n m)
