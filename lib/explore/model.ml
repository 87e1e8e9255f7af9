type effect = E_activate of int | E_deactivate
type handler = { accepts : int list; effects : effect list }

type beh = {
  bidx : int;
  bname : string;
  cyclic : bool;
  has_action : bool;
  action_effects : effect list;
  percept_handlers : handler array;
  message_handlers : handler array;
  all : beh array Lazy.t;
}

type t = {
  name : string;
  dir : string;
  constants : (string * Tla.t) list;
  params : Semantics.Machine.params;
  percepts : string array;
  default_priority : int array;
  overrides : int list;
  objects : string array;
  messages : string array;
  max_notify : int;
  max_put : int;
  max_send : int;
  behaviours : beh array;
  initial : int list;
  inversion_bound : int;
}

exception Error of string

let fail fmt = Printf.ksprintf (fun s -> raise (Error s)) fmt

let read_file path =
  match open_in_bin path with
  | exception Sys_error m -> fail "%s" m
  | ic ->
    Fun.protect ~finally:(fun () -> close_in_noerr ic)
      (fun () -> really_input_string ic (in_channel_length ic))

(* Remove \* comments (outside strings) and (* ... *) comments. *)
let strip_comments s =
  let b = Buffer.create (String.length s) in
  let n = String.length s in
  let rec go i in_str depth =
    if i >= n then ()
    else if depth > 0 then
      if i + 1 < n && s.[i] = '*' && s.[i + 1] = ')' then go (i + 2) false (depth - 1)
      else if i + 1 < n && s.[i] = '(' && s.[i + 1] = '*' then go (i + 2) false (depth + 1)
      else go (i + 1) false depth
    else if in_str then begin
      Buffer.add_char b s.[i];
      if s.[i] = '\\' && i + 1 < n then (Buffer.add_char b s.[i + 1]; go (i + 2) true 0)
      else go (i + 1) (s.[i] <> '"') 0
    end else if s.[i] = '"' then (Buffer.add_char b '"'; go (i + 1) true 0)
    else if i + 1 < n && s.[i] = '\\' && s.[i + 1] = '*' then begin
      let j = try String.index_from s i '\n' with Not_found -> n in
      go j false 0
    end else if i + 1 < n && s.[i] = '(' && s.[i + 1] = '*' then go (i + 2) false 1
    else (Buffer.add_char b s.[i]; go (i + 1) false 0) in
  go 0 false 0;
  Buffer.contents b

(* The definitions NAME == value of a module, for literal values. *)
let definitions text =
  let s = strip_comments text in
  let lines = String.split_on_char '\n' s in
  let defs = ref [] in
  let offset = ref 0 in
  List.iter (fun line ->
      let start = !offset in
      offset := !offset + String.length line + 1;
      match String.index_opt line '=' with
      | Some k when k + 1 < String.length line && line.[k + 1] = '=' ->
        let name = String.trim (String.sub line 0 k) in
        if name <> "" && String.for_all (function 'a'..'z' | 'A'..'Z' | '0'..'9' | '_' -> true | _ -> false) name
        then (match Tla.parse_prefix s (start + k + 2) with
            | (v, _) -> defs := (name, v) :: !defs
            | exception Tla.Parse_error _ -> ())
      | _ -> ()) lines;
  List.rev !defs

(* CONSTANT X <- MCX lines of a cfg. *)
let bindings cfg =
  let s = strip_comments cfg in
  String.split_on_char '\n' s
  |> List.filter_map (fun line ->
      match String.split_on_char ' ' (String.trim line) |> List.filter (( <> ) "") with
      | ("CONSTANT" | "CONSTANTS") :: x :: "<-" :: def :: _ -> Some (x, `Def def)
      | ("CONSTANT" | "CONSTANTS") :: x :: "=" :: v :: _ -> Some (x, `Val v)
      | _ -> None)

let is_agent_loop_model path =
  match read_file path with
  | text -> (try ignore (Str_find.find text "EXTENDS AgentLoop"); true with Not_found -> false)
  | exception Error _ -> false

