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
  | Deliver of { message : message; seq : int; in_step : bool }
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

let observable = function
  | Transfer _ | Transfer_one _ | Transfer_spin _ | Transfer_end | Dequeue _ | Skip _
  | End_dispatch { discarded = false; _ } | Next_iteration | Idle -> false
  | _ -> true

let action = function
  | Create _ -> Some "Init"
  | Notify { overridden; _ } -> Some (if overridden then "NotifyWith" else "Notify")
  | Refused _ | Refused_put _ | Undeliverable _ | Destroy -> None
  | Put _ -> Some "Put" | Deliver { in_step; _ } -> Some (if in_step then "SendInStep" else "Send")
  | Transfer _ -> Some "Transfer"
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
  seed : int option; level : string; agents : (string * string) list;
  containers : (string * string) list;
  behaviours : behaviour_info list; percepts : (string * int) list;
}

(* ------------------------------------------------------------ encoding *)

let version = 2
let main_container = "main"

let without_containers = function
  | `Assoc f -> `Assoc (List.remove_assoc "containers" f)
  | j -> j
let levels = [ "full"; "observable" ]

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
  | Deliver { message; seq; _ } -> message_fields message @ [ "seq", int seq ]
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
     | Error { at; message } ->
       (* a file name need not be UTF-8, and JSON text must be *)
       [ "at", str (Utf8.repair at); "message", str (Utf8.repair message) ])

let line_to_json l =
  `Assoc ([ "step", int l.step; "agent", str l.agent; "event", str (event_name l.event);
            "action", (match action l.event with Some a -> str a | None -> `Null) ]
          @ fields l.event)

let header_to_json h =
  `Assoc ([
    "trace", str "jadescript-ref"; "version", int version;
    "variant", str h.variant; "tie_policy", str h.tie_policy; "budget", int h.budget;
    "o2a_capacity", opt_int h.o2a_capacity; "seed", opt_int h.seed; "level", str h.level;
    "agents", `List (List.map (fun (n, ty) -> `Assoc [ "name", str n; "type", str ty ]) h.agents) ]
  @ (if h.containers = [] then [] else [ "containers", `Assoc (List.map (fun (n, c) -> (n, str c)) h.containers) ])
  @ [
    "program", `Assoc [
      "behaviours", `List (List.map (fun b ->
          `Assoc [ "name", str b.name; "kind", str b.kind; "action", `Bool b.has_action;
                   "percept_handlers", int b.percept_handlers;
                   "message_handlers", int b.message_handlers ]) h.behaviours);
      "percepts", `Assoc (List.map (fun (n, k) -> (n, int k)) h.percepts) ] ])

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
   one of the event, the header of version 1 or 2 with known values. A bad
   value is never read as 0 or "" (D25: the format is closed). *)

exception Bad of string

let bad fmt = Printf.ksprintf (fun s -> raise (Bad s)) fmt

let int32_min = -0x8000_0000
let int32_max = 0x7fff_ffff

let describe : Yojson.Safe.t -> string = function
  | `Int _ | `Intlit _ -> "an integer" | `Float _ -> "a decimal number" | `String _ -> "a text"
  | `Bool _ -> "a boolean" | `Null -> "null" | `List _ | `Tuple _ -> "a list"
  | `Assoc _ -> "an object" | `Variant _ -> "a variant"

(* Look-ups by key with [String.equal], not the polymorphic comparison:
   the judge reads millions of lines through them. *)
let rec assoc_opt f = function
  | (k, v) :: rest -> if String.equal k f then Some v else assoc_opt f rest
  | [] -> None

let rec mem_assoc f = function
  | (k, _) :: rest -> String.equal k f || mem_assoc f rest
  | [] -> false

let field f fs = match assoc_opt f fs with Some v -> v | None -> bad "no field %S" f
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
let get_opt_int f fs = match assoc_opt f fs with
  | None -> bad "no field %S" f
  | Some `Null -> None
  | Some v -> Some (int_value f v)
