module Make (B : Machine.BODIES) = struct
  module M = Machine.Make (B)

  type agent = { name : string; config : M.t }
  type t = { agents : agent array }

  type event =
    | Step of string * M.lbl
    | Delivered of { sender : string; receiver : string; message : B.message }
    | To_platform of { sender : string; receiver : string; message : B.message }
    | Undeliverable of { sender : string; receiver : string; message : B.message }

  let platform_agents = [ "ams"; "df" ]

  let create l = { agents = Array.of_list (List.map (fun (name, config) -> { name; config }) l) }

  let find t name =
    let rec go i =
      if i >= Array.length t.agents then None
      else if String.equal t.agents.(i).name name then Some i
      else go (i + 1) in
    go 0

  let set t i config =
    let agents = Array.copy t.agents in
    agents.(i) <- { (agents.(i)) with config };
    { agents }

  let arrival p t at ~sender ~receiver message =
    match at with
    | Some i -> (Some (i, M.send p t.agents.(i).config message), Delivered { sender; receiver; message })
    | None when List.mem receiver platform_agents -> (None, To_platform { sender; receiver; message })
    | None -> (None, Undeliverable { sender; receiver; message })

  let deliver p t ~sender ~receiver message =
    match arrival p t (find t receiver) ~sender ~receiver message with
    | (Some (i, c), ev) -> (set t i c, ev)
    | (None, ev) -> (t, ev)

  let arrival_in_step p t at ~sender ~receiver message =
    match at with
    | Some i ->
      Option.map (fun c -> (i, c, Delivered { sender; receiver; message }))
        (M.send_in_step p t.agents.(i).config message)
    | None -> None

  let deliver_in_step p t ~sender ~receiver message =
    Option.map (fun (i, c, ev) -> (set t i c, ev))
      (arrival_in_step p t (find t receiver) ~sender ~receiver message)

  (* Deliver what agent i's bodies sent during its last step, in order; each
     delivery is reported with the platform right after it. *)
  let flush ?(on_event = fun _ _ -> ()) p t i =
    let c = t.agents.(i).config in
    let (world, out) = B.take_outbox c.world in
    match out with
    | [] -> (t, [])    (* nothing sent: the platform as it is *)
    | _ ->
    let t = set t i { c with world } in
    List.fold_left (fun (t, evs) (receiver, m) ->
        let (t, ev) = deliver p t ~sender:t.agents.(i).name ~receiver m in
        on_event t ev;
        (t, ev :: evs)) (t, []) out
    |> fun (t, evs) -> (t, List.rev evs)

  (* The rules that end a loop iteration. *)
  let ends_iteration (l : M.lbl) = match l with
    | Machine.Behaviour_step _ | Machine.Next_iteration | Machine.Idle -> true
    | _ -> false

  let iteration ?(max_steps = 1_000_000) ?(on_event = fun _ _ -> ()) ?(step = M.step) ?(keep = true) p t i =
    let name = t.agents.(i).name in
    let rec go t n acc =
      if n >= max_steps then (t, List.rev acc)
      else match step p t.agents.(i).config with
        | [] -> (t, List.rev acc)
        | (l, c) :: _ ->
          let t = set t i c in
          on_event t (Step (name, l));
          let (t, evs) = flush ~on_event p t i in
          let acc = if keep then List.rev_append evs (Step (name, l) :: acc) else acc in
          if ends_iteration l then (t, List.rev acc) else go t (n + 1) acc in
    go t 0 []

  let all_idle t = Array.for_all (fun a -> M.is_idle a.config) t.agents

  (* R6: creation order, or a permutation drawn from the seed (Fisher-Yates
     from the last index down, as docs/trace-format.md states it). *)
  let round rand t =
    let n = Array.length t.agents in
    let idx = List.init n Fun.id in
    match rand with
    | None -> idx
    | Some r ->
      let a = Array.of_list idx in
      for k = n - 1 downto 1 do
        let j = Random.State.int r (k + 1) in
        let x = a.(k) in a.(k) <- a.(j); a.(j) <- x
      done;
      Array.to_list a
end
