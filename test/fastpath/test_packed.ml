(* The packed agent (lib/engine/packed.ml, D32, D39) held equal to
   the reference machine: its rings (Ring), its percept codec
   (Percept_codec), and the agent itself, rule by rule, on random programs
   and random host operations. *)

open Syntax
open Test_support
open Support
module V = Interp.Value
module Mc = Semantics.Machine
module Ring = Engine.Private.Packed.Ring
module Codec = Engine.Private.Percept_codec
(* one application of the compiled bodies serves the tests' agents: what
   it keeps of an instance is checked to be that very instance's *)
module CBm = Engine.Private.Compiled_bodies.Make ()
module Pk = Engine.Private.Packed.Make (CBm) (Engine.Private.Percept_codec)
module RM = Pk.M

(* ------------------------------------------------------------ rings *)

(* A ring against a plain list model: pushes and drops interleaved, many
   times across its chunks (of 4, 16 ints and the default) and through
   its growth. *)
let ring_model () =
  let rand = Random.State.make [| seed |] in
  for round = 1 to 50 do
    let pool = Ring.pool ~chunk:(match round mod 3 with 0 -> 4 | 1 -> 16 | _ -> Ring.default_chunk) () in
    let r : string Ring.t = Ring.create ~pool () in
    let ints = Queue.create () and boxes = Queue.create () in
    let next = ref 0 in
    for _ = 1 to 2000 do
      (match Random.State.int rand (if round mod 2 = 0 then 5 else 3) with
       | 0 | 3 | 4 -> incr next; Ring.push r !next; Queue.push !next ints
       | 1 -> let n = Random.State.int rand (Queue.length ints + 1) in
         Ring.drop r n; for _ = 1 to n do ignore (Queue.pop ints) done
       | _ ->
         if Random.State.bool rand || Queue.is_empty boxes then begin
           let s = string_of_int !next in Ring.push_box r s; Queue.push s boxes end
         else begin Ring.drop_box r; ignore (Queue.pop boxes) end);
      Alcotest.(check int) "length" (Queue.length ints) (Ring.length r);
      Alcotest.(check int) "boxes" (Queue.length boxes) (Ring.boxes r);
      List.iteri (fun i x -> if Ring.get r i <> x then Alcotest.failf "int %d: %d, not %d" i (Ring.get r i) x)
        (List.of_seq (Queue.to_seq ints));
      List.iteri (fun j x -> if Ring.get_box r j <> x then Alcotest.failf "box %d: %s, not %s" j (Ring.get_box r j) x)
        (List.of_seq (Queue.to_seq boxes))
    done
  done

(* A drained ring gives its large array back; one that is not drained
   keeps everything. *)
let ring_shrink () =
  let r : int Ring.t = Ring.create () in
  for i = 1 to 100_000 do Ring.push r i done;
  Ring.push_box r 7;
  Ring.shrink r;
  Alcotest.(check int) "not drained: kept" 100_000 (Ring.length r);
  Alcotest.(check int) "its last int" 100_000 (Ring.get r 99_999);
  Ring.drop r 100_000; Ring.drop_box r;
  Ring.shrink r;
  if Ring.offheap_words r > 100 || Ring.heap_words r > 100 then
    Alcotest.failf "drained: %d and %d words kept" (Ring.offheap_words r) (Ring.heap_words r);
  Ring.push r 5; Ring.push_box r 9;
  Alcotest.(check (pair int int)) "usable after" (5, 9) (Ring.get r 0, Ring.get_box r 0)

(* D39: chunks emptied by one ring are taken by the next to grow, and a
   pool keeps at most 8. One ring's ints moved to another int by int: the
   pool makes the first ring's chunks and about two more, not twice as
   many; the memory held (the rings' and the pool's chunks) stays about
   one copy. *)
let ring_chunks_reused () =
  let pool = Ring.pool ~chunk:8 () in
  let o2a : unit Ring.t = Ring.create ~pool () and bucket : unit Ring.t = Ring.create ~pool () in
  for i = 1 to 400 do Ring.push o2a i done;
  Alcotest.(check int) "50 chunks for 400 ints" 50 (Ring.chunks o2a);
  Alcotest.(check int) "made: the O2A ring's" 50 (Ring.made pool);
  let held () = Ring.offheap_words o2a + Ring.offheap_words bucket + Ring.pool_offheap_words pool in
  let most = ref 0 in
  while Ring.length o2a > 0 do
    Ring.push bucket (Ring.get o2a 0); Ring.drop o2a 1;
    most := max !most (held ())
  done;
  Alcotest.(check int) "moved, in order" 400 (Ring.length bucket);
  List.iter (fun i -> Alcotest.(check int) "int" (i + 1) (Ring.get bucket i)) (List.init 400 Fun.id);
  if Ring.made pool > 52 then Alcotest.failf "the pool made %d chunks for 50 chunks of ints" (Ring.made pool);
  if !most > 52 * 8 then Alcotest.failf "%d words held while moving 400 ints" !most;
  (* drained: the ring gives its chunks back, the pool keeps 8 *)
  Ring.drop bucket 400;
  Ring.shrink bucket; Ring.shrink o2a;
  Alcotest.(check int) "drained: no chunk" 0 (Ring.chunks bucket + Ring.chunks o2a);
  Alcotest.(check int) "the pool keeps 8" 8 (Ring.free_chunks pool);
  let made = Ring.made pool in
  for i = 1 to 64 do Ring.push o2a i done;
  Alcotest.(check int) "taken from the pool, none made" made (Ring.made pool);
  Alcotest.(check int) "the pool's 8 used again" 0 (Ring.free_chunks pool);
  Alcotest.(check int) "a bad chunk size" 0
    (match Ring.pool ~chunk:12 () with _ -> 1 | exception Invalid_argument _ -> 0)

(* ------------------------------------------------------------ codec *)

let sch name slots = V.Schema { sname = name; slots = Array.of_list (List.map (fun (n, v) -> (n, ref v)) slots) }

(* Equal as the interpreter's values are built (Int 1 and Double 1.0
   differ); a host object is compared by identity. *)
