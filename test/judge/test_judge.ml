(* The judge (lib/judge; docs/trace-format.md, "Judging a run"): the program
   explains every line of every conformance vector's expected trace, and of
   the same runs written at the observable level; it rejects, each at a
   located line, every tampered trace (test/support/tamper.ml), the trace of
   a defective implementation (lib/defects) where it differs in a way the
   program cannot explain, and a trace copied from another program. *)

open Test_support
open Support

module O = Interp.Oracle


(* ------------------------------------------------------------ vectors *)

type vec = {
  v : O.vector;
  env : Typing.Tenv.t;
  agents : (string * string * Interp.Value.t list) list;
  options : Judge.options;
  expected : string list;   (* the expected trace's lines, header first *)
}

(* The value of option [opt] in a vector's args. *)
let rec opt name = function
  | o :: v :: _ when o = name -> Some v
  | _ :: r -> opt name r
  | [] -> None

let rec all_opts name = function
  | o :: v :: r when o = name -> v :: all_opts name r
  | _ :: r -> all_opts name r
  | [] -> []

(* The program and the agents of a vector, as run takes them
   (bin/cmd_run.ml, agent_spec). *)
let load_vec (v : O.vector) =
  (* the files as run names them, from the vector's folder (errors name
     them so) *)
  let cwd = Sys.getcwd () in
  Sys.chdir v.dir;
  let parsed = Fun.protect ~finally:(fun () -> Sys.chdir cwd) (fun () -> List.map Syntax.Parse.file v.files) in
  let env, diags = Typing.check parsed in
  if List.exists (fun d -> d.Syntax.Diag.severity = Syntax.Diag.Error) diags then
    Alcotest.failf "%s: the program does not check" v.name;
  let agents = List.map (fun spec ->
      match String.split_on_char ':' spec with
      | name :: ty :: rest ->
        let args = String.concat ":" rest in
        (name, ty, List.map (fun a -> match List.assoc_opt a (Interp.Host.objects ()) with
             | Some x -> x
             | None -> Interp.Eval.literal_value env (Syntax.Parse.expr ~file:"--agent" a))
             (Interp.Host.split_args args))
      | _ -> Alcotest.failf "%s: --agent %s" v.name spec) (all_opts "--agent" v.args) in
  let fuel = match opt "--fuel" v.args with Some f -> int_of_string f | None -> Judge.default_options.fuel in
  { v; env; agents; options = { Judge.default_options with fuel };
    expected = lines_of (Filename.concat v.dir "expected.jsonl") }

let vecs = lazy (List.map load_vec (O.load (Filename.concat root "conformance")))

let judge (x : vec) lines = with_lines lines (fun f -> Judge.judge x.env ~agents:x.agents ~options:x.options f)

let show = function
  | Judge.Accepted { lines; _ } -> Printf.sprintf "accepted (%d lines)" lines
  | Judge.Rejected { line; message } -> Printf.sprintf "rejected at line %d: %s" line message

(* The first line (of the file: the header is 1) where two traces differ;
   [None] when equal. *)
let first_difference a b =
  let rec go i a b = match a, b with
    | [], [] -> None
    | x :: a', y :: b' -> if String.equal x y then go (i + 1) a' b' else Some i
    | _ -> Some i in
  go 1 a b

(* The judge must reject [tampered], a trace differing from the explained trace
   [good] first at line [d]: at a line of the file (or the one after its
   last), never before [d], since every line before it is explained. *)
exception Bad of string
let refuse fmt = Printf.ksprintf (fun m -> raise (Bad m)) fmt

let rejected_at what (x : vec) ~good tampered =
  let d = match first_difference good tampered with Some d -> d | None -> refuse "%s: not changed" what in
  match judge x tampered with
  | Judge.Accepted _ as a -> refuse "%s: %s" what (show a)
  | Judge.Rejected { line; message } ->
    if line < d || line > List.length tampered + 1 then
      refuse "%s: rejected at line %d, but the lines differ first at line %d (of %d): %s"
        what line d (List.length tampered) message;
    if message = "" then refuse "%s: rejected without a reason" what;
    line

let rejected_located what x ~good b =
  match rejected_at what x ~good b with
  | line -> line
  | exception Bad m -> Alcotest.fail m

(* ------------------------------------------------- (a) accepted *)

let expected_accepted () =
  let vs = Lazy.force vecs in
  Alcotest.(check bool) "there are vectors" true (List.length vs >= 80);
  List.iter (fun x ->
      match judge x x.expected with
      | Judge.Accepted { lines; complete = _; cut; level; containers = _ } ->
        Alcotest.(check int) (x.v.name ^ ": every line read") (List.length x.expected) lines;
        Alcotest.(check bool) (x.v.name ^ ": not cut") false cut;
        Alcotest.(check string) (x.v.name ^ ": level") "full" (Judge.string_of_level level)
      | r -> Alcotest.failf "%s: %s" x.v.name (show r)) vs

(* ------------------------------------------------- (b) tampered *)

(* Each kind of tampering on the first few traces it applies to (taken in
   turn from a different starting vector for each kind, with its own seed),
   so that every kind is tried on several traces in seconds; every trace
   it applies to with JSREF_LONG=1, as make conformance runs it). *)
