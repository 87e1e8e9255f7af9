(* Tests of lib/semantics (the machine) and lib/explore (its agreement with
   spec/AgentLoop.tla, checked by TLC). *)

open Semantics
open Explore
open Test_support
open Support
module Mc = Machine

let long = Sys.getenv_opt "JSREF_LONG" = Some "1"

(* ------------------------------------------------- priority queue *)

(* The reference: a list kept sorted by (priority descending, seq ascending). *)
let pq_ops = QCheck.(list_of_size Gen.(int_bound 80) (pair (int_bound 3) bool))

let pqueue_pops_in_order ops =
  let seq = ref 0 in
  let model = ref [] and q = ref Pqueue.empty in
  List.for_all (fun (prio, is_pop) ->
      if is_pop then
        match Pqueue.pop !q, List.sort (fun (a : int Pqueue.entry) b ->
            compare (- a.prio, a.seq) (- b.prio, b.seq)) !model with
        | None, [] -> true
        | Some (e, q'), best :: rest -> q := q'; model := rest; e = best
        | _ -> false
      else begin
        incr seq;
        let e = { Pqueue.p = prio * 10; prio; seq = !seq } in
        q := Pqueue.insert e !q; model := e :: !model;
        Pqueue.size !q = List.length !model
      end) ops

let pqueue_candidates ops =
  let q = List.fold_left (fun q (i, (prio, _)) -> Pqueue.insert { Pqueue.p = i; prio; seq = i } q)
      Pqueue.empty (List.mapi (fun i x -> (i, x)) ops) in
  match Pqueue.to_sorted_list q with
  | [] -> Pqueue.candidates ~stable:true q = []
  | top :: _ as all ->
    Pqueue.candidates ~stable:true q = [top]
    && List.sort compare (Pqueue.candidates ~stable:false q)
       = List.sort compare (List.filter (fun (e : int Pqueue.entry) -> e.prio = top.prio) all)
    && List.for_all (fun e -> not (Pqueue.mem e (Pqueue.remove e q))
                              && Pqueue.size (Pqueue.remove e q) = Pqueue.size q - 1) all

(* Any inserts, not only growing seqs (duplicates and smaller seqs take the
   bucket queue's slow path), mixed with pops and removals; every version is
   also checked again after later versions were built from it (persistence). *)
type pq_op = Ins of int * int | Pop | Rm of int

let pq_any_ops =
  let open QCheck in
  let op = Gen.(frequency [ 3, map2 (fun p s -> Ins (p, s)) (int_bound 4) (int_bound 12);
                            2, map2 (fun p s -> Ins (p, s)) (int_bound 300) (int_bound 12);
                            3, return Pop; 1, map (fun i -> Rm i) (int_bound 20) ]) in
  make ~print:(fun l -> String.concat "; " (List.map (function
      | Ins (p, s) -> Printf.sprintf "ins %d/%d" p s | Pop -> "pop" | Rm i -> Printf.sprintf "rm %d" i) l))
    Gen.(list_size (int_bound 60) op)

let pqueue_any_order ops =
  let key (e : int Pqueue.entry) = (- e.prio, e.seq) in
  let sorted m = List.sort (fun a b -> compare (key a, a.p) (key b, b.p)) m in
  let rec drop x = function [] -> [] | y :: r -> if y = x then r else y :: drop x r in
  let agrees q m =
    Pqueue.size q = List.length m
    && Pqueue.to_sorted_list q = sorted m
    && (match sorted m with
        | [] -> Pqueue.top q = None && Pqueue.candidates ~stable:true q = []
        | best :: _ ->
          let same_top (e : int Pqueue.entry) = e.prio = best.prio in
          (match Pqueue.top q with Some t -> key t = key best | None -> false)
          && List.sort compare (Pqueue.candidates ~stable:true q)
             = List.sort compare (List.filter (fun e -> same_top e && e.seq = best.seq) m)
          && List.sort compare (Pqueue.candidates ~stable:false q)
             = List.sort compare (List.filter same_top m)) in
  let versions = ref [] and n = ref 0 in
  let (q, m) = List.fold_left (fun (q, m) op ->
      versions := (q, m) :: !versions;
      match op with
      | Ins (prio, seq) -> incr n; let e = { Pqueue.p = !n; prio; seq } in (Pqueue.insert e q, e :: m)
      | Pop -> (match Pqueue.pop q with
          | None ->
            if m <> [] then failwith "pop of a non-empty queue gave nothing";
            (q, m)
          | Some (e, q') ->
            if not (List.mem e m) || key e <> key (List.hd (sorted m)) then failwith "popped a wrong entry";
            (q', drop e m))
      | Rm i -> (match List.nth_opt (sorted m) i with
          | Some e -> if not (Pqueue.mem e q) then failwith "mem"; (Pqueue.remove e q, drop e m)
          | None -> (q, m))) (Pqueue.empty, []) ops in
  agrees q m && List.for_all (fun (q, m) -> agrees q m) !versions

let fqueue_is_a_queue l =
  let q = List.fold_left (fun q x -> Fqueue.push x q) Fqueue.empty l in
  let rec drain q acc = match Fqueue.pop q with None -> List.rev acc | Some (x, q) -> drain q (x :: acc) in
  drain q [] = l && Fqueue.to_list q = l
  && Fqueue.fold_newest (fun acc x -> x :: acc) [] q = l
  && (let k = List.length l / 2 in
      let (a, b) = (List.filteri (fun i _ -> i < k) l, List.filteri (fun i _ -> i >= k) l) in
      let half = List.fold_left (fun q x -> Fqueue.push x q) Fqueue.empty a in
      let half = match Fqueue.pop half with Some (_, q) when a <> [] -> Fqueue.push (List.hd a) q | _ -> half in
      let a' = match a with [] -> [] | x :: r -> r @ [ x ] in
      Fqueue.to_list (Fqueue.append b half) = a' @ b
      && Fqueue.length (Fqueue.append b half) = List.length l
      && Fqueue.fold_newest (fun acc x -> x :: acc) [] (Fqueue.append b half) = a' @ b)
  && (match Fqueue.remove_first (fun x -> x mod 3 = 0) q with
      | None -> not (List.exists (fun x -> x mod 3 = 0) l)
      | Some (x, q') ->
        let rec without = function [] -> [] | y :: r -> if y = x then r else y :: without r in
        x mod 3 = 0 && Fqueue.to_list q' = without l)

(* ---------------------------------------------- scenario models *)

let str s = Tla.Str s
let int i = Tla.Int i
let handler accepts effects =
  Tla.record [ "accepts", Tla.set (List.map str accepts); "effects", Tla.Seq effects ]
let activate b = Tla.record [ "op", str "activate"; "b", str b ]
let deactivate = Tla.record [ "op", str "deactivate" ]

let model ?(variant = "reference") ?(tie = "Stable") ?(percepts = [ "a", 1 ]) ?(objects = [])
    ?(messages = []) ?(behaviours = [ "B", "cyclic", false, [], [], [] ]) ?(initial = [ "B" ])
    ?(max_notify = 2) ?(capacity = 3) () =
  let per f = Tla.record (List.map (fun ((b, _, _, _, _, _) as x) -> (b, f x)) behaviours) in
  Model.of_constants ~name:"Scenario" ~dir:"." [
    "Variant", str variant; "TiePolicy", str tie; "Budget", int 1;
    "Percepts", Tla.set (List.map (fun (p, _) -> str p) percepts);
    "DefaultPriority", Tla.record (List.map (fun (p, k) -> (p, int k)) percepts);
    "Overrides", Tla.set []; "Objects", Tla.set (List.map str objects);
    "Messages", Tla.set (List.map str messages);
    "MaxNotify", int max_notify; "MaxPut", int (List.length objects);
    "MaxSend", int (List.length messages); "Flood", Tla.Bool false;
    "O2ACapacity", int capacity;
    "Behaviours", Tla.set (List.map (fun (b, _, _, _, _, _) -> str b) behaviours);
    "Kind", per (fun (_, k, _, _, _, _) -> str k);
    "HasAction", per (fun (_, _, a, _, _, _) -> Tla.Bool a);
    "ActionEffects", per (fun (_, _, _, e, _, _) -> Tla.Seq e);
    "PerceptHandlers", per (fun (_, _, _, _, ph, _) -> Tla.Seq ph);
    "MessageHandlers", per (fun (_, _, _, _, _, mh) -> Tla.Seq mh);
    "InitialBehaviours", Tla.Seq (List.map str initial);
    "MaxActive", int 3; "InversionBound", int 9 ]

(* Run the agent until it idles or [n] steps, after the host actions [host];
   return the labels of the agent steps. *)
let run_agent (m : Model.t) host n =
  let c = Model.M.init m.params ~world:() (List.map (fun i -> m.behaviours.(i)) m.initial) in
  let c = List.fold_left (fun c f -> f m c) c host in
  let rec go c n acc =
    if n = 0 then (List.rev acc, c)
    else match Model.M.step m.params c with
      | [] -> (List.rev acc, c)
      | (l, c') :: _ -> go c' (n - 1) (l :: acc) in
  go c n []

let notify name (m : Model.t) c =
  let i = let rec f k = if m.percepts.(k) = name then k else f (k + 1) in f 0 in
  Model.M.notify m.params c i m.default_priority.(i)
let put (m : Model.t) c = Model.M.put m.params c 0
let send (m : Model.t) c = Model.M.send m.params c 0

let names labels = List.map Mc.action_name labels

let ties_in_seq_order () =
  (* R3b: equal priorities are dispatched first notified, first handled. *)
  let m = model ~percepts:[ "a", 5; "b", 5 ] ~behaviours:[ "B", "cyclic", true, [], [], [] ] () in
  let (ls, _) = run_agent m [ notify "b"; notify "a"; notify "b" ] 40 in
  let seqs = List.filter_map (function Mc.Dequeue e -> Some e.seq | _ -> None) ls in
  Alcotest.(check (list int)) "dequeued in seq order" [ 1; 2; 3 ] seqs

let priority_first () =
  (* R3b: highest priority first, whatever the arrival order. *)
  let m = model ~percepts:[ "low", 1; "high", 9 ] ~max_notify:3 () in
  let (ls, _) = run_agent m [ notify "low"; notify "high"; notify "low" ] 40 in
  let order = List.filter_map (function Mc.Dequeue e -> Some e.prio | _ -> None) ls in
  Alcotest.(check (list int)) "priorities in dequeue order" [ 9; 1; 1 ] order

let every_applicable_handler_runs () =
  (* R3b/R4a: each applicable handler runs, in activation then declaration order. *)
  let m = model ~behaviours:[ "B1", "cyclic", true, [], [ handler [ "a" ] []; handler [] []; handler [ "a" ] [] ], [];
                              "B2", "cyclic", true, [], [ handler [ "a" ] [] ], [] ]
      ~initial:[ "B2"; "B1" ] () in
  let (ls, _) = run_agent m [ notify "a" ] 12 in
  let handled = List.filter_map (function
      | Mc.Handle { id; h; _ } -> Some (Printf.sprintf "%d.%d" id h)
      | Mc.Skip { id; h } -> Some (Printf.sprintf "skip %d.%d" id h) | _ -> None) ls in
  (* B2 was activated first (id 1), then B1 (id 2). *)
  Alcotest.(check (list string)) "handlers tried" [ "1.1"; "2.1"; "skip 2.2"; "2.3" ] handled

let deactivated_handler_skipped () =
  (* R4b: a handler whose behaviour an earlier handler deactivated does not run. *)
  let m = model ~behaviours:[ "B", "cyclic", true, [], [ handler [ "a" ] [ deactivate ]; handler [ "a" ] [] ], [] ] () in
  let (ls, c) = run_agent m [ notify "a" ] 10 in
  let tried = List.filter_map (function
      | Mc.Handle { h; _ } -> Some ("run " ^ string_of_int h)
      | Mc.Skip { h; _ } -> Some ("skip " ^ string_of_int h) | _ -> None) ls in
  Alcotest.(check (list string)) "second handler skipped" [ "run 1"; "skip 2" ] tried;
  Alcotest.(check int) "no active behaviour left" 0 (List.length c.active)

let discard_recorded () =
  (* R3b: a percept no handler applied to is discarded, and that is recorded. *)
  let m = model () in
  let (ls, _) = run_agent m [ notify "a" ] 10 in
  Alcotest.(check bool) "EndDispatch with discarded = true" true
    (List.exists (function Mc.End_dispatch { discarded = true; seq = 1 } -> true | _ -> false) ls)

let oneshot_removed () =
  (* R5c: a one-shot behaviour is deactivated after its first step. *)
  let m = model ~behaviours:[ "O", "oneshot", true, [], [], [] ] ~initial:[ "O" ] () in
  let (ls, c) = run_agent m [] 10 in
  Alcotest.(check int) "one behaviour step" 1
    (List.length (List.filter (function Mc.Behaviour_step _ -> true | _ -> false) ls));
  Alcotest.(check int) "not active afterwards" 0 (List.length c.active);
  Alcotest.(check bool) "the agent idles" true (Model.M.is_idle c)

let blocked_until_message () =
  (* R5d: no action block and no message: blocked until a message arrives. *)
  let m = model ~messages:[ "m" ] ~behaviours:[ "B", "cyclic", false, [], [], [ handler [ "m" ] [] ] ] () in
  let (_, c) = run_agent m [] 10 in
  Alcotest.(check (list int)) "blocked" [ 1 ] c.blocked;
  Alcotest.(check bool) "idle" true (Model.M.is_idle c);
  let c = Model.M.send m.params c 0 in
  Alcotest.(check (list int)) "woken into ready" [ 1 ] c.ready;
  let (ls, c) = (fun c -> let rec go c acc n = if n = 0 then (List.rev acc, c) else
                            match Model.M.step m.params c with [] -> (List.rev acc, c)
                                                             | (l, c') :: _ -> go c' (l :: acc) (n - 1) in go c [] 10) c in
  Alcotest.(check bool) "the message is consumed by a step" true
    (List.exists (function Mc.Behaviour_step { msg = Some (Mc.M_message _); _ } -> true | _ -> false) ls);
  Alcotest.(check int) "message queue empty" 0 (Fqueue.length c.msgq)

let restart_in_place () =
  (* R5d revised (D42): a message that arrives during a step that blocked
     its behaviour leaves the behaviour runnable at its place; the window
     lasts until the agent's next rule, and a plain Send closes it. *)
  let m = model ~messages:[ "x"; "y" ]
      ~behaviours:[ "B1", "cyclic", false, [], [], [ handler [ "x" ] [] ];
                    "B2", "cyclic", false, [], [], [ handler [ "y" ] [] ] ]
      ~initial:[ "B1"; "B2" ] () in
  let p = m.params in
  let c0 = Model.M.init p ~world:() (List.map (fun i -> m.behaviours.(i)) m.initial) in
  Alcotest.(check bool) "no window before a step" true (Model.M.send_in_step p c0 1 = None);
  let after rule c = match rule p c with [ (_, c') ] -> c' | _ -> Alcotest.fail "one result expected" in
  let c = after Model.M.behaviour_step (after Model.M.transfer c0) in
  Alcotest.(check (list int)) "B1 blocked" [ 1 ] c.blocked;
  Alcotest.(check (list int)) "B2 ready" [ 2 ] c.ready;
  (match Model.M.send_in_step p c 1 with
   | None -> Alcotest.fail "the window is open after the step"
   | Some c' ->
     Alcotest.(check (list int)) "B1 back at its place, before B2" [ 1; 2 ] c'.ready;
     Alcotest.(check int) "the round goes on with B2" 2 c'.pos;
     Alcotest.(check (list int)) "nothing blocked" [] c'.blocked;
     Alcotest.(check string) "named SendInStep" "SendInStep" (Model.M.last_action_name c');
     (match Model.M.send_in_step p c' 0 with
      | None -> Alcotest.fail "a second message during the same step"
      | Some c'' ->
        Alcotest.(check (list int)) "a second one is a Send" [ 1; 2 ] c''.ready;
        Alcotest.(check int) "two messages" 2 c''.msg_seq);
     let s = Model.M.send p c' 0 in
     Alcotest.(check string) "a Send is named Send" "Send" (Model.M.last_action_name s);
     Alcotest.(check bool) "a Send closes the window" true (Model.M.send_in_step p s 0 = None);
     let (_, c2) = List.hd (Model.M.step p c') in
     Alcotest.(check bool) "the agent's next rule closes it" true (Model.M.send_in_step p c2 0 = None));
  (* as a Send after the step, the same message leaves B1 blocked *)
  let s = Model.M.send p c 1 in
  Alcotest.(check (list int)) "Send: woken to the end" [ 2; 1 ] s.ready

let objects_stay_reference_spin_printed () =
  (* R3a: objects stay in O2A, percepts behind them still move; the printed
     loop peeks at the object forever. *)
  let m = model ~objects:[ "o" ] () in
  let (_, c) = run_agent m [ put; notify "a" ] 10 in
  Alcotest.(check int) "reference: the percept was handled" 1 (Mc.Int_set.cardinal c.done_);
  Alcotest.(check int) "reference: the object is still in O2A" 1 (Fqueue.length c.o2a);
  let mp = model ~variant:"printed" ~objects:[ "o" ] () in
  let (ls, c) = run_agent mp [ put; notify "a" ] 50 in
  Alcotest.(check bool) "printed: spins" true
    (List.for_all (function Mc.Transfer_spin _ -> true | _ -> false) ls);
  Alcotest.(check int) "printed: the percept never leaves O2A" 2 (Fqueue.length c.o2a)

let scheduler_round_robin () =
  (* R5f: runnable behaviours run in turn; activation appends to the ready list. *)
  let m = model ~behaviours:[ "A", "cyclic", true, [], [], []; "B", "cyclic", true, [], [], [] ]
      ~initial:[ "A"; "B" ] () in
  let (ls, _) = run_agent m [] 30 in
  let ids = List.filter_map (function Mc.Behaviour_step { id; _ } -> Some id | _ -> None) ls in
  Alcotest.(check (list int)) "alternating" [ 1; 2; 1; 2; 1; 2; 1; 2; 1; 2 ]
    (List.filteri (fun i _ -> i < 10) ids)

(* Decisions D1-D7 of docs/semantics.md that no ruling makes. *)

let d1_oneshot_not_blocked () =
  let m = model ~behaviours:[ "O", "oneshot", false, [], [], [] ] ~initial:[ "O" ] () in
  let (_, c) = run_agent m [] 10 in
  Alcotest.(check (list int)) "not blocked" [] c.blocked;
  Alcotest.(check int) "deactivated" 0 (List.length c.active)

let d2_snapshot_ids_reserved () =
  (* B's first handler deactivates B (id 1) and activates C: C must not take
     id 1, which the snapshot still names for B's second handler. *)
  let m = model ~behaviours:[ "B", "cyclic", true, [], [ handler [ "a" ] [ deactivate; activate "C" ];
                                                        handler [ "a" ] [] ], [];
                              "C", "cyclic", true, [], [ handler [ "a" ] [] ], [] ] () in
  let (ls, c) = run_agent m [ notify "a" ] 8 in
  Alcotest.(check (list int)) "C got id 2" [ 2 ] (List.map (fun (a : _ Mc.instance) -> a.id) c.active);
  Alcotest.(check bool) "B's second handler skipped, C's not tried" true
    (List.exists (function Mc.Skip { id = 1; h = 2 } -> true | _ -> false) ls
     && not (List.exists (function Mc.Handle { id = 2; _ } | Mc.Skip { id = 2; _ } -> true | _ -> false) ls))

let d3_put_does_not_wake () =
  let m = model ~objects:[ "o" ] ~behaviours:[ "B", "cyclic", false, [], [], [] ] () in
  let (_, c) = run_agent m [] 10 in
  Alcotest.(check bool) "idle" true (Model.M.is_idle c);
  let c = Model.M.put m.params c 0 in
  Alcotest.(check bool) "still idle after a put" true (Model.M.is_idle c);
  Alcotest.(check int) "no agent step" 0 (List.length (Model.M.step m.params c))

let d4_printed_never_idles () =
  let m = model ~variant:"printed" ~behaviours:[ "B", "cyclic", false, [], [], [] ] () in
  let (ls, c) = run_agent m [] 50 in
  Alcotest.(check bool) "not idle" false (Model.M.is_idle c);
  Alcotest.(check bool) "busy loop" true
    (List.length (List.filter (function Mc.Next_iteration -> true | _ -> false) ls) > 10)

(* ----------------------------------------------------------- platform *)

(* Two agents: "a" runs a one-shot behaviour that sends "ping" to "b" and to
   "nobody"; "b" has a cyclic behaviour whose message handler answers "pong". *)
module Ping = struct
  type percept = unit
  type message = string
  type obj = unit
  type beh = Pinger | Ponger
  type world = { outbox : (string * string) list; got : string list }
  type bindings = unit
  let cyclic = function Pinger -> false | Ponger -> true
  let has_action = function Pinger -> true | Ponger -> false
  let percept_handlers _ = 0
  let message_handlers = function Pinger -> 1 | Ponger -> 1
  let percept_applicable w ~id:_ _ _ () = (w, None)
  let run_percept_handler w ~id:_ ~active:_ _ _ () () = (w, [])
  let run_action w ~id:_ ~active:_ _ = ({ w with outbox = w.outbox @ [ ("b", "ping"); ("nobody", "ping") ] }, [])
  let message_accepted w ~id:_ b _ m =
    (w, if (b = Ponger && m = "ping") || (b = Pinger && m = "pong") then Some () else None)
  let run_message_handler w ~id:_ ~active:_ b _ m () =
    let w = { w with got = w.got @ [ m ] } in
    ((if b = Ponger then { w with outbox = w.outbox @ [ ("a", "pong") ] } else w), [])
  let take_outbox w = ({ w with outbox = [] }, w.outbox)
end

module P = Semantics.Platform.Make (Ping)

let platform_ping_pong () =
  let p = Mc.default_params in
  let w = { Ping.outbox = []; got = [] } in
  let t = P.create [ ("a", P.M.init p ~world:w [ Ping.Pinger ]); ("b", P.M.init p ~world:w [ Ping.Ponger ]) ] in
  (* rounds of R6, the agents that are not idle in creation order *)
  let rec run t n acc =
    if n = 0 || P.all_idle t then (t, List.rev acc)
    else
      let (t, acc) = List.fold_left (fun (t, acc) i ->
          if P.M.is_idle t.P.agents.(i).config then (t, acc)
          else let (t, evs) = P.iteration p t i in (t, List.rev_append evs acc)) (t, acc) (P.round None t) in
      run t (n - 1) acc in
  let (t, evs) = run t 20 [] in
  let delivered = List.filter_map (function
      | P.Delivered { sender; receiver; message } -> Some (sender ^ ">" ^ receiver ^ ":" ^ message)
      | _ -> None) evs in
  Alcotest.(check (list string)) "ping delivered to b, pong back to a" [ "a>b:ping"; "b>a:pong" ] delivered;
  Alcotest.(check bool) "the message to an unknown agent is reported (R5e)" true
    (List.exists (function P.Undeliverable { receiver = "nobody"; _ } -> true | _ -> false) evs);
  Alcotest.(check (list string)) "b handled the ping" [ "ping" ] t.agents.(1).config.world.got;
  Alcotest.(check bool) "everyone idle at the end" true (P.all_idle t);
  (* R6: one iteration of one agent is atomic: its steps are contiguous. *)
  let owners = List.filter_map (function P.Step (n, _) -> Some n | _ -> None) evs in
  let rec runs = function a :: (b :: _ as r) -> (if a <> b then 1 else 0) + runs r | _ -> 0 in
  Alcotest.(check bool) "agents interleave by whole iterations" true (runs owners <= 6)

(* -------------------------------------------- agreement with TLC *)

let model_paths = lazy (Conformance.models ())

let agreement_cases () =
  List.map (fun path ->
      let name = Filename.remove_extension (Filename.basename path) in
      Alcotest.test_case ("same state graph as TLC: " ^ name) `Slow (fun () ->
          let m = Model.load path in
          let r = Conformance.check m in
          if not (Compare.agree r) then Alcotest.fail (Compare.render r);
          Alcotest.(check bool) "non-trivial graph" true (r.explorer_states > 10)))
    (Lazy.force model_paths)

let mutants_caught () =
  let ms = List.map Model.load (Lazy.force model_paths) in
  List.iter (fun (row : Conformance.mutant_row) ->
      match row.caught_by with
      | Some _ -> ()
      | None -> Alcotest.failf "mutant %s agrees with TLC on every model" row.mutant)
    (Conformance.mutant_table ms)

let rand_dir = lazy (
  let dir = Filename.concat (Filename.get_temp_dir_name ()) (Printf.sprintf "jsref-rand-%d" (Unix.getpid ())) in
  (try Unix.mkdir dir 0o700 with Unix.Unix_error (Unix.EEXIST, _, _) -> ());
  dir)

let random_counter = ref 0

let arb_random_model =
  QCheck.make ~print:(fun cs -> String.concat "\n" (List.map (fun (c, v) -> c ^ " = " ^ Tla.to_string v) cs))
    Random_model.constants

let random_model_agrees cs =
  incr random_counter;
  let path = Random_model.write ~dir:(Lazy.force rand_dir) ~name:(Printf.sprintf "MCRandom%d" !random_counter) cs in
  let m = Model.load path in
  let g = Explorer.explore ~max_states:50_000 m in
  let (dot, _) = Tlc.state_graph m in
  let r = Compare.graphs g dot in
  if not (Compare.agree r) then QCheck.Test.fail_reportf "%s" (Compare.render r);
  true

let simulation_replayed () =
  List.iter (fun name ->
      let m = Model.load (List.find (fun p -> Filename.basename p = name ^ ".tla") (Lazy.force model_paths)) in
      match Conformance.replay_simulation m ~traces:(if long then 200 else 10) ~depth:40 ~seed with
      | Ok n -> Alcotest.(check bool) "replayed some" true (n > 0)
      | Error e -> Alcotest.fail e) [ "MCReference"; "MCNative"; "MCTiesUnstable" ]

let runs_validated () =
  List.iter (fun name ->
      let m = Model.load (List.find (fun p -> Filename.basename p = name ^ ".tla") (Lazy.force model_paths)) in
      let runs = Conformance.random_runs m ~runs:(if long then 200 else 10) ~depth:40 ~seed in
      match Conformance.validate_runs m runs with
      | Ok n -> Alcotest.(check int) "all accepted" (List.length runs) n
      | Error e -> Alcotest.fail e) [ "MCReference"; "MCBudgeted"; "MCPrintedObject" ]

let wrong_run_rejected () =
  (* The validation has teeth too: a run that reaches a state only the mutant
     reaches is not a behaviour of the spec. *)
  let path = List.find (fun p -> Filename.basename p = "MCTiesStable.tla") (Lazy.force model_paths) in
  let m = Model.load path in
  let mutant = m in
  let g = Explorer.explore ~rules:(Mutant.rules Mutant.Ties_to_largest_seq) m in
  let r = Compare.graphs g (Conformance.tlc_graph m) in
  let target = List.find_map (function
      | Compare.State (Compare.Explorer_only, v) -> Some v
      | Compare.Transition (Compare.Explorer_only, _, _, v) -> Some v
      | _ -> None) r.differences in
  match target with
  | None -> Alcotest.fail "the mutant reaches no state of its own on MCTiesStable"
  | Some v ->
    let key = Tla.to_string v in
    let i = ref (-1) in
    Array.iteri (fun k c -> if !i < 0 && Tla.to_string (Project.state mutant c) = key then i := k) g.states;
    let run = List.map (fun (_, k) -> Project.state mutant g.states.(k)) (Explorer.shortest_path g !i) in
    Alcotest.(check bool) "a path of several steps" true (List.length run > 2);
    (match Conformance.validate_runs m [ run ] with
     | Ok _ -> Alcotest.fail "TLC accepted a run of the mutant"
     | Error _ -> ());
    (* and the same path without its last step is accepted *)
    let prefix = List.filteri (fun j _ -> j < List.length run - 1) run in
    (match Conformance.validate_runs m [ prefix ] with
     | Ok _ -> ()
     | Error e -> Alcotest.failf "TLC rejected the common prefix: %s" e)

(* ----------------------------------------------------- explore's limits *)

(* A command that must fail with one line on stderr and exit status 1. *)
let one_line what cmd =
  let (status, _, err) = run_command cmd in
  Alcotest.(check int) (what ^ ": exit 1") 1 status;
  Alcotest.(check int) (what ^ ": one line: " ^ err) 1
    (List.length (List.filter (( <> ) "") (String.split_on_char '\n' err)))

(* A model's constants out of range are one error naming the constant; the
   state count is bounded by --max-states (an exhaustion error, not an
   out-of-memory death). *)
let explore_limits () =
  let rejected what f =
    match f () with
    | _ -> Alcotest.failf "%s: accepted" what
    | exception Model.Error e ->
      Alcotest.(check bool) (what ^ ": " ^ e) true (String.length e > 0) in
  let with_budget b = List.map (fun (k, v) -> if k = "Budget" then (k, int b) else (k, v)) in
  let base = (model ()).Model.constants in
  ignore (Model.of_constants ~name:"Ok" ~dir:"." base);
  rejected "MCBudget == -1" (fun () -> Model.of_constants ~name:"Neg" ~dir:"." (with_budget (-1) base));
  rejected "MCBudget == 0" (fun () -> Model.of_constants ~name:"Zero" ~dir:"." (with_budget 0 base));
  let set k n = List.map (fun (k', v) -> if k' = k then (k', int n) else (k', v)) base in
  rejected "MaxNotify 9 is not explorable" (fun () ->
      Model.check_explorable (Model.of_constants ~name:"Big" ~dir:"." (set "MaxNotify" 9)));
  rejected "O2ACapacity 17 is not explorable" (fun () ->
      Model.check_explorable (Model.of_constants ~name:"Big" ~dir:"." (set "O2ACapacity" 17)));
  rejected "a negative priority" (fun () ->
      Model.of_constants ~name:"P" ~dir:"." (List.map (fun (k, v) ->
          if k = "DefaultPriority" then (k, Tla.record [ "a", int (-3) ]) else (k, v)) base));
  (* every model of spec/models is within the ranges *)
  List.iter (fun p -> Model.check_explorable (Model.load p)) (Lazy.force model_paths);
  (* the state bound *)
  let m = Model.load (List.find (fun p -> Filename.basename p = "MCReference.tla") (Lazy.force model_paths)) in
  (match Explorer.explore ~max_states:100 m with
   | _ -> Alcotest.fail "100 states: explored anyway"
   | exception Failure e ->
     Alcotest.(check bool) ("exhaustion: " ^ e) true (String.sub e 0 11 = "exhaustion:"));
  let n = Array.length (Explorer.explore m).states in
  Alcotest.(check int) "all the states within as many" n
    (Array.length (Explorer.explore ~max_states:n m).states);
  (match Explorer.explore ~max_states:(n - 1) m with
   | _ -> Alcotest.fail "one state fewer: explored anyway"
   | exception Failure _ -> ());
  (* through the command *)
  let path = List.find (fun p -> Filename.basename p = "MCReference.tla") (Lazy.force model_paths) in
  one_line "--max-states 100" (Printf.sprintf "%s explore %s --max-states 100" exe path);
  one_line "--max-states 0" (Printf.sprintf "%s explore %s --max-states 0" exe path);
  one_line "--max-states -5" (Printf.sprintf "%s explore %s --max-states=-5" exe path)

(* D31: the counting path (fingerprints, frontier only) finds exactly the
   states, transitions and final states of the exact explorer on every
   model, and no two states of a model share a fingerprint. *)
let d31_fingerprints_count_exactly () =
  List.iter (fun p ->
      let m = Model.load p in
      let g = Explorer.explore m in
      let c = Explorer.count m in
      let n = Array.length g.states in
      Alcotest.(check int) (m.name ^ ": distinct states") n c.distinct;
      Alcotest.(check int) (m.name ^ ": generated = transitions + initial")
        (Array.length g.edges + 1) c.generated;
      Alcotest.(check int) (m.name ^ ": final states") (List.length g.deadlocks) c.final;
      let fps = Hashtbl.create n in
      Array.iter (fun st -> Hashtbl.replace fps (Explorer.state_fingerprint st) ()) g.states;
      Alcotest.(check int) (m.name ^ ": fingerprints all different") n (Hashtbl.length fps))
    (Conformance.models ~full:true ());
  (* the bound, and the flags that do not go together: one line, exit 1 *)
  let path = List.find (fun p -> Filename.basename p = "MCReference.tla") (Lazy.force model_paths) in
  (match Explorer.count ~max_states:100 (Model.load path) with
   | _ -> Alcotest.fail "100 states: counted anyway"
   | exception Failure e ->
     Alcotest.(check bool) ("exhaustion: " ^ e) true (String.sub e 0 11 = "exhaustion:"));
  one_line "--fingerprints --max-states 100" (Printf.sprintf "%s explore %s --fingerprints --max-states 100" exe path);
  one_line "--fingerprints --against-tlc" (Printf.sprintf "%s explore %s --fingerprints --against-tlc" exe path);
  one_line "--fingerprints --all" (Printf.sprintf "%s explore --all --fingerprints" exe)

(* D36: the counting path's fingerprint of a successor, made from its
   parent's part hashes and only the parts the rule changed (an agent rule:
   the fields that are not physically the parent's; a host rule: predicted
   from the action before the successor is made), is the fingerprint
   computed from scratch: for every transition of every model (full ones
   too), by the reference's rules and by the counting path's own successors
   (the fast engine shares fields differently). And the counting path's
   successors are the exact explorer's, as a multiset of keys. *)
let d36_incremental_fingerprint () =
  let checked = ref 0 in
  List.iter (fun p ->
      let m = Model.load p in
      let g = Explorer.explore m in
      Array.iter (fun (c : Model.M.t) ->
          let keys l = List.sort compare (List.map Explorer.key l) in
          let reference = List.map snd (Explorer.successors m c) in
          let counted_fps = Explorer.count_successors m c in
          let counted = List.map snd counted_fps in
          List.iter (fun (fp, c') ->
              incr checked;
              if fp <> Explorer.state_fingerprint c' then
                Alcotest.failf "%s: from %s to %s: fingerprint %d from scratch, %d on the counting path"
                  m.name (Explorer.show m c) (Explorer.show m c') (Explorer.state_fingerprint c') fp)
            counted_fps;
          if keys counted <> keys reference then
            Alcotest.failf "%s: from %s\nthe counting path takes %d successors: %s\nthe explorer %d: %s"
              m.name (Explorer.show m c) (List.length counted)
              (String.concat " | " (List.map (Explorer.show m) counted)) (List.length reference)
              (String.concat " | " (List.map (Explorer.show m) reference));
          List.iter (fun c' ->
              incr checked;
              let whole = Explorer.state_fingerprint c' and inc = Explorer.fingerprint_after ~parent:c c' in
              if whole <> inc then
                Alcotest.failf "%s: from %s to %s: fingerprint %d from scratch, %d from the parent's parts"
                  m.name (Explorer.show m c) (Explorer.show m c') whole inc)
            (reference @ counted)) g.states)
    (Conformance.models ~full:true ());
  Alcotest.(check bool) (Printf.sprintf "checked %d transitions" !checked) true (!checked > 100_000)

(* D31 and D36 beyond spec/models: on random models (any variant, tie
   policy, overrides, objects, messages and behaviours), the count is the
   exact explorer's and the counting path's fingerprint of every transition
   is the one computed from scratch. Models over 20,000 states are left
   out (assumed away). *)
let d36_random_models cs =
  let m = Model.of_constants ~name:"MCRandom" ~dir:"." cs in
  match Explorer.explore ~max_states:20_000 m with
  | exception Failure _ -> QCheck.assume_fail ()
  | g ->
    let c = Explorer.count m in
    let n = Array.length g.states in
    if c.distinct <> n || c.generated <> Array.length g.edges + 1 || c.final <> List.length g.deadlocks then
      QCheck.Test.fail_reportf "counted %d states, %d generated, %d final; the exact explorer %d, %d, %d"
        c.distinct c.generated c.final n (Array.length g.edges + 1) (List.length g.deadlocks);
    Array.iter (fun (st : Model.M.t) ->
        let counted = Explorer.count_successors m st in
        let keys l = List.sort compare (List.map Explorer.key l) in
        if keys (List.map snd counted) <> keys (List.map snd (Explorer.successors m st)) then
          QCheck.Test.fail_reportf "from %s: the counting path's successors differ" (Explorer.show m st);
        List.iter (fun (fp, c') ->
            if fp <> Explorer.state_fingerprint c' then
              QCheck.Test.fail_reportf "from %s to %s: fingerprint %d from scratch, %d on the counting path"
                (Explorer.show m st) (Explorer.show m c') (Explorer.state_fingerprint c') fp) counted)
      g.states;
    true

(* ---------------------------------------------------------- TLA+ strings *)

(* Tla.string_literal read back by the project's reader of TLA+ values
   (Tla.parse, which reads TLC's output): the same string; a string TLC
   cannot read (a backtick, a byte beyond ASCII) is refused. *)
let tla_string_round_trip s =
  if String.exists (fun c -> c = '`' || c >= '\128') s then
    match Tla.string_literal s with
    | exception Invalid_argument _ -> true
    | l -> QCheck.Test.fail_reportf "%S written %s, which TLC cannot read" s l
  else
  match Tla.parse (Tla.string_literal s) with
  | Tla.Str t when t = s -> true
  | v -> QCheck.Test.fail_reportf "%S written %s, read back as %s" s (Tla.string_literal s) (Tla.to_string v)
  | exception Tla.Parse_error m -> QCheck.Test.fail_reportf "%S written %s: %s" s (Tla.string_literal s) m

(* Tla.string_literal read by TLC: a module holding each string as a
   literal makes TLC check its length in characters and print it
   (PrintT), and what TLC prints, read back, is the string. The strings:
   every ASCII byte but the backtick between two letters (control
   characters, NUL, DEL, a quote and a backslash among them), every escape
   at once, text that looks like an escape or a comment. *)
let tla_strings_read_by_tlc () =
  let strings =
    List.filter_map (fun c -> if c = Char.code '`' then None else Some ("a" ^ String.make 1 (Char.chr c) ^ "b"))
      (List.init 128 Fun.id)
    @ [ "\"\\\n\t\r\012"; "\\n\\\"\\"; ""; "\"\""; "'(* *)\\* '"; "\000\001\127\031" ] in
  let text = Buffer.create 4096 in
  Buffer.add_string text "---- MODULE EscapeCheck ----\nEXTENDS TLC, Sequences\nVARIABLE x\n";
  List.iteri (fun i s ->
      Printf.bprintf text "ASSUME Len(%s) = %d\nASSUME PrintT(<<%d, %s>>)\n"
        (Tla.string_literal s) (String.length s) i (Tla.string_literal s)) strings;
  Buffer.add_string text "Init == x = 0\nNext == UNCHANGED x\n====\n";
  let r = Tlc.run_text ~module_name:"EscapeCheck" ~text:(Buffer.contents text)
      ~cfg_lines:[ "INIT Init"; "NEXT Next" ] ~options:[ "-workers"; "1" ] in
  if r.exit_code <> 0 then Alcotest.failf "TLC exit %d:\n%s" r.exit_code r.output;
  let printed = List.filter_map (fun l ->
      if String.length l > 2 && String.sub l 0 2 = "<<" then
        match Tla.parse l with
        | Tla.Seq [ Tla.Int i; Tla.Str s ] -> Some (i, s)
        | _ -> Alcotest.failf "TLC printed %S" l
      else None) (String.split_on_char '\n' r.output) in
  Alcotest.(check int) "every string printed" (List.length strings) (List.length printed);
  List.iteri (fun i s ->
      Alcotest.(check string) (Printf.sprintf "string %d read back" i) s
        (try List.assoc i printed with Not_found -> Alcotest.failf "string %d not printed" i)) strings

let () =
  Alcotest.run "semantics" [
    ("queues", [
        qcheck ~count:500 "priority queue pops by priority then seq" pq_ops pqueue_pops_in_order;
        qcheck ~count:300 "candidates and remove" pq_ops pqueue_candidates;
        qcheck ~count:500 "priority queue under any inserts, pops and removals" pq_any_ops pqueue_any_order;
        qcheck ~count:300 "fqueue is a FIFO" QCheck.(list_of_size Gen.(int_bound 80) small_int) fqueue_is_a_queue ]);
    ("rulings", [
        Alcotest.test_case "R3b ties in seq order" `Quick ties_in_seq_order;
        Alcotest.test_case "R3b highest priority first" `Quick priority_first;
        Alcotest.test_case "R3b/R4a every applicable handler" `Quick every_applicable_handler_runs;
        Alcotest.test_case "R4b deactivated handler skipped" `Quick deactivated_handler_skipped;
        Alcotest.test_case "R3b discard recorded" `Quick discard_recorded;
        Alcotest.test_case "R5c one-shot removed" `Quick oneshot_removed;
        Alcotest.test_case "R5d blocked until a message" `Quick blocked_until_message;
        Alcotest.test_case "R5d revised: restart in place" `Quick restart_in_place;
        Alcotest.test_case "R3a objects stay; printed spins" `Quick objects_stay_reference_spin_printed;
        Alcotest.test_case "R5f round robin" `Quick scheduler_round_robin ]);
    ("limits", [ Alcotest.test_case "explore: model ranges, --max-states" `Quick explore_limits;
                 Alcotest.test_case "D31 fingerprints count exactly" `Quick d31_fingerprints_count_exactly;
                 Alcotest.test_case "D36 incremental fingerprint = from scratch" `Quick d36_incremental_fingerprint;
                 qcheck ~count:40 "D36 random models: count = exact, fingerprints = from scratch"
                   arb_random_model d36_random_models ]);
    ("decisions", [
        Alcotest.test_case "D1 one-shot deactivated, not blocked" `Quick d1_oneshot_not_blocked;
        Alcotest.test_case "D2 snapshot ids reserved" `Quick d2_snapshot_ids_reserved;
        Alcotest.test_case "D3 put does not wake" `Quick d3_put_does_not_wake;
        Alcotest.test_case "D4 printed never idles" `Quick d4_printed_never_idles ]);
    ("platform", [ Alcotest.test_case "R5e R6 ping-pong between agents" `Quick platform_ping_pong ]);
    ("tlc", agreement_cases () @ [
        Alcotest.test_case "every mutant is caught" `Slow mutants_caught;
        qcheck ~count:4 ~long_factor:10 "random models agree with TLC" arb_random_model random_model_agrees;
        Alcotest.test_case "TLC behaviours replayed" `Slow simulation_replayed;
        Alcotest.test_case "OCaml runs validated by TLC" `Slow runs_validated;
        Alcotest.test_case "a mutant's run is rejected" `Slow wrong_run_rejected;
        Alcotest.test_case "TLA+ strings: TLC reads them back" `Quick tla_strings_read_by_tlc;
        qcheck ~count:2000 "TLA+ strings: Tla.parse reads them back" tricky_text tla_string_round_trip ]);
  ]
