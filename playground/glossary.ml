type entry = { term : string; kind : string; text : string; doc : string }

let ghost_names = [ "dispatched"; "done"; "waits" ]

let ghosts =
  let line v = match List.assoc_opt v Glossary_data.variables with
    | Some t -> Printf.sprintf "%s: %s" v t
    | None -> v in
  { term = "ghosts"; kind = "the spec's ghost variables";
    text = "counters the spec keeps only to state its properties; the loop never reads them. "
           ^ String.concat "; " (List.map line ghost_names);
    doc = "spec.md#variables" }

let all =
  List.map (fun (term, text, doc) -> { term; kind = "rulings"; text; doc }) Glossary_data.groups
  @ List.map (fun (term, text, doc) -> { term; kind = "ruling"; text; doc }) Glossary_data.rulings
  @ List.map (fun (term, text, doc) -> { term; kind = "decision"; text; doc }) Glossary_data.decisions
  @ List.map (fun (term, kind, text) ->
      { term; kind = "property (" ^ kind ^ ")"; text; doc = "spec.md#properties" }) Glossary_data.properties
  @ [ ghosts;
      { term = "lasso"; kind = "TLC";
        text = "the counterexample TLC prints for a liveness property: a run that ends in a loop of states repeated forever";
        doc = "spec.md#the-counterexamples-that-matter" } ]
  @ List.map (fun (r : Replays.t) ->
      { term = r.id; kind = "TLC model"; text = r.title; doc = "spec.md#the-counterexamples-that-matter" }) Replays.all

let to_json () =
  `List (List.map (fun e ->
      `Assoc [ "term", `String e.term; "kind", `String e.kind; "text", `String e.text; "doc", `String e.doc ]) all)
