(* jadescript-ref compile FILE... --target jade --out DIR *)

open Syntax
open Cmdliner

let compile files target out =
  match
    ignore (target : [ `Jade ]);
    (* parse and check exactly as check and run do; diagnostics printed alike *)
    let env = Cmd_run.load files in
    match Backend.Jade.generate env ~files with
    | Error (at, msg) ->
      prerr_endline (Diag.to_string (Diag.make Diag.Type at ("the JADE back end does not support this: " ^ msg)));
      1
    | Ok units ->
      (match Backend.Jade.write ~out units with
       | () -> 0
       | exception Sys_error m ->
         prerr_endline ("jadescript-ref: error: cannot write the Java sources into " ^ out ^ ": " ^ m); 1)
  with
  | code -> code
  | exception Cmd_run.Stop code -> code
  | exception Diag.Failed d -> prerr_endline (Diag.to_string d); 1
  | exception Stack_overflow ->
    let p = { Source.file = List.hd files; line = 1; column = 1 } in
    prerr_endline (Diag.to_string (Diag.make Diag.Crash { Source.left = p; right = p }
                                    "the input is nested too deeply to process")); 1
  | exception e ->
    let p = { Source.file = List.hd files; line = 1; column = 1 } in
    prerr_endline (Diag.to_string (Diag.make Diag.Crash { Source.left = p; right = p } (Printexc.to_string e))); 1

let cmd =
  let files = Arg.(non_empty & pos_all string [] & info [] ~docv:"FILE" ~doc:"The program's files.") in
  let target = Arg.(value & opt (enum [ ("jade", `Jade) ]) `Jade & info ["target"] ~docv:"TARGET"
                      ~doc:"The platform to compile for: $(b,jade) (Java 17 on JADE 4.3).") in
  let out = Arg.(required & opt (some string) None & info ["out"] ~docv:"DIR"
                   ~doc:"Write the Java sources into $(i,DIR)/jsgen/ (package jsgen).") in
  Cmd.v (Cmd.info "compile" ~doc:"Compile a Jadescript program to Java for JADE."
           ~man:[`S Manpage.s_description;
                 `P "Parses and type-checks the program as $(b,check) does, then writes one Java \
                     class per schema, agent type and behaviour type, and $(i,Program.java), into \
                     $(i,DIR)/jsgen/. They compile against the runtime of runtime/jade \
                     (runtime/jade/CONTRACT.md) with $(b,javac -Xlint:all -Werror) and run with the \
                     reference interpreter's semantics. A syntax or type error, or a construct the \
                     back end does not support, is reported as $(i,FILE:LINE:COL: error: message) \
                     and the exit status is 1."])
    Term.(const compile $ files $ target $ out)