let per_kind = if Sys.getenv_opt "JSREF_LONG" = Some "1" then max_int else 3

let tampered_rejected ?(not_here = []) level_traces () =
  let traces = Array.of_list (level_traces ()) in
  let n = Array.length traces in
  let tried = ref 0 and failures = ref [] and kinds_applied = ref 0 in
  List.iteri (fun ki (k : Tamper.t) ->
      if not (List.mem k.name not_here) then
      let applied = ref 0 and i = ref 0 in
      while !applied < per_kind && !i < n do
        let (x, good) = traces.((ki * 7 + !i) mod n) in
        let seed = ki + !i in
        (match k.apply (Random.State.make [| seed |]) good with
         | None -> ()
         | Some tampered ->
           incr applied; incr tried;
           match rejected_at (Printf.sprintf "%s, %s (seed %d)" x.v.name k.name seed) x ~good tampered with
           | _ -> ()
           | exception Bad m -> failures := m :: !failures);
        incr i
      done;
      if !applied > 0 then incr kinds_applied) Tamper.all;
  (match List.rev !failures with
   | [] -> ()
   | fs -> Alcotest.failf "%d of %d tampered traces not rejected so:\n%s" (List.length fs) !tried
             (String.concat "\n" fs));
  Printf.printf "%d tampered traces rejected, %d kinds of %d applied\n" !tried !kinds_applied (List.length Tamper.all);
  Alcotest.(check bool) "most kinds apply" true (!kinds_applied * 4 >= List.length Tamper.all * 3)

let full_traces () = List.map (fun x -> (x, x.expected)) (Lazy.force vecs)

(* ------------------------------------------------- runs of the CLI *)

(* The vector run by jadescript-ref with [extra] options: its trace. *)
let run_vector (x : vec) extra =
  let tr = Filename.temp_file "jsref-judge-run" ".jsonl" in
  let cmd = Printf.sprintf "cd %s && %s run %s %s --events events.jsonl --trace %s %s"
      (Filename.quote x.v.dir) exe (String.concat " " (List.map Filename.quote x.v.files))
      (String.concat " " (List.map Filename.quote x.v.args)) (Filename.quote tr) extra in
  let (status, _, err) = run_command cmd in
  let l = if Sys.file_exists tr then lines_of tr else [] in
  (try Sys.remove tr with Sys_error _ -> ());
  (status, err, l)

(* ------------------------------------------------- (c) defects *)

(* A defect is run on the vectors (those of its ruling first) up to the first whose trace
   differs from the expected one; the judge must reject that trace, never
   before the first difference, unless the defect changes only what the
   judge is not given: the schedule (R6 revised: the agents' rules in any
   order) or the host's own operations (the trace of a notify whose
   override was ignored is that of a host that gave none: the judge has no
   events file). These are named here, each with its reason; any other
   defect it lets through fails the test. *)
let not_the_program = [
  "rounds-reversed", "R6: any order of the agents' rules is a schedule";
  "seed-ignored", "R6: any order of the agents' rules is a schedule";
  "sends-reversed", "R6, R5e: messages to different receivers arrive in any order";
  "sends-by-receiver", "R6, R5e: messages to different receivers arrive in any order";
  "override-ignored", "the host's notify: a notify with no override";
  "override-zero-is-none", "the host's notify: a notify with no override";
]

