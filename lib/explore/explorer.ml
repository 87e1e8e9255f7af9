open Semantics.Machine

type graph = {
  model : Model.t;
  states : Model.M.t array;
  initial : int list;
  edges : (int * string * int) array;
  deadlocks : int list;
  seconds : float;
}

let successors_by agent_steps (m : Model.t) (c : Model.M.t) =
  let p = m.params in
  let host = ref [] in
  let add l c = host := (l, c) :: !host in
  let room = Model.M.o2a_has_room p c in
  if room && (p.flood || c.next_seq < m.max_notify) then begin
    Array.iteri (fun i _ ->
        let c' = Model.M.notify p c i m.default_priority.(i) in
        add c'.last c') m.percepts;
    Array.iteri (fun i _ ->
        List.iter (fun k ->
            let c' = Model.M.notify_with p c i k in
            add c'.last c') m.overrides) m.percepts
  end;
  if room && c.puts < m.max_put then
    Array.iteri (fun o _ -> let c' = Model.M.put p c o in add c'.last c') m.objects;
  if c.msg_seq < m.max_send then begin
    Array.iteri (fun x _ -> let c' = Model.M.send p c x in add c'.last c') m.messages;
    (* SendInStep, in the window of the last behaviour step (R5d revised) *)
    Array.iteri (fun x _ ->
        match Model.M.send_in_step p c x with Some c' -> add c'.last c' | None -> ()) m.messages
  end;
  List.rev_append !host (agent_steps p c)

let successors ?(rules = Model.M.rules) m c = successors_by (Model.M.step_by rules) m c

(* The fast engine on the models' bodies (with the pre-test the acceptance
   tables give), for the counting path: its [step] is the reference's, rule
   for rule, on every reachable configuration of every model (test "engine
   step = reference step, every model state", test/semantics). *)
module Fast_bodies = struct
  include Model.Bodies
  let percept_may_apply () (b : Model.beh) h p = List.mem p b.percept_handlers.(h - 1).accepts
  (* a model's percepts are numbered from 0: the number is the kind *)
  let percept_kind p = if p >= 0 && p < 4096 then p else -1
  let percept_handle w ~id ~active b h p = Engine.handle_in_two percept_applicable run_percept_handler w ~id ~active b h p
end

module FE = Engine.Make (Fast_bodies)

(* ------------------------------------------------------------- keys *)

let add_int b n =
  (* Variable-length, so that small numbers cost one byte. *)
  let n = if n < 0 then (- n) * 2 + 1 else n * 2 in
  let rec go n = if n < 128 then Buffer.add_char b (Char.unsafe_chr n)
    else (Buffer.add_char b (Char.unsafe_chr (128 lor (n land 127))); go (n lsr 7)) in
  go n

let add_entry b (e : int entry) = add_int b e.p; add_int b e.prio; add_int b e.seq

let add_msg b = function
  | M_message { m; mseq } -> add_int b 0; add_int b m; add_int b mseq
  | M_percept e -> add_int b 1; add_entry b e

let add_label b (l : Model.M.lbl) =
  match l with
  | Init -> add_int b 0
  | Notify e -> add_int b 1; add_entry b e
  | Notify_with e -> add_int b 2; add_entry b e
  | Put o -> add_int b 3; add_int b o
  | Send (m, s) -> add_int b 4; add_int b m; add_int b s
  | Transfer n -> add_int b 5; add_int b n
  | Transfer_one e -> add_int b 6; add_entry b e
  | Transfer_spin o -> add_int b 7; add_int b o
  | Transfer_end -> add_int b 8
  | Dequeue e -> add_int b 9; add_entry b e
  | Handle { id; h; p; seq } -> add_int b 10; add_int b id; add_int b h; add_int b p; add_int b seq
  | Skip { id; h } -> add_int b 11; add_int b id; add_int b h
  | End_dispatch { seq; discarded } -> add_int b 12; add_int b seq; add_int b (Bool.to_int discarded)
  | Behaviour_step { id; msg } ->
    add_int b 13; add_int b id;
    (match msg with None -> add_int b 0 | Some x -> add_int b 1; add_msg b x)
  | Next_iteration -> add_int b 14
  | Idle -> add_int b 15

let key_buffer = Buffer.create 256

let key (c : Model.M.t) =
  let b = key_buffer in
  Buffer.clear b;
  let sep () = Buffer.add_char b '\255' in
  Semantics.Fqueue.fold (fun () -> function
      | O_percept e -> add_int b 0; add_entry b e
      | O_object o -> add_int b 1; add_int b o) () c.o2a;
  sep ();
  List.iter (add_entry b) (Semantics.Pqueue.to_sorted_list c.pq);
  sep ();
  Semantics.Fqueue.fold (fun () x -> add_msg b x) () c.msgq;
  sep ();
  add_int b c.next_seq; add_int b c.msg_seq; add_int b c.puts;
  List.iter (fun (a : Model.beh instance) -> add_int b a.id; add_int b a.beh.bidx) c.active;
  sep ();
  List.iter (add_int b) c.ready; sep ();
  List.iter (add_int b) c.blocked; sep ();
  add_int b c.pos;
  add_int b (match c.phase with
      | Transfer_phase -> 0 | Dispatch_phase -> 1 | Handle_phase -> 2 | Idle_phase -> 3);
  (match c.cur with
   | None -> add_int b 0
   | Some d ->
     add_int b 1; add_entry b d.e; add_int b (Bool.to_int d.applied);
     List.iter (fun (id, h) -> add_int b id; add_int b h) d.todo; sep ());
  add_int b c.dispatched;
  Int_set.iter (add_int b) c.done_; sep ();
  List.iter (fun (s, _, n) -> add_int b s; add_int b n) c.waits; sep ();
  add_label b c.last;
  (match c.stepped with
   | Not_stepped -> add_int b 0
   | Stepped_kept -> add_int b 1
   | Stepped_blocked s ->
     add_int b 2;
     List.iter (fun (a : Model.beh instance) -> add_int b a.id; add_int b a.beh.bidx) s.active;
     sep ();
     List.iter (add_int b) s.ready; sep ();
     List.iter (add_int b) s.blocked; sep ();
     add_int b s.pos);
  Buffer.contents b

(* ------------------------------------------------------------- show *)

let show (m : Model.t) (c : Model.M.t) =
  let e (x : int entry) = Printf.sprintf "(%s,%d,#%d)" m.percepts.(x.p) x.prio x.seq in
  let list f l = "[" ^ String.concat "; " (List.map f l) ^ "]" in
  let msg = function
    | M_message { m = x; mseq } -> Printf.sprintf "msg(%s,#%d)" m.messages.(x) mseq
    | M_percept x -> e x in
  let phase = match c.phase with
    | Transfer_phase -> "Transfer_phase" | Dispatch_phase -> "Dispatch_phase"
    | Handle_phase -> "Handle_phase" | Idle_phase -> "Idle_phase" in
  let stepped = match c.stepped with
    | Not_stepped -> ""
    | Stepped_kept -> "; stepped=kept"
    | Stepped_blocked s ->
      Printf.sprintf "; stepped=blocked(ready=%s; blocked=%s; pos=%d)"
        (list string_of_int s.ready) (list string_of_int s.blocked) s.pos in
  Printf.sprintf "{phase=%s; o2a=%s; pq=%s; msgq=%s; active=%s; ready=%s; blocked=%s; pos=%d%s; last=%s%s}"
    phase
    (list (function O_percept x -> e x | O_object o -> "obj " ^ m.objects.(o)) (Semantics.Fqueue.to_list c.o2a))
    (list e (Semantics.Pqueue.to_sorted_list c.pq))
    (list msg (Semantics.Fqueue.to_list c.msgq))
    (list (fun (a : Model.beh instance) -> Printf.sprintf "%d:%s" a.id a.beh.bname) c.active)
    (list string_of_int c.ready) (list string_of_int c.blocked) c.pos
    (match c.cur with
     | None -> ""
     | Some d -> Printf.sprintf "; cur=%s todo=%s applied=%b" (e d.e)
                   (list (fun (i, h) -> Printf.sprintf "%d.%d" i h) d.todo) d.applied)
    (Model.M.last_action_name c) stepped

(* ---------------------------------------------------------- explore *)

(* About 650 bytes a state (with its key and edges): a million states fit in
   well under a gigabyte; the largest model of spec/models has 110k. *)
let default_max_states = 1_000_000

let explore ?(max_states = default_max_states) ?rules (m : Model.t) =
  let t0 = Unix.gettimeofday () in
  let ids : (string, int) Hashtbl.t = Hashtbl.create 65536 in
  let states = ref (Array.make 1024 (Obj.magic 0)) and count = ref 0 in
  let edges = ref [] and deadlocks = ref [] in
  let queue = Queue.create () in
  let intern c =
    let k = key c in
    match Hashtbl.find_opt ids k with
    | Some i -> i
    | None ->
      let i = !count in
      if i >= max_states then
        failwith (Printf.sprintf "exhaustion: the model has more than %d states, exploration \
                                  stopped (a larger bound: --max-states)" max_states);
      Hashtbl.add ids k i;
      if i >= Array.length !states then begin
        let a = Array.make (2 * i) (Obj.magic 0) in
        Array.blit !states 0 a 0 i; states := a
      end;
      !states.(i) <- c;
      incr count;
      Queue.push i queue;
      i in
  let init = Model.M.init m.params ~world:()
      (List.map (fun i -> m.behaviours.(i)) m.initial) in
  let i0 = intern init in
  while not (Queue.is_empty queue) do
    let i = Queue.pop queue in
    let succs = successors ?rules m !states.(i) in
    if succs = [] then deadlocks := i :: !deadlocks;
    List.iter (fun (l, c') ->
        let j = intern c' in
        ignore l;
        edges := (i, Model.M.last_action_name c', j) :: !edges) succs
  done;
  { model = m; states = Array.sub !states 0 !count; initial = [i0];
    edges = Array.of_list (List.rev !edges); deadlocks = List.rev !deadlocks;
    seconds = Unix.gettimeofday () -. t0 }

let shortest_path g target =
  let n = Array.length g.states in
  let pred = Array.make n (-1, "") in
  let seen = Array.make n false in
  let q = Queue.create () in
  List.iter (fun i -> seen.(i) <- true; Queue.push i q) g.initial;
  let out = Array.make n [] in
  Array.iter (fun (a, l, b) -> out.(a) <- (l, b) :: out.(a)) g.edges;
  while not (Queue.is_empty q) do
    let i = Queue.pop q in
    List.iter (fun (l, j) ->
        if not seen.(j) then (seen.(j) <- true; pred.(j) <- (i, l); Queue.push j q))
      (List.rev out.(i))
  done;
  let rec back i acc =
    match pred.(i) with
    | (-1, _) -> ("Init", i) :: acc
    | (p, l) -> back p ((l, i) :: acc) in
  if target < n && seen.(target) then back target [] else []

(* ------------------------------------------------- fingerprints (D31, D36) *)

(* A 63-bit fingerprint of a configuration, from the same values as its
   canonical key [key] (without building the string), in two levels (D36).
   Each part of the configuration that is a structure (the O2A queue, the
   priority queue, the message queue, the active behaviours, the ready and
   blocked lists, the dispatch in progress and the two ghosts) has a part
   hash of its own; the fingerprint folds the part hashes, the numbers (the
   counters, pos, the phase) and the last action, in a fixed order. A
   successor is a new record around mostly the same fields as its parent's
   (the rules are [{ c with ... }]): where a field is physically the same
   value as the parent's, its part hash is the parent's, and only the parts
   that the rule changed are hashed again ([node_after]). Physical equality
   implies equality, so the result is the fingerprint computed from scratch
   whatever the rules did (test "D36 incremental fingerprint = from
   scratch").

   Every int is folded into an accumulator by xor and a multiply by a dense
   odd constant (arithmetic modulo 2^63); a part hash and the fingerprint
   end with a mix that makes every bit depend on every bit. The priority
   queue, a set, is hashed order-free: the sum of its entries' own mixes
   (the key sorts it instead). *)
let fp_mul = 0x5bd1e9955bd1e995
let fp_seed = 0x2545F4914F6CDD1D

(* [h] threaded through, so that it stays in a register *)
let[@inline] mix h n = (h lxor n) * fp_mul
let[@inline] mix_entry h (e : int entry) = mix (mix (mix h e.p) e.prio) e.seq

(* every bit of the result depends on every bit of [h] *)
let[@inline] avalanche h =
  let h = (h lxor (h lsr 31)) * 0x7fb5d329728ea185 in
  h lxor (h lsr 27)

let mix_msg h = function
  | M_message { m; mseq } -> mix (mix (mix h 0) m) mseq
  | M_percept e -> mix_entry (mix h 1) e

let mix_label h (l : Model.M.lbl) =
  match l with
  | Init -> mix h 0
  | Notify e -> mix_entry (mix h 1) e
  | Notify_with e -> mix_entry (mix h 2) e
  | Put o -> mix (mix h 3) o
  | Send (m, s) -> mix (mix (mix h 4) m) s
  | Transfer n -> mix (mix h 5) n
  | Transfer_one e -> mix_entry (mix h 6) e
  | Transfer_spin o -> mix (mix h 7) o
  | Transfer_end -> mix h 8
  | Dequeue e -> mix_entry (mix h 9) e
  | Handle { id; h = hd; p; seq } -> mix (mix (mix (mix (mix h 10) id) hd) p) seq
  | Skip { id; h = hd } -> mix (mix (mix h 11) id) hd
  | End_dispatch { seq; discarded } -> mix (mix (mix h 12) seq) (Bool.to_int discarded)
  | Behaviour_step { id; msg } ->
    let h = mix (mix h 13) id in
    (match msg with None -> mix h 0 | Some x -> mix_msg (mix h 1) x)
  | Next_iteration -> mix h 14
  | Idle -> mix h 15

(* in queue order; [Fqueue.to_list] allocates only when the queue's back list
   is not empty *)
let rec mix_o2a h = function
  | [] -> h
  | O_percept e :: r -> mix_o2a (mix_entry (mix h 0) e) r
  | O_object o :: r -> mix_o2a (mix (mix h 1) o) r

let rec mix_msgs h = function [] -> h | x :: r -> mix_msgs (mix_msg h x) r
let rec mix_ints h = function [] -> h | x :: r -> mix_ints (mix h x) r
let rec mix_active h = function
  | [] -> h
  | (a : Model.beh instance) :: r -> mix_active (mix (mix h a.id) a.beh.bidx) r
let rec mix_todo h = function [] -> h | (id, hd) :: r -> mix_todo (mix (mix h id) hd) r
(* as the key: a wait's priority is its percept's, which the key has *)
let rec mix_waits h = function [] -> h | (s, _, n) :: r -> mix_waits (mix (mix h s) n) r

(* The part hashes. For the four lists that a host rule extends at its end
   (the O2A and message queues, ready, waits), the accumulator before the
   final mix is kept too: the hash of the list with one more element is one
   step from it. *)
let acc_o2a q = mix_o2a fp_seed (Semantics.Fqueue.to_list q)
let acc_msgq q = mix_msgs fp_seed (Semantics.Fqueue.to_list q)
let acc_ints l = mix_ints fp_seed l
let acc_waits l = mix_waits fp_seed l
let pq_sum = ref 0
let pq_entry (e : int entry) = pq_sum := !pq_sum + avalanche (mix_entry fp_seed e)
let part_pq pq =
  pq_sum := 0;
  Semantics.Pqueue.fold (fun () e -> pq_entry e) () pq;
  avalanche (mix (mix fp_seed (Semantics.Pqueue.size pq)) !pq_sum)
let part_active l = avalanche (mix_active fp_seed l)
let part_cur = function
  | None -> 0
  | Some d -> avalanche (mix_todo (mix (mix_entry fp_seed d.e) (Bool.to_int d.applied)) d.todo)
let part_done s = avalanche (Int_set.fold (fun x h -> mix h x) s fp_seed)
let h_nil = avalanche (acc_ints [])

(* The window of the last behaviour step (R5d revised), mixed into the
   label's hash: Send and SendInStep have the same label, and differ here. *)
let part_stepped = function
  | Not_stepped -> 0
  | Stepped_kept -> 1
  | Stepped_blocked s ->
    let h = mix (mix_active fp_seed s.active) (List.length s.ready) in
    avalanche (mix (mix_ints (mix (mix_ints h s.ready) (List.length s.blocked)) s.blocked) s.pos)
let with_stepped l st = mix l (part_stepped st)
let mix_last (c : Model.M.t) = with_stepped (mix_label fp_seed c.last) c.stepped

let phase_int = function
  | Transfer_phase -> 0 | Dispatch_phase -> 1 | Handle_phase -> 2 | Idle_phase -> 3

(* The fingerprint from the part hashes, the numbers and the label's hash:
   four chains that do not wait for each other (the processor runs them
   side by side: a multiply waits for the one before it), then one. *)
let[@inline] fold_fp h_o2a h_pq h_msgq h_cur h_waits h_active h_ready h_blocked h_done
    next_seq msg_seq puts pos phase dispatched l =
  let a = mix (mix (mix (mix (mix fp_seed h_o2a) h_pq) h_msgq) h_cur) h_waits in
  let b = mix (mix (mix (mix fp_seed h_active) h_ready) h_blocked) h_done in
  let n = mix (mix (mix (mix (mix (mix fp_seed next_seq) msg_seq) puts) pos) phase) dispatched in
  let h = avalanche (mix (mix (mix a b) n) l) in
  if h = 0 then 1 else h     (* 0 marks an empty slot of the table *)

(* A configuration of the counting path with its part hashes, its
   fingerprint and its depth (the states on the path from the initial one
   that found it). A host rule's successor is made only once its
   fingerprint is found new ([build]): until then [c] is its parent's
   configuration and [act] the host action to take from it. *)
type node = {
  mutable c : Model.M.t;
  a_o2a : int; h_o2a : int; h_pq : int; a_msgq : int; h_msgq : int; h_active : int;
  a_ready : int; h_ready : int; h_blocked : int; h_cur : int; h_done : int;
  a_waits : int; h_waits : int;
  fp : int;
  d : int;
  act : int;      (* -1: [c] is made; else kind + 4 * index (kinds: 0 notify,
                     1 notify with a priority, 2 put, 3 send) *)
  act_k : int;    (* the priority of a notification *)
}

(* every part hashed *)
let node_of (c : Model.M.t) =
  let a_o2a = acc_o2a c.o2a and a_msgq = acc_msgq c.msgq in
  let a_ready = acc_ints c.ready and a_waits = acc_waits c.waits in
  let h_o2a = avalanche a_o2a and h_pq = part_pq c.pq and h_msgq = avalanche a_msgq in
  let h_active = part_active c.active and h_ready = avalanche a_ready in
  let h_blocked = avalanche (acc_ints c.blocked) and h_cur = part_cur c.cur in
  let h_done = part_done c.done_ and h_waits = avalanche a_waits in
  let fp = fold_fp h_o2a h_pq h_msgq h_cur h_waits h_active h_ready h_blocked h_done
      c.next_seq c.msg_seq c.puts c.pos (phase_int c.phase) c.dispatched (mix_last c) in
  { c; a_o2a; h_o2a; h_pq; a_msgq; h_msgq; h_active; a_ready; h_ready; h_blocked; h_cur;
    h_done; a_waits; h_waits; fp; d = 1; act = -1; act_k = 0 }

(* A successor [c] of [n.c] by an agent rule: only the parts that are not
   physically the parent's are hashed. *)
let node_after n (c : Model.M.t) =
  let c0 = n.c in
  let same_o2a = c.o2a == c0.o2a and same_msgq = c.msgq == c0.msgq in
  let same_ready = c.ready == c0.ready and same_waits = c.waits == c0.waits in
  let a_o2a = if same_o2a then n.a_o2a else acc_o2a c.o2a in
  let h_o2a = if same_o2a then n.h_o2a else avalanche a_o2a in
  let h_pq = if c.pq == c0.pq then n.h_pq else part_pq c.pq in
  let a_msgq = if same_msgq then n.a_msgq else acc_msgq c.msgq in
  let h_msgq = if same_msgq then n.h_msgq else avalanche a_msgq in
  let h_active = if c.active == c0.active then n.h_active else part_active c.active in
  let a_ready = if same_ready then n.a_ready else acc_ints c.ready in
  let h_ready = if same_ready then n.h_ready else avalanche a_ready in
  let h_blocked = if c.blocked == c0.blocked then n.h_blocked else avalanche (acc_ints c.blocked) in
  let h_cur = if c.cur == c0.cur then n.h_cur else part_cur c.cur in
  let h_done = if c.done_ == c0.done_ then n.h_done else part_done c.done_ in
  let a_waits = if same_waits then n.a_waits else acc_waits c.waits in
  let h_waits = if same_waits then n.h_waits else avalanche a_waits in
  let fp = fold_fp h_o2a h_pq h_msgq h_cur h_waits h_active h_ready h_blocked h_done
      c.next_seq c.msg_seq c.puts c.pos (phase_int c.phase) c.dispatched (mix_last c) in
  { c; a_o2a; h_o2a; h_pq; a_msgq; h_msgq; h_active; a_ready; h_ready; h_blocked; h_cur;
    h_done; a_waits; h_waits; fp; d = n.d + 1; act = -1; act_k = 0 }

(* The successors by the host rules, before they are made: their part
   hashes and fingerprints from the parent's and what the rule changes, as
   Machine.notify_effect, put and send change it (test "D36 incremental
   fingerprint = from scratch" holds the two equal on every transition of
   every model). [wake] is Machine.wake_idle's phase. *)
let wake (c : Model.M.t) = if c.phase = Idle_phase then 0 else phase_int c.phase

(* Notify (kind 0, label tag 1) or NotifyWith (kind 1, tag 2) of percept [i]
   with priority [k]: O_percept {i; k; seq} at the end of O2A, next_seq,
   (seq, k, 0) at the end of waits when the ghosts are kept (hashed as
   (seq, 0), as [mix_waits] does), the phase woken. *)
let notify_node p (n : node) kind i k =
  let c = n.c in
  let seq = if p.flood then 0 else c.next_seq + 1 in
  let a_o2a = mix (mix (mix (mix n.a_o2a 0) i) k) seq in
  let h_o2a = avalanche a_o2a in
  let ghosts = p.ghosts && not p.flood in
  let a_waits = if ghosts then mix (mix n.a_waits seq) 0 else n.a_waits in
  let h_waits = if ghosts then avalanche a_waits else n.h_waits in
  let l = with_stepped (mix (mix (mix (mix fp_seed (kind + 1)) i) k) seq) c.stepped in
  let fp = fold_fp h_o2a n.h_pq n.h_msgq n.h_cur h_waits n.h_active n.h_ready n.h_blocked n.h_done
      seq c.msg_seq c.puts c.pos (wake c) c.dispatched l in
  { n with a_o2a; h_o2a; a_waits; h_waits; fp; d = n.d + 1; act = kind + 4 * i; act_k = k }

(* Put of object [o]: O_object o at the end of O2A, puts + 1; no wake (D3). *)
let put_node (n : node) o =
  let c = n.c in
  let a_o2a = mix (mix n.a_o2a 1) o in
  let h_o2a = avalanche a_o2a in
  let fp = fold_fp h_o2a n.h_pq n.h_msgq n.h_cur n.h_waits n.h_active n.h_ready n.h_blocked n.h_done
      c.next_seq c.msg_seq (c.puts + 1) c.pos (phase_int c.phase) c.dispatched
      (with_stepped (mix (mix fp_seed 3) o) c.stepped) in
  { n with a_o2a; h_o2a; fp; d = n.d + 1; act = 2 + 4 * o; act_k = 0 }

(* Send of message [x]: M_message {x; seq} at the end of the message queue,
   msg_seq, the blocked behaviours at the end of ready, none blocked, the
   phase woken. *)
let send_node (n : node) x =
  let c = n.c in
  let seq = c.msg_seq + 1 in
  let a_msgq = mix (mix (mix n.a_msgq 0) x) seq in
  let h_msgq = avalanche a_msgq in
  let a_ready = mix_ints n.a_ready c.blocked in
  let h_ready = avalanche a_ready in
  let fp = fold_fp n.h_o2a n.h_pq h_msgq n.h_cur n.h_waits n.h_active h_ready h_nil n.h_done
      c.next_seq seq c.puts c.pos (wake c) c.dispatched
      (with_stepped (mix (mix (mix fp_seed 4) x) seq) Not_stepped) in
  { n with a_msgq; h_msgq; a_ready; h_ready; h_blocked = h_nil; fp; d = n.d + 1;
           act = 3 + 4 * x; act_k = 0 }

(* The host rules within the model's bounds, as [successors] takes them,
   consed onto [acc]. *)
let rec notify_nodes p (m : Model.t) n i acc =
  if i < 0 then acc
  else notify_nodes p m n (i - 1) (notify_node p n 0 i m.default_priority.(i) :: acc)

let rec notify_with_nodes p n i ks acc =
  match ks with
  | [] -> acc
  | k :: r -> notify_with_nodes p n i r (notify_node p n 1 i k :: acc)

let rec overridden_nodes p (m : Model.t) n i acc =
  if i < 0 then acc else overridden_nodes p m n (i - 1) (notify_with_nodes p n i m.overrides acc)

let rec put_nodes n o acc = if o < 0 then acc else put_nodes n (o - 1) (put_node n o :: acc)
let rec send_nodes n x acc = if x < 0 then acc else send_nodes n (x - 1) (send_node n x :: acc)

(* SendInStep of message [x] (R5d revised), in the window of the last
   behaviour step: rare (the window lasts until the agent's next rule), so
   its successor is made at once and hashed as an agent rule's. *)
let rec send_in_step_nodes p n x acc =
  if x < 0 then acc
  else send_in_step_nodes p n (x - 1)
      (match Model.M.send_in_step p n.c x with Some c' -> node_after n c' :: acc | None -> acc)

let host_nodes (m : Model.t) (n : node) acc =
  let p = m.params and c = n.c in
  let room = Model.M.o2a_has_room p c in
  let acc =
    if c.msg_seq < m.max_send then
      send_in_step_nodes p n (Array.length m.messages - 1) (send_nodes n (Array.length m.messages - 1) acc)
    else acc in
  let acc = if room && c.puts < m.max_put then put_nodes n (Array.length m.objects - 1) acc else acc in
  if room && (p.flood || c.next_seq < m.max_notify) then
    notify_nodes p m n (Array.length m.percepts - 1)
      (overridden_nodes p m n (Array.length m.percepts - 1) acc)
  else acc

(* A host rule's successor made, by the rule itself. *)
let build p (n : node) =
  if n.act >= 0 then begin
    let i = n.act lsr 2 in
    n.c <- (match n.act land 3 with
        | 0 -> Model.M.notify p n.c i n.act_k
        | 1 -> Model.M.notify_with p n.c i n.act_k
        | 2 -> Model.M.put p n.c i
        | _ -> Model.M.send p n.c i)
  end

let rec agent_nodes n acc = function
  | [] -> acc
  | (_, c') :: r -> agent_nodes n (node_after n c' :: acc) r

let state_fingerprint c = (node_of c).fp
let fingerprint_after ~parent c = (node_after (node_of parent) c).fp

(* The visited set: an open-addressing table of fingerprints in a Bigarray
   (outside the OCaml heap: the collector never scans it), at most three
   quarters full. The type of the slots is written out, so that a read or a
   write is one instruction, not a call into the runtime. *)
module Fp_set = struct
  open Bigarray
  type slots = (int, int_elt, c_layout) Array1.t
  type t = { mutable slots : slots; mutable mask : int; mutable count : int }

  let make n : slots = let a = Array1.create int c_layout n in Array1.fill a 0; a
  let create () = { slots = make 65536; mask = 65535; count = 0 }
  let bytes t = Array1.dim t.slots * 8

  (* true when [h] was absent (it is now present); linear probing;
     inlined where it is called: [add] runs once for every state generated *)
  let[@inline always] add_raw (a : slots) mask h =
    let i = ref (h land mask) and r = ref 2 in      (* 2: still probing *)
    while !r = 2 do
      let x = Array1.unsafe_get a !i in
      if x = 0 then (Array1.unsafe_set a !i h; r := 1)
      else if x = h then r := 0
      else i := (!i + 1) land mask
    done;
    !r = 1

  let grow t =
    let old = t.slots in
    let n = 2 * Array1.dim old in
    let a = make n in
    for i = 0 to Array1.dim old - 1 do
      let x = Array1.unsafe_get old i in
      if x <> 0 then ignore (add_raw a (n - 1) x)
    done;
    t.slots <- a; t.mask <- n - 1

  let add t h =
    if 4 * (t.count + 1) > 3 * (t.mask + 1) then grow t;
    add_raw t.slots t.mask h && (t.count <- t.count + 1; true)
end

type count = {
  c_model : Model.t;
  distinct : int;
  generated : int;
  final : int;
  depth : int;
  table_bytes : int;
  c_seconds : float;
}

let collision_probability c =
  (* each of the [generated] look-ups compares with at most [distinct]
     fingerprints of 63 bits *)
  float_of_int c.distinct *. float_of_int c.generated /. (2. ** 63.)

(* Most configurations generated are already seen and die young; a larger
   minor heap (8 MB) lets them die there, and a lazier major collector marks
   the few that live on (the states found, not yet expanded) less often.
   Restored afterwards. *)
let with_explorer_gc f =
  let old = Gc.get () in
  Gc.set { old with minor_heap_size = max old.minor_heap_size (1 lsl 20); space_overhead = 400 };
  Fun.protect ~finally:(fun () -> Gc.set old) f

(* The reference's agent rules, asked only of those whose enabling
   condition holds in the configuration's phase (every rule of
   Machine.step_by names its phase); where the fast engine has a faster way
   (the batch Transfer, Dequeue as one pop) its [step], held equal to the
   reference's by test. *)
let agent_successors p (c : Model.M.t) =
  match c.phase with
  | Transfer_phase ->
    if p.variant = Reference || p.variant = Budgeted then FE.step p c
    else Model.M.transfer p c @ Model.M.transfer_one p c @ Model.M.transfer_spin p c
         @ Model.M.transfer_end p c
  | Dispatch_phase ->
    if p.variant <> Native && p.tie = Stable && not p.flood && not (Model.M.dispatch_over p c)
    then FE.step p c
    else Model.M.dequeue p c @ Model.M.behaviour_step p c @ Model.M.next_iteration p c
         @ Model.M.idle p c
  | Handle_phase -> Model.M.handle_or_skip p c @ Model.M.end_dispatch p c
  | Idle_phase -> []

let count_successors (m : Model.t) c =
  let n = node_of c in
  List.map (fun n' -> build m.params n'; (n'.fp, n'.c))
    (host_nodes m n (agent_nodes n [] (agent_successors m.params c)))

type tally = { mutable generated : int; mutable final : int; mutable depth : int;
               mutable fps : int array }

let count ?(max_states = default_max_states) ?rules (m : Model.t) =
  with_explorer_gc @@ fun () ->
  let t0 = Unix.gettimeofday () in
  let p = m.params in
  (* the reference's rules by phase, unless a mutant's rules are asked for *)
  let agent = match rules with Some r -> Model.M.step_by r p | None -> agent_successors p in
  let seen = Fp_set.create () in
  let t = { generated = 0; final = 0; depth = 0; fps = Array.make 64 0 } in
  let fresh fp =
    Fp_set.add seen fp
    && (seen.count <= max_states
        || failwith (Printf.sprintf "exhaustion: the model has more than %d states, exploration \
                                     stopped (a larger bound: --max-states)" max_states)) in
  (* the fingerprints of [nodes] into t.fps, from index [k] up; their number *)
  let rec note k = function
    | [] -> k
    | (n' : node) :: r ->
      if k >= Array.length t.fps then begin
        let a = Array.make (2 * k) 0 in Array.blit t.fps 0 a 0 k; t.fps <- a
      end;
      Array.unsafe_set t.fps k n'.fp;
      note (k + 1) r in
  (* the new ones, made, onto the stack; [k] indexes [nodes]' head in t.fps *)
  let rec push k nodes stack =
    match nodes with
    | [] -> stack
    | (n' : node) :: r ->
      if Array.unsafe_get t.fps k = 0 then push (k + 1) r stack
      else begin
        build p n';
        if n'.d > t.depth then t.depth <- n'.d;
        push (k + 1) r (n' :: stack)
      end in
  (* Depth first, a state marked seen when it is generated: only the states
     found and not yet expanded are kept. The fingerprints of a state's
     successors are looked up together, one after the other, so that the
     processor fetches their slots of the table at the same time. *)
  let rec loop = function
    | [] -> ()
    | n :: stack ->
      let nodes = host_nodes m n (agent_nodes n [] (agent n.c)) in
      match note 0 nodes with
      | 0 -> t.final <- t.final + 1; loop stack
      | k ->
        t.generated <- t.generated + k;
        for i = 0 to k - 1 do
          Array.unsafe_set t.fps i (Bool.to_int (fresh (Array.unsafe_get t.fps i)))
        done;
        loop (push 0 nodes stack) in
  let n0 = node_of (Model.M.init p ~world:() (List.map (fun i -> m.behaviours.(i)) m.initial)) in
  t.generated <- 1; t.depth <- 1;
  ignore (fresh n0.fp);
  loop [ n0 ];
  { c_model = m; distinct = seen.count; generated = t.generated; final = t.final;
    depth = t.depth; table_bytes = Fp_set.bytes seen; c_seconds = Unix.gettimeofday () -. t0 }
