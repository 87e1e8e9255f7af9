open Semantics.Machine

type graph = {
  model : Model.t;
  states : Model.M.t array;
  initial : int list;
  edges : (int * string * int) array;
  deadlocks : int list;
  seconds : float;
}

let successors ?(rules = Model.M.rules) (m : Model.t) (c : Model.M.t) =
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
  List.rev_append !host (Model.M.step_by rules p c)

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