let defects_caught () =
  let vs = Lazy.force vecs in
  let caught = ref [] and passed = ref [] and wrong = ref [] and unseen = ref [] in
  List.iter (fun (d : Defects.t) ->
      if d.can_differ then begin
        let rec go = function
          | [] -> unseen := d.name :: !unseen
          | x :: rest ->
            let (_, _, l) = run_vector x ("--defect " ^ d.name) in
            if l = [] || first_difference x.expected l = None then go rest
            else match rejected_at (d.name ^ " on " ^ x.v.name) x ~good:x.expected l with
              | line -> caught := (d.name, x.v.name, line) :: !caught
              | exception Bad m ->
                if List.mem_assoc d.name not_the_program && (match judge x l with Judge.Accepted _ -> true | _ -> false)
                then passed := (d.name, x.v.name) :: !passed
                else wrong := m :: !wrong in
        (* the vectors of the defect's ruling first (fewer runs) *)
        let (mine, others) = List.partition (fun x -> List.mem d.ruling x.v.rulings) vs in
        go (mine @ others)
      end) Defects.all;
  List.iter (fun (d, v, line) -> Printf.printf "caught   %-30s on %s at line %d\n" d v line) (List.rev !caught);
  List.iter (fun (d, v) -> Printf.printf "accepted %-30s on %s (%s)\n" d v (List.assoc d not_the_program)) (List.rev !passed);
  List.iter (fun d -> Printf.printf "no vector shows %s\n" d) (List.rev !unseen);
  let shown = List.length (List.filter (fun (d : Defects.t) -> d.can_differ) Defects.all) - List.length !unseen in
  Printf.printf "the judge catches %d of the %d defects the vectors show\n" (List.length !caught) shown;
  (match !wrong with
   | [] -> ()
   | ws -> Alcotest.failf "defects the judge does not reject where it must:\n%s" (String.concat "\n" (List.rev ws)));
  Alcotest.(check int) "caught + not the program's = shown" shown (List.length !caught + List.length !passed);
  Alcotest.(check bool) "at least 40 defects shown" true (shown >= 40)

(* ------------------------------------------------- (d) copied traces *)

(* A cheating implementation writes another program's expected trace (the
   next vector's whose program differs in more than comments): as it is (the header is not this program's: line 1), or under this run's own
   header (the first line the program cannot explain). *)
let copied_rejected () =
  let vs = Array.of_list (Lazy.force vecs) in
  let n = Array.length vs in
  let pairs = ref 0 in
  Array.iteri (fun i x ->
      (* the next vector of another program (vectors with the same program
         and other host events are runs of one program) *)
      let text (v : vec) =
        List.concat_map (fun f -> List.filter (fun l -> let l = String.trim l in l <> "" && l.[0] <> '#')
                            (String.split_on_char '\n' (read_file (Filename.concat v.v.dir f)))) v.v.files in
      let rec other j = let y = vs.(j mod n) in if text y <> text x then y else other (j + 1) in
      let y = other (i + 1) in
      (* as it is: rejected, at the header when it is not this run's *)
      if first_difference x.expected y.expected <> None then begin
        let line = rejected_located (Printf.sprintf "%s copying %s" x.v.name y.v.name) x ~good:x.expected y.expected in
        if List.hd x.expected <> List.hd y.expected && line <> 1 then
          Alcotest.failf "%s copying %s: rejected at line %d, not at its header" x.v.name y.v.name line
      end;
      match x.expected, y.expected with
      | h :: _, _ :: ylines ->
        let bad = h :: ylines in
        if first_difference x.expected bad <> None then begin
          incr pairs;
          ignore (rejected_located (Printf.sprintf "%s copying %s under its own header" x.v.name y.v.name) x
                    ~good:x.expected bad)
        end
      | _ -> Alcotest.failf "%s: an empty trace" x.v.name) vs;
  Alcotest.(check bool) "copies judged" true (!pairs >= n - 1)

(* ------------------------------------------------- (e) observable *)

let observable = lazy (
  List.map (fun x ->
      let (status, err, l) = run_vector x "--level observable" in
      if l = [] then Alcotest.failf "%s --level observable: no trace (status %d): %s" x.v.name status err;
      (x, l)) (Lazy.force vecs))

(* A kind of tampering that can leave a valid observable trace: two
   adjacent shown steps of one agent swapped (a handle and a behaviour
   step) may be the same run with the percept notified in the middle of an
   iteration, its hidden Transfer one iteration later (found with
   JSREF_LONG=1 on vectors 006 and 061); a full trace's transfer line pins
   the order. *)
let observable_valid = [ "loop steps of one agent swapped" ]

let observable_accepted () =
  List.iter (fun (x, l) ->
      (match Yojson.Safe.from_string (List.hd l) with
       | `Assoc f -> Alcotest.(check (option string)) (x.v.name ^ ": header level") (Some "observable")
                       (match List.assoc_opt "level" f with Some (`String s) -> Some s | _ -> None)
       | _ -> Alcotest.failf "%s: no header" x.v.name);
      (* it leaves out lines of the full trace, and keeps the rest *)
      Alcotest.(check bool) (x.v.name ^ ": shorter than the full trace") true (List.length l < List.length x.expected);
      match judge x l with
      | Judge.Accepted { level = Judge.Observable; cut = false; lines; _ } ->
        Alcotest.(check int) (x.v.name ^ ": every line read") (List.length l) lines
      | r -> Alcotest.failf "%s (observable): %s" x.v.name (show r)) (Lazy.force observable)

