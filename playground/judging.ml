(* The judge (lib/judge) for the page: the trace written to a file of
   js_of_ocaml's file system (or a temporary file natively), then judged. *)

let options t =
  { Judge.default_options with fuel = (Session.setup t).fuel }

let judge_file ~path t =
  Judge.judge (Session.env t) ~agents:(Session.agent_specs t) ~options:(options t) path

let write path text =
  let oc = open_out_bin path in
  Fun.protect ~finally:(fun () -> close_out_noerr oc) (fun () -> output_string oc text)

let text ~path t s =
  write path s;
  judge_file ~path t

let session ~path t =
  text ~path t (String.concat "" (List.map (fun l -> l ^ "\n") (Session.trace t)))

let to_json = function
  | Judge.Accepted { lines; complete; cut; level; containers = _ } ->
    `Assoc [ "accepted", `Bool true; "lines", `Int lines; "complete", `Bool complete;
             "cut", `Bool cut; "level", `String (Judge.string_of_level level) ]
  | Judge.Rejected { line; message } ->
    `Assoc [ "accepted", `Bool false; "line", `Int line; "message", `String message ]
