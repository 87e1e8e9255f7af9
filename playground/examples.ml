type t = {
  id : string;
  title : string;
  about : string;
  files : (string * string) list;
  agents : string list;
  o2a_capacity : int option;
  fuel : int option;
  seed : int option;
  variant : string option;
  max_steps : int option;
  events : string list;
}

let file path = try List.assoc path Examples_data.files with Not_found -> ""

let event_lines text =
  List.filter (fun l -> let l = String.trim l in l <> "" && l.[0] <> '#')
    (String.split_on_char '\n' text)

let of_vector (name, fs) =
  let json = try Yojson.Safe.from_string (List.assoc "vector.json" fs) with _ -> `Null in
  let field k = match json with `Assoc f -> List.assoc_opt k f | _ -> None in
  let args = match field "args" with
    | Some (`List l) -> List.filter_map (function `String s -> Some s | _ -> None) l
    | _ -> [] in
  let rec go acc = function
    | "--agent" :: a :: rest -> go { acc with agents = acc.agents @ [ a ] } rest
    | "--o2a-capacity" :: n :: rest -> go { acc with o2a_capacity = int_of_string_opt n } rest
    | "--fuel" :: n :: rest -> go { acc with fuel = int_of_string_opt n } rest
    | "--seed" :: n :: rest -> go { acc with seed = int_of_string_opt n } rest
    | "--variant" :: v :: rest -> go { acc with variant = Some v } rest
    | "--max-steps" :: n :: rest -> go { acc with max_steps = int_of_string_opt n } rest
    | _ :: rest -> go acc rest
    | [] -> acc in
  let rulings = match field "rulings" with
    | Some (`List l) -> List.filter_map (function `String s -> Some s | _ -> None) l
    | _ -> [] in
  go { id = name;
       title = Printf.sprintf "%s (%s)" name (String.concat ", " rulings);
       about = (match field "about" with Some (`String s) -> s | _ -> "");
       files = List.filter (fun (f, _) -> Filename.check_suffix f ".jade") fs;
       agents = []; o2a_capacity = None; fuel = None; seed = None; variant = None; max_steps = None;
       events = event_lines (try List.assoc "events.jsonl" fs with Not_found -> "") } args

let robome = {
  id = "robome"; title = "RoboMe (the paper's agent, Figures 5-7 completed)";
  about = "The paper's RoboMe agent: four percept types with priorities (falling 10, obstacle 8, \
           qrCodeRead 4, position 2) and one cyclic behaviour whose handlers drive the robot. \
           The events are the tutorial's short drive: the robot is at (0, 1) when it reads the QR \
           code A7, then the host sends position(0, 2) with its own priority 9 (R2a). Do them all, \
           run to idle, and compare worldMap with currentPosition: A7 is filed under \
           position(0.0, 2.0) while the robot ends at position(0.0, 1.0). Priorities reorder what \
           the map believes: the override overtook the code, and position(0, 1) came last \
           (exercise 7 asks you to fix it).";
  files = [ "robome.jade", file "examples/robome/robome.jade" ];
  agents = [ "r:RoboMe:@robome" ]; o2a_capacity = None; fuel = None; seed = None; variant = None; max_steps = None;
  events = [ {|{"agent": "r", "notify": "position(0, 1)"}|};
             {|{"agent": "r", "notify": "qrCodeRead(\"A7\")"}|};
             {|{"agent": "r", "notify": "obstacle"}|};
             {|{"agent": "r", "notify": "position(0, 2)", "priority": 9}|} ];
}

let vectors = List.map of_vector Examples_data.vectors

let shapes =
  let v = List.find_opt (fun (x : t) -> x.id = "062-paper-shapes-two-agents") vectors in
  { id = "shapes"; title = "Shapes (Figures 1-3, corrected, with a provider)";
    about = "The paper's Shapes example: ShapeRequester's on create activates HandleShapeCreated \
             and the one-shot RequestNewShape, which sends a request to a ShapeProvider agent; \
             the provider answers with the shape it made. Two agents, messages, no percepts.";
    files = (match v with
        | Some v -> List.sort (fun (a, _) (b, _) -> compare (a = "provider.jade") (b = "provider.jade")) v.files
        | None -> [ "shapes_corrected.jade", file "examples/typing/shapes_corrected.jade" ]);
    agents = (match v with Some v -> v.agents | None -> []);
    o2a_capacity = None; fuel = None; seed = None; variant = None; max_steps = None; events = [] }

let all = robome :: shapes :: vectors

let find id = List.find_opt (fun x -> x.id = id) all

let to_json x =
  let opt = function Some n -> `Int n | None -> `Null in
  `Assoc [ "id", `String x.id; "title", `String x.title; "about", `String x.about;
           "files", `List (List.map (fun (n, t) -> `Assoc [ "name", `String n; "text", `String t ]) x.files);
           "agents", `List (List.map (fun a -> `String a) x.agents);
           "o2a_capacity", opt x.o2a_capacity; "fuel", opt x.fuel; "seed", opt x.seed;
           "variant", (match x.variant with Some v -> `String v | None -> `Null);
           "max_steps", opt x.max_steps;
           "events", `List (List.map (fun e -> `String e) x.events) ]
