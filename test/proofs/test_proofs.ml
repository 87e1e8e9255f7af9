(* The proofs tied to the code (docs/proofs.md):

   - the machine proved in Coq (proofs/Loop.v), extracted to OCaml
     (library proved), takes the same steps as Machine.step, and its host
     rules give the same configurations as the machine's, on every state
     of every model of spec/models and along random runs far beyond the
     models' bounds;
   - the theorem statements that coqc checked (proofs/audit.txt, written
     by proofs/check.sh at build time) are the statements of
     docs/proofs.md, word for word, and rest on no axiom;
   - the bounds proved for every size agree with the models: the largest
     inversion and the largest number of dispatches in one iteration that
     the explorer finds in each model never exceed the proved bound, the
     expected TLC outcome of BoundedInversion and DispatchesWithinBudget
     (the models' "\* expect" lines, spec/results.md) follows from the
     bound, and the bound is reached wherever the model lets the host
     notify enough percepts. *)

open Semantics
open Explore
module Mc = Machine
module L = Proved.Loop

let long = Sys.getenv_opt "JSREF_LONG" = Some "1"

(* ------------------------------------------------------ conversions *)

let params_of (p : Mc.params) : L.params =
  { L.p_variant = (match p.variant with
        | Mc.Printed -> L.Printed | Mc.Reference -> L.Reference
        | Mc.Budgeted -> L.Budgeted | Mc.Native -> L.Native);
    p_tie = (match p.tie with Mc.Stable -> L.Stable | Mc.Unstable -> L.Unstable);
    p_budget = p.budget; p_max_active = p.max_active; p_capacity = p.o2a_capacity;
    p_flood = p.flood }

let effects (b : Model.beh) effs =
  List.map (function
      | Model.E_activate i -> L.Activate (Lazy.force b.all).(i)
      | Model.E_deactivate -> L.Deactivate) effs

(* The bodies of a model, as the spec reads its constants: the same tables
   that Model.Bodies gives the machine. *)
let bodies : (int, int, Model.beh) L.bodies = {
  L.cyclic = (fun b -> b.Model.cyclic);
  has_action = (fun b -> b.Model.has_action);
  action_effects = (fun b -> effects b b.Model.action_effects);
  percept_handlers = (fun b -> Array.length b.Model.percept_handlers);
  percept_accepts = (fun b h x -> List.mem x b.Model.percept_handlers.(h - 1).accepts);
  percept_effects = (fun b h _ -> effects b b.Model.percept_handlers.(h - 1).effects);
  message_handlers = (fun b -> Array.length b.Model.message_handlers);
  message_accepts = (fun b h m -> List.mem m b.Model.message_handlers.(h - 1).accepts);
  message_effects = (fun b h _ -> effects b b.Model.message_handlers.(h - 1).effects);
}

let peqb (a : int) b = a = b

let entry_to (e : int Mc.entry) : int L.entry = { L.ep = e.p; eprio = e.prio; eseq = e.seq }
let entry_of (e : int L.entry) : int Mc.entry = { Mc.p = e.ep; prio = e.eprio; seq = e.eseq }

let msg_to = function
  | Mc.M_message { m; mseq } -> L.M_message (m, mseq)
  | Mc.M_percept e -> L.M_percept (entry_to e)
let msg_of = function
  | L.M_message (m, mseq) -> Mc.M_message { m; mseq }
  | L.M_percept e -> Mc.M_percept (entry_of e)

let o2a_to = function Mc.O_percept e -> L.O_percept (entry_to e) | Mc.O_object o -> L.O_object o
let o2a_of = function L.O_percept e -> Mc.O_percept (entry_of e) | L.O_object o -> Mc.O_object o

let label_to : Model.M.lbl -> (int, int, int) L.label = function
  | Mc.Init -> L.L_init
  | Mc.Notify e -> L.L_notify (entry_to e)
  | Mc.Notify_with e -> L.L_notify_with (entry_to e)
  | Mc.Put o -> L.L_put o
  | Mc.Send (m, s) -> L.L_send (m, s)
  | Mc.Transfer n -> L.L_transfer n
  | Mc.Transfer_one e -> L.L_transfer_one (entry_to e)
  | Mc.Transfer_spin o -> L.L_transfer_spin o
  | Mc.Transfer_end -> L.L_transfer_end
  | Mc.Dequeue e -> L.L_dequeue (entry_to e)
  | Mc.Handle { id; h; p; seq } -> L.L_handle (id, h, p, seq)
  | Mc.Skip { id; h } -> L.L_skip (id, h)
  | Mc.End_dispatch { seq; discarded } -> L.L_end_dispatch (seq, discarded)
  | Mc.Behaviour_step { id; msg } -> L.L_behaviour_step (id, Option.map msg_to msg)
  | Mc.Next_iteration -> L.L_next_iteration
  | Mc.Idle -> L.L_idle

let label_of : (int, int, int) L.label -> Model.M.lbl = function
  | L.L_init -> Mc.Init
  | L.L_notify e -> Mc.Notify (entry_of e)
  | L.L_notify_with e -> Mc.Notify_with (entry_of e)
  | L.L_put o -> Mc.Put o
  | L.L_send (m, s) -> Mc.Send (m, s)
  | L.L_transfer n -> Mc.Transfer n
  | L.L_transfer_one e -> Mc.Transfer_one (entry_of e)
  | L.L_transfer_spin o -> Mc.Transfer_spin o
  | L.L_transfer_end -> Mc.Transfer_end
  | L.L_dequeue e -> Mc.Dequeue (entry_of e)
  | L.L_handle (id, h, p, seq) -> Mc.Handle { id; h; p; seq }
  | L.L_skip (id, h) -> Mc.Skip { id; h }
  | L.L_end_dispatch (seq, discarded) -> Mc.End_dispatch { seq; discarded }
  | L.L_behaviour_step (id, msg) -> Mc.Behaviour_step { id; msg = Option.map msg_of msg }
  | L.L_next_iteration -> Mc.Next_iteration
  | L.L_idle -> Mc.Idle

let phase_to = function
  | Mc.Transfer_phase -> L.Transfer_phase | Mc.Dispatch_phase -> L.Dispatch_phase
  | Mc.Handle_phase -> L.Handle_phase | Mc.Idle_phase -> L.Idle_phase
let phase_of = function
  | L.Transfer_phase -> Mc.Transfer_phase | L.Dispatch_phase -> Mc.Dispatch_phase
  | L.Handle_phase -> Mc.Handle_phase | L.Idle_phase -> Mc.Idle_phase

type proved = (int, int, int, Model.beh) L.config

(* A configuration of the machine as the proved machine holds it. *)
let config_to (c : Model.M.t) : proved =
  { L.o2a = List.map o2a_to (Fqueue.to_list c.o2a);
    pq = List.map entry_to (Pqueue.to_sorted_list c.pq);
    msgq = List.map msg_to (Fqueue.to_list c.msgq);
    next_seq = c.next_seq; msg_seq = c.msg_seq; puts = c.puts;
    active = List.map (fun (a : Model.beh Mc.instance) -> { L.iid = a.id; ibeh = a.beh }) c.active;
    ready = c.ready; blocked = c.blocked; pos = c.pos; phase_of = phase_to c.phase;
    cur = Option.map (fun (d : int Mc.dispatch) ->
        { L.de = entry_to d.e; todo = d.todo; applied = d.applied }) c.cur;
    dispatched = c.dispatched; done_ = Mc.Int_set.elements c.done_;
    waits = List.map (fun (s, k, n) -> ((s, k), n)) c.waits; last = label_to c.last }

(* What is compared: every variable, the priority queue and done as sorted
   lists (they are sets in the spec; the proved machine keeps done as a
   list, one element per exit, so a duplicate would show), behaviours by
   their index. *)
type view = {
  v_o2a : (int, int) Mc.o2a_item list; v_pq : int Mc.entry list;
  v_msgq : (int, int) Mc.msg_item list; v_nums : int list;
  v_active : (int * int) list; v_ready : int list; v_blocked : int list;
  v_phase : Mc.phase; v_cur : (int Mc.entry * (int * int) list * bool) option;
  v_done : int list; v_waits : (int * int * int) list; v_last : Model.M.lbl;
}

let view_of_machine (c : Model.M.t) = {
  v_o2a = Fqueue.to_list c.o2a; v_pq = List.sort compare (Pqueue.to_sorted_list c.pq);
  v_msgq = Fqueue.to_list c.msgq;
  v_nums = [ c.next_seq; c.msg_seq; c.puts; c.pos; c.dispatched ];
  v_active = List.map (fun (a : Model.beh Mc.instance) -> (a.id, a.beh.bidx)) c.active;
  v_ready = c.ready; v_blocked = c.blocked; v_phase = c.phase;
  v_cur = Option.map (fun (d : int Mc.dispatch) -> (d.e, d.todo, d.applied)) c.cur;
  v_done = Mc.Int_set.elements c.done_; v_waits = c.waits; v_last = c.last }

let view_of_proved (c : proved) = {
  v_o2a = List.map o2a_of c.o2a; v_pq = List.sort compare (List.map entry_of c.pq);
  v_msgq = List.map msg_of c.msgq;
  v_nums = [ c.next_seq; c.msg_seq; c.puts; c.pos; c.dispatched ];
  v_active = List.map (fun (a : Model.beh L.instance) -> (a.iid, a.ibeh.Model.bidx)) c.active;
  v_ready = c.ready; v_blocked = c.blocked; v_phase = phase_of c.phase_of;
  v_cur = Option.map (fun (d : int L.dispatch) -> (entry_of d.de, d.todo, d.applied)) c.cur;
  v_done = List.sort compare c.done_;
  v_waits = List.map (fun ((s, k), n) -> (s, k, n)) c.waits; v_last = label_of c.last }

let sorted_results views = List.sort compare views

let machine_steps p c =
  sorted_results (List.map (fun (l, c') -> (l, view_of_machine c')) (Model.M.step p c))

let proved_steps p c =
  sorted_results (List.map (fun (l, c') -> (label_of l, view_of_proved c'))
                    (L.step peqb bodies (params_of p) (config_to c)))

(* A view, one field per line, for a failure message. *)
let show_view v =
  let ints l = "[" ^ String.concat ";" (List.map string_of_int l) ^ "]" in
  let entry (e : int Mc.entry) = Printf.sprintf "(%d,%d,#%d)" e.p e.prio e.seq in
  let list f l = "[" ^ String.concat ";" (List.map f l) ^ "]" in
  let msg = function
    | Mc.M_message { m; mseq } -> Printf.sprintf "msg(%d,#%d)" m mseq
    | Mc.M_percept e -> entry e in
  String.concat "; " [
    "o2a=" ^ list (function Mc.O_percept e -> entry e | Mc.O_object o -> Printf.sprintf "obj %d" o) v.v_o2a;
    "pq=" ^ list entry v.v_pq; "msgq=" ^ list msg v.v_msgq;
    "next_seq,msg_seq,puts,pos,dispatched=" ^ ints v.v_nums;
    "active=" ^ list (fun (i, b) -> Printf.sprintf "%d:B%d" i b) v.v_active;
    "ready=" ^ ints v.v_ready; "blocked=" ^ ints v.v_blocked;
    "cur=" ^ (match v.v_cur with
        | None -> "none"
        | Some (e, todo, a) -> Printf.sprintf "%s todo=%s applied=%b" (entry e)
                                 (list (fun (i, h) -> Printf.sprintf "%d.%d" i h) todo) a);
    "done=" ^ ints v.v_done;
    "waits=" ^ list (fun (s, k, n) -> Printf.sprintf "(#%d,%d,%d)" s k n) v.v_waits;
    "last=" ^ Mc.action_name v.v_last ]

let describe_results r =
  if r = [] then "(nothing)"
  else String.concat "\n  | " (List.map (fun (l, v) -> Mc.action_name l ^ " -> " ^ show_view v) r)

(* The host rules of both machines from [c]: every percept notified with
   its priority, and with every override, every object put, every message
   sent, and the host's notifyEvent, accepted, with a negative priority,
   on a full O2A queue. Returns the number of comparisons. *)
let compare_host ~where ~percepts ~overrides ~objects ~messages p (c : Model.M.t) =
  let lp = params_of p and lc = config_to c in
  let n = ref 0 in
  let same what a b =
    incr n;
    if view_of_machine a <> view_of_proved b then
      Alcotest.failf "%s: %s from %s\ngives in the machine %s\nand in the proved machine %s" where what
        (show_view (view_of_machine c)) (show_view (view_of_machine a)) (show_view (view_of_proved b)) in
  if Model.M.o2a_has_room p c <> L.o2a_has_room lp lc then
    Alcotest.failf "%s: o2a_has_room differs" where;
  (* Notify and NotifyWith, as the explorer takes them *)
  List.iter (fun (x, k) ->
      same "notify" (Model.M.notify p c x k) (L.notify lp lc x k)) percepts;
  List.iter (fun (x, _) ->
      List.iter (fun k -> same "notify_with" (Model.M.notify_with p c x k) (L.notify_with lp lc x k))
        overrides) percepts;
  (* the host's notifyEvent, accepted or refused (R2a, R2d) *)
  (match percepts with
   | [] -> ()
   | (x, k) :: _ ->
     (match Model.M.notify_event p c x ~default:k ~priority:None, L.notify_event lp lc x k None with
      | Ok a, L.Ok b -> same "notifyEvent(p)" a b
      | Error Mc.O2a_full, L.Error L.O2a_full -> incr n
      | _ -> Alcotest.failf "%s: notifyEvent(p) answers differently" where);
     (match Model.M.notify_event p c x ~default:0 ~priority:(Some (k + 1)),
            L.notify_event lp lc x 0 (Some (L.Natural (k + 1))) with
      | Ok a, L.Ok b -> same "notifyEvent(p, k)" a b
      | Error Mc.O2a_full, L.Error L.O2a_full -> incr n
      | _ -> Alcotest.failf "%s: notifyEvent(p, k) answers differently" where);
     (match Model.M.notify_event p c x ~default:0 ~priority:(Some (-3)),
            L.notify_event lp lc x 0 (Some (L.Negative 3)) with
      | Error (Mc.Negative_priority (-3)), L.Error (L.Negative_priority (L.Negative 3)) -> incr n
      | _ -> Alcotest.failf "%s: notifyEvent(p, -3) answers differently" where));
  List.iter (fun o -> same "put" (Model.M.put p c o) (L.put lc o)) objects;
  List.iter (fun x -> same "send" (Model.M.send p c x) (L.send lc x)) messages;
  !n

(* --------------------------------------------- every model state *)

(* Every model of spec/models, the full ones too, and its state graph,
   computed once. *)
let models =
  let all = lazy (List.map Model.load (Conformance.models ~full:true ())) in
  fun () -> Lazy.force all

let graphs : (string, Explorer.graph) Hashtbl.t = Hashtbl.create 32

let graph (m : Model.t) =
  match Hashtbl.find_opt graphs m.name with
  | Some g -> g
  | None -> let g = Explorer.explore m in Hashtbl.replace graphs m.name g; g

let range n = List.init n Fun.id

let extracted_is_machine_on_models () =
  let states = ref 0 and host = ref 0 and per_action = Hashtbl.create 16 in
  List.iter (fun (m : Model.t) ->
      let g = graph m in
      let percepts = List.mapi (fun i k -> (i, k)) (Array.to_list m.default_priority) in
      Array.iter (fun (c : Model.M.t) ->
          incr states;
          let a = machine_steps m.params c and b = proved_steps m.params c in
          if a <> b then
            Alcotest.failf "%s: from %s\nMachine.step takes\n  %s\nthe proved step takes\n  %s" m.name
              (Explorer.show m c) (describe_results a) (describe_results b);
          List.iter (fun (l, _) ->
              let k = Mc.action_name l in
              Hashtbl.replace per_action k (1 + Option.value ~default:0 (Hashtbl.find_opt per_action k))) a;
          host := !host + compare_host ~where:m.name ~percepts ~overrides:m.overrides
              ~objects:(range (Array.length m.objects))
              ~messages:(range (Array.length m.messages)) m.params c) g.states) (models ());
  (* every agent rule was compared somewhere *)
  List.iter (fun a ->
      if not (Hashtbl.mem per_action a) then Alcotest.failf "no model state takes %s" a)
    [ "Transfer"; "TransferOne"; "TransferSpin"; "TransferEnd"; "Dequeue"; "Handle"; "Skip";
      "EndDispatch"; "BehaviourStep"; "NextIteration"; "Idle" ];
  Alcotest.(check bool) (Printf.sprintf "%d configurations, %d host results compared" !states !host)
    true (!states > 200_000)

(* ------------------------------------- random runs beyond the models *)

(* Random bodies well beyond the models' bounds: up to 6 behaviour types,
   each with up to 4 percept handlers and 3 message handlers over up to 7
   percepts and 4 messages, with activate and deactivate effects. *)
let random_behaviours rand ~percepts ~messages =
  let n = 1 + Random.State.int rand 6 in
  let effects () =
    List.init (Random.State.int rand 3) (fun _ ->
        if Random.State.bool rand then Model.E_activate (Random.State.int rand n)
        else Model.E_deactivate) in
  let accepts k = List.filter (fun _ -> Random.State.int rand 3 = 0) (range k) in
  let handlers k m = Array.init (Random.State.int rand (m + 1)) (fun _ ->
      { Model.accepts = accepts k; effects = effects () }) in
  let specs = Array.init n (fun i ->
      (i, Random.State.int rand 4 > 0, Random.State.int rand 3 = 0, effects (),
       handlers percepts 4, handlers messages 3)) in
  let rec all = lazy (Array.map (fun (i, cyclic, has_action, action_effects, ph, mh) ->
      { Model.bidx = i; bname = Printf.sprintf "B%d" i; cyclic; has_action; action_effects;
        percept_handlers = ph; message_handlers = mh; all }) specs) in
  Lazy.force all

let random_params rand : Mc.params =
  { Mc.variant = [| Mc.Printed; Mc.Reference; Mc.Budgeted; Mc.Native |].(Random.State.int rand 4);
    tie = (if Random.State.int rand 4 = 0 then Mc.Unstable else Mc.Stable);
    budget = 1 + Random.State.int rand 6;
    max_active = (if Random.State.bool rand then None else Some (1 + Random.State.int rand 10));
    o2a_capacity = (if Random.State.bool rand then None else Some (1 + Random.State.int rand 12));
    flood = Random.State.int rand 8 = 0; ghosts = true }

(* One random run: from Init, 400 steps, each a host rule (a notification
   with a random priority, up to 2^30 - 1, an object, a message) or one of the
   agent's enabled rules, chosen at random; at every configuration the
   agent rules and the host rules of both machines are compared. *)
let random_run seed =
  let rand = Random.State.make [| seed |] in
  let percepts = 1 + Random.State.int rand 7 and messages = 1 + Random.State.int rand 4 in
  let behs = random_behaviours rand ~percepts ~messages in
  let p = random_params rand in
  let initial = List.init (Random.State.int rand 5) (fun _ -> behs.(Random.State.int rand (Array.length behs))) in
  let where = Printf.sprintf "random run %d" seed in
  let prio () = if Random.State.int rand 5 = 0 then Random.State.int rand 0x3fffffff else Random.State.int rand 6 in
  let c = ref (Model.M.init p ~world:() initial) and states = ref 0 and max_seq = ref 0 in
  for _ = 1 to 400 do
    incr states;
    let a = machine_steps p !c and b = proved_steps p !c in
    if a <> b then
      Alcotest.failf "%s: from %s\nMachine.step takes\n  %s\nthe proved step takes\n  %s" where
        (show_view (view_of_machine !c)) (describe_results a) (describe_results b);
    ignore (compare_host ~where ~percepts:[ (Random.State.int rand percepts, prio ()) ]
              ~overrides:[ prio () ] ~objects:[ 0 ] ~messages:[ Random.State.int rand messages ] p !c);
    let agent = Model.M.step p !c in
    let room = Model.M.o2a_has_room p !c in
    c := (match Random.State.int rand 10 with
        | 0 | 1 when room -> Model.M.notify p !c (Random.State.int rand percepts) (prio ())
        | 2 when room -> Model.M.notify_with p !c (Random.State.int rand percepts) (prio ())
        | 3 when room && Random.State.int rand 4 = 0 -> Model.M.put p !c 0
        | 4 -> Model.M.send p !c (Random.State.int rand messages)
        | _ when agent <> [] -> snd (List.nth agent (Random.State.int rand (List.length agent)))
        | _ -> Model.M.send p !c 0);
    max_seq := max !max_seq !c.next_seq
  done;
  (!states, !max_seq)

let extracted_is_machine_on_random_runs () =
  let runs = if long then 600 else 60 in
  let states = ref 0 and longest = ref 0 in
  for seed = 1 to runs do
    let (n, m) = random_run seed in
    states := !states + n; longest := max !longest m
  done;
  (* beyond the models: they notify at most 8 percepts *)
  Alcotest.(check bool) (Printf.sprintf "%d configurations, up to %d percepts notified in a run"
                           !states !longest) true (!longest > 100)

(* --------------------------------------------- the audited statements *)

let read_file path =
  let ic = open_in_bin path in
  Fun.protect ~finally:(fun () -> close_in_noerr ic)
    (fun () -> really_input_string ic (in_channel_length ic))

(* A file of the source tree: looked for from the current folder up (dune
   runs the test in _build/default/test/proofs, scripts/test from the
   root), then from the source tree above _build. *)
let repo_file rel =
  let rec up dir =
    let p = Filename.concat dir rel in
    if Sys.file_exists p then Some p
    else let d = Filename.dirname dir in if d = dir then None else up d in
  let rec outside_build d =
    if Filename.basename d = "_build" then Filename.dirname d
    else let u = Filename.dirname d in if u = d then d else outside_build u in
  let exe_dir = Filename.dirname Sys.executable_name in
  let exe_dir = if Filename.is_relative exe_dir then Filename.concat (Sys.getcwd ()) exe_dir else exe_dir in
  match up (Sys.getcwd ()) with
  | Some p -> p
  | None -> match up (outside_build exe_dir) with
    | Some p -> p
    | None -> Alcotest.failf "%s not found" rel

(* coqc's answer to proofs/Audit.v, written at build time next to the
   extracted machine: test/proofs/test_proofs.exe is in the same build
   folder as proofs/audit.txt. *)
let audit_file () =
  let exe_dir = Filename.dirname Sys.executable_name in
  Filename.concat exe_dir (Filename.concat Filename.parent_dir_name
                             (Filename.concat Filename.parent_dir_name "proofs/audit.txt"))

let words s = String.split_on_char ' ' (String.map (function '\n' | '\t' | '\r' -> ' ' | c -> c) s)
              |> List.filter (( <> ) "")

(* coqc's answer to Audit.v without the "Arguments" lines (and their
   continuation lines) that a Print adds. *)
let audit_lines text =
  let rec go skipping = function
    | [] -> []
    | l :: rest ->
      if String.length l >= 10 && String.sub l 0 10 = "Arguments " then go true rest
      else if skipping && String.length l > 0 && l.[0] = ' ' then go true rest
      else l :: go false rest in
  go false (String.split_on_char '\n' text)

(* The ```coq blocks of a markdown text, in order. *)
let coq_blocks text =
  let rec go acc cur = function
    | [] -> List.rev acc
    | l :: rest ->
      (match cur with
       | None -> if String.trim l = "```coq" then go acc (Some []) rest else go acc None rest
       | Some lines ->
         if String.trim l = "```" then go (String.concat "\n" (List.rev lines) :: acc) None rest
         else go acc (Some (l :: lines)) rest) in
  go [] None (String.split_on_char '\n' text)

let closed = "Closed under the global context"

let statements_are_the_documented_ones () =
  let audit = audit_lines (read_file (audit_file ())) in
  (* every theorem rests on no axiom, and no proof was admitted *)
  (match List.rev (List.filter (fun l -> String.trim l <> "") audit) with
   | last :: _ when String.trim last = closed -> ()
   | _ ->
     (* Print Assumptions lists them after a line "Axioms:" *)
     let rec from = function [] -> [] | l :: r -> if String.trim l = "Axioms:" then l :: r else from r in
     Alcotest.failf "the theorems rest on axioms or admitted proofs (proofs/audit.txt):\n%s"
       (String.concat "\n" (List.filteri (fun i _ -> i < 20) (from audit))));
  let checked = List.filter (fun l -> String.trim l <> closed) audit in
  let theorems = List.filter (fun l -> String.length l > 1 && l.[0] = '@') checked in
  let docs = coq_blocks (read_file (repo_file "docs/proofs.md")) in
  let a = words (String.concat "\n" checked) and d = words (String.concat "\n" docs) in
  if a <> d then begin
    let rec first i a d = match a, d with
      | x :: a', y :: d' when x = y -> first (i + 1) a' d'
      | _ -> (i, a, d) in
    let (i, a', d') = first 0 a d in
    let show l = String.concat " " (List.filteri (fun i _ -> i < 14) l) in
    Alcotest.failf "docs/proofs.md's coq blocks differ from the statements coqc checked \
                    (proofs/audit.txt), at word %d:\n  coqc: %s\n  docs: %s" i (show a') (show d')
  end;
  Alcotest.(check int) "theorems stated" 16 (List.length theorems)

(* ------------------------------------- the bounds against TLC's results *)

(* The expected outcome of a property in a model: its "\* expect" line. *)
let expectation (m : Model.t) prop =
  let text = read_file (Filename.concat m.dir (m.name ^ ".tla")) in
  List.find_map (fun l ->
      match words l with
      | "\\*" :: "expect" :: q :: outcome when q = prop -> Some (List.hd outcome = "holds")
      | _ -> None) (String.split_on_char '\n' text)

(* The outcome TLC observed (spec/results.md, generated by make spec). *)
let observed model prop =
  let text = read_file (repo_file "spec/results.md") in
  List.find_map (fun l ->
      match List.map String.trim (String.split_on_char '|' l) with
      | _ :: m :: _ :: q :: _ :: obs :: _ when m = model && q = prop -> Some (obs = "holds")
      | _ -> None) (String.split_on_char '\n' text)

type bound_row = {
  model : string; bound : int; max_notify : int; inversion : int; dispatches : int;
  inversion_bound : int; budget : int;
}

(* For every model of the reference or budgeted loop (without the flood
   abstraction): the proved bound (the extracted dispatch_bound), the
   largest inversion and the most dispatches of one iteration over all its
   states. *)
let bound_rows () =
  List.filter_map (fun (m : Model.t) ->
      let p = m.params in
      if p.flood || not (p.variant = Mc.Reference || p.variant = Mc.Budgeted) then None
      else
        match L.dispatch_bound (params_of p) with
        | None -> None
        | Some bound ->
          let g = graph m in
          let inversion = ref 0 and dispatches = ref 0 in
          Array.iter (fun (c : Model.M.t) ->
              List.iter (fun (_, _, n) -> inversion := max !inversion n) c.waits;
              dispatches := max !dispatches c.dispatched) g.states;
          Some { model = m.name; bound; max_notify = m.max_notify; inversion = !inversion;
                 dispatches = !dispatches; inversion_bound = m.inversion_bound; budget = p.budget })
    (models ())

let bounds_agree_with_tlc () =
  let rows = bound_rows () in
  List.iter (fun r ->
      let where = r.model in
      (* the theorems: nothing beyond the bound *)
      if r.inversion > r.bound then Alcotest.failf "%s: an inversion of %d beyond the bound %d" where r.inversion r.bound;
      if r.dispatches > r.bound then Alcotest.failf "%s: %d dispatches beyond the bound %d" where r.dispatches r.bound;
      (* exactness: the model reaches the bound wherever its host may notify
         enough percepts (bound + 1 for an inversion, bound for dispatches) *)
      let reach_inv = min r.bound (r.max_notify - 1) and reach_disp = min r.bound r.max_notify in
      if r.dispatches <> reach_disp then
        Alcotest.failf "%s: %d dispatches in an iteration, expected min(bound %d, MaxNotify %d)"
          where r.dispatches r.bound r.max_notify;
      let prios = let m = List.find (fun (m : Model.t) -> m.name = r.model) (models ()) in
        List.sort_uniq compare (Array.to_list m.default_priority @ m.overrides) in
      let reach_inv = if List.length prios >= 2 then reach_inv else 0 in
      if r.inversion <> reach_inv then
        Alcotest.failf "%s: the largest inversion is %d, expected %d" where r.inversion reach_inv;
      (* TLC: BoundedInversion holds exactly when the reachable inversion is
         within InversionBound, DispatchesWithinBudget when the reachable
         dispatches are within Budget *)
      let m = List.find (fun (m : Model.t) -> m.name = r.model) (models ()) in
      let check prop predicted =
        (match expectation m prop with
         | Some e when e <> predicted ->
           Alcotest.failf "%s: %s is expected to %s, the bound says it %s" where prop
             (if e then "hold" else "fail") (if predicted then "holds" else "fails")
         | _ -> ());
        (match observed r.model prop with
         | Some o when o <> predicted ->
           Alcotest.failf "%s: TLC found %s %s, the bound says it %s" where prop
             (if o then "holding" else "violated") (if predicted then "holds" else "fails")
         | _ -> ()) in
      check "BoundedInversion" (reach_inv <= r.inversion_bound);
      check "DispatchesWithinBudget" (reach_disp <= r.budget)) rows;
  (* the table of docs/proofs.md states the same numbers *)
  let docs = read_file (repo_file "docs/proofs.md") in
  List.iter (fun r ->
      let row = Printf.sprintf "| %s | %d | %d | %d | %d |" r.model r.bound r.max_notify r.inversion r.dispatches in
      match Str_find.find docs row with
      | _ -> ()
      | exception Not_found -> Alcotest.failf "docs/proofs.md has no row %S" row) rows;
  Alcotest.(check bool) (Printf.sprintf "%d models compared" (List.length rows)) true (List.length rows >= 8)

let () =
  Alcotest.run "proofs" [
    ("extracted machine", [
        Alcotest.test_case "proved step = Machine.step, every state of every model" `Quick
          extracted_is_machine_on_models;
        Alcotest.test_case "proved step = Machine.step, random runs beyond the models" `Quick
          extracted_is_machine_on_random_runs ]);
    ("theorems", [
        Alcotest.test_case "statements checked by coqc = docs/proofs.md, no axiom" `Quick
          statements_are_the_documented_ones;
        Alcotest.test_case "proved bounds = the models' largest, and TLC's verdicts" `Quick
          bounds_agree_with_tlc ]);
  ]
