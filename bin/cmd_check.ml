(* jadescript-ref check FILE...: the type checker (docs/typing.md).

   The files are one program: the declarations of each are visible in all.
   A file that does not parse is reported and left out; the others are still
   checked. Every diagnostic is printed, sorted by position, one line each on
   stderr. Exit 1 if there is an error, 0 otherwise (warnings alone: 0). *)

open Syntax
open Cmdliner

let at_start file =
  let p = { Source.file; line = 1; column = 1 } in
  { Source.left = p; right = p }

let parse file =
  match Parse.file file with
  | r -> Ok r
  | exception Diag.Failed d -> Error d
  | exception Stack_overflow ->
    Error (Diag.make Diag.Syntax (at_start file) "the input is nested too deeply to process")
  | exception e -> Error (Diag.make Diag.Crash (at_start file) (Printexc.to_string e))

let run no_warnings files =
  let parsed = List.map parse files in
  let syntax = List.filter_map (function Error d -> Some d | Ok _ -> None) parsed in
  let ok = List.filter_map (function Ok r -> Some r | Error _ -> None) parsed in
  let _, diags = Typing.check ok in
  let all = List.sort Diag.compare (syntax @ diags) in
  let shown = if no_warnings then List.filter (fun d -> d.Diag.severity = Diag.Error) all
    else all in
  List.iter (fun d -> prerr_endline (Diag.to_string d)) shown;
  if List.exists (fun d -> d.Diag.severity = Diag.Error) all then 1 else 0

let cmd =
  let no_warnings = Arg.(value & flag & info ["no-warnings"] ~doc:"Do not print warnings.") in
  let files = Arg.(non_empty & pos_all string [] & info [] ~docv:"FILE"
                     ~doc:"Jadescript source files, checked together as one program.") in
  Cmd.v (Cmd.info "check" ~doc:"Type-check Jadescript files as one program."
           ~man:[`S Manpage.s_description;
                 `P "Parses every file, then checks them together as one program: the \
                     declarations of each file are visible in every other (the paper \
                     splits the Shapes example over three figures). Reports every type \
                     error as $(i,FILE:LINE:COL: error: message), sorted by position, and \
                     warnings (a property never read, a handler that can never run) as \
                     $(i,FILE:LINE:COL: warning: message). A file with a syntax error is \
                     reported and left out; the others are still checked. The rules are \
                     in docs/typing.md.";
                 `S "EXIT STATUS";
                 `P "0 when there is no error (warnings alone give 0); 1 when there is \
                     an error."])
    Term.(const run $ no_warnings $ files)
