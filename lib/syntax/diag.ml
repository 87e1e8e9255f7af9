type kind = Syntax | Type | Runtime | Crash
type severity = Error | Warning
type t = { kind : kind; severity : severity; at : Source.region; message : string }

exception Failed of t

let make ?(severity = Error) kind at message = { kind; severity; at; message }
let error kind at message = raise (Failed (make kind at message))
let errorf kind at fmt = Printf.ksprintf (error kind at) fmt

let one_line s =
  String.map (function '\n' | '\r' -> ' ' | c -> c) s |> String.trim

let to_string d =
  let sev = match d.severity with Error -> "error" | Warning -> "warning" in
  let msg = match d.kind with
    | Crash -> "internal error: " ^ d.message
    | Syntax | Type | Runtime -> d.message in
  Printf.sprintf "%s: %s: %s" (Source.string_of_region d.at) sev (one_line msg)

let compare a b =
  let p = a.at.Source.left and q = b.at.Source.left in
  Stdlib.compare (p.file, p.line, p.column, a.message) (q.file, q.line, q.column, b.message)