let same_value a b = a == b || (match a, b with V.Native _, _ | _, V.Native _ -> false | _ -> a = b)

let native = V.Native { nid = 3; cls = "Robot"; methods = [ ("go", fun _ -> V.Unit) ] }

(* Every kind of value, packed or boxed, round-trips through a ring, several
   in a row, at their places. *)
let probe = "probe" and probe_x = "x"

let codec_round_trip () =
  let m = V.map_empty () in
  (match m with V.Map mv -> V.map_set mv (V.Int 1) (V.Text "a") | _ -> ());
  let values = [
    (sch "position" [ ("k", V.Int 3) ], true);
    (sch "position" [ ("k", V.Int (-2147483648)) ], true);
    (sch "position" [ ("k", V.Int 2147483647) ], true);
    (sch "position" [ ("k", V.Int 2147483648) ], true);      (* beyond 32 bits: a host's *)
    (sch "position" [ ("k", V.Int (-2147483649)) ], true);
    (sch "flag" [ ("on", V.Bool true) ], true);
    (* one schema name and one slot name (the same strings), the slot an
       int, a boolean, a text: three kinds, each found by the names'
       addresses and how its slot is written *)
    (sch probe [ (probe_x, V.Int 7) ], true);
    (sch probe [ (probe_x, V.Bool true) ], true);
    (sch probe [ (probe_x, V.Text "t") ], true);
    (sch probe [ (probe_x, V.Int (-7)) ], true);
    (sch "falling" [], true);
    (sch "at" [ ("x", V.Int 1); ("ok", V.Bool true); ("y", V.Int 0) ], true);
    (sch "at" [ ("x", V.Int 1); ("ok", V.Bool false); ("y", V.Int (-5)) ], true);
    (sch "at" [ ("x", V.Bool false); ("ok", V.Int 1); ("y", V.Int 0) ], true);  (* other kinds: another tag *)
    (sch "at" [ ("a", V.Int 1); ("ok", V.Bool false); ("y", V.Int 0) ], true);  (* other slot names *)
    (sch "seen" [ ("t", V.Text "x y"); ("b", V.Bool true) ], true);        (* a text: a box *)
    (sch "msg" [ ("a", V.Text "p"); ("n", V.Int 2); ("b", V.Text ""); ("ok", V.Bool false) ], true);
    (sch "four" [ ("a", V.Text "1"); ("b", V.Text "2"); ("c", V.Text "3"); ("d", V.Text "4") ], false);
    (sch "reading" [ ("v", V.Double 1.5); ("f", V.Float 0.5) ], false);
    (sch "box" [ ("p", sch "point" [ ("x", V.Int 1) ]) ], false);
    (sch "tags" [ ("l", V.list_of [ V.Int 1; V.Int 2 ]) ], false);
    (sch "who" [ ("a", V.Aid "r") ], false);
    (V.Int 4, false); (V.Bool true, false); (V.Float 2.5, false); (V.Double 1e300, false);
    (V.Text "é\n", false); (V.Aid "x", false); (V.list_of [ V.Text "a" ], false); (m, false);
    (native, false); (V.Agent_ref "a", false); (V.Behaviour_ref 2, false); (V.Unit, false) ] in
  let c = Codec.create () in
  let r = Ring.create () in
  (* twice over, so that the second time every tag is already given *)
  let all = values @ values in
  let tags = List.map (fun (v, packed) ->
      let at = Ring.length r and boxes = Ring.boxes r in
      Ring.push r 0;
      let tag = Codec.encode c v r in
      Ring.set r at tag;
      Alcotest.(check bool) (V.to_literal v ^ " packed") packed (Engine.Private.Packed.tag_kind tag > 0);
      Alcotest.(check int) (V.to_literal v ^ " width") (at + 1 + Engine.Private.Packed.tag_width tag) (Ring.length r);
      Alcotest.(check int) (V.to_literal v ^ " boxes") (boxes + Engine.Private.Packed.tag_boxes tag) (Ring.boxes r);
      tag) all in
  (* position, flag, three kinds of probe, falling, three kinds of at,
     seen, msg *)
  Alcotest.(check int) "kinds interned once each" 11 (Codec.kinds c);
  let pos = ref 0 and box = ref 0 in
  List.iter2 (fun (v, packed) tag ->
      Alcotest.(check int) "tag" tag (Ring.get r !pos);
      let v' = Codec.read c tag r ~pos:(!pos + 1) ~box:!box in
      if not (same_value v v') then Alcotest.failf "%s read back as %s" (V.to_literal v) (V.to_literal v');
      if packed && v == v' then Alcotest.failf "%s: not a fresh value" (V.to_literal v);
      pos := !pos + 1 + Engine.Private.Packed.tag_width tag;
      box := !box + Engine.Private.Packed.tag_boxes tag)
    all tags;
  Alcotest.(check int) "every int read" (Ring.length r) !pos;
  (* D39: encode_one answers the tag and int of exactly the percepts of
     one 32-bit int slot (an integer or a boolean) or of no slot, and
     read_int gives them back *)
  List.iter2 (fun (v, _) tag ->
      let one = Codec.encode_one c v in
      let int_slot = match v with
        | V.Schema { slots = [| (_, x) |]; _ } ->
          (match !x with V.Int n -> Some n | V.Bool b -> Some (if b then 1 else 0) | _ -> None)
        | V.Schema { slots = [||]; _ } -> Some 0
        | _ -> None in
      let expected = match int_slot with
        | Some n when n >= -2147483648 && n <= 2147483647 -> true | _ -> false in
      Alcotest.(check bool) (V.to_literal v ^ " a word") expected (one <> 0);
      if one <> 0 then begin
        Alcotest.(check int) (V.to_literal v ^ " its tag") tag (one land (1 lsl 20 - 1));
        Alcotest.(check bool) (V.to_literal v ^ " a word's tag") true (Engine.Private.Packed.word_tag tag);
        let v' = Codec.read_int c tag (one asr 20) in
        if not (same_value v v') then Alcotest.failf "%s read back as %s" (V.to_literal v) (V.to_literal v')
      end)
    all tags;
  let word_tag kind width boxes = Engine.Private.Packed.word_tag (Engine.Private.Packed.make_tag ~kind ~width ~boxes) in
  Alcotest.(check bool) "kind 1: a word" true (word_tag 1 1 0);
  Alcotest.(check bool) "kind 15: a word" true (word_tag 15 1 0);
  Alcotest.(check bool) "kind 16: not a word" false (word_tag 16 1 0);
  Alcotest.(check bool) "kind 0 (boxed): not a word" false (word_tag 0 1 0);
  Alcotest.(check bool) "width 0 (no slot): a word" true (word_tag 1 0 0);
  Alcotest.(check bool) "width 0, a box: not a word" false (word_tag 1 0 1);
  Alcotest.(check bool) "width 2: not a word" false (word_tag 1 2 0);
  Alcotest.(check bool) "a box: not a word" false (word_tag 1 1 1);
  (* a decoded value's slots are its own: setting one changes no other *)
  let r = Ring.create () in
  let tag = Codec.encode c (sch "position" [ ("k", V.Int 3) ]) r in
  (match Codec.read c tag r ~pos:0 ~box:0, Codec.read c tag r ~pos:0 ~box:0 with
   | V.Schema a, V.Schema b ->
     snd a.slots.(0) := V.Int 9;
     Alcotest.(check bool) "fresh slots" true (!(snd b.slots.(0)) = V.Int 3)
   | _ -> Alcotest.fail "not a schema")

(* ------------------------------------------------ the packed agent *)

(* A random host drives two copies of the same agent: the reference
   machine ([RM.step], one rule at a time, on a persistent configuration)
   and the packed agent (its [step], or the derived rule [dispatch], which
   the reference then follows rule by rule). After every host operation
   (every other notify or so) and every rule: the same labels, the same body
   events, [to_config] of the packed agent = the reference configuration,
   the same refusals. *)
type op = Notify of V.t * int * int option * bool | Put of V.t | Send of V.t | Steps of int | Dispatches of int

let packed_equals_reference_exn (prog, seed) =
  let text = Print.program prog in
  let env, diags = Typing.check [ Parse.string ~file:"gen.jade" text ] in
  if List.exists (fun d -> d.Diag.severity = Diag.Error) diags then
    QCheck.Test.fail_reportf "the generated program does not check";
  let rand = Random.State.make [| seed |] in
  let percept () =
    let ps = Event_gen.percept_types env in
    let s = List.nth ps (Random.State.int rand (List.length ps)) in
    let args = List.map (fun (_, ty) -> Event_gen.small_literal rand ty) s.s_slots in
    let text = if args = [] then s.s_name else s.s_name ^ "(" ^ String.concat ", " args ^ ")" in
    Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" text) in
  let variant = List.nth [ Mc.Reference; Mc.Budgeted; Mc.Reference; Mc.Budgeted; Mc.Printed; Mc.Native ] (seed mod 6) in
  let p = { Mc.default_params with variant;
                                   tie = (if seed mod 7 = 3 then Mc.Unstable else Mc.Stable);
                                   budget = 1 + Random.State.int rand 3;
                                   ghosts = seed mod 11 = 5;
                                   o2a_capacity = (if Random.State.bool rand then None else Some (1 + Random.State.int rand 6)) } in
  let notify () =
    let (v, default) = percept () in
    let prio = match Random.State.int rand 5 with
      | 0 -> Some (Random.State.int rand 9) | 1 when Random.State.int rand 4 = 0 -> Some (-1) | _ -> None in
    (* compared after one notify in four: runs of notifies reach a
       Transfer unread (the plain agent's runs, taken as they wait) *)
    Notify (v, default, prio, Random.State.int rand 4 = 0) in
  let ops = List.concat (List.init (5 + Random.State.int rand 25) (fun _ ->
      match Random.State.int rand 11 with
      | 0 | 1 | 2 | 3 -> [ notify () ]
      | 4 -> [ Put (V.list_of [ V.Int (Random.State.int rand 5) ]) ]
      | 5 -> [ Send (fst (percept ())) ]
      | 6 | 7 -> [ Steps (1 + Random.State.int rand 25) ]
      | 8 | 9 -> [ Dispatches (1 + Random.State.int rand 3) ]
      | _ -> List.init (3 + Random.State.int rand 10) (fun _ -> notify ()))) in   (* a small flood *)
  let args_for () =
    let rand = Random.State.make [| seed; 1 |] in
    let params = match Typing.Tenv.agent_create env "Ag" with Some r -> r.r_params | None -> [] in
    List.map (fun (_, ty) -> Interp.Eval.literal_value env (Parse.expr ~file:"a" (Event_gen.small_literal rand ty))) params in
  let (ar, behs_r) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:(args_for ()) in
  let (ap, behs_p) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:(args_for ()) in
  (* the events the bodies recorded so far, oldest first *)
  let events (a : Interp.Eval.agent) = List.rev_map Show.event a.events in
  if events ar <> events ap then QCheck.Test.fail_reportf "on create differs";
  let c = ref (RM.init p ~world:ar behs_r) in
  (* every percept packed; a mix (packed once two wait); the default
     (boxed while fewer than 4,096 wait) *)
  let pack_above = match seed mod 3 with 0 -> 0 | 1 -> 2 | _ -> Pk.default_pack_above in
  (* chunks of 2, 4, 8 ints (crossed every few percepts) and the default;
     no word, words only for priorities and seq offsets below 3 or 5, words
     wherever they fit (D39) *)
  let chunk = match seed mod 4 with 0 -> 2 | 1 -> 4 | 2 -> 8 | _ -> Ring.default_chunk in
  let word_x_limit = match seed mod 5 with 0 -> 0 | 1 -> 3 | 2 -> 5 | _ -> 1 lsl 26 in
  let t = Pk.of_config ~pack_above ~chunk ~word_x_limit p (RM.init p ~world:ap behs_p) in
  let history = Buffer.create 256 in
  let fail fmt = Printf.ksprintf (fun s ->
      QCheck.Test.fail_reportf "%s\nafter: %s\nparams: %s budget=%d cap=%s pack_above=%d chunk=%d word_x_limit=%d packed=%b\n%s" s (Buffer.contents history)
        (Mc.string_of_variant p.variant) p.budget
        (match p.o2a_capacity with Some k -> string_of_int k | None -> "-") pack_above chunk word_x_limit (Pk.packed t) text) fmt in
  let compare_now what =
    Buffer.add_string history (what ^ " | ");
    let r = Show.config !c and k = Show.config (Pk.to_config t) in
    if r <> k then fail "configurations differ after %s:\nreference: %s\npacked:    %s" what r k;
    let er = events !c.world and ep = events (Pk.world t) in
    if er <> ep then fail "events differ after %s:\n%s\n%s" what (String.concat "|" er) (String.concat "|" ep) in
  let ref_step () = match RM.step p !c with
    | [] -> None
    | (l, c') :: _ -> c := c'; Some l in
  List.iter (function
      | Notify (v, default, priority, check) ->
        let r = RM.notify_event p !c v ~default ~priority in
        let k = Pk.notify_event t v ~default ~priority in
        (match r, k with
         | Ok c', Ok () -> c := c'
         | Error x, Error y when x = y -> ()
         | _ -> fail "notify %s: refusals differ" (V.to_literal v));
        (* not after every notify: the packed agent writes a run of
           notifies into its configuration when it is next read *)
        if check then compare_now ("notify " ^ V.to_literal v)
        else Buffer.add_string history ("notify " ^ V.to_literal v ^ " | ")
      | Put o ->
        let room = RM.o2a_has_room p !c in
        if room <> Pk.o2a_has_room t then fail "put: room differs";
        if room then begin c := RM.put p !c o; Pk.put t o end;
        compare_now "put"
      | Send v ->
        let m = { Interp.Eval.perf = "inform"; content = v; sender = "host" } in
        c := RM.send p !c m; Pk.send t m;
        compare_now "send"
      | Steps n ->
        for _ = 1 to n do
          let lr = ref_step () and lk = Pk.step t in
          let show = function Some l -> Show.label l | None -> "none" in
          if show lr <> show lk then fail "step: reference %s, packed %s" (show lr) (show lk);
          compare_now ("step " ^ show lr)
        done
      | Dispatches n ->
        for i = 1 to n do
          let labels = ref [] in
          if (seed + i) mod 2 = 1 then begin
            (* unobserved: the handlers by plan (Fast.BODIES.percept_kind);
               the reference takes its rules up to the EndDispatch. Where
               no dispatch is enabled, a step first (at most 3). *)
            let run = (seed + i) mod 4 = 3 in
            let rec attempt k =
              (* one Dispatch, or a run of them (Packed.dispatch_run) *)
              let max = if seed mod 2 = 0 then None else Some (1 + i mod 3) in
              let n = if run then Pk.dispatch_run ?max t else if Pk.dispatch t then 1 else 0 in
              (match max with
               | Some m when n > m -> fail "a run of %d dispatches, at most %d asked" n m
               | _ -> ());
              if n > 0 then begin
                let rec follow k = match ref_step () with
                  | Some (Mc.End_dispatch _) -> ()
                  | Some _ when k < 100_000 -> follow (k + 1)
                  | l -> fail "unobserved dispatch: the reference's rules end with %s"
                           (match l with Some l -> Show.label l | None -> "none") in
                for _ = 1 to n do follow 0 done;
                (* a whole run stops only where Dequeue is not enabled *)
                if run && max = None && not (RM.dispatch_over p !c) then
                  fail "a run of %d dispatches stopped before the dispatches were over" n;
                compare_now (if run then Printf.sprintf "a run of %d dispatches" n else "unobserved dispatch")
              end else if k < 3 then begin
                let lr = ref_step () and lk = Pk.step t in
                let show = function Some l -> Show.label l | None -> "none" in
                if show lr <> show lk then fail "step: reference %s, packed %s" (show lr) (show lk);
                compare_now ("step " ^ show lr);
                if lk <> None then attempt (k + 1)
              end in
            attempt 0
          end else
          if Pk.dispatch ~observe:(fun l w -> labels := Show.label l :: !labels; w) t then begin
            let taken = List.rev !labels in
            let followed = List.map (fun _ -> match ref_step () with
                | Some l -> Show.label l | None -> "none") taken in
            if taken <> followed then
              fail "dispatch: %s; the reference: %s" (String.concat " " taken) (String.concat " " followed);
            compare_now ("dispatch " ^ String.concat " " taken)
          end
        done)
    ops;
  true

let packed_equals_reference x =
  try packed_equals_reference_exn x with
  | QCheck.Test.Test_fail _ as e -> raise e
  | e -> QCheck.Test.fail_reportf "exception %s" (Printexc.to_string e)

(* The bench's workload (bench/programs/percepts.jade): four percept types,
   three behaviours; and a fifth type of two texts (a record of two boxes)
   and one of a double (boxed whole). *)
let bench_program =
  Support.bench_workload
    ~types:[ "predicate note(a as text, n as integer, b as text) extends percept with priority = 4";
             "predicate level(x as double) extends percept with priority = 8" ]
    ~handlers:[ ("note(a, n, b)", "log a + n + b"); ("level(x)", "log \"level \" + x") ] ()

let packed_bench_program () =
  let prog = (Parse.string ~file:"bench.jade" bench_program).program in
  for seed = 0 to 59 do
    match packed_equals_reference (prog, seed) with
    | _ -> ()
    | exception QCheck.Test.Test_fail (_, msgs) -> Alcotest.failf "seed %d: %s" seed (String.concat "\n" msgs)
  done

(* Fixed scenarios on the bench program: objects among percepts, growth of
   the rings past their first array and around it, refusals at capacity. *)
let packed_agent_unit () =
  let env, _ = Typing.check [ Parse.string ~file:"bench.jade" bench_program ] in
  let pv text = fst (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" text)) in
  let agent p =
    let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
    Pk.of_config ~pack_above:0 p (RM.init p ~world:a behs) in
  let o2a_of t = List.map (function Mc.O_percept e -> Show.entry e | Mc.O_object o -> V.to_literal o)
      (Semantics.Fqueue.to_list (Pk.to_config t).o2a) in
  (* objects between percepts, at their places *)
  let t = agent Mc.default_params in
  Alcotest.(check bool) "packed" true (Pk.packed t);
  Pk.put t (V.Int 1);
  ignore (Pk.notify_event t (pv "position(5)") ~default:2 ~priority:None);
  Pk.put t (V.Int 2); Pk.put t (V.Int 3);
  ignore (Pk.notify_event t (pv "qrCodeRead(\"A7\")") ~default:4 ~priority:(Some 9));
  ignore (Pk.notify_event t (pv "falling") ~default:10 ~priority:None);
  Pk.put t (V.Int 4);
  Alcotest.(check (list string)) "O2A in order"
    [ "1"; "position(5)/2/1"; "2"; "3"; "qrCodeRead(\"A7\")/9/2"; "falling/10/3"; "4" ] (o2a_of t);
  Alcotest.(check (option string)) "transfer" (Some "Transfer(3)") (Option.map Show.label (Pk.step t));
  Alcotest.(check (list string)) "objects stay" [ "1"; "2"; "3"; "4" ] (o2a_of t);
  Alcotest.(check (option string)) "highest first" (Some "Dequeue(falling/10/3)") (Option.map Show.label (Pk.step t));
  (* a flood: growth and wrap-around, ties in seq order *)
  let t = agent Mc.default_params in
  for k = 1 to 5000 do
    ignore (Pk.notify_event t (pv (Printf.sprintf "position(%d)" k)) ~default:2 ~priority:(Some (k mod 3)))
  done;
  Alcotest.(check int) "waiting" 5000 (Pk.waiting t);
  ignore (Pk.step t);
  let seqs = ref [] in
  while Pk.dispatch ~observe:(fun l w -> (match l with Mc.Dequeue e -> seqs := (e.prio, e.seq) :: !seqs | _ -> ()); w) t do () done;
  let expected = List.concat_map (fun prio ->
      List.filter_map (fun k -> if k mod 3 = prio then Some (prio, k) else None) (List.init 5000 (fun i -> i + 1)))
      [ 2; 1; 0 ] in
  Alcotest.(check (list (pair int int))) "dequeue order" expected (List.rev !seqs);
  Alcotest.(check int) "none left" 0 (Pk.waiting t);
  (* refusals at capacity: percepts and objects count, nothing changes *)
  let t = agent { Mc.default_params with o2a_capacity = Some 2 } in
  Pk.put t (V.Int 1);
  ignore (Pk.notify_event t (pv "position(1)") ~default:2 ~priority:None);
  let before = Show.config (Pk.to_config t) in
  Alcotest.(check bool) "full" true (Pk.notify_event t (pv "position(2)") ~default:2 ~priority:None = Error Mc.O2a_full);
  Alcotest.(check bool) "negative" true
    (Pk.notify_event t (pv "position(2)") ~default:2 ~priority:(Some (-1)) = Error (Mc.Negative_priority (-1)));
  Alcotest.(check string) "refusals change nothing" before (Show.config (Pk.to_config t));
  (* Budgeted, budget 1, every behaviour blocked while percepts wait: the
     rules the packed agent leaves to Fast (BehaviourStep, NextIteration)
     see that the priority queue is not empty *)
  let p = { Mc.default_params with variant = Mc.Budgeted; budget = 1 } in
  let t = agent p in
  let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
  let c = ref (RM.init p ~world:a behs) in
  for k = 1 to 6 do
    let v = pv (Printf.sprintf "position(%d)" k) in
    ignore (Pk.notify_event t v ~default:2 ~priority:None);
    c := RM.notify p !c v 2
  done;
  let rec run n acc_r acc_k =
    if n = 0 then (List.rev acc_r, List.rev acc_k) else
    let lr = match RM.step p !c with [] -> "none" | (l, c') :: _ -> c := c'; Show.label l in
    let lk = match Pk.step t with None -> "none" | Some l -> Show.label l in
    run (n - 1) (lr :: acc_r) (lk :: acc_k) in
  let (lr, lk) = run 80 [] [] in
  Alcotest.(check bool) "NextIteration taken with percepts waiting" true (List.mem "NextIteration" lr);
  Alcotest.(check (list string)) "budgeted: the same rules" lr lk;
  Alcotest.(check string) "budgeted: the same configuration" (Show.config !c) (Show.config (Pk.to_config t));
  (* not packable: the plain configuration *)
  let t = agent { Mc.default_params with tie = Mc.Unstable } in
  Alcotest.(check bool) "unstable ties: not packed" false (Pk.packed t);
  (* the default: plain while fewer than 4,096 wait, packed from the notify
     that makes 4,096 until none wait, then plain again *)
  let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
  let t = Pk.of_config Mc.default_params (RM.init Mc.default_params ~world:a behs) in
  Alcotest.(check int) "the threshold" 4096 Pk.default_pack_above;
  Pk.put t (V.Int 0);
  for k = 1 to 4094 do ignore (Pk.notify_event t (pv (Printf.sprintf "position(%d)" k)) ~default:2 ~priority:None) done;
  Alcotest.(check bool) "4,095 waiting: plain" false (Pk.packed t);
  ignore (Pk.notify_event t (pv "falling") ~default:10 ~priority:None);
  Alcotest.(check bool) "4,096 waiting: packed" true (Pk.packed t);
  Alcotest.(check (list string)) "the object first, in O2A" [ "0"; "position(1)/2/1" ]
    (List.filteri (fun i _ -> i < 2) (o2a_of t));
  ignore (Pk.step t);
  let n = ref 0 in
  while Pk.dispatch t do incr n done;
  Alcotest.(check int) "every percept dispatched" 4095 !n;
  Alcotest.(check bool) "none waiting: plain again" false (Pk.packed t);
  Alcotest.(check (list string)) "the object stays" [ "0" ] (o2a_of t);
  ignore (Pk.notify_event t (pv "position(7)") ~default:2 ~priority:None);
  Alcotest.(check (list string)) "plain again, a notify after the object" [ "0"; "position(7)/2/4096" ] (o2a_of t)

(* Packed, plain again, packed again with a percept already in the
   priority queue: it goes to a bucket before the one the last dispatch
   left off at, and Dequeue must find it there (the random hosts found
   this: an index out of bounds). *)
let packed_again_finds_top () =
  let env, _ = Typing.check [ Parse.string ~file:"bench.jade" bench_program ] in
  let pv text = fst (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" text)) in
  let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
  let p = Mc.default_params in
  let t = Pk.of_config ~pack_above:2 p (RM.init p ~world:a behs) in
  let notify text prio = ignore (Pk.notify_event t (pv text) ~default:prio ~priority:None) in
  let dispatched = ref [] in
  let drain () =
    let rec go () =
      if Pk.dispatch ~observe:(fun l w -> (match l with Mc.Dequeue e -> dispatched := Show.entry e :: !dispatched | _ -> ()); w) t
      then go () else match Pk.step t with Some _ -> go () | None -> () in
    go () in
  (* packed: falling and position; both dispatched, falling's bucket first *)
  notify "falling" 10; notify "position(1)" 2;
  Alcotest.(check bool) "packed at 2 waiting" true (Pk.packed t);
  drain ();
  Alcotest.(check bool) "plain again" false (Pk.packed t);
  (* plain: falling transferred into the priority queue, then a notify packs *)
  notify "falling" 10;
  (match Pk.step t with Some (Mc.Transfer 1) -> () | _ -> Alcotest.fail "a Transfer of one percept");
  notify "position(2)" 2;
  Alcotest.(check bool) "packed again" true (Pk.packed t);
  drain ();
  Alcotest.(check (list string)) "every percept, highest priority first"
    [ "falling/10/1"; "position(1)/2/2"; "falling/10/3"; "position(2)/2/4" ] (List.rev !dispatched)

(* The plain agent's run of notifies, unread until the Transfer: the step
   takes it as it waits (newest first, Fast.transfer_newest_first). Runs of
   1 to 40 percepts of every type and priority, NotifyWith among them, from
   an idle agent, against the reference. *)
let plain_run_transferred () =
  let env, _ = Typing.check [ Parse.string ~file:"bench.jade" bench_program ] in
  let texts = [| "falling"; "obstacle(3)"; "qrCodeRead(\"A7\")"; "position(9)"; "note(\"a\", 2, \"b\")"; "level(1.5)" |] in
  let pv i = Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" texts.(i mod Array.length texts)) in
  let rand = Random.State.make [| seed |] in
  List.iter (fun n ->
      let p = Mc.default_params in
      let agent () = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
      let (ar, br) = agent () and (ak, bk) = agent () in
      let c = ref (RM.init p ~world:ar br) in
      let t = Pk.of_config p (RM.init p ~world:ak bk) in
      let rec idle_ref () = match RM.step p !c with [] -> () | (_, c') :: _ -> c := c'; idle_ref () in
      let rec idle_packed () = match Pk.step t with None -> () | Some _ -> idle_packed () in
      for round = 1 to 3 do
        idle_ref (); idle_packed ();
        for _ = 1 to n do
          let i = Random.State.int rand 60 in
          let (v, default) = pv i in
          (* priorities below and beyond the plain agent's small ones (62) *)
          let priority = if i mod 5 = 0 then Some (if i mod 2 = 0 then i mod 11 else 50 + i) else None in
          (match RM.notify_event p !c v ~default ~priority with Ok c' -> c := c' | Error _ -> Alcotest.fail "refused");
          (match Pk.notify_event t v ~default ~priority with Ok () -> () | Error _ -> Alcotest.fail "refused")
        done;
        let lr = match RM.step p !c with [] -> "none" | (l, c') :: _ -> c := c'; Show.label l in
        let lk = match Pk.step t with None -> "none" | Some l -> Show.label l in
        Alcotest.(check string) (Printf.sprintf "run of %d, round %d: the label" n round) lr lk;
        Alcotest.(check string) (Printf.sprintf "run of %d, round %d: the configuration" n round)
          (Show.config !c) (Show.config (Pk.to_config t))
      done;
      Alcotest.(check bool) "plain" false (Pk.packed t))
    [ 1; 2; 5; 40 ]

(* An unobserved dispatch takes the handlers by plan; a body with effects
   hands the rest to the rules with the ids they reserve: here instance 1
   leaves and activates C while its handler is still the head of the
   snapshot, so C gets id 3, not 1 (ApplyEffects, NewId; R5g). *)
(* [b_takes]: the percept B's handler takes (ping: a plan of two handlers;
   pong: of one, A's, which [dispatch_run] takes without the general
   path); [by_run]: the dispatch as a run. *)
let reserves_ids ~b_takes ~by_run () =
  let text = String.concat "\n" [
      "ontology O";
      "\tproposition ping extends percept with priority = 3";
      "\tproposition pong extends percept with priority = 2";
      "";
      "agent Ag uses ontology O";
      "\tproperty n as integer = 0";
      "\ton create do";
      "\t\tactivate behaviour A";
      "\t\tactivate behaviour B";
      "";
      "cyclic behaviour A for agent Ag";
      "\ton percept when content matches ping do";
      "\t\tdeactivate this";
      "\t\tactivate behaviour C";
      "";
      "cyclic behaviour B for agent Ag";
      "\ton percept when content matches " ^ b_takes ^ " do";
      "\t\tn = n + 1";
      "";
      "cyclic behaviour C for agent Ag";
      "\ton percept when content matches ping do";
      "\t\tn = n + 10";
      "" ] in
  let env, diags = Typing.check [ Parse.string ~file:"ids.jade" text ] in
  if Typing.has_errors diags then Alcotest.fail "the program does not check";
  let pv = fst (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" "ping")) in
  let p = Mc.default_params in
  let agent () = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
  let (ar, br) = agent () and (ak, bk) = agent () in
  let c = ref (RM.init p ~world:ar br) in
  let t = Pk.of_config p (RM.init p ~world:ak bk) in
  let ref_step () = match RM.step p !c with [] -> None | (l, c') :: _ -> c := c'; Some l in
  c := RM.notify p !c pv 3; ignore (Pk.notify_event t pv ~default:3 ~priority:None);
  (match ref_step (), Pk.step t with
   | Some (Mc.Transfer 1), Some (Mc.Transfer 1) -> ()
   | _ -> Alcotest.fail "a Transfer of one percept on both");
  if by_run then Alcotest.(check int) "a run of one dispatch" 1 (Pk.dispatch_run t)
  else Alcotest.(check bool) "a dispatch, unobserved" true (Pk.dispatch t);
  let rec follow () = match ref_step () with
    | Some (Mc.End_dispatch _) -> () | Some _ -> follow () | None -> Alcotest.fail "no EndDispatch" in
  follow ();
  let ids (c : RM.t) = List.map (fun (a : Interp.Eval.beh Mc.instance) ->
      Printf.sprintf "%d:%s" a.id (Interp.Eval.beh_type a.beh)) c.active in
  Alcotest.(check (list string)) "the reference's ids" [ "2:B"; "3:C" ] (ids !c);
  Alcotest.(check string) "the same configuration" (Show.config !c) (Show.config (Pk.to_config t))
(* A codec that breaks encode_one's contract: it answers the int of any
   one-int percept, beyond 32 bits too. The packed agent must not trust it
   (a word has 32 bits for the int). *)
module Loose_codec = struct
  include Engine.Private.Percept_codec
  let encode_one c (p : V.t) = match p with
    | V.Schema { slots = [| (_, v) |]; _ } ->
      (match !v with
       | V.Int n -> (n lsl 20) lor encode c p (Ring.create ())
       | _ -> encode_one c p)
    | _ -> encode_one c p
end
module Pk_loose = Engine.Private.Packed.Make (CBm) (Loose_codec)

(* D39 on the bench program: words for a 32-bit int slot at both ends of
   its range, the long form for a slot beyond it and for a seq too far
   from its bucket's first; a priority as large as a host likes (it is
   the bucket's, not in the word); chunks crossed, and none moved by
   Transfer. *)
let packed_words () =
  let env, _ = Typing.check [ Parse.string ~file:"bench.jade" bench_program ] in
  let pv text = fst (Interp.Eval.percept_value env ~agent_type:"Ag" (Parse.expr ~file:"e" text)) in
  let position k = match pv "position(1)" with
    | V.Schema s -> V.Schema { s with slots = [| (fst s.slots.(0), ref (V.Int k)) |] }
    | _ -> Alcotest.fail "not a schema" in
  let agent ?word_x_limit ~chunk () =
    let p = Mc.default_params in
    let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
    Pk.of_config ~pack_above:0 ~chunk ?word_x_limit p (RM.init p ~world:a behs) in
  let o2a_of t = List.map (function Mc.O_percept e -> Show.entry e | Mc.O_object o -> V.to_literal o)
      (Semantics.Fqueue.to_list (Pk.to_config t).o2a) in
  let notify t ?prio v = ignore (Pk.notify_event t v ~default:2 ~priority:prio) in
  let dequeued t =
    let es = ref [] in
    while Pk.dispatch ~observe:(fun l w -> (match l with Mc.Dequeue e -> es := Show.entry e :: !es | _ -> ()); w) t do () done;
    List.rev !es in
  (* the agent's rules up to its Transfer *)
  let transfer t =
    let rec go n = match Pk.step t with
      | Some (Mc.Transfer _) -> ()
      | Some _ when n > 0 -> go (n - 1)
      | _ -> Alcotest.fail "no Transfer" in
    go 100 in
  let t = agent ~chunk:4 () in
  List.iter (fun k -> notify t (position k)) [ -2147483648; 2147483647; 2147483648; -2147483649; 0; 7 ];
  notify t ~prio:(1 lsl 26) (position 1);
  notify t ~prio:((1 lsl 26) - 1) (position 2);
  let o2a = [ "position(-2147483648)/2/1"; "position(2147483647)/2/2"; "position(2147483648)/2/3";
              "position(-2147483649)/2/4"; "position(0)/2/5"; "position(7)/2/6";
              "position(1)/67108864/7"; "position(2)/67108863/8" ] in
  Alcotest.(check (list string)) "O2A" o2a (o2a_of t);
  (* a word each, but two ints for a slot beyond 32 bits; each of the
     priorities 2^26 and 2^26 - 1 a bucket of its own, its first word *)
  Alcotest.(check int) "ints in O2A" 10 (Pk.ring_ints t);
  Alcotest.(check (option string)) "transfer" (Some "Transfer(8)") (Option.map Show.label (Pk.step t));
  Alcotest.(check int) "ints in the priority queue" 10 (Pk.ring_ints t);
  Alcotest.(check (list string)) "dequeued: the same percepts, highest first"
    (List.nth o2a 6 :: List.nth o2a 7 :: List.filteri (fun i _ -> i < 6) o2a) (dequeued t);
  (* words only for offsets 0 and 1: in the bucket, seqs 1 and 2 words,
     the others long, from their notify on; the bucket drained, its first
     seq is the next one pushed *)
  let t = agent ~chunk:4 ~word_x_limit:2 () in
  for k = 1 to 10 do notify t ~prio:1 (position k) done;
  Alcotest.(check int) "ints in O2A: 2 words, 8 long" 18 (Pk.ring_ints t);
  transfer t;
  Alcotest.(check int) "ints in the priority queue: the same" 18 (Pk.ring_ints t);
  Alcotest.(check (list string)) "dequeued in order"
    (List.init 10 (fun i -> Printf.sprintf "position(%d)/1/%d" (i + 1) (i + 1))) (dequeued t);
  for k = 11 to 13 do notify t ~prio:1 (position k) done;
  transfer t;
  Alcotest.(check int) "again from the bucket's new first seq: 2 words, 1 long" 4 (Pk.ring_ints t);
  Alcotest.(check (list string)) "dequeued in order, again"
    [ "position(11)/1/11"; "position(12)/1/12"; "position(13)/1/13" ] (dequeued t);
  (* a flood of 4,000 words in chunks of 8: 500 chunks; Transfer moves
     no int and makes no chunk *)
  let t = agent ~chunk:8 () in
  for k = 1 to 4000 do notify t (position k) done;
  Alcotest.(check int) "made for the notifies" 500 (Pk.chunks_made t);
  transfer t;
  Alcotest.(check int) "Transfer: no chunk made" 500 (Pk.chunks_made t);
  Alcotest.(check int) "every percept" 4000 (List.length (dequeued t));
  (* drained: the rings hold no chunk, the pool at most 8 *)
  if Pk.offheap_words t > 8 * 8 then Alcotest.failf "drained: %d words kept" (Pk.offheap_words t);
  (* the agent, not only the codec, keeps a word's int to 32 bits *)
  let (a, behs) = Interp.Eval.create_agent ~config:{ Interp.Eval.default_config with fuel = 500 } env ~name:"g" ~atype:"Ag" ~args:[] in
  let t = Pk_loose.of_config ~pack_above:0 ~chunk:4 Mc.default_params (RM.init Mc.default_params ~world:a behs) in
  List.iter (fun k -> ignore (Pk_loose.notify_event t (position k) ~default:2 ~priority:None))
    [ 2147483648; -2147483649; 5 ];
  Alcotest.(check int) "a loose codec: two long records and a word" 5 (Pk_loose.ring_ints t);
  Alcotest.(check (list string)) "a loose codec: the same percepts"
    [ "position(2147483648)/2/1"; "position(-2147483649)/2/2"; "position(5)/2/3" ]
    (List.map (function Mc.O_percept e -> Show.entry e | Mc.O_object o -> V.to_literal o)
       (Semantics.Fqueue.to_list (Pk_loose.to_config t).o2a))

let () =
  Alcotest.run "packed" [
    ("rings", [
        Alcotest.test_case "ring = a list, through growth and wrap-around" `Quick ring_model;
        Alcotest.test_case "a drained ring gives its array back" `Quick ring_shrink;
        Alcotest.test_case "D39 chunks used again, one copy" `Quick ring_chunks_reused ]);
    ("codec", [ Alcotest.test_case "D32 every kind of value round-trips" `Quick codec_round_trip ]);
    ("agent", [
        Alcotest.test_case "objects, growth, order, refusals" `Quick packed_agent_unit;
        Alcotest.test_case "D32 packed again, Dequeue finds the top bucket" `Quick packed_again_finds_top;
        Alcotest.test_case "a dispatch by plan reserves the ids the rules reserve" `Quick
          (reserves_ids ~b_takes:"ping" ~by_run:false);
        Alcotest.test_case "a run, one handler for the percept, reserves the ids too" `Quick
          (reserves_ids ~b_takes:"pong" ~by_run:true);
        Alcotest.test_case "a plain run of notifies transferred as it waits" `Quick plain_run_transferred;
        Alcotest.test_case "D39 words, the long form, chunks" `Quick packed_words;
        Alcotest.test_case "= reference, the bench's program and two more types, 60 hosts" `Quick packed_bench_program;
        qcheck ~count:150 ~long_factor:10 "D32 packed = reference after every operation"
          (QCheck.pair Typed_gen.arb_program QCheck.small_nat) packed_equals_reference ]);
  ]
