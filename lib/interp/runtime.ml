module P = Semantics.Platform.Make (Eval.Bodies)
module M = P.M
module E = Engine.Fast.Make (Engine.Interp_bodies)
module Mc = Semantics.Machine
module T = Typing.Tenv
module V = Value

type options = {
  params : Mc.params;
  seed : int option;
  fuel : int;
  max_steps : int;
  trace : out_channel option;
  on_log : string -> string -> unit;
  on_error : Syntax.Source.region -> string -> unit;
}

type t = {
  env : T.t;
  opts : options;
  mutable platform : P.t;
  mutable steps : int;           (* agent steps so far *)
  mutable events : int;          (* trace events written *)
  rand : Random.State.t option;
  puts : (string, int) Hashtbl.t;   (* objects put per agent, for their index *)
  types : (string * int, string) Hashtbl.t;
      (* (agent, instance id) -> behaviour type, as of the previous step *)
}

(* -------------------------------------------------------------- trace *)

let str s = `String s
let int i = `Int i

let write t (fields : (string * Yojson.Safe.t) list) =
  t.events <- t.events + 1;
  match t.opts.trace with
  | None -> ()
  | Some oc ->
    output_string oc (Yojson.Safe.to_string (`Assoc (("step", int t.events) :: fields)));
    output_char oc '\n'

let entry_fields (e : V.t Mc.entry) =
  [ "percept", str (V.to_literal e.p); "priority", int e.prio; "seq", int e.seq ]

let message_fields (m : Eval.message) =
  [ "performative", str m.perf; "content", str (V.to_literal m.content); "from", str m.sender ]

let behaviour_of (c : M.t) id =
  match List.find_opt (fun (a : Eval.beh Mc.instance) -> a.id = id) c.active with
  | Some a -> Eval.beh_type a.beh
  | None -> "?"

let label_fields (c : M.t) (l : M.lbl) : (string * Yojson.Safe.t) list =
  let ev name = [ "event", str name; "action", str (Mc.action_name l) ] in
  match l with
  | Mc.Init -> ev "init"
  | Mc.Notify e | Mc.Notify_with e -> ev "notify" @ entry_fields e
  | Mc.Put o -> ev "put" @ [ "object", str (V.to_literal o) ]
  | Mc.Send (m, seq) -> ev "deliver" @ message_fields m @ [ "seq", int seq ]
  | Mc.Transfer n -> ev "transfer" @ [ "moved", int n ]
  | Mc.Transfer_one e -> ev "transfer_one" @ entry_fields e
  | Mc.Transfer_spin o -> ev "transfer_spin" @ [ "object", str (V.to_literal o) ]
  | Mc.Transfer_end -> ev "transfer_end"
  | Mc.Dequeue e -> ev "dequeue" @ entry_fields e
  | Mc.Handle { id; h; p; seq } ->
    ev "handle" @ [ "instance", int id; "behaviour", str (behaviour_of c id); "handler", int h;
                    "percept", str (V.to_literal p); "seq", int seq ]
  | Mc.Skip { id; h } -> ev "skip" @ [ "instance", int id; "behaviour", str (behaviour_of c id); "handler", int h ]
  | Mc.End_dispatch { seq; discarded } ->
    ev (if discarded then "discard" else "end_dispatch") @ [ "seq", int seq ]
  | Mc.Behaviour_step { id; msg } ->
    ev "behaviour_step"
    @ [ "instance", int id; "behaviour", str (behaviour_of c id);
        "message", (match msg with
            | None -> `Null
            | Some (Mc.M_message { m; mseq }) -> `Assoc (message_fields m @ [ "seq", int mseq ])
            | Some (Mc.M_percept e) -> `Assoc (entry_fields e)) ]
  | Mc.Next_iteration -> ev "next_iteration"
  | Mc.Idle -> ev "idle"

let body_event t agent action (e : Eval.event) =
  let base name = [ "agent", str agent; "event", str name; "action", str action ] in
  match e with
  | Eval.Log s -> t.opts.on_log agent s; write t (base "log" @ [ "text", str s ])
  | Eval.Invoke { meth; cls; args; result } ->
    write t (base "invoke" @ [ "method", str meth; "object", str cls;
                               "args", `List (List.map (fun v -> str (V.to_literal v)) args);
                               "result", str (V.to_literal result) ])
  | Eval.Sent { perf; content; receivers } ->
    write t (base "send" @ [ "performative", str perf; "content", str (V.to_literal content);
                             "to", `List (List.map str receivers) ])
  | Eval.Activated b -> write t (base "activate" @ [ "behaviour", str b ])
  | Eval.Deactivated id -> write t (base "deactivate" @ [ "instance", int id ])
  | Eval.Error (at, msg) ->
    t.opts.on_error at msg;
    write t (base "error" @ [ "at", str (Syntax.Source.string_of_region at); "message", str msg ])

let find t name = P.find t.platform name