let get_obj f fs = match field f fs with `Assoc o -> o | v -> bad "field %S is %s, not an object" f (describe v)

(* The fields of an object are exactly [expected] (in any order), each once. *)
let exact_fields what fs expected =
  let rec dups = function
    | (k, _) :: rest -> if mem_assoc k rest then bad "field %S appears twice%s" k what else dups rest
    | [] -> () in
  dups fs;
  List.iter (fun (k, _) -> if not (List.exists (String.equal k) expected) then bad "unknown field %S%s" k what) fs

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
  [ "Init"; "Notify"; "NotifyWith"; "Put"; "Send"; "SendInStep"; "Transfer"; "TransferOne"; "TransferSpin"; "TransferEnd";
    "Dequeue"; "Handle"; "Skip"; "EndDispatch"; "BehaviourStep"; "NextIteration"; "Idle"; "destroy" ]

let event_of name fs =
  let action = match assoc_opt "action" fs with
    | Some (`String a) -> a
    | Some `Null -> ""
    | Some v -> bad "field \"action\" is %s, not a text or null" (describe v)
    | None -> bad "no field \"action\"" in
  let body b =
    if not (List.exists (String.equal action) body_actions) then bad "a %s event happens during a step: its action %S is not one" name action;
    Body { action; body = b } in
  match name with
  | "create" -> Create { agent_type = get_str "type" fs; args = get_strs "args" fs;
                         behaviours = get_strs "behaviours" fs }
  | "notify" -> Notify { entry = entry_of fs; overridden = action = "NotifyWith" }
  | "refused" when mem_assoc "object" fs ->
    Refused_put { obj = get_str "object" fs; reason = get_str "reason" fs }
  | "refused" -> Refused { percept = get_str "percept" fs; reason = get_str "reason" fs }
  | "put" -> Put { obj = get_str "object" fs; index = get_pos "index" fs }
  | "deliver" -> Deliver { message = message_of fs; seq = get_pos "seq" fs; in_step = action = "SendInStep" }
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
      | `Assoc m when mem_assoc "performative" m ->
        exact_fields " in \"message\"" m [ "performative"; "content"; "from"; "seq" ];
        Some (Took_message (message_of m, get_pos "seq" m))
      | `Assoc m ->
        exact_fields " in \"message\"" m [ "percept"; "priority"; "seq" ];
        Some (Took_percept (entry_of m))
      | v -> bad "field \"message\" is %s, not an object or null" (describe v) in
    let handler = match mem_assoc "handler" fs, mem_assoc "effects" fs with
      | true, _ -> Some (get_pos "handler" fs, get_effects "effects" fs)
      | false, true -> bad "field \"effects\" without \"handler\""
      | false, false -> None in
    if handler <> None && taken = None then bad "a behaviour step that took no message has no handler";
    Behaviour_step {
      instance = get_pos "instance" fs; behaviour = get_str "behaviour" fs; taken;
      action_effects = (if mem_assoc "action_effects" fs then Some (get_effects "action_effects" fs) else None);
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

(* The keys of a line of this event, as [line_to_json] writes them: the
   same for every event of a name (and, for a behaviour step, of the same
   optional fields), so computed once per such shape. *)
let names_of_shape : (string * bool * bool, string list) Hashtbl.t = Hashtbl.create 32

let expected_names ev =
  let shape = match ev with
    | Behaviour_step { action_effects; handler; _ } -> (event_name ev, action_effects <> None, handler <> None)
    | Refused_put _ -> ("refused_put", false, false)
    | _ -> (event_name ev, false, false) in
  match Hashtbl.find_opt names_of_shape shape with
  | Some l -> l
  | None ->
    let l = List.map fst (match line_to_json { step = 1; agent = ""; event = ev } with `Assoc f -> f | _ -> []) in
    Hashtbl.replace names_of_shape shape l; l

