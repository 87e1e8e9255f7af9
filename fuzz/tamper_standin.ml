(* STAND-IN, DELETE AT MERGE. The tampering of traces belongs to
   test/support/tamper.ml (another branch of issue 15), with exactly this
   interface; this file is a minimal copy so that the fuzz campaign's
   validate target builds on its own branch. At merge: delete this file
   and change the line [module Tamper = Tamper_standin] of fuzz/inputs.ml
   to [module Tamper = Test_support.Tamper]. The JSON here is edited through Yojson,
   not with string literals of the format. *)

type t = { name : string;
           apply : Random.State.t -> string list -> string list option }

let json l = Yojson.Safe.from_string l
let str j = Yojson.Safe.to_string j

let map_field f k = function
  | `Assoc fs -> `Assoc (List.map (fun (k', v) -> if k' = k then (k', f v) else (k', v)) fs)
  | j -> j

let on_header f = function
  | h :: rest -> (match f (json h) with Some h -> Some (str h :: rest) | None -> None)
  | [] -> None

let on_some_line rs pred f = function
  | h :: rest ->
    let idx = List.filteri (fun _ l -> pred (json l)) rest |> List.length in
    if idx = 0 then None else
      let k = Random.State.int rs idx in
      let seen = ref (-1) in
      Some (h :: List.map (fun l -> let j = json l in
                            if pred j then begin incr seen; if !seen = k then str (f j) else l end
                            else l) rest)
  | [] -> None

let event_is e j = match j with `Assoc fs -> List.assoc_opt "event" fs = Some (`String e) | _ -> false

let all = [
  { name = "version 99"; apply = (fun _ -> on_header (fun h -> Some (map_field (fun _ -> `Int 99) "version" h))) };
  { name = "unknown variant"; apply = (fun _ -> on_header (fun h -> Some (map_field (fun _ -> `String "zigzag") "variant" h))) };
  { name = "no header"; apply = (fun _ -> function _ :: (_ :: _ as rest) -> Some rest | _ -> None) };
  { name = "unknown event"; apply = (fun rs ls -> on_some_line rs (fun _ -> true) (map_field (fun _ -> `String "teleport") "event") ls) };
  { name = "dequeue of another priority"; apply = (fun rs ls ->
        on_some_line rs (event_is "dequeue") (map_field (function `Int p -> `Int (p + 1) | j -> j) "priority") ls) };
  { name = "dropped dequeue"; apply = (fun rs -> function
        | h :: rest when List.exists (fun l -> event_is "dequeue" (json l)) rest ->
          let n = List.length (List.filter (fun l -> event_is "dequeue" (json l)) rest) in
          let k = Random.State.int rs n and seen = ref (-1) in
          Some (h :: List.filter (fun l -> not (event_is "dequeue" (json l)) || (incr seen; !seen <> k)) rest)
        | _ -> None) };
]
