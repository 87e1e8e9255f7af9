module Types = Types
module Tenv = Tenv

let check files =
  try Check.program files with
  | Stack_overflow ->
    (Tenv.create (),
     [Syntax.Diag.make Syntax.Diag.Type Syntax.Source.no_region
        "the program is nested too deeply to check"])
  | e ->
    (Tenv.create (),
     [Syntax.Diag.make Syntax.Diag.Crash Syntax.Source.no_region (Printexc.to_string e)])

let has_errors ds = List.exists (fun d -> d.Syntax.Diag.severity = Syntax.Diag.Error) ds
let performatives = Check.performative_names
