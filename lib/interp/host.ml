module V = Value

let objects () =
  let calls = [ "startListening"; "callStop"; "callMoveForward"; "callMoveBackward";
                "callTurnLeft"; "callTurnRight"; "callHeadTiltUp"; "callHeadTiltDown"; "callHeadReset" ] in
  [ "@robome", V.Native { nid = 1; cls = "RoboMe"; methods = List.map (fun m -> (m, fun _ -> V.Unit)) calls } ]

let split_args s =
  let parts = ref [] and b = Buffer.create 16 and depth = ref 0 and quoted = ref false in
  String.iteri (fun i c ->
      if !quoted then begin
        Buffer.add_char b c;
        if c = '"' && (i = 0 || s.[i - 1] <> '\\') then quoted := false
      end else match c with
        | '"' -> quoted := true; Buffer.add_char b c
        | '(' | '[' | '{' -> incr depth; Buffer.add_char b c
        | ')' | ']' | '}' -> decr depth; Buffer.add_char b c
        | ',' when !depth = 0 -> parts := Buffer.contents b :: !parts; Buffer.clear b
        | c -> Buffer.add_char b c) s;
  if Buffer.length b > 0 || !parts <> [] then parts := Buffer.contents b :: !parts;
  List.rev_map String.trim !parts