let line_of_json j =
  match j with
  | `Assoc fs ->
    (try
       let step = match field "step" fs with
         | `Int i when i >= 1 -> i
         | `Int i -> bad "field \"step\" must be at least 1 (it is %d)" i
         | v -> bad "field \"step\" is %s, not an integer" (describe v) in
       let l = { step; agent = get_str "agent" fs; event = event_of (get_str "event" fs) fs } in
       exact_fields "" fs (expected_names l.event);
       (match action l.event, assoc_opt "action" fs with
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
       (* version 1: no level (every rule has its line); version 2 names it *)
       let v = match List.assoc_opt "version" fs with
         | Some (`Int v) when v = 1 || v = version -> v
         | Some (`Int v) -> bad "trace format version %d is not supported (this reader knows versions 1 and %d)" v version
         | Some v -> bad "field \"version\" is %s, not the integer %d" (describe v) version
         | None -> bad "the header has no field \"version\" (this reader knows versions 1 and %d)" version in
       exact_fields " in the header" fs
         ([ "trace"; "version"; "variant"; "tie_policy"; "budget"; "o2a_capacity"; "seed" ]
          @ (if v = 1 then [] else [ "level"; "containers" ]) @ [ "agents"; "program" ]);
       let level = if v = 1 then "full" else one_of "level" fs levels in
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
       let h = { variant = one_of "variant" fs variants; tie_policy = one_of "tie_policy" fs tie_policies;
            budget = get_pos "budget" fs; o2a_capacity; seed; level;
            agents = (match field "agents" fs with
                | `List l -> List.map (function
                    | `Assoc a ->
                      exact_fields " in an agent" a [ "name"; "type" ];
                      (get_str "name" a, get_str "type" a)
                    | v -> bad "an agent is an object, not %s" (describe v)) l
                | v -> bad "field \"agents\" is %s, not a list" (describe v));
            containers = (match List.assoc_opt "containers" fs with
                | None -> []
                | Some (`Assoc cs) ->
                  exact_fields " in \"containers\"" cs (List.map fst cs);
                  List.map (fun (n, c) -> match c with
                      | `String c when c <> "" -> (n, c)
                      | v -> bad "the container of %s is %s, not a non-empty text" n (describe v)) cs
                | Some v -> bad "field \"containers\" is %s, not an object" (describe v));
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
                (n, k)) percepts } in
       List.iter (fun (n, _) -> if not (List.mem_assoc n h.agents) then
                     bad "field \"containers\" names %s, which is not an agent of the header" n) h.containers;
       Ok h
     with Bad m -> Error m)
  | _ -> Error "not a jadescript-ref trace (no header line)"

(* --------------------------------------------------- direct encoding (D30) *)

(* A line written straight into bytes, byte for byte what
   [Yojson.Safe.to_string (line_to_json l)] writes: the same fields in the
   same order, and no JSON tree in between. Keys, event names and actions
   are copied as constants (the part of a line before its first value
   depends only on the event's constructor and the agent); integers are
   written by a digit loop, texts copied at once when they need no escape.
   Create (once per agent) and Refused_put go through the tree. The tests
   "trace: direct encoding = JSON tree" and "a writer numbers its lines"
   hold the two equal over every event (D30). *)

(* The bytes written so far: [b] from 0 to [p]. *)
type out = { mutable b : Bytes.t; mutable p : int }

let new_out n = { b = Bytes.create n; p = 0 }

let grow o n =
  let nb = Bytes.create (max (2 * Bytes.length o.b) (o.p + n)) in
  Bytes.blit o.b 0 nb 0 o.p;
  o.b <- nb

(* Room for [n] more bytes. *)
let room o n = if o.p + n > Bytes.length o.b then grow o n [@@inline]

let add_char o c = room o 1; Bytes.unsafe_set o.b o.p c; o.p <- o.p + 1

(* A string written as it is (a constant: a key, punctuation, JSON that is
   already encoded): one copy (a loop over the bytes costs more from 4
   bytes on). *)
let add_raw o s =
  let n = String.length s in
  room o n;
  Bytes.unsafe_blit_string s 0 o.b o.p n;
  o.p <- o.p + n

(* Does [s] need no JSON escape from [i] to [n] (none of the characters
   Yojson escapes: a quote, a backslash, a control character, DEL)? *)
let rec plain s i n =
  i >= n
  || (let c = String.unsafe_get s i in
      c >= ' ' && c <> '"' && c <> '\\' && c <> '\x7F' && plain s (i + 1) n)

(* The last few texts found to need no escape, by address: a trace writes
   the same few names (the agent's, its behaviours', a percept's text on
   its notify, dequeue and handle lines) again and again, and a string
   does not change. *)
let plain_seen = Array.make 8 ""
let plain_next = ref 0

let known_plain s n =
  let a = plain_seen in
  s == Array.unsafe_get a 0 || s == Array.unsafe_get a 1 || s == Array.unsafe_get a 2
  || s == Array.unsafe_get a 3 || s == Array.unsafe_get a 4 || s == Array.unsafe_get a 5
  || s == Array.unsafe_get a 6 || s == Array.unsafe_get a 7
  || (plain s 0 n && begin a.(!plain_next) <- s; plain_next := (!plain_next + 1) land 7; true end)

(* A text as a JSON string: copied at once when it needs no escape,
   otherwise by Yojson. *)
let write_string o s =
  let n = String.length s in
  if known_plain s n then begin
    room o (n + 2);
    let b = o.b and p = o.p in
    Bytes.unsafe_set b p '"';
    Bytes.unsafe_blit_string s 0 b (p + 1) n;
    Bytes.unsafe_set b (p + 1 + n) '"';
    o.p <- p + n + 2
  end else begin
    let t = Buffer.create (n + 16) in
    Yojson.Safe.write_string t s;
    add_raw o (Buffer.contents t)
  end

(* A natural number's decimal digits, as Yojson writes them, by a digit
   loop; a negative one by Yojson. *)
let digit n = Char.unsafe_chr (48 + n)

let write_int o i =
  if i >= 0 && i < 100 then begin
    (* most integers of a trace: instances, handlers, priorities *)
    room o 2;
    let b = o.b and p = o.p in
    if i < 10 then begin Bytes.unsafe_set b p (digit i); o.p <- p + 1 end
    else begin Bytes.unsafe_set b p (digit (i / 10)); Bytes.unsafe_set b (p + 1) (digit (i mod 10)); o.p <- p + 2 end
  end else if i >= 0 then begin
    let rec count n k = if n < 10 then k else count (n / 10) (k + 1) in
    let k = count i 1 in
    room o k;
    let b = o.b in
    let rec put n j =
      Bytes.unsafe_set b j (Char.unsafe_chr (48 + n mod 10));
      if n >= 10 then put (n / 10) (j - 1) in
    put i (o.p + k - 1);
    o.p <- o.p + k
  end else begin
    let t = Buffer.create 24 in
    Yojson.Safe.write_int t i;
    add_raw o (Buffer.contents t)
  end

let put_str o key s = add_raw o key; write_string o s
let put_int o key i = add_raw o key; write_int o i

let put_list o key f l =
  add_raw o key;
  add_char o '[';
  List.iteri (fun i x -> if i > 0 then add_char o ','; f x) l;
  add_char o ']'

let put_effects o key l = put_list o key (fun e -> write_string o (effect_to_string e)) l

(* [sep] comes before the first field: "," inside a line, "" in an object
   of its own *)
let put_entry_rest o e =
  put_int o ",\"priority\":" e.priority;
  put_int o ",\"seq\":" e.seq

let put_entry o sep e =
  put_str o (sep ^ "\"percept\":") e.percept;
  put_entry_rest o e

let put_message o sep m =
  put_str o (sep ^ "\"performative\":") m.performative;
  put_str o ",\"content\":" m.content;
  put_str o ",\"from\":" m.from

(* What follows the agent in a line of this event, up to the first field's
   value: its event name and action (never escaped: this module's own
   names) and the first field's key. Computed once for each constructor
   below, from [event_name] and [action] themselves. *)
let event_part ev first =
  ",\"event\":\"" ^ event_name ev ^ "\",\"action\":"
  ^ (match action ev with Some a -> "\"" ^ a ^ "\"" | None -> "null") ^ first

let e0 = { percept = ""; priority = 0; seq = 0 }
let k_notify = event_part (Notify { entry = e0; overridden = false }) ",\"percept\":"
let k_notify_with = event_part (Notify { entry = e0; overridden = true }) ",\"percept\":"
let k_transfer_one = event_part (Transfer_one e0) ",\"percept\":"
let k_dequeue = event_part (Dequeue e0) ",\"percept\":"
let k_handle =
  event_part (Handle { instance = 0; behaviour = ""; handler = 0; percept = ""; seq = 0; effects = [] })
    ",\"instance\":"
let k_skip = event_part (Skip { instance = 0; behaviour = ""; handler = 0 }) ",\"instance\":"
let k_end_dispatch = event_part (End_dispatch { seq = 0; discarded = false }) ",\"seq\":"
let k_discard = event_part (End_dispatch { seq = 0; discarded = true }) ",\"seq\":"

(* The hot events' constant parts, in the order of [agent_parts] below. *)
let event_parts =
  [| k_notify; k_notify_with; k_transfer_one; k_dequeue; k_handle; k_skip; k_end_dispatch; k_discard |]

(* For the last agent seen (physically: a run writes the same few names on
   every line), its name with its key as JSON, and that followed by each of
   [event_parts]. *)
let agent_json = ref ("", ",\"agent\":\"\"", Array.map (fun k -> ",\"agent\":\"\"" ^ k) event_parts)

let agent_parts agent =
  match !agent_json with
  | (a, _, _) as r when a == agent -> r
  | _ ->
    let t = new_out 16 in
    put_str t ",\"agent\":" agent;
    let j = Bytes.sub_string t.b 0 t.p in
    let r = (agent, j, Array.map (fun k -> j ^ k) event_parts) in
    agent_json := r;
    r

let put_agent o agent = let (_, j, _) = agent_parts agent in add_raw o j

(* The agent and the constant part [event_parts.(k)] after it. *)
let put_agent_event o agent k = let (_, _, a) = agent_parts agent in add_raw o (Array.unsafe_get a k)

(* The line after its step number: [step] is only for the events that go
   through the JSON tree. *)
let encode_after o ~step ~agent event =
  (* the line up to the agent's name included *)
  let start () = put_agent o agent in
  (* ... and its event name and action, for the events without a constant *)
  let head () =
    start ();
    add_raw o ",\"event\":\"";
    add_raw o (event_name event);
    (match event, action event with
     | Body _, Some a -> put_str o "\",\"action\":" a
     | _, Some a -> add_raw o "\",\"action\":\""; add_raw o a; add_char o '"'
     | _, None -> add_raw o "\",\"action\":null") in
  match event with
  | Notify { entry; overridden } ->
    put_agent_event o agent (if overridden then 1 else 0);
    write_string o entry.percept; put_entry_rest o entry; add_char o '}'
  | Transfer_one entry ->
    put_agent_event o agent 2; write_string o entry.percept; put_entry_rest o entry; add_char o '}'
  | Dequeue entry ->
    put_agent_event o agent 3; write_string o entry.percept; put_entry_rest o entry; add_char o '}'
  | Refused { percept; reason } ->
    head (); put_str o ",\"percept\":" percept; put_str o ",\"reason\":" reason; add_char o '}'
  | Put { obj; index } ->
    head (); put_str o ",\"object\":" obj; put_int o ",\"index\":" index; add_char o '}'
  | Deliver { message; seq; _ } ->
    head (); put_message o "," message; put_int o ",\"seq\":" seq; add_char o '}'
  | Undeliverable { receiver; performative; content } ->
    head (); put_str o ",\"to\":" receiver; put_str o ",\"performative\":" performative;
    put_str o ",\"content\":" content; add_char o '}'
  | Transfer n -> head (); put_int o ",\"moved\":" n; add_char o '}'
  | Transfer_spin ob -> head (); put_str o ",\"object\":" ob; add_char o '}'
  | Transfer_end | Next_iteration | Idle | Destroy -> head (); add_char o '}'
  | Handle { instance; behaviour; handler; percept; seq; effects = e } ->
    put_agent_event o agent 4; write_int o instance;
    put_str o ",\"behaviour\":" behaviour;
    put_int o ",\"handler\":" handler; put_str o ",\"percept\":" percept;
    put_int o ",\"seq\":" seq;
    (match e with [] -> add_raw o ",\"effects\":[]" | _ -> put_effects o ",\"effects\":" e);
    add_char o '}'
  | Skip { instance; behaviour; handler } ->
    put_agent_event o agent 5; write_int o instance;
    put_str o ",\"behaviour\":" behaviour;
    put_int o ",\"handler\":" handler;
    add_char o '}'
  | End_dispatch { seq; discarded } ->
    put_agent_event o agent (if discarded then 7 else 6); write_int o seq; add_char o '}'
  | Behaviour_step { instance; behaviour; taken; action_effects; handler } ->
    head ();
    put_int o ",\"instance\":" instance; put_str o ",\"behaviour\":" behaviour;
    (match taken with
     | None -> add_raw o ",\"message\":null"
     | Some (Took_message (m, seq)) ->
       add_raw o ",\"message\":{"; put_message o "" m; put_int o ",\"seq\":" seq;
       add_char o '}'
     | Some (Took_percept e) ->
       add_raw o ",\"message\":{"; put_entry o "" e; add_char o '}');
    (match action_effects with Some e -> put_effects o ",\"action_effects\":" e | None -> ());
    (match handler with
     | Some (h, e) -> put_int o ",\"handler\":" h; put_effects o ",\"effects\":" e
     | None -> ());
    add_char o '}'
  | Body { body; _ } ->
    head ();
    (match body with
     | Log s -> put_str o ",\"text\":" s
     | Invoke { meth; obj; args; result } ->
       put_str o ",\"method\":" meth; put_str o ",\"object\":" obj;
       put_list o ",\"args\":" (write_string o) args; put_str o ",\"result\":" result
     | Send { performative; content; receivers } ->
       put_str o ",\"performative\":" performative; put_str o ",\"content\":" content;
       put_list o ",\"to\":" (write_string o) receivers
     | Activate beh -> put_str o ",\"behaviour\":" beh
     | Deactivate id -> put_int o ",\"instance\":" id
     | Error { at; message } ->
       (* a file name need not be UTF-8, and JSON text must be *)
       put_str o ",\"at\":" (Utf8.repair at); put_str o ",\"message\":" (Utf8.repair message));
    add_char o '}'
  | Create _ | Refused_put _ ->
    (* the tree's line after its step number (which holds no comma) *)
    let j = Yojson.Safe.to_string (line_to_json { step; agent; event }) in
    let k = String.index j ',' in
    add_raw o (String.sub j k (String.length j - k))

let step_key = "{\"step\":"

let line_to_buffer b l =
  let o = new_out 256 in
  add_raw o step_key;
  write_int o l.step;
  encode_after o ~step:l.step ~agent:l.agent l.event;
  Buffer.add_subbytes b o.b 0 o.p

(* ------------------------------------------------- reading, the fast way *)

(* Most lines a judge or a check reads are lines this module wrote: the
   fields in the writer's order, no space, no escape but a quote's or a
   backslash's. Such a line is read straight into a [line], with the
   constraints of [line_of_json] on its numbers and texts, and accepted
   only if [encode_after] writes it back byte for byte; then
   [line_of_json] of its JSON tree gives the same line (the writer writes
   what [line_to_json] holds, D30). Any other line is [None], and is read
   the general way. *)
exception Slow

let last_agent = ref ""

(* Is [o] byte for byte [s]? *)
let same_bytes o s =
  let n = String.length s in
  o.p = n && String.equal (Bytes.sub_string o.b 0 n) s

let fast_line s =
  let n = String.length s in
  let i = ref 0 in
  let lit k =
    let m = String.length k in
    if !i + m > n then raise Slow;
    for j = 0 to m - 1 do
      if String.unsafe_get s (!i + j) <> String.unsafe_get k j then raise Slow
    done;
    i := !i + m in
  let peek () = if !i < n then String.unsafe_get s !i else '\000' in
  (* a non-negative integer of at least [lo], at most [int32_max] *)
  let int lo =
    let start = !i in
    let v = ref 0 in
    while !i < n && (let c = String.unsafe_get s !i in c >= '0' && c <= '9') do
      v := !v * 10 + (Char.code (String.unsafe_get s !i) - 48);
      if !v > int32_max then raise Slow;
      incr i
    done;
    if !i = start || (!i - start > 1 && String.unsafe_get s start = '0') || !v < lo then raise Slow;
    !v in
  let str () =
    if peek () <> '"' then raise Slow;
    incr i;
    let start = !i in
    let rec plain () =
      if !i >= n then raise Slow;
      match String.unsafe_get s !i with
      | '"' -> let t = String.sub s start (!i - start) in incr i; t
      | '\\' -> escaped (Buffer.create 32)
      | c when c < ' ' -> raise Slow
      | _ -> incr i; plain ()
    and escaped b =
      Buffer.add_substring b s start (!i - start);
      let rec go () =
        if !i + 1 >= n then raise Slow;
        match String.unsafe_get s !i with
        | '"' -> incr i; Buffer.contents b
        | '\\' ->
          (match String.unsafe_get s (!i + 1) with
           | ('"' | '\\') as c -> Buffer.add_char b c; i := !i + 2; go ()
           | _ -> raise Slow)
        | c when c < ' ' -> raise Slow
        | c -> Buffer.add_char b c; incr i; go () in
      go () in
    plain () in
  let strs () =
    lit "[";
    if peek () = ']' then (incr i; [])
    else begin
      let rec go acc =
        let t = str () in
        match peek () with
        | ',' -> incr i; go (t :: acc)
        | ']' -> incr i; List.rev (t :: acc)
        | _ -> raise Slow in
      go []
    end in
  let entry () =
    lit ",\"percept\":"; let percept = str () in
    lit ",\"priority\":"; let priority = int 0 in
    lit ",\"seq\":"; let seq = int 1 in
    { percept; priority; seq } in
  let effects key = lit key; List.map effect_of_string (strs ()) in
  (* does the text go on with [k]? *)
  let key k =
    let m = String.length k in
    !i + m <= n && (let rec go j = j >= m || (String.unsafe_get s (!i + j) = String.unsafe_get k j && go (j + 1)) in go 0) in
  match
    lit "{\"step\":"; let step = int 1 in
    lit ",\"agent\":"; let agent = str () in
    (* the agent's name of the last line, the same string: the encoder
       keeps its parts for it by address *)
    let agent = if String.equal agent !last_agent then !last_agent else (last_agent := agent; agent) in
    lit ",\"event\":"; let name = str () in
    lit ",\"action\":";
    let action = if peek () = 'n' then (lit "null"; "") else str () in
    let event = match name with
      | "notify" -> let entry = entry () in Notify { entry; overridden = action = "NotifyWith" }
      | "transfer" -> lit ",\"moved\":"; Transfer (int 0)
      | "transfer_one" -> Transfer_one (entry ())
      | "transfer_end" -> Transfer_end
      | "dequeue" -> Dequeue (entry ())
      | "handle" ->
        lit ",\"instance\":"; let instance = int 1 in
        lit ",\"behaviour\":"; let behaviour = str () in
        lit ",\"handler\":"; let handler = int 1 in
        lit ",\"percept\":"; let percept = str () in
        lit ",\"seq\":"; let seq = int 1 in
        let effects = effects ",\"effects\":" in
        Handle { instance; behaviour; handler; percept; seq; effects }
      | "skip" ->
        lit ",\"instance\":"; let instance = int 1 in
        lit ",\"behaviour\":"; let behaviour = str () in
        lit ",\"handler\":"; let handler = int 1 in
        Skip { instance; behaviour; handler }
      | "end_dispatch" | "discard" -> lit ",\"seq\":"; End_dispatch { seq = int 1; discarded = name = "discard" }
      | "behaviour_step" ->
        lit ",\"instance\":"; let instance = int 1 in
        lit ",\"behaviour\":"; let behaviour = str () in
        lit ",\"message\":";
        let taken =
          if peek () = 'n' then (lit "null"; None)
          else begin
            if key "{\"performative\":" then begin
              lit "{\"performative\":"; let performative = str () in
              lit ",\"content\":"; let content = str () in
              lit ",\"from\":"; let from = str () in
              lit ",\"seq\":"; let seq = int 1 in
              lit "}"; Some (Took_message ({ performative; content; from }, seq))
            end else begin
              lit "{\"percept\":"; let percept = str () in
              lit ",\"priority\":"; let priority = int 0 in
              lit ",\"seq\":"; let seq = int 1 in
              lit "}"; Some (Took_percept { percept; priority; seq })
            end
          end in
        let action_effects =
          if key ",\"action_effects\":" then Some (effects ",\"action_effects\":") else None in
        let handler =
          if key ",\"handler\":" then begin
            lit ",\"handler\":"; let h = int 1 in Some (h, effects ",\"effects\":")
          end else None in
        if handler <> None && taken = None then raise Slow;
        Behaviour_step { instance; behaviour; taken; action_effects; handler }
      | "next_iteration" -> Next_iteration
      | "idle" -> Idle
      | "destroy" -> Destroy
      | "log" ->
        if not (List.exists (String.equal action) body_actions) then raise Slow;
        lit ",\"text\":"; Body { action; body = Log (str ()) }
      | _ -> raise Slow in
    lit "}";
    if !i <> n then raise Slow;
    { step; agent; event }
  with
  | exception (Slow | Bad _) -> None
  | l ->
    (* the line as the writer writes it *)
    let o = new_out (n + 16) in
    add_raw o step_key;
    write_int o l.step;
    encode_after o ~step:l.step ~agent:l.agent l.event;
    if same_bytes o s then Some l else None

(* ------------------------------------------------------------- writing *)

(* A writer to a channel keeps the lines in [out] and hands them to the
   channel [chunk] bytes at a time, in one [output] each; [complete] is
   where the last whole line ends (a signal may stop the program in the
   middle of one: only whole lines are ever written). *)
type writer = { emit : (string -> unit) option; mutable lines : int; out : out;
                mutable complete : int;
                oc : out_channel option (* to_channel's *);
                digits : Bytes.t; mutable first : int
                (* [lines] in decimal: [digits] from [first] on *) }

let chunk = 65536

let new_writer emit out oc =
  { emit; lines = 0; out; complete = 0; oc; digits = Bytes.make 20 '0'; first = 19 }

let writer emit = new_writer (Some emit) (new_out 256) None

(* [lines + 1], and its decimal digits, without a division *)
let next_line w =
  w.lines <- w.lines + 1;
  let d = w.digits in
  let rec carry i =
    if Bytes.unsafe_get d i = '9' then begin
      Bytes.unsafe_set d i '0';
      if i = w.first then w.first <- i - 1;
      carry (i - 1)
    end else Bytes.unsafe_set d i (Char.unsafe_chr (Char.code (Bytes.unsafe_get d i) + 1)) in
  carry 19

(* The whole lines not yet handed to the channel, handed over. They are
   dropped from [out] first: a channel that fails is not given them twice. *)
let pending w =
  match w.oc with
  | Some oc when w.complete > 0 ->
    let n = w.complete and o = w.out in
    let rest = o.p - n in
    if rest = 0 then begin w.complete <- 0; o.p <- 0; output oc o.b 0 n end
    else begin
      (* the start of a line is there too (a signal's exit during it); the
         copy is made before anything is dropped (an allocation is where a
         signal's handler may run) *)
      let whole = Bytes.sub o.b 0 n in
      w.complete <- 0;
      Bytes.blit o.b n o.b 0 rest;
      o.p <- rest;
      output oc whole 0 n
    end
  | _ -> ()

(* After a flush the bytes are given back (a process that runs many
   traced runs, a test or the fuzz campaign, keeps every writer to a
   channel until it exits); a later line takes new ones. *)
let flush w =
  pending w;
  match w.oc with
  | Some oc -> if w.out.p = 0 then w.out.b <- Bytes.empty; Stdlib.flush oc
  | None -> ()

let to_channel oc =
  let w = new_writer (Some (output_string oc)) (new_out 4096) (Some oc) in
  (* flushed when the program ends: normally, by [exit] (a signal handler
     may call it), or by an uncaught exception *)
  at_exit (fun () -> try flush w with Sys_error _ -> ());
  w

let nowhere () = new_writer None (new_out 1) None

(* The line just encoded in [w.out], with its newline, handed on. *)
let line_done w =
  add_char w.out '\n';
  match w.oc, w.emit with
  | Some _, _ -> w.complete <- w.out.p; if w.complete >= chunk then pending w
  | None, Some emit -> emit (Bytes.sub_string w.out.b 0 w.out.p); w.out.p <- 0
  | None, None -> w.out.p <- 0

let write_header w h =
  match w.emit with
  | Some _ -> add_raw w.out (Yojson.Safe.to_string (header_to_json h)); line_done w
  | None -> ()

let write w ~agent event =
  match w.emit with
  | Some _ ->
    next_line w;
    let o = w.out in
    add_raw o step_key;
    let n = 20 - w.first in
    room o n;
    Bytes.unsafe_blit w.digits w.first o.b o.p n;
    o.p <- o.p + n;
    encode_after o ~step:w.lines ~agent event;
    line_done w
  | None -> w.lines <- w.lines + 1

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
          else match Json_read.of_string l with
            | Ok j -> go (f acc n j) (n + 1)
            | Error e ->
              failwith (Printf.sprintf "%s:%d:%d: error: not JSON: %s" path n e.column e.message) in
      go init 1)

exception Located of int * string


(* A trace line is far shorter than this; a longer one (a file of zeros, a
   runaway writer) is an error, not a line read into memory without end. *)
let max_line = 16 * 1024 * 1024

(* The next line, without its newline; [None] at the end of the file.
   @raise Located when longer than [max_line] *)
let last_had_newline = ref true

(* A channel read a block at a time (input_char per byte was a fifth of
   the judge's time): [buf] holds bytes [pos] to [lim] not yet taken;
   [acc] the start of a line that spans blocks. *)
type reader = { ic : in_channel; buf : Bytes.t; mutable pos : int; mutable lim : int; acc : Buffer.t }

let reader ic = { ic; buf = Bytes.create 65536; pos = 0; lim = 0; acc = Buffer.create 256 }

let bounded_line r n =
  let too_long () = raise (Located (n, Printf.sprintf "a line longer than %d bytes: not a trace" max_line)) in
  Buffer.clear r.acc;
  let rec go () =
    if r.pos >= r.lim then begin
      r.pos <- 0;
      r.lim <- input r.ic r.buf 0 (Bytes.length r.buf)
    end;
    if r.lim = 0 then begin
      last_had_newline := false;
      if Buffer.length r.acc = 0 then None else Some (Buffer.contents r.acc)
    end else
      let b = r.buf and lim = r.lim in
      let rec nl k = if k >= lim then -1 else if Bytes.unsafe_get b k = '\n' then k else nl (k + 1) in
      match nl r.pos with
      | k when k >= 0 ->
        let len = k - r.pos in
        if Buffer.length r.acc + len > max_line then too_long ();
        let line =
          if Buffer.length r.acc = 0 then Bytes.sub_string r.buf r.pos len
          else (Buffer.add_subbytes r.acc r.buf r.pos len; Buffer.contents r.acc) in
        r.pos <- k + 1;
        last_had_newline := true;
        Some line
      | _ ->
        let len = r.lim - r.pos in
        if Buffer.length r.acc + len > max_line then too_long ();
        Buffer.add_subbytes r.acc r.buf r.pos len;
        r.pos <- r.lim;
        go () in
  go ()

(* Only bytes below 0x80: valid UTF-8 at once (most lines). *)
let ascii s =
  let rec go i = i < 0 || (Char.code (String.unsafe_get s i) < 0x80 && go (i - 1)) in
  go (String.length s - 1)

let first_invalid l = if ascii l then None else Utf8.first_invalid l

(* What the JSON reader said, with its column (a trace line is one line). *)
let json_error (e : Json_read.error) = Printf.sprintf "%s (column %d)" e.message e.column

let read_located path =
  let located n fmt = Printf.ksprintf (fun m -> raise (Located (n, m))) fmt in
  match
    let ic = open_in_bin path in
    let r = reader ic in
    Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
        let rec go h acc n =
          match bounded_line r n with
          | None -> (h, acc)
          | Some l when String.trim l = "" -> go h acc (n + 1)
          | Some l ->
            (match first_invalid l with
             | Some k -> located n "not JSON: byte %d is not valid UTF-8" (k + 1)
             | None -> ());
            match if h <> None then fast_line l else None with
            | Some x -> go h ((n, x) :: acc) (n + 1)
            | None ->
            let j = match Json_read.of_string l with
              | Ok j -> j
              | Error e -> located n "not JSON: %s" (json_error e) in
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

(* One line at a time, as read_located reads them: [f] gets the header,
   then each line, with its number; memory does not grow with the file. A
   last line with no newline that is not JSON (a run killed while it wrote
   it) is not read: [Ok true] says so. *)
let stream_cut path ~header ~line =
  let located n fmt = Printf.ksprintf (fun m -> raise (Located (n, m))) fmt in
  let cut_at = ref 0 in
  match
    let ic = open_in_bin path in
    let r = reader ic in
    Fun.protect ~finally:(fun () -> close_in_noerr ic) (fun () ->
        let rec go seen n =
          match bounded_line r n with
          | None -> (seen, false)
          | Some l when String.trim l = "" -> go seen (n + 1)
          | Some l ->
            let cut = not !last_had_newline in
            (match first_invalid l with
             | Some k -> if cut && seen then (cut_at := n; raise Exit)
               else located n "not JSON: byte %d is not valid UTF-8" (k + 1)
             | None -> ());
            match if seen then fast_line l else None with
            | Some x -> line n x; go seen (n + 1)
            | None ->
            let j = match Json_read.of_string l with
              | Ok j -> j
              | Error e -> if cut && seen then (cut_at := n; raise Exit) else located n "not JSON: %s" (json_error e) in
            if not seen then begin
              match header_of_json j with
              | Ok h -> header h; go true (n + 1)
              | Error m -> located n "%s" m
            end else begin
              match line_of_json j with
              | Ok l -> line n l; go seen (n + 1)
              | Error m -> located n "%s" m
            end in
        try go false 1 with Exit -> (true, true))
  with
  | (true, cut) -> Ok (if cut then Some !cut_at else None)
  | (false, _) -> Error (1, "not a jadescript-ref trace (no header line)")
  | exception Located (n, m) -> Error (n, m)
  | exception Sys_error m -> Error (1, m)

let stream path ~header ~line =
  Result.map Option.is_some (stream_cut path ~header ~line)

let read_file path =
  match read_located path with
  | Ok r -> Ok r
  | Error (n, m) -> Error (Printf.sprintf "%s:%d:1: error: %s" path n m)
