(* The interpreter's machine as text (show.mli). *)

module V = Interp.Value
module Mc = Semantics.Machine

type config =
  (Interp.Value.t, Interp.Eval.message, Interp.Value.t, Interp.Eval.beh, Interp.Eval.agent)
    Semantics.Machine.config

type label = (Interp.Value.t, Interp.Eval.message, Interp.Value.t) Semantics.Machine.label

let entry (e : V.t Mc.entry) = Printf.sprintf "%s/%d/%d" (V.to_literal e.p) e.prio e.seq

let label (l : label) =
  Mc.action_name l ^ (match l with
      | Mc.Dequeue e | Mc.Notify e | Mc.Notify_with e -> "(" ^ entry e ^ ")"
      | Mc.Handle { id; h; seq; p } -> Printf.sprintf "(%d,%d,%d,%s)" id h seq (V.to_literal p)
      | Mc.Skip { id; h } -> Printf.sprintf "(%d,%d)" id h
      | Mc.End_dispatch { seq; discarded } -> Printf.sprintf "(%d,%b)" seq discarded
      | Mc.Behaviour_step { id; _ } -> Printf.sprintf "(%d)" id
      | Mc.Transfer n -> Printf.sprintf "(%d)" n
      | Mc.Put o -> "(" ^ V.to_literal o ^ ")"
      | _ -> "")

let config (c : config) =
  Printf.sprintf "phase=%s o2a=[%s] pq=[%s] msgq=%d next_seq=%d msg_seq=%d puts=%d dispatched=%d \
                  active=[%s] ready=[%s] blocked=[%s] pos=%d cur=%s done=%d waits=%d last=%s"
    (match c.phase with Mc.Transfer_phase -> "transfer" | Dispatch_phase -> "dispatch"
                      | Handle_phase -> "handle" | Idle_phase -> "idle")
    (String.concat ";" (List.map (function Mc.O_percept e -> entry e | Mc.O_object o -> "obj " ^ V.to_literal o)
                          (Semantics.Fqueue.to_list c.o2a)))
    (String.concat ";" (List.map entry (Semantics.Pqueue.to_sorted_list c.pq)))
    (Semantics.Fqueue.length c.msgq) c.next_seq c.msg_seq c.puts c.dispatched
    (String.concat ";" (List.map (fun (a : Interp.Eval.beh Mc.instance) ->
         Printf.sprintf "%d:%s" a.id (Interp.Eval.beh_type a.beh)) c.active))
    (String.concat ";" (List.map string_of_int c.ready))
    (String.concat ";" (List.map string_of_int c.blocked)) c.pos
    (match c.cur with
     | None -> "-"
     | Some d -> Printf.sprintf "%s todo=%s applied=%b" (entry d.e)
                   (String.concat "," (List.map (fun (i, h) -> Printf.sprintf "%d.%d" i h) d.todo)) d.applied)
    (Mc.Int_set.cardinal c.done_) (List.length c.waits) (label c.last)

let event = function
  | Interp.Eval.Log s -> "log " ^ s
  | Interp.Eval.Invoke { meth; _ } -> "invoke " ^ meth
  | Interp.Eval.Sent { perf; content; receivers } ->
    Printf.sprintf "send %s %s to %s" perf (V.to_literal content) (String.concat "," receivers)
  | Interp.Eval.Activated b -> "activate " ^ b
  | Interp.Eval.Deactivated i -> "deactivate " ^ string_of_int i
  | Interp.Eval.Error (_, at, m) -> Printf.sprintf "error %s %s" (Syntax.Source.string_of_region at) m
  | Interp.Eval.Ran { handler; effects } ->
    Printf.sprintf "ran %s: %d effects" (if handler > 0 then string_of_int handler else "action")
      (List.length effects)
