(* A playground session: the run of bin/cmd_run.ml and lib/interp/runtime.ml,
   taken one rule at a time. The trace is written as runtime.ml writes it,
   by Interp.Tracer; test/browser/test_playground_engine.ml compares the two
   traces on every conformance vector. *)

open Syntax
module Mc = Semantics.Machine
module P = Interp.Runtime.P
module M = P.M
module V = Interp.Value
module E = Interp.Eval
module T = Typing.Tenv

type setup = {
  files : (string * string) list;
  agents : string list;
  variant : Mc.variant;
  tie : Mc.tie_policy;
  budget : int;
  o2a_capacity : int option;
  seed : int option;
  fuel : int;
  max_steps : int;
  interleave : int option;
}

let default_setup = {
  files = []; agents = []; variant = Mc.Reference; tie = Mc.Stable; budget = 1;
  o2a_capacity = None; seed = None; fuel = 100_000; max_steps = 1_000_000; interleave = None;
}

type host_action =
  | Notify of { agent : string; percept : string; priority : int option }
  | Put of { agent : string; obj : string }
  | Message of { agent : string; perf : string; content : string; during : bool }
      (* [during]: it arrives during the agent's next behaviour step (D42) *)

type outcome = Stepped | All_idle | Limit

type cmd = H of host_action | R of int * bool | Round | A of int
         | D of string * bool | Draw | Fin
(* R (choice, refill): a rule; refill false inside run_rounds. Round: the
   start of a round of run_rounds, its rules follow. A i: one single rule of
   agent i (run_rules, D23; in the finer interleaving, the rule the student
   gave agent i). The finer interleaving (D45) only: D (receiver, in_step)
   the arrival of the oldest message in flight to the receiver; Draw one
   event drawn from the seed; Fin the end of the run. *)

type state = {
  env : T.t;
  params : Mc.params;
  mutable platform : P.t;
  mutable steps : int;
  rand : Random.State.t option;
  mutable tr : Interp.Tracer.t;         (* writes into [lines] *)
  mutable lines : string list;          (* the trace, newest first *)
  mutable out : string list;            (* what run prints, newest first *)
  mutable round : int list;             (* agents still to run in this round *)
  mutable current : int option;         (* the agent in the middle of an iteration *)
  mutable held : (string * E.message) list;
      (* the host's messages for an agent's next behaviour step (D42), oldest first *)
  max_steps : int;
  names : (string * int, string) Hashtbl.t;
  (* (agent, instance id) -> behaviour type, for every instance seen active:
     the label of a rule names a behaviour that may have left (a one-shot
     after its step, R5c; a deactivated one, R4b) *)
  specs : (string * string * V.t list) list;   (* the agents: name, type, arguments *)
  fine : Random.State.t option;
      (* the finer interleaving (R6 revised, D45): the messages between
         agents stay in flight until an arrival is asked for, and draws
         come from this *)
  mutable inflight : (string * (string * E.message)) list;
      (* D45: (receiver, (sender, message)), oldest first: the messages sent
         and not yet arrived; per receiver, in the order of the sends (R5e) *)
  mutable finished : bool;              (* the run ended: every agent destroyed *)
}

type t = {
  setup : setup;
  mutable st : state;
  mutable history : cmd list;           (* newest first *)
  mutable nhist : int;
}

let setup t = t.setup

(* --------------------------------------------------------- checking *)

let parse_all files =
  List.map (fun (name, text) ->
      match Parse.string ~file:name text with
      | r -> Ok r
      | exception Diag.Failed d -> Error d) files

let diagnostics files =
  let parsed = parse_all files in
  let syntax = List.filter_map (function Error d -> Some d | Ok _ -> None) parsed in
  let ok = List.filter_map (function Ok r -> Some r | Error _ -> None) parsed in
  let env, diags = Typing.check ok in
  (env, List.sort Diag.compare (syntax @ diags))

let check files =
  match diagnostics files with
  | (_, ds) -> List.map Diag.to_string ds
  | exception e -> [ "internal error: " ^ Printexc.to_string e ]

(* ------------------------------------------------------------ trace *)

let str s = `String s
let int i = `Int i

let first_file = ref "program.jade"

let on_error st kind (at : Source.region) msg =
  let (file, line, col) =
    if at.left.line = 0 then (!first_file, 1, 1) else (at.left.file, at.left.line, at.left.column) in
  st.out <- Printf.sprintf "%s:%d:%d: error: %s" file line col (E.wording kind msg) :: st.out

(* The session's tracer: its lines go to [st.lines], logs and errors to what
   run prints. *)
let tracer st =
  let w = Trace.writer (fun line -> st.lines <- String.sub line 0 (String.length line - 1) :: st.lines) in
  Interp.Tracer.create w ~on_body:(fun agent -> function
      | E.Log s -> st.out <- (agent ^ ": " ^ s) :: st.out
      | E.Error (kind, at, msg) -> on_error st kind at msg
      | _ -> ())

let world st i = st.platform.agents.(i).config.world

let behaviour_of ?(known = fun _ -> None) (c : M.t) id =
  match List.find_opt (fun (a : E.beh Mc.instance) -> a.id = id) c.active with
  | Some a -> E.beh_type a.beh
  | None -> Option.value (known id) ~default:"?"

let remember st name (c : M.t) =
  List.iter (fun (a : E.beh Mc.instance) -> Hashtbl.replace st.names (name, a.id) (E.beh_type a.beh)) c.active

(* The name of instance [id] of agent [name], also after it left. *)
let known st name id = Hashtbl.find_opt st.names (name, id)

let index st name = match P.find st.platform name with
  | Some i -> i
  | None -> Semantics.Fault.crash "Session: no agent %s" name

(* An event of the platform, with the platform right after it; [before]: the
   configuration the rule started from (default: the platform's until now). *)
let on_event ?before st (pl : P.t) (e : P.event) =
  let prev = st.platform in
  st.platform <- pl;
  match e with
  | P.Step (name, l) ->
    let i = index st name in
    let before = match before with Some c -> c | None -> prev.agents.(i).config in
    (* the bodies' events, taken from the agent *)
    let (world, evs) = E.take_events pl.agents.(i).config.world in
    let after = { pl.agents.(i).config with world } in
    let agents = Array.copy pl.agents in
    agents.(i) <- { (agents.(i)) with config = after };
    st.platform <- { P.agents };
    if after.active != before.active then begin
      (* every list of instances is remembered when it appears (and at the
         agent's creation), so a step that leaves it alone adds nothing *)
      remember st name before; remember st name after
    end;
    Interp.Tracer.step st.tr ~agent:name ~before ~after l evs
  | P.Delivered { receiver; _ } ->
    Interp.Tracer.host st.tr ~agent:receiver pl.agents.(index st receiver).config
  | P.Undeliverable { sender; receiver; message } ->
    Interp.Tracer.undeliverable st.tr ~sender ~receiver message
  | P.To_platform _ -> ()

(* A message that reaches [receiver] now, as the runtime delivers it
   (Interp.Runtime): one for ams or df is theirs, never answered; for an
   agent not on the platform, ams's failure goes back to the sender at once
   (R5e, D44). *)
let rec arrive st ~sender ~receiver m =
  let (pl, ev) = P.deliver st.params st.platform ~sender ~receiver m in
  on_event st pl ev;
  match ev with
  | P.Undeliverable _ ->
    let answer = Interp.Runtime.failure ~receiver in
    (* in flight in the finer interleaving (D45), as Runtime does *)
    if st.fine = None then arrive st ~sender:"ams" ~receiver:sender answer
    else send st ~sender:"ams" ~receiver:sender answer
  | P.Delivered _ | P.To_platform _ | P.Step _ -> ()

(* A message sent by an agent's body (R5e): it arrives at once in run's
   schedule, and is in flight in the finer interleaving (D45). *)
and send st ~sender ~receiver m =
  if st.fine = None then arrive st ~sender ~receiver m
  else st.inflight <- st.inflight @ [ (receiver, (sender, m)) ]

(* A host message that reaches [receiver] during its last behaviour step
   (R5d, D42): SendInStep where its window is open, else a plain delivery. *)
let arrive_in_step st ~receiver m =
  match P.deliver_in_step st.params st.platform ~sender:"host" ~receiver m with
  | Some (pl, P.Delivered _) ->
    st.platform <- pl;
    Interp.Tracer.host ~in_step:true st.tr ~agent:receiver pl.agents.(index st receiver).config
  | Some (pl, ev) -> on_event st pl ev
  | None -> arrive st ~sender:"host" ~receiver m

(* ----------------------------------------------------------- agents *)

exception Bad of string

let agent_spec env spec =
  let fail msg = raise (Bad (Printf.sprintf "--agent %s: error: %s" spec msg)) in
  match String.index_opt spec ':' with
  | None -> fail "expected NAME:TYPE[:ARG,...]"
  | Some i ->
    let name = String.trim (String.sub spec 0 i) in
    let rest = String.sub spec (i + 1) (String.length spec - i - 1) in
    let (ty, args) = match String.index_opt rest ':' with
      | None -> (rest, "")
      | Some j -> (String.sub rest 0 j, String.sub rest (j + 1) (String.length rest - j - 1)) in
    let ty = String.trim ty in
    if name = "" || ty = "" then fail "expected NAME:TYPE[:ARG,...]";
    if T.agent env ty = None then fail (Printf.sprintf "there is no agent type %s" ty);
    let values = List.map (fun a ->
        match List.assoc_opt a (Interp.Host.objects ()) with
        | Some v -> v
        | None ->
          (match E.literal_value env (Parse.expr ~file:"--agent" a) with
           | v -> v
           | exception Diag.Failed d -> fail d.message
           | exception (E.Trap (_, m) | E.Link (_, m)) -> fail m)) (Interp.Host.split_args args) in
    (name, ty, values)

let params_of (s : setup) =
  { Mc.default_params with variant = s.variant; tie = s.tie; budget = max 1 s.budget;
                           o2a_capacity = s.o2a_capacity; ghosts = true }

let boot (s : setup) : (state, string list) result =
  match diagnostics s.files with
  | exception e -> Error [ "internal error: " ^ Printexc.to_string e ]
  | (env, ds) ->
    let errors = List.filter (fun (d : Diag.t) -> d.severity = Diag.Error) ds in
    if errors <> [] then Error (List.map Diag.to_string errors)
    else begin
      (match s.files with (f, _) :: _ -> first_file := f | [] -> ());
      match
        let specs = List.map (agent_spec env) (List.filter (fun a -> String.trim a <> "") s.agents) in
        if specs = [] then raise (Bad "error: no agent: give at least one NAME:TYPE");
        (* as run: names unique, host reserved (the sender of host messages) *)
        ignore (List.fold_left (fun seen (n, ty, _) ->
            if n = "host" then
              raise (Bad (Printf.sprintf "--agent %s:%s: error: the name host is reserved: it is the sender of the host's messages (R5e)" n ty));
            if n = "ams" || n = "df" then
              raise (Bad (Printf.sprintf "--agent %s:%s: error: the name %s is the platform's own agent's (R5e): no agent of the program takes it" n ty n));
            if List.mem n seen then
              raise (Bad (Printf.sprintf "--agent %s:%s: error: there is already an agent %s (agent names are unique)" n ty n));
            n :: seen) [] specs);
        let st = { env; params = params_of s; platform = P.create []; steps = 0;
                   rand = Option.map (fun n -> Random.State.make [| n |]) s.seed;
                   tr = Interp.Tracer.create (Trace.nowhere ()) ~on_body:(fun _ _ -> ());
                   lines = []; out = [];
                   round = []; current = None; held = []; max_steps = s.max_steps;
                   names = Hashtbl.create 16; specs;
                   fine = Option.map (fun n -> Random.State.make [| n; 45 |]) s.interleave;
                   inflight = []; finished = false } in
        st.tr <- tracer st;
        Interp.Tracer.header st.tr env st.params ~seed:s.seed (List.map (fun (n, ty, _) -> (n, ty)) specs);
        let created = List.map (fun (name, ty, args) ->
            let (a, behs) =
              try E.create_agent ~config:{ E.default_config with fuel = s.fuel } env ~name ~atype:ty ~args
              with E.Link (_, m) -> raise (Bad ("error: " ^ m)) in
            let (a, evs) = E.take_events a in
            Interp.Tracer.created st.tr ~agent:name ~agent_type:ty args behs evs;
            (name, M.init st.params ~world:a behs)) specs in
        st.platform <- P.create created;
        List.iter (fun (name, c) -> remember st name c) created;
        Array.iteri (fun i _ ->
            let ag = st.platform.agents.(i) in
            let (world, out) = E.Bodies.take_outbox ag.config.world in
            let agents = Array.copy st.platform.agents in
            agents.(i) <- { ag with config = { ag.config with world } };
            st.platform <- { P.agents };
            List.iter (fun (receiver, m) -> send st ~sender:ag.name ~receiver m) out) st.platform.agents;
        st
      with
      | st -> Ok st
      | exception Bad m -> Error [ m ]
      | exception Diag.Failed d -> Error [ Diag.to_string d ]
      | exception (Stack_overflow | Out_of_memory) -> Error [ "error: the run ran out of memory or stack" ]
    end

(* ------------------------------------------------------------- host *)

let set_config st i c =
  let agents = Array.copy st.platform.agents in
  agents.(i) <- { (agents.(i)) with config = c };
  st.platform <- { P.agents }

let located what (d : Diag.t) =
  Printf.sprintf "%s:%d:%d: error: %s" what d.at.left.line d.at.left.column d.message

let do_host st (h : host_action) : (unit, string) result =
  let agent = match h with Notify { agent; _ } | Put { agent; _ } | Message { agent; _ } -> agent in
  match P.find st.platform agent with
  | None -> Error (Printf.sprintf "host: there is no agent %s" agent)
  | Some _ when st.finished -> Error "host: no agent is left: the run has ended"
  | Some i ->
    let c = st.platform.agents.(i).config in
    let atype = (world st i).atype.a_name in
    let parse what text k =
      match Parse.expr ~file:what text with
      | exception Diag.Failed d -> Error (located what d)
      | e ->
        (match k e with
         | r -> r
         | exception (E.Trap (at, m) | E.Link (at, m)) ->
           Error (Printf.sprintf "%s:%d:%d: error: %s" what (max 1 at.left.line) (max 1 at.left.column) m)) in
    match h with
    | Notify { percept; priority; _ } ->
      parse "notify" percept (fun e ->
          let (v, default) = E.percept_value st.env ~agent_type:atype e in
          match M.notify_event st.params c v ~default ~priority with
          | Error (Mc.Negative_priority k) -> Error (Printf.sprintf "host: priority %d is negative (R2a)" k)
          | Error Mc.O2a_full ->
            Interp.Tracer.refused st.tr ~agent v;
            Error "host: the O2A queue is full (R2d)"
          | Ok c -> set_config st i c; Interp.Tracer.host st.tr ~agent c; Ok ())
    | Put { obj; _ } ->
      parse "put" obj (fun e ->
          let v = E.literal_value st.env e in
          if not (M.o2a_has_room st.params c) then begin
            (* R2d: recorded as refused, with the object, as run does *)
            Interp.Tracer.refused_put st.tr ~agent v;
            Error "host: the O2A queue is full (R2d)"
          end else begin
            let c = M.put st.params c v in
            set_config st i c;
            Interp.Tracer.host st.tr ~agent c;
            Ok ()
          end)
    | Message { perf; content; during; _ } ->
      parse "message" content (fun e ->
          let v = E.literal_value st.env e in
          let perf = if String.trim perf = "" then "inform" else String.trim perf in
          let m = { E.perf; content = v; sender = "host" } in
          (* D42: held until the agent's next behaviour step *)
          if during then st.held <- st.held @ [ (agent, m) ]
          else arrive st ~sender:"host" ~receiver:agent m;
          Ok ())

(* ------------------------------------------------------------ rules *)

let idle st i = M.is_idle st.platform.agents.(i).config

(* The next agent; [commit] makes the choice (pops the round, draws the seed). *)
let pick ?(refill = true) ~commit st =
  match st.current with
  | Some i -> Some i
  | None ->
    let rec from_round round fresh =
      match round with
      | i :: rest when not (idle st i) -> Some (i, rest)
      | _ :: rest -> from_round rest fresh
      | [] ->
        if fresh || not refill || P.all_idle st.platform then None
        else
          let rand = if commit then st.rand else Option.map Random.State.copy st.rand in
          from_round (P.round rand st.platform) true in
    match from_round st.round false with
    | None -> (if commit then st.round <- []); None
    | Some (i, rest) -> (if commit then (st.round <- rest; st.current <- Some i)); Some i

let ends_iteration (l : M.lbl) = match l with
  | Mc.Behaviour_step _ | Mc.Next_iteration | Mc.Idle -> true
  | _ -> false

let do_rule ?refill ?agent st choice : outcome =
  if st.finished then All_idle
  else if st.steps >= st.max_steps then Limit
  else match (match agent with Some i -> Some i | None -> pick ?refill ~commit:true st) with
    | None -> All_idle
    | Some i ->
      let name = st.platform.agents.(i).name in
      match M.step st.params st.platform.agents.(i).config with
      | [] -> st.current <- None; All_idle
      | cands ->
        let (l, c) = match List.nth_opt cands choice with Some x -> x | None -> List.hd cands in
        let before = st.platform.agents.(i).config in
        set_config st i c;
        on_event ~before st st.platform (P.Step (name, l));
        let (w, out) = E.Bodies.take_outbox (world st i) in
        set_config st i { st.platform.agents.(i).config with world = w };
        List.iter (fun (receiver, m) -> send st ~sender:name ~receiver m) out;
        st.steps <- st.steps + 1;
        (* D42: the host's messages held for this behaviour step arrive
           during it (SendInStep, R5d), as Runtime.rule delivers them *)
        (match l with
         | Mc.Behaviour_step _ ->
           let (mine, others) = List.partition (fun (a, _) -> a = name) st.held in
           st.held <- others;
           List.iter (fun (_, m) -> arrive_in_step st ~receiver:name m) mine
         | _ -> ());
        if ends_iteration l then st.current <- None;
        Stepped

(* ---------------------------------------------------------- session *)

let create s =
  match boot s with
  | Ok st -> Ok { setup = s; st; history = []; nhist = 0 }
  | Error e -> Error e

let record t c = t.history <- c :: t.history; t.nhist <- t.nhist + 1

let guarded f =
  try f () with
  | Stack_overflow -> Error "error: the evaluation went too deep (stack overflow)"
  | Out_of_memory -> Error "error: out of memory"
  | Invalid_argument m | Failure m -> Error ("internal error: " ^ m)
  | Semantics.Fault.Crash m -> Error ("internal error (a broken invariant): " ^ m)
  | Not_found -> Error "internal error: Not_found"

let host t h =
  match guarded (fun () -> do_host t.st h) with
  | Ok () -> record t (H h); Ok ()
  | Error m ->
    (* a refusal (R2d) is in the trace, as run records it: keep it on replay *)
    if String.length m >= 10 && String.sub m 0 10 = "host: the " then record t (H h);
    Error m

let rule t choice =
  match guarded (fun () -> Ok (do_rule t.st choice)) with
  | Ok Stepped -> record t (R (choice, true)); Stepped
  | Ok o -> o
  | Error m -> t.st.out <- m :: t.st.out; Limit

let step ?(choice = 0) t = rule t choice

let iteration t =
  let rec go first =
    match rule t 0 with
    | Stepped -> if t.st.current = None then Stepped else go false
    | o -> if first then o else Stepped in
  go true

let run_idle ?(limit = 5000) t =
  let rec go n =
    if n >= limit then (n, Stepped)
    else match rule t 0 with
      | Stepped -> go (n + 1)
      | All_idle when t.st.held <> [] ->
        (* D42: held messages whose step never came arrive as plain
           deliveries, in agent name order (Runtime.release_held) *)
        let held = List.stable_sort (fun (a, _) (b, _) -> compare a b) t.st.held in
        t.st.held <- [];
        List.iter (fun (a, m) -> arrive t.st ~sender:"host" ~receiver:a m) held;
        go n
      | o -> (n, o) in
  go 0

(* One round of run's {"run": 1}: every agent that is not idle runs one
   iteration, in the round's order (the one in progress, if any, is
   finished first; a new round draws its order from the seed). *)
let round_cmds st =
  if st.current = None && st.round = [] then
    st.round <- P.round st.rand st.platform

(* D20, as Runtime.run_rounds: no round when every agent is idle (nothing
   can change until the host acts; no order is drawn), none past the step
   limit, none after a round that took no step. *)
let run_rounds t n =
  let rec rounds n =
    if n > 0 && t.st.steps < t.st.max_steps && not (P.all_idle t.st.platform) then begin
      let before = t.st.steps in
      record t Round;
      round_cmds t.st;
      let rec go () =
        match guarded (fun () -> Ok (do_rule ~refill:false t.st 0)) with
        | Ok Stepped -> record t (R (0, false)); go ()
        | Ok _ -> ()
        | Error m -> t.st.out <- m :: t.st.out in
      go ();
      if t.st.steps > before then rounds (n - 1)
    end in
  rounds n

(* {"run": {"rules": n}} (D23, as Runtime.run_rules): n single rules, each
   by the first agent in creation order that is not idle. The agent is not
   held as the one in progress: a later round runs every agent's iteration
   in the round's order, a stopped one going on from where it stood. *)
let first_not_idle st =
  let n = Array.length st.platform.agents in
  let rec go i = if i >= n then None else if idle st i then go (i + 1) else Some i in
  go 0

let single_rule st i =
  let r = do_rule ~agent:i st 0 in
  st.current <- None; r

let run_rules t n =
  let rec go k =
    if k > 0 then
      match first_not_idle t.st with
      | None -> ()
      | Some i ->
        match guarded (fun () -> Ok (single_rule t.st i)) with
        | Ok Stepped -> record t (A i); go (k - 1)
        | Ok _ -> ()
        | Error m -> t.st.out <- m :: t.st.out in
  go n

(* ------------------------------------- the finer interleaving (D45) *)

let interleaved t = t.st.fine <> None

(* The receivers with a message in flight, in name order. *)
let receivers st =
  List.sort_uniq compare (List.map fst st.inflight)

(* Is the window of agent [name]'s last behaviour step open (R5d revised:
   between the step and the agent's next rule)? *)
let window st name =
  match P.find st.platform name with
  | Some i -> st.platform.agents.(i).config.stepped <> Mc.Not_stepped
  | None -> false

(* The oldest message in flight to [receiver] arrives: during the
   receiver's last behaviour step (SendInStep) when [in_step] and its
   window is open. *)
let do_arrival st receiver in_step : (unit, string) result =
  if st.finished then Error "the run has ended"
  else match List.assoc_opt receiver st.inflight with
    | None -> Error (Printf.sprintf "no message is in flight to %s" receiver)
    | Some (sender, m) ->
      if in_step && not (window st receiver) then
        Error (Printf.sprintf "%s is not in the window of a behaviour step: a message can arrive during a step only between the step and the agent's next rule (R5d)" receiver)
      else begin
        (* the oldest to this receiver leaves; the others keep their order *)
        let rec drop = function
          | [] -> []
          | (r, _) :: rest when r = receiver -> rest
          | e :: rest -> e :: drop rest in
        st.inflight <- drop st.inflight;
        (if in_step then
           match P.deliver_in_step st.params st.platform ~sender ~receiver m with
           | Some (pl, P.Delivered _) ->
             st.platform <- pl;
             Interp.Tracer.host ~in_step:true st.tr ~agent:receiver pl.agents.(index st receiver).config
           | Some (pl, ev) -> on_event st pl ev
           | None -> arrive st ~sender ~receiver m
         else arrive st ~sender ~receiver m);
        Ok ()
      end

(* One event drawn from the seed, as Runtime's finer run draws them: a
   rule of an agent that is not idle, or the arrival of the oldest message
   in flight to some receiver (during its step, by a coin, when its window
   is open). *)
let do_draw st : (string, string) result =
  match st.fine with
  | None -> Error "not the finer interleaving"
  | Some _ when st.finished -> Error "the run has ended"
  | Some rand ->
    let n = Array.length st.platform.agents in
    let agents = List.filter (fun i -> not (idle st i)) (List.init n Fun.id) in
    let choices = List.map (fun i -> `Rule i) agents @ List.map (fun r -> `Arrive r) (receivers st) in
    match choices with
    | [] -> Error "nothing can happen: every agent is idle and no message is in flight"
    | _ ->
      match List.nth choices (Random.State.int rand (List.length choices)) with
      | `Rule i ->
        let name = st.platform.agents.(i).name in
        (match single_rule st i with
         | Stepped -> Ok (Printf.sprintf "drawn: a rule of %s" name)
         | All_idle -> Ok (Printf.sprintf "drawn: %s, which has no rule to take" name)
         | Limit -> Error "the step limit is reached")
      | `Arrive r ->
        let in_step = window st r && Random.State.bool rand in
        Result.map (fun () -> Printf.sprintf "drawn: a message arrives at %s%s" r
                       (if in_step then ", during its behaviour step (SendInStep)" else ""))
          (do_arrival st r in_step)

(* The end of the run, as Runtime.finish: every message in flight arrives
   (receivers in name order, the oldest first), then the host's messages
   held for a step that did not come (D42), then every agent is destroyed
   (its on destroy runs). *)
let do_finish st =
  if not st.finished then begin
    let rec go () =
      match receivers st with
      | [] -> ()
      | r :: _ -> ignore (do_arrival st r false); go () in
    go ();
    let held = List.stable_sort (fun (a, _) (b, _) -> compare a b) st.held in
    st.held <- [];
    List.iter (fun (a, m) -> arrive st ~sender:"host" ~receiver:a m) held;
    Array.iter (fun (ag : P.agent) ->
        let (_, evs) = E.take_events (E.destroy_agent ag.config.world) in
        Interp.Tracer.destroyed st.tr ~agent:ag.name evs) st.platform.agents;
    st.finished <- true
  end

let rule_of t name =
  match P.find t.st.platform name with
  | None -> Error (Printf.sprintf "there is no agent %s" name)
  | Some i ->
    match guarded (fun () -> Ok (single_rule t.st i)) with
    | Ok Stepped -> record t (A i); Ok Stepped
    | Ok o -> Ok o
    | Error m -> t.st.out <- m :: t.st.out; Error m

let arrival t ~receiver ~during =
  match guarded (fun () -> do_arrival t.st receiver during) with
  | Ok () -> record t (D (receiver, during)); Ok ()
  | Error m -> Error m

let draw t =
  match guarded (fun () -> do_draw t.st) with
  | Ok m -> record t Draw; Ok m
  | Error m -> Error m

let finish t =
  if t.st.finished then false
  else match guarded (fun () -> do_finish t.st; Ok ()) with
    | Ok () -> record t Fin; true
    | Error m -> t.st.out <- m :: t.st.out; false

let finished t = t.st.finished
let env t = t.st.env
let agent_specs t = t.st.specs

let replay t cmds =
  match boot t.setup with
  | Error _ -> ()
  | Ok st ->
    List.iter (function
        | H h -> ignore (guarded (fun () -> do_host st h))
        | R (c, refill) -> ignore (guarded (fun () -> Ok (do_rule ~refill st c)))
        | Round -> round_cmds st
        | A i -> ignore (guarded (fun () -> Ok (single_rule st i)))
        | D (r, in_step) -> ignore (guarded (fun () -> do_arrival st r in_step))
        | Draw -> ignore (guarded (fun () -> do_draw st))
        | Fin -> ignore (guarded (fun () -> do_finish st; Ok ()))) cmds;
    t.st <- st

let back t =
  match t.history with
  | [] -> false
  | _ :: rest ->
    let rest = match rest with Round :: r -> r | r -> r in
    t.history <- rest; t.nhist <- List.length rest;
    replay t (List.rev rest);
    true

let history_length t = t.nhist
let steps t = t.st.steps
let trace t = List.rev t.st.lines
let output t = List.rev t.st.out

(* ------------------------------------------------------------- view *)

let next_agent t = if interleaved t then None else pick ~commit:false t.st

let entry_view (e : V.t Mc.entry) =
  `Assoc [ "percept", str (V.to_literal e.p); "priority", int e.prio; "seq", int e.seq ]

let label_text ?known (c : M.t) (l : M.lbl) =
  let behaviour_of = behaviour_of ?known in
  let e (x : V.t Mc.entry) = Printf.sprintf "%s (priority %d, #%d)" (V.to_literal x.p) x.prio x.seq in
  match l with
  | Mc.Init -> "Init"
  | Mc.Notify x -> "Notify " ^ e x
  | Mc.Notify_with x -> "NotifyWith " ^ e x
  | Mc.Put o -> "Put " ^ V.to_literal o
  | Mc.Send (m, seq) -> Printf.sprintf "Send %s %s (m%d)" m.perf (V.to_literal m.content) seq
  | Mc.Transfer n -> Printf.sprintf "Transfer (%d moved)" n
  | Mc.Transfer_one x -> "TransferOne " ^ e x
  | Mc.Transfer_spin o -> "TransferSpin on the object " ^ V.to_literal o
  | Mc.Transfer_end -> "TransferEnd"
  | Mc.Dequeue x -> "Dequeue " ^ e x
  | Mc.Handle { id; h; seq; _ } -> Printf.sprintf "Handle: %s #%d handler %d took #%d" (behaviour_of c id) id h seq
  | Mc.Skip { id; h } -> Printf.sprintf "Skip: %s #%d handler %d" (behaviour_of c id) id h
  | Mc.End_dispatch { seq; discarded } ->
    Printf.sprintf "EndDispatch #%d%s" seq (if discarded then ": discarded, no handler applied" else "")
  | Mc.Behaviour_step { id; msg } ->
    Printf.sprintf "BehaviourStep of %s #%d%s" (behaviour_of c id) id
      (match msg with
       | None -> ""
       | Some (Mc.M_message { m; mseq }) -> Printf.sprintf ", took %s %s (m%d)" m.perf (V.to_literal m.content) mseq
       | Some (Mc.M_percept x) -> ", took the percept " ^ e x)
  | Mc.Next_iteration -> "NextIteration"
  | Mc.Idle -> "Idle"

(* Percept handler [h] (from 1) of behaviour type [beh], as R4a counts them. *)
let handler_decl t beh h =
  let hs = List.filter (fun (x : T.handler) -> x.h_kind = T.On_percept) (T.behaviour_handlers t.st.env beh) in
  List.nth_opt hs (h - 1)

(* The handler's declaration, for the dispatch in progress: the source line. *)
let handler_info t beh h =
  match handler_decl t beh h with
  | None -> ("", "")
  | Some x ->
    let line = x.h_at.left.line in
    let text = match List.assoc_opt x.h_at.left.file t.setup.files with
      | None -> ""
      | Some src ->
        (match List.nth_opt (String.split_on_char '\n' src) (line - 1) with
         | Some l -> String.trim l
         | None -> "") in
    (Printf.sprintf "%s:%d" x.h_at.left.file line, text)

(* What the next rule of agent i will be, told from its configuration alone
   (no body runs): the order of Machine.step's arms. *)
let next_rules t i : string list =
  let p = t.st.params in
  let c = t.st.platform.agents.(i).config in
  let beh id = behaviour_of ~known:(known t.st t.st.platform.agents.(i).name) c id in
  match c.phase, c.cur with
  | Mc.Idle_phase, _ -> []
  | Mc.Transfer_phase, _ when p.variant = Mc.Printed ->
    (match Semantics.Fqueue.peek c.o2a with
     | None -> [ "TransferEnd" ]
     | Some (Mc.O_percept e) -> [ Printf.sprintf "TransferOne %s (#%d)" (V.to_literal e.p) e.seq ]
     | Some (Mc.O_object o) -> [ "TransferSpin on the object " ^ V.to_literal o ])
  | Mc.Transfer_phase, _ ->
    let n = Semantics.Fqueue.fold (fun n x -> match x with Mc.O_percept _ -> n + 1 | _ -> n) 0 c.o2a in
    [ Printf.sprintf "Transfer (%d percept%s)" n (if n = 1 then "" else "s") ]
  | Mc.Dispatch_phase, _
    when p.variant <> Mc.Native && not (Semantics.Pqueue.is_empty c.pq)
         && not (p.variant = Mc.Budgeted && c.dispatched >= p.budget) ->
    List.map (fun (e : V.t Mc.entry) -> Printf.sprintf "Dequeue %s (priority %d, #%d)" (V.to_literal e.p) e.prio e.seq)
      (Semantics.Pqueue.candidates ~stable:(p.tie = Mc.Stable) c.pq)
  | Mc.Dispatch_phase, _ when c.ready <> [] ->
    let id = List.nth c.ready (c.pos - 1) in
    [ Printf.sprintf "BehaviourStep of %s #%d" (beh id) id ]
  | Mc.Dispatch_phase, _ when p.variant <> Mc.Printed && M.idle_condition c -> [ "Idle" ]
  | Mc.Dispatch_phase, _ -> [ "NextIteration" ]
  | Mc.Handle_phase, Some d ->
    (match d.todo with
     | [] -> [ Printf.sprintf "EndDispatch #%d%s" d.e.seq (if d.applied then "" else " (discard: no handler applied)") ]
     | (id, h) :: _ ->
       if List.exists (fun (a : E.beh Mc.instance) -> a.id = id) c.active
       then [ Printf.sprintf "Handle or Skip: %s #%d handler %d (its when decides)" (beh id) id h ]
       else [ Printf.sprintf "Skip: %s #%d handler %d (deactivated, R4b)" (beh id) id h ])
  | Mc.Handle_phase, None -> []

let choices t = match next_agent t with None -> [] | Some i -> next_rules t i

(* Where the program code that the next rule of agent [i] runs is written:
   the percept handler tried next (its [on percept] line), or the behaviour
   that steps next (the first statement of its action section, else its
   declaration). [`Null] for the rules that run no code of the program
   (Transfer, Dequeue, EndDispatch, Idle, ...). The conditions are those of
   [next_rules]. *)
let run_at t i =
  let p = t.st.params in
  let ag = t.st.platform.agents.(i) in
  let c = ag.config in
  let beh id = behaviour_of ~known:(known t.st ag.name) c id in
  let at kind (r : Source.region) =
    if r.left.line = 0 then `Null
    else `Assoc [ "file", str r.left.file; "line", int r.left.line; "kind", str kind ] in
  let dequeue_next =
    p.variant <> Mc.Native && not (Semantics.Pqueue.is_empty c.pq)
    && not (p.variant = Mc.Budgeted && c.dispatched >= p.budget) in
  match c.phase, c.cur with
  | Mc.Handle_phase, Some { todo = (id, h) :: _; _ }
    when List.exists (fun (a : E.beh Mc.instance) -> a.id = id) c.active ->
    (match handler_decl t (beh id) h with Some x -> at "handler" x.h_at | None -> `Null)
  | Mc.Dispatch_phase, _ when not dequeue_next && c.ready <> [] ->
    let b = beh (List.nth c.ready (c.pos - 1)) in
    (match T.behaviour_action t.st.env b, T.behaviour t.st.env b with
     | Some (s :: _), _ -> at "behaviour" s.at
     | _, Some d -> at "behaviour" d.b_decl.at
     | _, None -> `Null)
  | _ -> `Null

let phase_name = function
  | Mc.Transfer_phase -> "transfer" | Mc.Dispatch_phase -> "dispatch"
  | Mc.Handle_phase -> "handle" | Mc.Idle_phase -> "idle"

let agent_view t next i (ag : P.agent) =
  let c = ag.config in
  let a = c.world in
  let known = known t.st ag.name in
  let beh id = behaviour_of ~known c id in
  let o2a = List.map (function
      | Mc.O_percept e -> `Assoc [ "kind", str "percept"; "percept", str (V.to_literal e.p);
                                   "priority", int e.prio; "seq", int e.seq ]
      | Mc.O_object o -> `Assoc [ "kind", str "object"; "object", str (V.to_literal o) ])
      (Semantics.Fqueue.to_list c.o2a) in
  let msgq = List.map (function
      | Mc.M_message { m = (m : E.message); mseq } ->
        `Assoc [ "kind", str "message"; "performative", str m.perf; "content", str (V.to_literal m.content);
                 "from", str m.sender; "seq", int mseq ]
      | Mc.M_percept e -> `Assoc [ "kind", str "percept"; "percept", str (V.to_literal e.p);
                                   "priority", int e.prio; "seq", int e.seq ])
      (Semantics.Fqueue.to_list c.msgq) in
  let props = List.filter_map (fun (p : T.property) ->
      match E.property a p.p_name with
      | Some v -> Some (`Assoc [ "name", str p.p_name; "value", str (V.to_literal v) ])
      | None -> None) (T.agent_properties t.st.env a.atype.a_name) in
  let cur = match c.cur with
    | None -> `Null
    | Some d ->
      `Assoc [ "entry", entry_view d.e; "applied", `Bool d.applied;
               "todo", `List (List.map (fun (id, h) ->
                   let b = beh id in
                   let (at, text) = handler_info t b h in
                   `Assoc [ "instance", int id; "behaviour", str b; "handler", int h;
                            "active", `Bool (List.exists (fun (x : E.beh Mc.instance) -> x.id = id) c.active);
                            "at", str at; "source", str text ]) d.todo) ] in
  `Assoc [
    "name", str ag.name; "type", str a.atype.a_name; "phase", str (phase_name c.phase);
    "next", `Bool (next = Some i);
    "o2a", `List o2a;
    "pq", `List (List.map entry_view (Semantics.Pqueue.to_sorted_list c.pq));
    "msgq", `List msgq;
    "active", `List (List.map (fun (x : E.beh Mc.instance) ->
        `Assoc [ "instance", int x.id; "behaviour", str (E.beh_type x.beh) ]) c.active);
    "ready", `List (List.map int c.ready);
    "pos", int c.pos;
    "blocked", `List (List.map int c.blocked);
    "cur", cur;
    "dispatched", int c.dispatched;
    "waits", `List (List.map (fun (seq, prio, inv) ->
        `Assoc [ "seq", int seq; "priority", int prio; "inversions", int inv ]) c.waits);
    "done", int (Mc.Int_set.cardinal c.done_);
    "last", str (label_text ~known c c.last);
    "run_at", run_at t i;
    "last_action", str (Mc.action_name c.last);
    "props", `List props;
    "rules", `List (List.map str (next_rules t i));
    "idle", `Bool (M.is_idle c);
    "window", `Bool (window t.st ag.name);
  ]

let view t =
  let st = t.st in
  let next = next_agent t in
  `Assoc [
    "steps", int st.steps;
    "history", int t.nhist;
    "events", int (Trace.lines_written (Interp.Tracer.writer st.tr));
    "variant", str (Mc.string_of_variant st.params.variant);
    "tie", str (match st.params.tie with Mc.Stable -> "stable" | Mc.Unstable -> "unstable");
    "budget", int st.params.budget;
    "next", (match next with Some i -> str st.platform.agents.(i).name | None -> `Null);
    "all_idle", `Bool (P.all_idle st.platform);
    "agents", `List (Array.to_list (Array.mapi (agent_view t next) st.platform.agents));
    "interleave", (match t.setup.interleave with Some n -> int n | None -> `Null);
    "finished", `Bool st.finished;
    "in_flight", `List (List.map (fun (receiver, (sender, (m : E.message))) ->
        `Assoc [ "receiver", str receiver; "sender", str sender; "performative", str m.perf;
                 "content", str (V.to_literal m.content);
                 "window", `Bool (window st receiver) ]) st.inflight);
    "held", `List (List.map (fun (a, (m : E.message)) ->
        `Assoc [ "receiver", str a; "performative", str m.perf; "content", str (V.to_literal m.content) ]) st.held);
  ]

(* ------------------------------------------------ saving and restoring *)

(* The history as JSON, oldest first: host actions as the lines of an events
   file say them, runs of rules counted. *)
let host_line = function
  | Notify { agent; percept; priority } ->
    `Assoc ([ "agent", str agent; "notify", str percept ]
            @ (match priority with Some k -> [ "priority", int k ] | None -> []))
  | Put { agent; obj } -> `Assoc [ "agent", str agent; "put", str obj ]
  | Message { agent; perf; content; during } ->
    `Assoc ([ "agent", str agent; "message", str content; "performative", str perf ]
            @ (if during then [ "during", str "step" ] else []))

let export t =
  let rec go acc = function
    | [] -> List.rev acc
    | H h :: rest -> go (host_line h :: acc) rest
    | R (0, true) :: _ as l ->
      let rec count n = function R (0, true) :: r -> count (n + 1) r | r -> (n, r) in
      let (n, rest) = count 0 l in
      go (`Assoc [ "rules", int n ] :: acc) rest
    | R (c, _) :: rest -> go (`Assoc [ "choice", int c ] :: acc) rest
    | Round :: rest ->
      let rec count n = function R (_, false) :: r -> count (n + 1) r | r -> (n, r) in
      let (n, rest) = count 0 rest in
      go (`Assoc [ "round", int n ] :: acc) rest
    | A i :: _ as l ->
      let rec count n = function A j :: r when j = i -> count (n + 1) r | r -> (n, r) in
      let (n, rest) = count 0 l in
      go (`Assoc [ "single", int i; "n", int n ] :: acc) rest
    | D (r, during) :: rest -> go (`Assoc [ "arrive", str r; "in_step", `Bool during ] :: acc) rest
    | Draw :: _ as l ->
      let rec count n = function Draw :: r -> count (n + 1) r | r -> (n, r) in
      let (n, rest) = count 0 l in
      go (`Assoc [ "draw", int n ] :: acc) rest
    | Fin :: rest -> go (`Assoc [ "finish", `Bool true ] :: acc) rest in
  `List (go [] (List.rev t.history))

let restore s (j : Yojson.Safe.t) =
  let bad what = Error [ "error: the saved session is not readable: " ^ what ] in
  let field k = function `Assoc f -> List.assoc_opt k f | _ -> None in
  let text k j = match field k j with Some (`String s) -> Some s | _ -> None in
  let num k j = match field k j with Some (`Int n) when n >= 0 -> Some n | _ -> None in
  let times n c = List.init (min n 1_000_000) (fun _ -> c) in
  let cmd j =
    match text "agent" j, text "notify" j, text "put" j, text "message" j with
    | Some agent, Some percept, _, _ ->
      Some [ H (Notify { agent; percept; priority = num "priority" j }) ]
    | Some agent, None, Some obj, _ -> Some [ H (Put { agent; obj }) ]
    | Some agent, None, None, Some content ->
      Some [ H (Message { agent; content; perf = Option.value (text "performative" j) ~default:"inform";
                          during = text "during" j = Some "step" }) ]
    | _ ->
      match num "rules" j, num "choice" j, num "round" j, num "single" j with
      | Some n, _, _, _ -> Some (times n (R (0, true)))
      | _, Some c, _, _ -> Some [ R (c, true) ]
      | _, _, Some n, _ -> Some (Round :: times n (R (0, false)))
      | _, _, _, Some i -> Some (times (Option.value (num "n" j) ~default:1) (A i))
      | _ ->
        match text "arrive" j, num "draw" j, field "finish" j with
        | Some r, _, _ -> Some [ D (r, field "in_step" j = Some (`Bool true)) ]
        | _, Some n, _ -> Some (times n Draw)
        | _, _, Some (`Bool true) -> Some [ Fin ]
        | _ -> None in
  match j with
  | `List l ->
    let cmds = List.map cmd l in
    if List.mem None cmds then bad "an entry is neither a host action nor rules"
    else begin
      let cmds = List.concat_map Option.get cmds in
      match create s with
      | Error e -> Error e
      | Ok t ->
        (match cmds with
         | [] -> ()
         | _ ->
           replay t cmds;
           t.history <- List.rev cmds; t.nhist <- List.length cmds);
        Ok t
    end
  | _ -> bad "not a list"
