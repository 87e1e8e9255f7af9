module Types = Types
module Tenv = Tenv

(* Where to report a failure that has no place of its own: line 1 of the
   first file (a diagnostic is always located). *)
let first_file (files : Syntax.Parse.result list) =
  let file = match files with
    | { Syntax.Parse.program = { decls = d :: _; _ }; _ } :: _ -> d.at.left.file
    | _ -> "" in
  let p = { Syntax.Source.file; line = 1; column = 1 } in
  { Syntax.Source.left = p; right = p }

let check files =
  (* The parser bounds nesting (D27), so the checker cannot overflow the stack
     on a parsed program; a tree built otherwise still gets one located line. *)
  try Check.program files with
  | Stack_overflow ->
    (Tenv.create (),
     [Syntax.Diag.make Syntax.Diag.Type (first_file files)
        "the program is nested too deeply to check"])
  | e ->
    (Tenv.create (),
     [Syntax.Diag.make Syntax.Diag.Crash (first_file files) (Printexc.to_string e)])

let has_errors ds = List.exists (fun d -> d.Syntax.Diag.severity = Syntax.Diag.Error) ds
let performatives = Check.performative_names
