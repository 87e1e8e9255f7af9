(* The bench's speed goals (bench/README.md: 1 steady, 2 floods, 3 end to
   end, 4 explorer, 5 simulation; and the earlier goals still printed), each
   with the figure this run measured: every part records its own as it
   prints it, and `bench.exe all` ends with the table, so that one run
   shows every figure beside its goal. A part that did not run leaves its
   rows out. *)

type row = { goal : string; figure : string; met : bool option }

let rows : row list ref = ref []

let record ?met goal figure = rows := { goal; figure; met } :: !rows

let print () =
  match List.rev !rows with
  | [] -> ()
  | rs ->
    print_string "goals of this run, each with what this run measured:\n";
    List.iter (fun r ->
        let verdict = match r.met with Some true -> "met" | Some false -> "NOT MET" | None -> "" in
        Printf.printf "  %-58s %-7s %s\n" r.goal verdict r.figure) rs;
    let n = List.length (List.filter (fun r -> r.met = Some true) rs)
    and m = List.length (List.filter (fun r -> r.met = Some false) rs) in
    Printf.printf "  %d met, %d not met\n%!" n m
