(* Well-formed UTF-8 (RFC 3629, table 3-7 of the Unicode standard). *)

let first_invalid s =
  let n = String.length s in
  let byte i = if i < n then Char.code s.[i] else -1 in
  let cont i = let b = byte i in b >= 0x80 && b <= 0xBF in
  let rec go i =
    if i >= n then None
    else
      let b = byte i in
      let len =
        if b < 0x80 then 1
        else if b >= 0xC2 && b <= 0xDF then (if cont (i + 1) then 2 else 0)
        else if b >= 0xE0 && b <= 0xEF then
          let b1 = byte (i + 1) in
          let lo = if b = 0xE0 then 0xA0 else 0x80 and hi = if b = 0xED then 0x9F else 0xBF in
          if b1 >= lo && b1 <= hi && cont (i + 2) then 3 else 0
        else if b >= 0xF0 && b <= 0xF4 then
          let b1 = byte (i + 1) in
          let lo = if b = 0xF0 then 0x90 else 0x80 and hi = if b = 0xF4 then 0x8F else 0xBF in
          if b1 >= lo && b1 <= hi && cont (i + 2) && cont (i + 3) then 4 else 0
        else 0 in
      if len = 0 then Some i else go (i + len) in
  go 0

let repair s =
  match first_invalid s with
  | None -> s
  | Some _ ->
    let b = Buffer.create (String.length s + 8) in
    let rec go from =
      let rest = String.sub s from (String.length s - from) in
      match first_invalid rest with
      | None -> Buffer.add_string b rest
      | Some k ->
        Buffer.add_string b (String.sub rest 0 k);
        Buffer.add_string b "\xef\xbf\xbd";
        go (from + k + 1) in
    go 0;
    Buffer.contents b
