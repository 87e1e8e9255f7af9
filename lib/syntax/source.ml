type pos = { file : string; line : int; column : int }
type region = { left : pos; right : pos }
type 'a phrase = { at : region; it : 'a }

let no_pos = { file = ""; line = 0; column = 0 }
let no_region = { left = no_pos; right = no_pos }
let ( @@ ) it at = { it; at }

let of_lexing (p : Lexing.position) =
  { file = p.pos_fname; line = p.pos_lnum; column = p.pos_cnum - p.pos_bol + 1 }

let region_of_lexing l r = { left = of_lexing l; right = of_lexing r }
let span a b = { left = a.left; right = b.right }

let string_of_pos p =
  if p.line = 0 then p.file ^ ":0:0"
  else Printf.sprintf "%s:%d:%d" p.file p.line p.column

let string_of_region r = string_of_pos r.left
