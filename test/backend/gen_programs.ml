(* gen_programs SEED N DIR: N random well-typed programs of the test
   generator (test/support/typed_gen.ml) with random host events, for the
   JADE back end: DIR/genK/program.jade, DIR/genK/events.jsonl and
   DIR/genK/args (the run arguments: the agent with its creation arguments).
   scripts/jade-compile-check compiles them with javac; running them on the
   interpreter and on JADE and comparing the traces is a differential test of
   the back end. *)

open Syntax

let percept_types = Test_support.Event_gen.percept_types

let literal_of = Test_support.Event_gen.small_literal

let () =
  let seed = int_of_string Sys.argv.(1) and n = int_of_string Sys.argv.(2) and dir = Sys.argv.(3) in
  let rand = Random.State.make [| seed |] in
  let mkdir d = if not (Sys.file_exists d) then Sys.mkdir d 0o755 in
  mkdir dir;
  let write p s = let oc = open_out_bin p in output_string oc s; close_out oc in
  for k = 1 to n do
    let prog = QCheck.Gen.generate1 ~rand Test_support.Typed_gen.program in
    let text = Print.program prog in
    let env, diags = Typing.check [ Parse.string ~file:"program.jade" text ] in
    if not (Typing.has_errors diags) then begin
      let d = Filename.concat dir (Printf.sprintf "gen%03d" k) in
      mkdir d;
      write (Filename.concat d "program.jade") text;
      let ps = percept_types env in
      let events = List.init (1 + Random.State.int rand 6) (fun _ ->
          if ps = [] || Random.State.int rand 4 = 0 then "{\"run\": 1}"
          else
            let s = List.nth ps (Random.State.int rand (List.length ps)) in
            let args = List.map (fun (_, ty) -> literal_of rand ty) s.s_slots in
            let p = if args = [] then s.s_name else s.s_name ^ "(" ^ String.concat ", " args ^ ")" in
            let prio = if Random.State.int rand 3 = 0 then Printf.sprintf ", \"priority\": %d" (Random.State.int rand 9) else "" in
            Printf.sprintf "{\"agent\": \"g\", \"notify\": %s%s}" (Yojson.Safe.to_string (`String p)) prio) in
      write (Filename.concat d "events.jsonl") (String.concat "\n" events ^ "\n");
      let params = match Typing.Tenv.agent_create env "Ag" with Some r -> r.r_params | None -> [] in
      let args = List.map (fun (_, ty) -> literal_of rand ty) params in
      write (Filename.concat d "args") ("g:Ag" ^ (if args = [] then "" else ":" ^ String.concat "," args) ^ "\n")
    end
  done
