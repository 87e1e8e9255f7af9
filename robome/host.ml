type mapping = { forward_level : int; backward_level : int; turn : Command.turn }

let default_mapping = { forward_level = 3; backward_level = 3; turn = Command.Degrees 90 }

type t = (string * (unit -> unit)) list

let method_names =
  [ "startListening"; "callStop"; "callMoveForward"; "callMoveBackward"; "callTurnLeft";
    "callTurnRight"; "callHeadTiltUp"; "callHeadTiltDown"; "callHeadReset" ]

let command_of m = function
  | "callStop" -> Some Command.Stop
  | "callMoveForward" -> Some (Command.Forward m.forward_level)
  | "callMoveBackward" -> Some (Command.Backward m.backward_level)
  | "callTurnLeft" -> Some (Command.Turn_left m.turn)
  | "callTurnRight" -> Some (Command.Turn_right m.turn)
  | "callHeadTiltUp" -> Some Command.Head_up
  | "callHeadTiltDown" -> Some Command.Head_down
  | "callHeadReset" -> Some Command.Head_reset
  | _ -> None

let make m ~enqueue ~start_listening =
  List.map (fun name ->
      match command_of m name with
      | Some c -> (name, fun () -> enqueue c)
      | None -> (name, start_listening)) method_names

let call h name =
  match List.assoc_opt name h with
  | Some f -> f (); Ok ()
  | None -> Error (Printf.sprintf "unknown native method %S" name)
