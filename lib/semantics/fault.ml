exception Crash of string

let crash fmt = Printf.ksprintf (fun s -> raise (Crash s)) fmt