let get cs name =
  match List.assoc_opt name cs with
  | Some v -> v
  | None -> fail "the model does not define the constant %s" name

let strings v = List.map Tla.to_str (Tla.to_list v)

(* The range of every number constant of a model (docs/spec.md, "Model
   constants"). Every model read is checked against the lower bounds (a
   budget of -1 means nothing); the upper bounds, which keep a state graph
   small enough to explore, are for the models of spec/models and [explore]
   ({!check_explorable}), not for the models validate and the simulation
   generate from a trace (one percept name per notification). *)
let ranges = [
  ("Budget", 1, 16); ("MaxActive", 1, 8); ("O2ACapacity", 1, 16);
  ("MaxNotify", 0, 8); ("MaxPut", 0, 8); ("MaxSend", 0, 8); ("InversionBound", 0, 64) ]
let max_priority = 0x7fffffff   (* a Jadescript integer (32 bits) *)
let max_names = 8               (* percepts, objects, messages, behaviours *)

let in_range name lo hi n =
  if n < lo || n > hi then
    (if hi = max_int then fail "constant MC%s == %d is out of range: at least %d" name n lo
     else fail "constant MC%s == %d is out of range: from %d to %d" name n lo hi);
  n

let int_constant g name =
  let (_, lo, _) = List.find (fun (n, _, _) -> n = name) ranges in
  in_range name lo max_int (Tla.to_int (g name))

let of_constants ~name ~dir cs =
  try
    let g = get cs in
    let names c = strings (g c) in
    let percepts = Array.of_list (List.sort compare (names "Percepts")) in
    let behaviours_names = Array.of_list (List.sort compare (names "Behaviours")) in
    let index arr what x =
      let rec go i = if i >= Array.length arr then fail "unknown %s %S" what x
        else if arr.(i) = x then i else go (i + 1) in
      go 0 in
    let messages = Array.of_list (List.sort compare (names "Messages")) in
    let objects = Array.of_list (List.sort compare (names "Objects")) in
    let per_beh c b = Tla.field b (g c) in
    (* A send (R5e) changes nothing in the sending agent's loop (ApplyEffect
       of the spec): the platform of several agents routes it, one agent's
       model leaves it out. *)
    let effect v = match Tla.to_str (Tla.field "op" v) with
      | "activate" -> Some (E_activate (index behaviours_names "behaviour" (Tla.to_str (Tla.field "b" v))))
      | "deactivate" -> Some E_deactivate
      | "send" -> ignore (Tla.to_str (Tla.field "to" v), Tla.to_str (Tla.field "m" v)); None
      | op -> fail "unknown effect %s" op in
    let effects l = List.filter_map effect (Tla.to_list l) in
    let handlers names c b =
      Tla.to_list (per_beh c b) |> List.map (fun h ->
          { accepts = List.sort compare (List.map (index names "accepted value") (strings (Tla.field "accepts" h)));
            effects = effects (Tla.field "effects" h) })
      |> Array.of_list in
    let rec all = lazy (Array.mapi (fun i b ->
        { bidx = i; bname = b;
          cyclic = (match Tla.to_str (per_beh "Kind" b) with
              | "cyclic" -> true | "oneshot" -> false | k -> fail "unknown kind %s" k);
          has_action = Tla.to_bool (per_beh "HasAction" b);
          action_effects = effects (per_beh "ActionEffects" b);
          percept_handlers = handlers percepts "PerceptHandlers" b;
          message_handlers = handlers messages "MessageHandlers" b;
          all }) behaviours_names) in
    let behaviours = Lazy.force all in
    let variant = match Semantics.Machine.variant_of_string (Tla.to_str (g "Variant")) with
      | Some v -> v | None -> fail "unknown Variant" in
    let tie = match Tla.to_str (g "TiePolicy") with
      | "Stable" -> Semantics.Machine.Stable | "Unstable" -> Semantics.Machine.Unstable
      | t -> fail "unknown TiePolicy %s" t in
    let flood = Tla.to_bool (g "Flood") in
    let params = { Semantics.Machine.variant; tie; budget = int_constant g "Budget";
                   max_active = Some (int_constant g "MaxActive");
                   o2a_capacity = Some (int_constant g "O2ACapacity");
                   flood; ghosts = true } in
    { name; dir; constants = cs; params; percepts;
      default_priority = Array.map (fun p ->
          in_range "DefaultPriority" 0 max_priority (Tla.to_int (Tla.field p (g "DefaultPriority")))) percepts;
      overrides = List.sort_uniq compare
          (List.map (fun v -> in_range "Overrides" 0 max_priority (Tla.to_int v)) (Tla.to_list (g "Overrides")));
      objects; messages;
      max_notify = int_constant g "MaxNotify"; max_put = int_constant g "MaxPut";
      max_send = int_constant g "MaxSend"; behaviours;
      initial = List.map (fun v -> index behaviours_names "behaviour" (Tla.to_str v))
          (Tla.to_list (g "InitialBehaviours"));
      inversion_bound = int_constant g "InversionBound" }
  with
  | Invalid_argument m -> fail "model %s: a constant has the wrong shape (%s)" name m
  | Error m -> fail "model %s: %s" name m