(* The full trace's loop steps, written into an observable trace, are lines
   the format says it has not. *)
let observable_with_loop_step () =
  let (x, l) = List.hd (Lazy.force observable) in
  let step = List.find (fun s -> match Yojson.Safe.from_string s with
      | `Assoc f -> List.assoc_opt "event" f = Some (`String "dequeue") | _ -> false) x.expected in
  let bad = match l with h :: c :: rest -> h :: c :: step :: rest | _ -> Alcotest.fail "short" in
  ignore (rejected_located "a dequeue line in an observable trace" x ~good:l bad)

(* ------------------------------------------- (f) data changed in place *)

(* A handler that adds to a map property in place, and says its size. The
   judge tries its body on every candidate configuration that may explain
   the line, and in an observable trace also while searching the hidden
   steps (Handle or Skip is decided by running the handler): each try must
   start from the data as the run had it, however the body changed it in
   place. Two pings of equal priority, under the unstable tie policy, are
   two candidates that both run the body before the Handle line picks one. *)
let in_place_program = {|ontology O
	proposition ping extends percept with priority = 1

agent A uses ontology O
	property seen as map of integer:integer = {}

	on create do
		activate behaviour B

cyclic behaviour B for agent A
	on percept when content matches ping do
		seen[size of seen] = 1
		log "seen " + size of seen
|}

(* Where [a] first occurs in [s]. *)
let find s a =
  let n = String.length a in
  let rec go i = if i + n > String.length s then None else if String.sub s i n = a then Some i else go (i + 1) in
  go 0

let data_changed_in_place () =
  let dir = Filename.concat (Filename.get_temp_dir_name ()) (Printf.sprintf "jsref-judge-inplace-%d" (Unix.getpid ())) in
  if not (Sys.file_exists dir) then Sys.mkdir dir 0o755;
  let file name = Filename.concat dir name in
  write_lines (file "p.jade") [ in_place_program ];
  write_lines (file "events.jsonl") [ {|{"agent":"a","notify":"ping"}|}; {|{"agent":"a","notify":"ping"}|} ];
  let env = match Typing.check [ Syntax.Parse.file (file "p.jade") ] with
    | env, [] -> env
    | _ -> Alcotest.fail "the program does not check" in
  List.iter (fun level ->
      let tr = file ("trace-" ^ level ^ ".jsonl") in
      let (status, _, err) = run_command (Printf.sprintf "%s run %s --agent a:A --events %s --trace %s --level %s"
                                            exe (file "p.jade") (file "events.jsonl") tr level) in
      if status <> 0 then Alcotest.failf "run --level %s: %s" level err;
      let lines = lines_of tr in
      (* the run logs seen 1, then seen 2: the judge must find the same *)
      if not (List.exists (fun l -> find l "seen 2" <> None) lines) then Alcotest.failf "%s: no second log" level;
      let unstable = match lines with
        | h :: rest ->
          let a = "\"tie_policy\":\"stable\"" in
          (match find h a with
           | Some i -> String.sub h 0 i ^ "\"tie_policy\":\"unstable\"" ^ String.sub h (i + String.length a) (String.length h - i - String.length a)
           | None -> Alcotest.fail "no tie policy in the header") :: rest
        | [] -> [] in
      List.iter (fun (what, lines) ->
          match with_lines lines (fun f -> Judge.judge env ~agents:[ ("a", "A", []) ] f) with
          | Judge.Accepted _ -> ()
          | r -> Alcotest.failf "%s trace, %s: %s" level what (show r))
        [ ("stable ties", lines); ("unstable ties", unstable) ]) [ "full"; "observable" ]

