(* Messages in flight (R5e, D47): one queue per receiver and container of
   the senders. *)

type 'a t = {
  containers : (string, string) Hashtbl.t;   (* agent -> its container, when not the main one *)
  count : int;                               (* how many containers, the main one included *)
  queues : (string * string, (string * 'a) Queue.t) Hashtbl.t;   (* (receiver, container) -> (sender, payload) *)
}

let create (h : Trace.header) =
  let named = List.sort_uniq compare
      (List.filter (fun c -> c <> Trace.main_container) (List.map snd h.containers)) in
  { containers = Hashtbl.of_seq (List.to_seq h.containers);
    count = 1 + List.length named;
    queues = Hashtbl.create 8 }

let container t agent =
  Option.value (Hashtbl.find_opt t.containers agent) ~default:Trace.main_container

let containers t = t.count

let queue t ~receiver ~sender =
  let k = (receiver, container t sender) in
  match Hashtbl.find_opt t.queues k with
  | Some q -> q
  | None -> let q = Queue.create () in Hashtbl.replace t.queues k q; q

let push t ~receiver ~sender x = Queue.push (sender, x) (queue t ~receiver ~sender)

let take t ~receiver ~sender = Queue.take_opt (queue t ~receiver ~sender)

let iter t f =
  Hashtbl.iter (fun (receiver, _) q -> Queue.iter (fun (sender, x) -> f ~receiver ~sender x) q) t.queues
