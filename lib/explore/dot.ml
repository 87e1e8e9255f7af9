type graph = {
  nodes : (string * Tla.t) list;
  initial : string list;
  edges : (string * string * string) list;
}

let unescape s =
  let b = Buffer.create (String.length s) in
  let n = String.length s in
  let rec go i =
    if i < n then
      if s.[i] = '\\' && i + 1 < n then begin
        (match s.[i + 1] with
         | 'n' | 'l' -> Buffer.add_char b '\n'
         | c -> Buffer.add_char b c);
        go (i + 2)
      end else (Buffer.add_char b s.[i]; go (i + 1)) in
  go 0;
  Buffer.contents b

let starts_with s p = String.length s >= String.length p && String.sub s 0 (String.length p) = p

let parse_state text =
  (* Join continuation lines, then parse each "/\ var = value". *)
  let lines = String.split_on_char '\n' text in
  let joined = List.fold_left (fun acc l ->
      let t = String.trim l in
      if t = "" then acc
      else if starts_with t "/\\ " then t :: acc
      else match acc with
        | last :: rest -> (last ^ " " ^ t) :: rest
        | [] -> [t]) [] lines |> List.rev in
  Tla.record (List.filter_map (fun l ->
      if not (starts_with l "/\\ ") then None
      else
        let body = String.sub l 3 (String.length l - 3) in
        match Str_find.find body " = " with
        | k ->
          let var = String.trim (String.sub body 0 k) in
          Some (var, Tla.parse (String.sub body (k + 3) (String.length body - k - 3)))
        | exception Not_found -> failwith ("Dot.parse_state: no '=' in " ^ l)) joined)

(* The quoted string starting at s.[i] = '"'; returns its raw contents and the
   index after the closing quote. *)
let quoted s i =
  let n = String.length s in
  let rec go j = if j >= n then failwith "Dot: unterminated string"
    else if s.[j] = '\\' then go (j + 2)
    else if s.[j] = '"' then j
    else go (j + 1) in
  let j = go (i + 1) in
  (String.sub s (i + 1) (j - i - 1), j + 1)

let parse text =
  let nodes = ref [] and initial = ref [] and edges = ref [] in
  let n = String.length text in
  (* Statements end with ";\n"; labels may contain ';' only inside quotes, so
     scan statement by statement, skipping quoted strings. *)
  let rec next_stmt i =
    if i >= n then ()
    else
      let rec find_end j =
        if j >= n then n
        else if text.[j] = '"' then find_end (snd (quoted text j))
        else if text.[j] = ';' || text.[j] = '\n' then j
        else find_end (j + 1) in
      let j = find_end i in
      let stmt = String.trim (String.sub text i (j - i)) in
      handle stmt;
      next_stmt (j + 1)
  and handle stmt =
    let id_end s = try String.index s ' ' with Not_found -> String.length s in
    if stmt = "" || not (match stmt.[0] with '-' | '0'..'9' -> true | _ -> false) then ()
    else
      let k = id_end stmt in
      let id = String.sub stmt 0 k in
      let rest = String.trim (String.sub stmt k (String.length stmt - k)) in
      let label_of r =
        match Str_find.find r "label=\"" with
        | p -> Some (unescape (fst (quoted r (p + 6))))
        | exception Not_found -> None in
      if starts_with rest "->" then begin
        let r = String.trim (String.sub rest 2 (String.length rest - 2)) in
        let k = id_end r in
        let dst = String.sub r 0 k in
        match label_of r with
        | Some l -> edges := (id, l, dst) :: !edges
        | None -> ()
      end else
        match label_of rest with
        | Some l when starts_with (String.trim l) "/\\" ->
          nodes := (id, parse_state l) :: !nodes;
          (match Str_find.find rest "style = filled" with
           | _ -> initial := id :: !initial
           | exception Not_found -> ())
        | _ -> () in
  next_stmt 0;
  { nodes = List.rev !nodes; initial = List.rev !initial; edges = List.rev !edges }
