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
  if c.msg_seq < m.max_send then
    Array.iteri (fun x _ -> let c' = Model.M.send p c x in add c'.last c') m.messages;
  List.rev_append !host (agent_steps p c)

let successors ?(rules = Model.M.rules) m c = successors_by (Model.M.step_by rules) m c

(* The fast engine on the models' bodies (with the pre-test the acceptance
   tables give), for the counting path: its [step] is the reference's, rule
   for rule, on every reachable configuration of every model (test "engine
   step = reference step, every model state", test/semantics). *)
module Fast_bodies = struct
  include Model.Bodies
  let percept_may_apply () (b : Model.beh) h p = List.mem p b.percept_handlers.(h - 1).accepts
end

module FE = Engine.Fast.Make (Fast_bodies)

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
  Printf.sprintf "{phase=%s; o2a=%s; pq=%s; msgq=%s; active=%s; ready=%s; blocked=%s; pos=%d%s; last=%s}"
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
    (action_name c.last)

(* ---------------------------------------------------------- explore *)

(* About 650 bytes a state (with its key and edges): a million states fit in
   well under a gigabyte; the largest model of spec/models has 105k. *)
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
        edges := (i, action_name l, j) :: !edges) succs
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

(* ------------------------------------------------- fingerprints (D31) *)

(* A 63-bit fingerprint of a configuration, computed from the same values,
   in the same order, as its canonical key [key] (without building the
   string): every int is folded into an accumulator by xor and a multiply by a
   dense odd constant (arithmetic modulo 2^63), a separator as a value no int
   of the key takes, and a final mix makes every bit depend on every value.
   The priority queue, a set, is folded order-free: the sum of its entries'
   own mixes (the key sorts it instead). The test "fingerprints" holds the
   two equal in the number of states on every model of spec/models. *)
let fp_mul = 0x5bd1e9955bd1e995
let fp_seed = 0x2545F4914F6CDD1D

(* [h] threaded through, so that it stays in a register *)
let[@inline] mix h n = (h lxor (n * 2)) * fp_mul    (* even: an int *)
let[@inline] sep h = (h lxor 1) * fp_mul             (* odd: a separator *)
let[@inline] mix_entry h (e : int entry) = mix (mix (mix h e.p) e.prio) e.seq

let fp_final h =
  let h = (h lxor (h lsr 31)) * 0x7fb5d329728ea185 in
  let h = h lxor (h lsr 27) in
  if h = 0 then 1 else h   (* 0 marks an empty slot *)

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
let rec mix_waits h = function [] -> h | (s, _, n) :: r -> mix_waits (mix (mix h s) n) r

(* the priority queue, a set: the sum of its entries' own mixes *)
let pq_sum = ref 0
let pq_entry (e : int entry) = pq_sum := !pq_sum + fp_final (mix_entry fp_seed e)

let state_fingerprint (c : Model.M.t) =
  pq_sum := 0;
  Semantics.Pqueue.iter pq_entry c.pq;
  let h = sep (mix_o2a fp_seed (Semantics.Fqueue.to_list c.o2a)) in
  let h = sep (mix (mix h (Semantics.Pqueue.size c.pq)) !pq_sum) in
  let h = sep (mix_msgs h (Semantics.Fqueue.to_list c.msgq)) in
  let h = mix (mix (mix h c.next_seq) c.msg_seq) c.puts in
  let h = sep (mix_active h c.active) in
  let h = sep (mix_ints h c.ready) in
  let h = sep (mix_ints h c.blocked) in
  let h = mix h c.pos in
  let h = mix h (match c.phase with
      | Transfer_phase -> 0 | Dispatch_phase -> 1 | Handle_phase -> 2 | Idle_phase -> 3) in
  let h = match c.cur with
    | None -> mix h 0
    | Some d -> sep (mix_todo (mix (mix_entry (mix h 1) d.e) (Bool.to_int d.applied)) d.todo) in
  let h = mix h c.dispatched in
  let h = sep (Int_set.fold (fun x h -> mix h x) c.done_ h) in
  let h = sep (mix_waits h c.waits) in
  fp_final (mix_label h c.last)

(* The visited set: an open-addressing table of fingerprints in a Bigarray
   (outside the OCaml heap: the collector never scans it), at most three quarters full. *)
module Fp_set = struct
  open Bigarray
  type t = { mutable slots : (int, int_elt, c_layout) Array1.t; mutable count : int }

  let make n = let a = Array1.create int c_layout n in Array1.fill a 0; a
  let create () = { slots = make 65536; count = 0 }
  let bytes t = Array1.dim t.slots * 8

  (* true when [h] was absent (it is now present) *)
  let add_raw a h =
    let mask = Array1.dim a - 1 in
    let rec probe i =
      let x = Array1.unsafe_get a i in
      if x = 0 then (Array1.unsafe_set a i h; true)
      else if x = h then false
      else probe ((i + 1) land mask) in
    probe (h land mask)

  let grow t =
    let old = t.slots in
    let a = make (2 * Array1.dim old) in
    for i = 0 to Array1.dim old - 1 do
      let x = Array1.unsafe_get old i in
      if x <> 0 then ignore (add_raw a x)
    done;
    t.slots <- a

  let add t h =
    if 4 * (t.count + 1) > 3 * Array1.dim t.slots then grow t;
    let fresh = add_raw t.slots h in
    if fresh then t.count <- t.count + 1;
    fresh
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
   the few that live on (the current path) less often. Restored afterwards. *)
let with_explorer_gc f =
  let old = Gc.get () in
  Gc.set { old with minor_heap_size = max old.minor_heap_size (1 lsl 20); space_overhead = 400 };
  Fun.protect ~finally:(fun () -> Gc.set old) f

let count ?(max_states = default_max_states) ?rules (m : Model.t) =
  with_explorer_gc @@ fun () ->
  let t0 = Unix.gettimeofday () in
  (* the fast engine unless a mutant's rules are asked for *)
  let agent_steps = match rules with Some r -> Model.M.step_by r | None -> FE.step in
  let seen = Fp_set.create () in
  let generated = ref 0 and final = ref 0 and depth = ref 0 and height = ref 0 in
  (* depth first: the stack holds, for each state on the current path, its
     successors not yet visited; a configuration dies young unless it is on
     the path, so the collector has little to keep *)
  let stack = ref [] in
  let visit c =
    incr generated;
    if Fp_set.add seen (state_fingerprint c) then begin
      if seen.count > max_states then
        failwith (Printf.sprintf "exhaustion: the model has more than %d states, exploration \
                                  stopped (a larger bound: --max-states)" max_states);
      match successors_by agent_steps m c with
      | [] -> incr final
      | succs ->
        stack := succs :: !stack; incr height;
        if !height > !depth then depth := !height
    end in
  visit (Model.M.init m.params ~world:() (List.map (fun i -> m.behaviours.(i)) m.initial));
  while !stack <> [] do
    match !stack with
    | ((_, c) :: rest) :: below -> stack := rest :: below; visit c
    | [] :: below -> stack := below; decr height
    | [] -> ()
  done;
  { c_model = m; distinct = seen.count; generated = !generated; final = !final;
    depth = !depth; table_bytes = Fp_set.bytes seen; c_seconds = Unix.gettimeofday () -. t0 }