(* D46: an error's place is normative, its wording is not. In every
   vector's trace that records a run-time error, the first error's message
   reworded is accepted; its place moved one column is rejected at that
   line. *)
let error_wording () =
  let module J = Yojson.Safe in
  let field k l = match J.from_string l with `Assoc f -> List.assoc_opt k f | _ -> None in
  let is_error l = field "event" l = Some (`String "error") in
  let set k v l = match J.from_string l with
    | `Assoc f -> J.to_string (`Assoc (List.map (fun (k', x) -> if k' = k then (k', v) else (k', x)) f))
    | _ -> l in
  let with_error = List.filter (fun x -> List.exists is_error (List.tl x.expected)) (Lazy.force vecs) in
  Alcotest.(check bool) "some vectors record an error" true (List.length with_error >= 5);
  List.iter (fun x ->
      let header = List.hd x.expected and events = List.tl x.expected in
      let i = ref (-1) in
      List.iteri (fun k l -> if !i < 0 && is_error l then i := k) events;
      let edit f = header :: List.mapi (fun k l -> if k = !i then f l else l) events in
      let reworded = edit (set "message" (`String "something else went wrong")) in
      (match judge x reworded with
       | Judge.Accepted _ -> ()
       | r -> Alcotest.failf "%s: the error reworded: %s" x.v.name (show r));
      let moved = edit (fun l ->
          let at = match field "at" l with Some (`String a) -> a | _ -> Alcotest.fail "an error without at" in
          let k = String.rindex at ':' in
          let col = int_of_string (String.sub at (k + 1) (String.length at - k - 1)) in
          set "at" (`String (Printf.sprintf "%s:%d" (String.sub at 0 k) (col + 1))) l) in
      match judge x moved with
      | Judge.Rejected { line; _ } when line = !i + 2 -> ()
      | r -> Alcotest.failf "%s: the error moved one column: %s (want line %d)" x.v.name (show r) (!i + 2))
    with_error

(* ----------------------------------------------------- two containers *)

(* D47: a free run of JADE with Bob in a peripheral container (kept from
   scripts/jade-generated --split, lib/gen's case 24 of seed 1): g, Bob and
   provider each send inform r1 to provider in on create, in that order;
   provider receives g's, its own, then Bob's, which crossed JVMs. Without
   the header's containers R5e orders all three sends and the trace is
   rejected at provider's own delivery; with them, sends from different
   containers are not ordered, and it is accepted; and two deliveries of
   one container swapped are still rejected. *)
let two_containers () =
  let dir = Filename.concat root "test/judge/cases/split-order" in
  let lines = lines_of (Filename.concat dir "trace.jsonl") in
  let header = List.hd lines and events = List.tl lines in
  let with_containers cs = match Yojson.Safe.from_string header with
    | `Assoc f ->
      let rec add = function
        | ("agents", a) :: rest -> ("agents", a) :: ("containers", cs) :: rest
        | x :: rest -> x :: add rest
        | [] -> [] in
      Yojson.Safe.to_string (`Assoc (add f))
    | _ -> Alcotest.fail "the header is not an object" in
  let judge_lines lines =
    with_lines lines (fun f ->
        let cmd = Printf.sprintf "cd %s && %s judge program.jade --agent g:Ag:@robome --agent Bob:Ag:@robome \
                                  --agent provider:Ag:@robome --variant reference --fuel 50 --max-steps 500 \
                                  --o2a-capacity 2 --events events.jsonl %s"
            (Filename.quote dir) (Filename.quote exe) (Filename.quote f) in
        let (status, out, err) = run_command cmd in
        (status, (if status = 0 then out else err), f)) in
  let rejected_at want (status, err, f) what =
    let prefix = Printf.sprintf "%s:%d:1: error: " f want in
    if status <> 1 || not (String.length err >= String.length prefix && String.sub err 0 (String.length prefix) = prefix) then
      Alcotest.failf "%s: want a rejection at line %d, got status %d: %s" what want status err in
  let delivery k l = match Yojson.Safe.from_string l with
    | `Assoc f -> List.assoc_opt "event" f = Some (`String "deliver") && List.assoc_opt "agent" f = Some (`String "provider")
                  && List.assoc_opt "seq" f = Some (`Int k)
    | _ -> false in
  (* as JADE wrote it, before headers named containers: one container *)
  let one = judge_lines lines in
  rejected_at 15 one "one container";
  let (_, err, _) = one in
  let contains s sub =
    let n = String.length sub in
    let rec at i = i + n <= String.length s && (String.sub s i n = sub || at (i + 1)) in at 0 in
  Alcotest.(check bool) "the rejection cites R5e" true (contains err "R5e");
  (* Bob in the peripheral container *)
  let split = with_containers (`Assoc [ "Bob", `String "peripheral" ]) in
  (match judge_lines (split :: events) with
   | (0, out, _) -> Alcotest.(check bool) "the verdict names the containers" true (contains out "2 containers")
   | (s, err, _) -> Alcotest.failf "two containers: want accepted, got status %d: %s" s err);
  (* g's and provider's deliveries (one container) swapped, seq kept *)
  let from who l = match Yojson.Safe.from_string l with
    | `Assoc f -> Yojson.Safe.to_string (`Assoc (List.map (fun (k, v) -> if k = "from" then (k, `String who) else (k, v)) f))
    | _ -> l in
  let swapped = List.map (fun l ->
      if delivery 1 l then from "provider" l else if delivery 2 l then from "g" l else l) events in
  Alcotest.(check bool) "the plant changed the trace" true (swapped <> events);
  rejected_at 14 (judge_lines (split :: swapped)) "one container's deliveries swapped";
  (* validate's checks between agents (no TLC) hold the same order *)
  let facts lines = with_lines lines (fun f ->
      match Explore.Validate.check f with
      | Error e -> Error e
      | Ok () -> match Trace.read_located f with
        | Error e -> Error e
        | Ok (h, ls) -> Explore.Trace_more.check h ls) in
  (match facts lines with
   | Error (15, _) -> ()
   | Error (n, m) -> Alcotest.failf "validate, one container: rejected at line %d, not 15: %s" n m
   | Ok () -> Alcotest.fail "validate, one container: accepted");
  (match facts (split :: events) with
   | Ok () -> ()
   | Error (n, m) -> Alcotest.failf "validate, two containers: rejected at line %d: %s" n m);
  (match facts (split :: swapped) with
   | Error (14, _) -> ()
   | Error (n, m) -> Alcotest.failf "validate, swapped: rejected at line %d, not 14: %s" n m
   | Ok () -> Alcotest.fail "validate, swapped: accepted");
  (* a header that puts an agent it does not have in a container *)
  rejected_at 1 (judge_lines (with_containers (`Assoc [ "Alice", `String "peripheral" ]) :: events)) "an unknown agent"

let () =
  Alcotest.run "judge" [
    "full", [
      Alcotest.test_case "every vector's expected trace is accepted" `Quick expected_accepted;
      Alcotest.test_case "tampered traces rejected at a located line" `Quick (tampered_rejected full_traces);
      Alcotest.test_case "traces of defective implementations rejected where they differ" `Quick defects_caught;
      Alcotest.test_case "a trace copied from another program rejected" `Quick copied_rejected;
    ];
    "observable", [
      Alcotest.test_case "every vector's run at the observable level is accepted" `Quick observable_accepted;
      Alcotest.test_case "tampered observable traces rejected at a located line" `Quick
        (tampered_rejected ~not_here:observable_valid (fun () -> Lazy.force observable));
      Alcotest.test_case "a loop step's line in an observable trace rejected" `Quick observable_with_loop_step;
    ];
    "data", [
      Alcotest.test_case "a body that changes a map in place, tried on several candidates" `Quick data_changed_in_place;
    ];
    "errors", [
      Alcotest.test_case "D46 an error's wording is not judged, its place is" `Quick error_wording;
    ];
    "containers", [
      Alcotest.test_case "D47 sends from two containers are not ordered, one container's are" `Quick two_containers;
    ];
  ]
