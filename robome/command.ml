type turn = Speed of int | Degrees of int

type t =
  | Stop
  | Forward of int
  | Backward of int
  | Turn_left of turn
  | Turn_right of turn
  | Head_up
  | Head_down
  | Head_reset

let level_ok s = s >= 1 && s <= 5
let turn_ok = function Speed s -> level_ok s | Degrees d -> d = 90 || d = 180 || d = 360

let valid = function
  | Stop | Head_up | Head_down | Head_reset -> true
  | Forward s | Backward s -> level_ok s
  | Turn_left t | Turn_right t -> turn_ok t

let is_motion = function Head_up | Head_down | Head_reset -> false | _ -> true

let turn_string = function
  | Speed s -> Printf.sprintf "speed %d" s
  | Degrees d -> Printf.sprintf "%ddeg" d

let to_string = function
  | Stop -> "stop"
  | Forward s -> Printf.sprintf "forward(%d)" s
  | Backward s -> Printf.sprintf "backward(%d)" s
  | Turn_left t -> Printf.sprintf "turn_left(%s)" (turn_string t)
  | Turn_right t -> Printf.sprintf "turn_right(%s)" (turn_string t)
  | Head_up -> "head_up"
  | Head_down -> "head_down"
  | Head_reset -> "head_reset"

let all_turns =
  List.init 5 (fun i -> Speed (i + 1)) @ [ Degrees 90; Degrees 180; Degrees 360 ]

let all =
  [ Stop; Head_up; Head_down; Head_reset ]
  @ List.concat_map (fun s -> [ Forward s; Backward s ]) [ 1; 2; 3; 4; 5 ]
  @ List.concat_map (fun t -> [ Turn_left t; Turn_right t ]) all_turns

let of_string s = List.find_opt (fun c -> to_string c = s) all
