(* make bench: measurements printed side by side from one run.

   parser: throughput of lib/syntax on a generated 10,000-line program, and where
   the time goes (lexing + layout alone, the full parse, printing). *)

open Syntax

let time_best ~runs f =
  let best = ref infinity and result = ref None in
  for _ = 1 to runs do
    Gc.compact ();
    let t0 = Unix.gettimeofday () in
    let r = f () in
    let dt = Unix.gettimeofday () -. t0 in
    if dt < !best then best := dt;
    result := Some r
  done;
  (!best, Option.get !result)

(* A program of about [n] lines: agents, behaviours with percept handlers, and
   an ontology, each with distinct names, in the paper's style. *)
let generate n =
  let b = Buffer.create (n * 40) in
  Buffer.add_string b "module bench.generated\n\nontology Percepts\n";
  for i = 0 to 9 do
    Printf.bprintf b "\tpredicate reading%d(x as double, y as double) extends percept\n\t\twith priority = %d\n" i i
  done;
  let lines () = List.length (String.split_on_char '\n' (Buffer.contents b)) in
  let i = ref 0 in
  while lines () < n do
    let k = !i in
    Printf.bprintf b "\nagent Robot%d uses ontology Percepts\n" k;
    Printf.bprintf b "\tproperty worldMap = {}\n\tproperty count as integer = 0\n\n";
    Printf.bprintf b "\ton create with interface as any do\n\t\tinvoke \"startListening\" on interface\n";
    Printf.bprintf b "\t\tactivate behaviour Handle%d with limit = %d, name = \"h%d\"\n\n" k (k * 7) k;
    Printf.bprintf b "\tfunction score(a as double, b as double) as double do\n";
    Printf.bprintf b "\t\tif a > b and not (a = 0.0) do\n\t\t\treturn a * 2.5 + b / 3.0 - %d\n" k;
    Printf.bprintf b "\t\telse if a < 0.0 do\n\t\t\treturn -a\n\t\telse do\n\t\t\treturn b\n\n";
    Printf.bprintf b "cyclic behaviour Handle%d for agent Robot%d\n\tproperty limit as integer = 0\n" k k;
    Printf.bprintf b "\ton create with limit as integer, name as text do\n\t\tlog name + \" starts\"\n\n";
    Printf.bprintf b "\ton percept when content matches reading%d(x, y) and x > 0.5 do\n" (k mod 10);
    Printf.bprintf b "\t\tworldMap[position(x, y)] = \"seen %d\"\n\t\tcount = count + 1\n" k;
    Printf.bprintf b "\t\tfor v in values of worldMap do\n\t\t\tlog v\n";
    Printf.bprintf b "\t\twhile count > limit do\n\t\t\tcount = count - 1\n";
    Printf.bprintf b "\n\ton inform when content matches reading%d(_, -1) do\n\t\tsend agree content to sender of message\n" (k mod 10);
    incr i
  done;
  Buffer.contents b

let lex_only text =
  let lexbuf = Lexing.from_string text in
  let layout = Layout.create (Lexer.create ()) lexbuf in
  let rec go n = match Layout.next layout with
    | (Parser.EOF, _, _) -> n
    | _ -> go (n + 1) in
  go 0

let parser_bench () =
  let text = generate 10_000 in
  let nlines = List.length (String.split_on_char '\n' text) in
  let runs = 7 in
  let (t_lex, ntok) = time_best ~runs (fun () -> lex_only text) in
  let (t_parse, r) = time_best ~runs (fun () -> Parse.string ~file:"gen.jade" text) in
  let (t_print, out) = time_best ~runs (fun () -> Print.program ~comments:r.comments r.program) in
  let rate t = float_of_int nlines /. t in
  Printf.printf "parser: generated program of %d lines, %d tokens, %d bytes (best of %d runs)\n"
    nlines ntok (String.length text) runs;
  Printf.printf "  %-30s %9.2f ms  %12.0f lines/s\n" "lex + layout" (t_lex *. 1e3) (rate t_lex);
  Printf.printf "  %-30s %9.2f ms  %12.0f lines/s\n" "parse (lex + layout + LR)" (t_parse *. 1e3) (rate t_parse);
  Printf.printf "  %-30s %9.2f ms  %12.0f lines/s\n" "print (fmt)" (t_print *. 1e3) (rate t_print);
  Printf.printf "  where the parse time goes: lexing and layout %.0f%%, LR automaton and tree %.0f%%\n"
    (100. *. t_lex /. t_parse) (100. *. (t_parse -. t_lex) /. t_parse);
  Printf.printf "  ratio parse/print time: %.2f; output %d bytes\n" (t_parse /. t_print) (String.length out)

let () =
  let what = if Array.length Sys.argv > 1 then Sys.argv.(1) else "all" in
  match what with
  | "parser" | "all" -> parser_bench ()
  | other -> Printf.eprintf "bench: unknown benchmark %s (known: parser, all)\n" other; exit 2