let load path =
  let base = Filename.remove_extension path in
  let tla = base ^ ".tla" and cfg = base ^ ".cfg" in
  let name = Filename.basename base in
  let defs = definitions (read_file tla) in
  let binds = bindings (read_file cfg) in
  let cs = List.map (fun (x, b) -> match b with
      | `Def d ->
        (match List.assoc_opt d defs with
         | Some v -> (x, v)
         | None -> fail "%s: %s is bound to %s, which is not a literal definition" cfg x d)
      | `Val v ->
        (match Tla.parse v with
         | v -> (x, v)
         | exception Tla.Parse_error m -> fail "%s: constant %s: %s" cfg x m)) binds in
  of_constants ~name ~dir:(Filename.dirname path) cs

module Bodies = struct
  type percept = int
  type message = int
  type obj = int
  type nonrec beh = beh
  type world = unit
  type bindings = unit

  let cyclic b = b.cyclic
  let has_action b = b.has_action
  let percept_handlers b = Array.length b.percept_handlers
  let message_handlers b = Array.length b.message_handlers

  let effects b effs =
    List.map (function
        | E_activate i -> Semantics.Machine.Activate (Lazy.force b.all).(i)
        | E_deactivate -> Semantics.Machine.Deactivate) effs

  let accepted l x = if List.mem x l then Some () else None
  let percept_applicable () ~id:_ b h p = ((), accepted b.percept_handlers.(h - 1).accepts p)
  let run_percept_handler () ~id:_ ~active:_ b h _ () = ((), effects b b.percept_handlers.(h - 1).effects)
  let run_action () ~id:_ ~active:_ b = ((), effects b b.action_effects)
  let message_accepted () ~id:_ b h m = ((), accepted b.message_handlers.(h - 1).accepts m)
  let run_message_handler () ~id:_ ~active:_ b h _ () = ((), effects b b.message_handlers.(h - 1).effects)
  let take_outbox () = ((), [])
end

module M = Semantics.Machine.Make (Bodies)

let check_explorable m =
  let upper name n =
    let (_, lo, hi) = List.find (fun (x, _, _) -> x = name) ranges in
    ignore (in_range name lo hi n) in
  try
    let p = m.params in
    upper "Budget" p.budget;
    Option.iter (upper "MaxActive") p.max_active;
    Option.iter (upper "O2ACapacity") p.o2a_capacity;
    upper "MaxNotify" m.max_notify; upper "MaxPut" m.max_put; upper "MaxSend" m.max_send;
    upper "InversionBound" m.inversion_bound;
    List.iter (fun (c, n) ->
        if n > max_names then fail "constant MC%s has %d elements; at most %d" c n max_names)
      [ ("Percepts", Array.length m.percepts); ("Objects", Array.length m.objects);
        ("Messages", Array.length m.messages); ("Behaviours", Array.length m.behaviours) ]
  with Error e -> fail "model %s: %s" m.name e
