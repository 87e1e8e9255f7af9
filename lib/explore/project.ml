open Semantics.Machine
module T = Tla

let variables = [ "o2a"; "pq"; "msgq"; "nextSeq"; "msgSeq"; "puts"; "active"; "ready";
                  "blocked"; "pos"; "phase"; "cur"; "dispatched"; "done"; "waits"; "last";
                  "stepped" ]

let str s = T.Str s
let int i = T.Int i

let entry (m : Model.t) (e : int entry) =
  T.record [ "p", str m.percepts.(e.p); "prio", int e.prio; "seq", int e.seq ]

let percept_item (m : Model.t) (e : int entry) =
  T.record [ "kind", str "percept"; "p", str m.percepts.(e.p); "prio", int e.prio;
             "seq", int e.seq ]

let o2a_item m = function
  | O_percept e -> percept_item m e
  | O_object o -> T.record [ "kind", str "object"; "obj", str m.Model.objects.(o) ]

let msg_item (m : Model.t) = function
  | M_message { m = x; mseq } ->
    T.record [ "kind", str "message"; "m", str m.messages.(x); "seq", int mseq ]
  | M_percept e -> percept_item m e

(* The record of [last]; [in_step]: a Send label that was SendInStep. *)
let last_record ~in_step (m : Model.t) (l : (int, int, int) label) =
  let act = match l with Send _ when in_step -> "SendInStep" | _ -> action_name l in
  let r fields = T.record (("act", str act) :: fields) in
  match l with
  | Init | Transfer_end | Next_iteration | Idle -> r []
  | Notify e | Notify_with e | Transfer_one e ->
    r [ "p", str m.percepts.(e.p); "prio", int e.prio; "seq", int e.seq ]
  | Put o | Transfer_spin o -> r [ "obj", str m.objects.(o) ]
  | Send (x, seq) -> r [ "m", str m.messages.(x); "seq", int seq ]
  | Transfer n -> r [ "moved", int n ]
  | Dequeue e -> r [ "e", entry m e ]
  | Handle { id; h; p; seq } -> r [ "id", int id; "h", int h; "p", str m.percepts.(p); "seq", int seq ]
  | Skip { id; h } -> r [ "id", int id; "h", int h ]
  | End_dispatch { seq; discarded } -> r [ "seq", int seq; "discarded", T.Bool discarded ]
  | Behaviour_step { id; msg } ->
    r [ "id", int id;
        "msg", (match msg with None -> T.record [ "kind", str "none" ] | Some x -> msg_item m x) ]

let label m l = last_record ~in_step:false m l

let active_seq (l : Model.beh instance list) =
  T.Seq (List.map (fun (a : Model.beh instance) ->
      T.record [ "id", int a.id; "b", str a.beh.bname ]) l)

(* [stepped] (R5d revised): NoStep, [kind |-> "kept"], or
   [kind |-> "blocked", bs |-> S2] with S2 a behaviour state as BS. *)
let stepped (c : Model.M.t) =
  let ints l = T.Seq (List.map int l) in
  match c.stepped with
  | Not_stepped -> T.record [ "kind", str "none" ]
  | Stepped_kept -> T.record [ "kind", str "kept" ]
  | Stepped_blocked s ->
    T.record [ "kind", str "blocked";
               "bs", T.record [ "active", active_seq s.active; "ready", ints s.ready;
                                "blocked", ints s.blocked; "pos", int s.pos ] ]

let no_dispatch =
  T.record [ "e", T.record [ "p", str ""; "prio", int 0; "seq", int 0 ];
             "todo", T.Seq []; "applied", T.Bool false ]

let phase = function
  | Transfer_phase -> "transfer" | Dispatch_phase -> "dispatch"
  | Handle_phase -> "handle" | Idle_phase -> "idle"

let state (m : Model.t) (c : Model.M.t) =
  let ints l = T.Seq (List.map int l) in
  T.record [
    "o2a", T.Seq (List.map (o2a_item m) (Semantics.Fqueue.to_list c.o2a));
    "pq", T.set (List.map (entry m) (Semantics.Pqueue.to_sorted_list c.pq));
    "msgq", T.Seq (List.map (msg_item m) (Semantics.Fqueue.to_list c.msgq));
    "nextSeq", int c.next_seq;
    "msgSeq", int c.msg_seq;
    "puts", int c.puts;
    "active", active_seq c.active;
    "ready", ints c.ready;
    "blocked", ints c.blocked;
    "pos", int c.pos;
    "phase", str (phase c.phase);
    "cur", (match c.cur with
        | None -> no_dispatch
        | Some d -> T.record [ "e", entry m d.e;
                               "todo", T.Seq (List.map (fun (id, h) ->
                                   T.record [ "id", int id; "h", int h ]) d.todo);
                               "applied", T.Bool d.applied ]);
    "dispatched", int c.dispatched;
    "done", T.set (List.map int (Int_set.elements c.done_));
    "waits", T.set (List.map (fun (s, _, n) -> T.Seq [ int s; int n ]) c.waits);
    "last", last_record ~in_step:(Model.M.last_action_name c = "SendInStep") m c.last;
    "stepped", stepped c;
  ]