let world t i = t.platform.agents.(i).config.world

let flush_body t i action = List.iter (body_event t t.platform.agents.(i).name action) (Eval.take_events (world t i))

let on_event t (pl : P.t) (e : P.event) =
  t.platform <- pl;
  match e with
  | P.Step (name, l) ->
    let i = Option.get (P.find pl name) in
    let a = world t i in
    let effects l = `List (List.map str l) in
    let extra = match l with
      | Mc.Handle _ -> [ "effects", effects a.last_effects ]
      | Mc.Behaviour_step { msg; _ } ->
        (match a.last_action_effects with Some e -> [ "action_effects", effects e ] | None -> [])
        @ (match msg, a.last_handler with
            | Some _, Some h -> [ "handler", int h; "effects", effects a.last_effects ]
            | _ -> [])
      | _ -> [] in
    let known id = Option.value (Hashtbl.find_opt t.types (name, id)) ~default:"?" in
    let fields = List.map (fun (k, v) ->
        if k <> "behaviour" then (k, v)
        else if a.last_behaviour <> "" && (match l with Mc.Skip _ -> false | _ -> true) then (k, str a.last_behaviour)
        else match l with
          | Mc.Handle { id; _ } | Mc.Behaviour_step { id; _ } | Mc.Skip { id; _ } -> (k, str (known id))
          | _ -> (k, v)) (label_fields pl.agents.(i).config l) in
    List.iter (fun (x : Eval.beh Mc.instance) -> Hashtbl.replace t.types (name, x.id) (Eval.beh_type x.beh))
      pl.agents.(i).config.active;
    write t (("agent", str name) :: fields @ extra);
    a.last_behaviour <- "";
    a.last_action_effects <- None; a.last_handler <- None; a.last_effects <- [];
    flush_body t i (Mc.action_name l)
  | P.Delivered { sender; receiver; message } ->
    let i = Option.get (P.find pl receiver) in
    write t (("agent", str receiver) :: label_fields pl.agents.(i).config pl.agents.(i).config.last);
    ignore sender; ignore message
  | P.Undeliverable { sender; receiver; message } ->
    write t [ "agent", str sender; "event", str "undeliverable"; "action", `Null;
              "to", str receiver; "performative", str message.perf;
              "content", str (V.to_literal message.content) ]

(* ---------------------------------------------------------- create *)

let create env opts specs =
  let t = { env; opts; platform = P.create []; steps = 0; events = 0;
            rand = Option.map (fun s -> Random.State.make [| s |]) opts.seed;
            puts = Hashtbl.create 8; types = Hashtbl.create 16 } in
  (match opts.trace with
   | None -> ()
   | Some oc ->
     let program = `Assoc [
         "behaviours", `List (List.map (fun (b : T.behaviour) ->
             let hs = T.behaviour_handlers env b.b_name in
             `Assoc [ "name", str b.b_name;
                      "kind", str (match b.b_kind with Syntax.Ast.Cyclic -> "cyclic" | Syntax.Ast.OneShot -> "oneshot");
                      "action", `Bool (T.behaviour_action env b.b_name <> None);
                      "percept_handlers", int (List.length (List.filter (fun (h : T.handler) -> h.h_kind = T.On_percept) hs));
                      "message_handlers", int (List.length (List.filter (fun (h : T.handler) -> h.h_kind <> T.On_percept) hs)) ])
             (T.behaviours env));
         "percepts", `Assoc (List.filter_map (fun (s : T.schema) ->
             if s.s_percept then Some (s.s_name, int s.s_priority) else None) (T.schemas env)) ] in
     let p = opts.params in
     output_string oc (Yojson.Safe.to_string (`Assoc [
         "trace", str "jadescript-ref"; "version", int 1;
         "variant", str (Mc.string_of_variant p.variant);
         "tie_policy", str (match p.tie with Mc.Stable -> "stable" | Mc.Unstable -> "unstable");
         "budget", int p.budget;
         "o2a_capacity", (match p.o2a_capacity with Some c -> int c | None -> `Null);
         "seed", (match opts.seed with Some s -> int s | None -> `Null);
         "agents", `List (List.map (fun (n, ty, _) -> `Assoc [ "name", str n; "type", str ty ]) specs);
         "program", program ]));
     output_char oc '\n');
  let created = List.map (fun (name, ty, args) ->
      let (a, behs) = Eval.create_agent env ~name ~atype:ty ~args ~fuel:opts.fuel in
      write t [ "agent", str name; "event", str "create"; "action", str "Init"; "type", str ty;
                "args", `List (List.map (fun v -> str (V.to_literal v)) args);
                "behaviours", `List (List.map (fun b -> str (Eval.beh_type b)) behs) ];
      List.iter (body_event t name "Init") (Eval.take_events a);
      (name, M.init opts.params ~world:a behs)) specs in
  t.platform <- P.create created;
  (* Messages sent by on create, once every agent exists. *)
  Array.iteri (fun i (ag : P.agent) ->
      let (w, out) = Eval.Bodies.take_outbox ag.config.world in
      ignore w;
      List.iter (fun (receiver, m) ->
          let (pl, ev) = P.deliver opts.params t.platform ~sender:ag.name ~receiver m in
          on_event t pl ev) out;
      ignore i) t.platform.agents;
  t

