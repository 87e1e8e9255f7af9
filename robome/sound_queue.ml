type t = {
  q : (Command.t * float) Queue.t;
  duration : float;
  gap : float;
  mutable free_at : float;
}

let create ~duration ~gap = { q = Queue.create (); duration; gap; free_at = 0. }

let enqueue t ~now c = Queue.add (c, now) t.q

let effect_of t issued = Float.max issued t.free_at +. t.duration

let next_effect t =
  match Queue.peek_opt t.q with None -> None | Some (_, issued) -> Some (effect_of t issued)

let pop t =
  match Queue.take_opt t.q with
  | None -> None
  | Some (c, issued) ->
    let at = effect_of t issued in
    t.free_at <- at +. t.gap;
    Some (c, issued, at)

let length t = Queue.length t.q
