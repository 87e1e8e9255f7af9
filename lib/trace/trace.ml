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
  | Create _ -> "create" | Notify _ -> "notify" | Refused _ -> "refused" | Put _ -> "put"
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
  | Refused _ | Undeliverable _ | Destroy -> None
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

exception Bad of string

let bad fmt = Printf.ksprintf (fun s -> raise (Bad s)) fmt

let field f fs = match List.assoc_opt f fs with Some v -> v | None -> bad "no field %S" f
let get_str f fs = match field f fs with `String s -> s | _ -> bad "field %S is not a string" f
let get_int f fs = match field f fs with `Int i -> i | _ -> bad "field %S is not an integer" f
let get_bool f fs = match field f fs with `Bool b -> b | _ -> bad "field %S is not a boolean" f
let get_strs f fs = match field f fs with
  | `List l -> List.map (function `String s -> s | _ -> bad "field %S holds a non-string" f) l
  | _ -> bad "field %S is not a list" f
let get_opt_int f fs = match List.assoc_opt f fs with
  | None | Some `Null -> None | Some (`Int i) -> Some i | Some _ -> bad "field %S is not an integer" f
let get_obj f fs = match field f fs with `Assoc o -> o | _ -> bad "field %S is not an object" f

let effect_of_string s =
  match String.split_on_char ' ' s with
  | [ "deactivate" ] -> Deactivated
  | [ "activate"; b ] -> Activated b
  | _ -> bad "unknown effect %S" s

let get_effects f fs = List.map effect_of_string (get_strs f fs)

let entry_of fs = { percept = get_str "percept" fs; priority = get_int "priority" fs; seq = get_int "seq" fs }
let message_of fs = { performative = get_str "performative" fs; content = get_str "content" fs; from = get_str "from" fs }

let event_of name fs =
  let action = match List.assoc_opt "action" fs with Some (`String a) -> a | _ -> "" in
  match name with
  | "create" -> Create { agent_type = get_str "type" fs; args = get_strs "args" fs;
                         behaviours = get_strs "behaviours" fs }
  | "notify" -> Notify { entry = entry_of fs; overridden = action = "NotifyWith" }
  | "refused" -> Refused { percept = get_str "percept" fs; reason = get_str "reason" fs }
  | "put" -> Put { obj = get_str "object" fs; index = get_int "index" fs }
  | "deliver" -> Deliver { message = message_of fs; seq = get_int "seq" fs }
  | "undeliverable" -> Undeliverable { receiver = get_str "to" fs; performative = get_str "performative" fs;
                                       content = get_str "content" fs }
  | "transfer" -> Transfer (get_int "moved" fs)
  | "transfer_one" -> Transfer_one (entry_of fs)
  | "transfer_spin" -> Transfer_spin (get_str "object" fs)
  | "transfer_end" -> Transfer_end
  | "dequeue" -> Dequeue (entry_of fs)
  | "handle" -> Handle { instance = get_int "instance" fs; behaviour = get_str "behaviour" fs;
                         handler = get_int "handler" fs; percept = get_str "percept" fs;
                         seq = get_int "seq" fs; effects = get_effects "effects" fs }
  | "skip" -> Skip { instance = get_int "instance" fs; behaviour = get_str "behaviour" fs;
                     handler = get_int "handler" fs }
  | "discard" | "end_dispatch" -> End_dispatch { seq = get_int "seq" fs; discarded = name = "discard" }
  | "behaviour_step" ->
    let taken = match field "message" fs with
      | `Null -> None
      | `Assoc m when List.mem_assoc "performative" m -> Some (Took_message (message_of m, get_int "seq" m))
      | `Assoc m -> Some (Took_percept (entry_of m))
      | _ -> bad "field \"message\" is not an object" in
    Behaviour_step {
      instance = get_int "instance" fs; behaviour = get_str "behaviour" fs; taken;
      action_effects = (if List.mem_assoc "action_effects" fs then Some (get_effects "action_effects" fs) else None);
      handler = (if List.mem_assoc "handler" fs then Some (get_int "handler" fs, get_effects "effects" fs) else None) }
  | "next_iteration" -> Next_iteration
  | "idle" -> Idle
  | "destroy" -> Destroy
  | "log" -> Body { action; body = Log (get_str "text" fs) }
  | "invoke" -> Body { action; body = Invoke { meth = get_str "method" fs; obj = get_str "object" fs;
                                               args = get_strs "args" fs; result = get_str "result" fs } }
  | "send" -> Body { action; body = Send { performative = get_str "performative" fs;
                                           content = get_str "content" fs; receivers = get_strs "to" fs } }
  | "activate" -> Body { action; body = Activate (get_str "behaviour" fs) }
  | "deactivate" -> Body { action; body = Deactivate (get_int "instance" fs) }
  | "error" -> Body { action; body = Error { at = get_str "at" fs; message = get_str "message" fs } }
  | e -> bad "unknown event %S" e

let line_of_json j =
  match j with
  | `Assoc fs ->
    (try Ok { step = get_int "step" fs; agent = get_str "agent" fs; event = event_of (get_str "event" fs) fs }
     with Bad m -> Error m)
  | _ -> Error "a trace line is a JSON object"

let header_of_json j =
  match j with
  | `Assoc fs when is_header j ->
    (try
       if get_str "trace" fs <> "jadescript-ref" then bad "not a jadescript-ref trace";
       let program = get_obj "program" fs in
       Ok { variant = get_str "variant" fs; tie_policy = get_str "tie_policy" fs;
            budget = get_int "budget" fs; o2a_capacity = get_opt_int "o2a_capacity" fs;
            seed = get_opt_int "seed" fs;
            agents = (match field "agents" fs with
                | `List l -> List.map (function
                    | `Assoc a -> (get_str "name" a, get_str "type" a)
                    | _ -> bad "an agent is an object") l
                | _ -> bad "field \"agents\" is not a list");
            behaviours = (match field "behaviours" program with
                | `List l -> List.map (function
                    | `Assoc b -> { name = get_str "name" b; kind = get_str "kind" b;
                                    has_action = get_bool "action" b;
                                    percept_handlers = get_int "percept_handlers" b;
                                    message_handlers = get_int "message_handlers" b }
                    | _ -> bad "a behaviour is an object") l
                | _ -> bad "field \"behaviours\" is not a list");
            percepts = List.map (function
                | (n, `Int k) -> (n, k)
                | (n, _) -> bad "the priority of %s is not an integer" n) (get_obj "percepts" program) }
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

let read_file path =
  match
    fold_file path (fun (h, acc) n j ->
        match h with
        | None ->
          (match header_of_json j with
           | Ok h -> (Some h, acc)
           | Error m -> failwith (Printf.sprintf "%s:%d:1: error: %s" path n m))
        | Some _ ->
          (match line_of_json j with
           | Ok l -> (h, (n, l) :: acc)
           | Error m -> failwith (Printf.sprintf "%s:%d:1: error: %s" path n m))) (None, [])
  with
  | (Some h, lines) -> Ok (h, List.rev lines)
  | (None, _) -> Error (Printf.sprintf "%s:1:1: error: not a jadescript-ref trace (no header line)" path)
  | exception Failure m -> Error m
  | exception Sys_error m -> Error (Printf.sprintf "%s:1:1: error: %s" path m)
