(* jadescript-ref: the command line.

   Every subcommand reports errors as one line FILE:LINE:COL: error: message on
   stderr and exits with 1; it never prints a backtrace. An error in one file
   does not stop the others from being processed. *)

open Syntax
open Cmdliner

(* Run [f], turning every exception into a located diagnostic: a Diag.Failed is
   the user's error; anything else is a crash of ours, still one line. *)
let guard ~file f =
  let at = let p = { Source.file; line = 1; column = 1 } in { Source.left = p; right = p } in
  match f () with
  | v -> Ok v
  | exception Diag.Failed d -> Error d
  | exception (Out.Failed _ as e) -> raise e   (* the output, not this file *)
  | exception Stack_overflow ->
    Error (Diag.make Diag.Syntax at "the input is nested too deeply to process")
  | exception Out_of_memory -> Error (Diag.make Diag.Crash at "out of memory")
  | exception e -> Error (Diag.make Diag.Crash at (Printexc.to_string e))

let report d = prerr_endline (Diag.to_string d)

(* Apply [f] to every file; exit status 1 if any failed. *)
let each_file files f =
  Out.protect @@ fun () ->
  let failed = ref false in
  List.iter (fun file ->
      match guard ~file (fun () -> f file) with
      | Ok () -> ()
      | Error d -> report d; failed := true) files;
  if !failed then 1 else 0

let files_arg =
  Arg.(non_empty & pos_all string [] & info [] ~docv:"FILE" ~doc:"Jadescript source files.")

(* ---------------------------------------------------------------- parse *)

let parse_cmd =
  let ast = Arg.(value & flag & info ["ast"] ~doc:"Print the abstract syntax tree of each file.") in
  let run ast files =
    each_file files (fun file ->
        let r = Parse.file file in
        if ast then Out.print (Ast_util.dump r.program)) in
  Cmd.v (Cmd.info "parse" ~doc:"Parse Jadescript files and report syntax errors."
           ~man:[`S Manpage.s_description;
                 `P "Exits with 0 when every file parses. Each syntax error is reported \
                     as $(i,FILE:LINE:COL: error: message); one error per file, and \
                     every file is tried."])
    Term.(const run $ ast $ files_arg)

(* ------------------------------------------------------------------ fmt *)

let first_difference a b =
  let la = String.split_on_char '\n' a and lb = String.split_on_char '\n' b in
  let rec go n = function
    | x :: xs, y :: ys -> if x = y then go (n + 1) (xs, ys) else n
    | _ -> n in
  go 1 (la, lb)

let fmt_cmd =
  let check = Arg.(value & flag & info ["check"]
                     ~doc:"Print nothing; exit with 1 if some file is not in canonical layout.") in
  let in_place = Arg.(value & flag & info ["i"; "in-place"] ~doc:"Rewrite the files in place.") in
  let run check in_place files =
    each_file files (fun file ->
        (* read once: FILE may be a pipe *)
        let original = match Parse.read_all file with
          | Ok text -> text
          | Error msg ->
            let p = { Source.file; line = 1; column = 1 } in
            Diag.errorf Diag.Syntax { Source.left = p; right = p } "cannot read this file: %s" msg in
        let r = Parse.string ~file original in
        let out = Print.program ~comments:r.comments r.program in
        if check then begin
          if out <> original then
            Diag.errorf Diag.Syntax
              (let p = { Source.file; line = first_difference original out; column = 1 } in
               { Source.left = p; right = p })
              "not in canonical layout (run jadescript-ref fmt -i %s)" file
        end else if in_place then begin
          if out <> original then
            match Out.replace file out with
            | Ok () -> ()
            | Error m ->
              let p = { Source.file; line = 1; column = 1 } in
              Diag.errorf Diag.Syntax { Source.left = p; right = p }
                "cannot write this file (it is left as it was): %s" m
        end else Out.print out) in
  Cmd.v (Cmd.info "fmt" ~doc:"Print Jadescript files in canonical layout."
           ~man:[`S Manpage.s_description;
                 `P "Prints each file in the canonical layout of docs/syntax.md: tabs, \
                     one item per line, canonical keyword spellings, minimal \
                     parentheses. Comments are kept. Formatting is idempotent and \
                     does not change the syntax tree."])
    Term.(const run $ check $ in_place $ files_arg)

(* ----------------------------------------------------------------- main *)

let main =
  let doc = "formal reference implementation of Jadescript percept handling" in
  let man = [
    `S Manpage.s_description;
    `P "jadescript-ref parses, formats, checks and runs Jadescript programs with \
        percepts (Iotti, Petrosino, Monica, Bergenti, AREA 2020) on a small-step \
        semantics that is model-checked against a TLA+ specification.";
    `S "EXIT STATUS";
    `P "0 on success; 1 when an input has an error (reported as \
        $(i,FILE:LINE:COL: error: message) on standard error) and on a command-line \
        error (an unknown option, a bad option value: one line \
        $(i,jadescript-ref: error: message)).";
  ] in
  Cmd.group (Cmd.info "jadescript-ref" ~version:"0.1.0" ~doc ~man) [parse_cmd; fmt_cmd; Cmd_check.cmd; Cmd_run.cmd; Cmd_compile.cmd; Cmd_validate.cmd; Cmd_judge.cmd; Cmd_conform.cmd; Cmd_defects.cmd; Corridor_sim.Cli.cmd; Cmd_explore.cmd]

(* An exception no command caught is still one line: a failed write (the
   standard output full or closed) is the user's environment, exit 1; anything
   else is a crash of ours, exit 125 as cmdliner would say. *)
(* A command-line error (an unknown option, a value cmdliner cannot
   convert) is one line and exit status 1, as every other bad input: not
   cmdliner's usage text and its status 124, which conform would read as a
   timeout (timeout(1) exits with 124). *)
let eval () =
  let err = Buffer.create 256 in
  let err_fmt = Format.formatter_of_buffer err in
  Format.pp_set_margin err_fmt 100_000;
  let r = Cmd.eval_value ~catch:false ~err:err_fmt main in
  Format.pp_print_flush err_fmt ();
  match r with
  | Ok (`Ok code) -> code
  | Ok (`Version | `Help) -> 0
  | Error (`Parse | `Term) ->
    let first = match String.split_on_char '\n' (Buffer.contents err) with l :: _ -> String.trim l | [] -> "" in
    (* "jadescript-ref run: option '--x': ..." -> "option '--x': ..." *)
    let rest = match String.index_opt first ':' with
      | Some i when String.length first >= 14 && String.sub first 0 14 = "jadescript-ref" ->
        String.trim (String.sub first (i + 1) (String.length first - i - 1))
      | _ -> first in
    Out.error (if rest = "" then "bad command line (jadescript-ref --help)" else rest ^ " (jadescript-ref --help)");
    1
  | Error `Exn -> 125

(* The stack. A program's width costs stack as well as its depth: the
   evaluator, the checker and the printer walk a list of a million items
   (a list literal, the statements of a block, the behaviours of a
   program, within the 64 MB of a source file) with [List.map] and
   recursion as deep as the list is long, and the system's usual 8 MB
   overflow near 200,000. So the soft limit is raised to 4 GiB (address
   space only: a page is used when it is reached), or to the hard limit if
   lower, and the command starts again, once (the variable
   JSREF_STACK_RAISED says it has), since the room the kernel leaves for
   the stack to grow into is set at exec from the limit then in force.
   Descriptors and arguments are kept: standard input and an events file
   given as a pipe are read by the second start only. The nesting a
   program may have is bounded apart (D27). Test: "stack" in
   test/hostile/test_hostile.ml. *)
external raise_stack : int -> bool = "jsref_raise_stack"

let stack_bytes = 4 * 1024 * 1024 * 1024

let () =
  if Sys.getenv_opt "JSREF_STACK_RAISED" = None && raise_stack stack_bytes then begin
    Unix.putenv "JSREF_STACK_RAISED" "1";
    (* if the program cannot start again, it goes on with the stack it has *)
    try Unix.execv Sys.executable_name Sys.argv with Unix.Unix_error _ -> ()
  end

let () =
  let code = match eval () with
    | code -> code
    | exception Out.Failed m -> Out.error m; Out.give_up_stdout (); 1
    | exception Sys_error m ->
      (match flush stdout with
       | () -> Out.error m
       | exception Sys_error _ ->
         Out.error ("cannot write the standard output: " ^ m); Out.give_up_stdout ());
      1
    | exception Stack_overflow -> Out.error "internal error: stack overflow"; 125
    | exception Out_of_memory -> Out.error "internal error: out of memory"; 125
    | exception e -> Out.error ("internal error: " ^ Printexc.to_string e); 125 in
  exit (Out.finish code)