(* ------------------------------------------------------------ host *)

let with_agent t agent k =
  match find t agent with
  | None -> Error (Printf.sprintf "there is no agent %s" agent)
  | Some i -> k i t.platform.agents.(i).config

let set_config t i c =
  let agents = Array.copy t.platform.agents in
  agents.(i) <- { (agents.(i)) with config = c };
  t.platform <- { t.platform with agents }

let notify t ~agent v ~default ~priority =
  with_agent t agent (fun i c ->
      match priority with
      | Some k when k < 0 -> Error (Printf.sprintf "priority %d is negative (R2a)" k)
      | _ when not (M.o2a_has_room t.opts.params c) ->
        write t [ "agent", str agent; "event", str "refused"; "action", `Null;
                  "percept", str (V.to_literal v); "reason", str "the O2A queue is full (R2d)" ];
        Error "the O2A queue is full (R2d)"
      | None ->
        let c = M.notify t.opts.params c v default in
        set_config t i c; write t (("agent", str agent) :: label_fields c c.last); Ok ()
      | Some k ->
        let c = M.notify_with t.opts.params c v k in
        set_config t i c; write t (("agent", str agent) :: label_fields c c.last); Ok ())

let put t ~agent v =
  with_agent t agent (fun i c ->
      if not (M.o2a_has_room t.opts.params c) then Error "the O2A queue is full (R2d)"
      else begin
        let c = M.put t.opts.params c v in
        set_config t i c;
        let k = 1 + Option.value (Hashtbl.find_opt t.puts agent) ~default:0 in
        Hashtbl.replace t.puts agent k;
        write t (("agent", str agent) :: label_fields c c.last @ [ "index", int k ]);
        Ok ()
      end)

let message t ~agent ~perf content =
  with_agent t agent (fun _ _ ->
      let (pl, ev) = P.deliver t.opts.params t.platform ~sender:"host" ~receiver:agent
          { Eval.perf; content; sender = "host" } in
      on_event t pl ev;
      Ok ())

(* ------------------------------------------------------------- run *)

let iterate t i =
  let left = t.opts.max_steps - t.steps in
  if left > 0 then begin
    let before = t.events in
    let (pl, evs) = P.iteration ~max_steps:left ~on_event:(on_event t) ~step:E.step t.opts.params t.platform i in
    t.platform <- pl;
    ignore before;
    t.steps <- t.steps + List.length (List.filter (function P.Step _ -> true | _ -> false) evs)
  end

let order t =
  let n = Array.length t.platform.agents in
  let idx = List.init n Fun.id in
  match t.rand with
  | None -> idx
  | Some r ->
    let a = Array.of_list idx in
    for k = n - 1 downto 1 do
      let j = Random.State.int r (k + 1) in
      let x = a.(k) in a.(k) <- a.(j); a.(j) <- x
    done;
    Array.to_list a

let run_rounds t n =
  for _ = 1 to n do
    List.iter (fun i -> if not (M.is_idle t.platform.agents.(i).config) then iterate t i) (order t)
  done

let run_until_idle t =
  let rec go () =
    if t.steps < t.opts.max_steps && not (P.all_idle t.platform) then begin
      run_rounds t 1; go ()
    end in
  go ()

let finish t =
  Array.iter (fun (ag : P.agent) ->
      let a = ag.config.world in
      Eval.destroy_agent a;
      write t [ "agent", str ag.name; "event", str "destroy"; "action", `Null ];
      List.iter (body_event t ag.name "destroy") (Eval.take_events a)) t.platform.agents;
  match t.opts.trace with Some oc -> flush oc | None -> ()

let steps t = t.steps
let agent_state t name = Option.map (fun i -> world t i) (find t name)
let platform t = t.platform
let env t = t.env

(* A run allocates many short-lived values (configurations, frames): a larger
   minor heap keeps them out of the major heap. Percepts waiting in O2A or in
   the priority queue are the opposite: under a flood every one of them is
   live until it is dispatched, and the major heap is mostly that backlog.
   A space overhead of 1000 lets the major collector mark it about a fifth as
   often as 200 would (OCaml's default is 120; bench/README.md: the host's
   notifies under a flood of 10M went from 730 ns to 270-370 ns each);
   garbage reaches the major heap slowly in this interpreter (configurations
   die young), so the heap stays close to the live data. *)
let tune_gc () =
  Gc.set { (Gc.get ()) with Gc.minor_heap_size = 4 * 1024 * 1024; space_overhead = 1000 }
