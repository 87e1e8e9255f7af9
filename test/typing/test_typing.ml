(* Tests of lib/typing and of the check command (docs/typing.md). *)

open Syntax
open Test_support
open Support

let parse file text =
  match Parse.string ~file text with
  | r -> r
  | exception Diag.Failed d -> Alcotest.failf "does not parse: %s" (Diag.to_string d)

let check_texts files =
  snd (Typing.check (List.map (fun (f, t) -> parse f t) files))

let errors ds = List.filter (fun d -> d.Diag.severity = Diag.Error) ds
let warnings ds = List.filter (fun d -> d.Diag.severity = Diag.Warning) ds
let show ds = String.concat "\n" (List.map Diag.to_string ds)

let contains s sub =
  let n = String.length s and m = String.length sub in
  let rec go i = i + m <= n && (String.sub s i m = sub || go (i + 1)) in
  go 0

(* ------------------------------------------------------------- examples *)

let examples_dir = Filename.concat root "examples"

let rec walk dir =
  Sys.readdir dir |> Array.to_list |> List.sort compare
  |> List.concat_map (fun f ->
      let p = Filename.concat dir f in
      if Sys.is_directory p then walk p else if Filename.check_suffix f ".jade" then [p] else [])

let paper f = Filename.concat examples_dir ("paper/" ^ f)
let shapes = List.map paper ["fig1_shapes_ontology.jade"; "fig2_shape_requester.jade";
                             "fig3_shape_behaviours.jade"]
let robome = List.map paper ["fig5_robome_ontology.jade"; "fig6_robome_agent.jade";
                             "fig7_handle_percepts.jade"]

(* The programs of examples/: the paper's split figures are one program each;
   every other file is a program of its own. *)
let example_programs =
  let grouped = shapes @ robome in
  [ ("paper figures 5-7 (RoboMe)", robome) ]
  @ List.filter_map (fun f -> if List.mem f grouped then None
                      else Some (Filename.basename f, [f])) (walk examples_dir)

let check_files files =
  snd (Typing.check (List.map (fun f -> parse f (read_file f)) files))

let example_cases =
  List.map (fun (name, files) ->
      Alcotest.test_case ("checks: " ^ name) `Quick (fun () ->
          let ds = errors (check_files files) in
          if ds <> [] then Alcotest.failf "%s" (show ds))) example_programs

let figure3_as_printed () =
  let ds = errors (check_files shapes) in
  match ds with
  | d :: _ ->
    Alcotest.(check string) "first error"
      (paper "fig3_shape_behaviours.jade" ^ ":5:47: error: unknown agent ShapeProvider in \
                                             'for agent ShapeProvider' of behaviour HandleShapeCreated")
      (Diag.to_string d)
  | [] -> Alcotest.fail "Figures 1-3 as printed should not check"

let robome_env () =
  let env, ds = Typing.check (List.map (fun f -> parse f (read_file f)) robome) in
  Alcotest.(check string) "no errors" "" (show (errors ds));
  let module E = Typing.Tenv in
  let prio s = match E.schema env s with Some s -> s.E.s_priority | None -> -1 in
  Alcotest.(check (list int)) "priorities (R1a)" [10; 8; 4; 2]
    (List.map prio ["falling"; "obstacle"; "qrCodeRead"; "position"]);
  let pty a x = match E.agent_property env a x with
    | Some p -> Typing.Types.to_string p.E.p_type | None -> "?" in
  Alcotest.(check string) "worldMap inferred from Figure 7" "map of position:text"
    (pty "RoboMe" "worldMap");
  Alcotest.(check string) "currentPosition" "position" (pty "RoboMe" "currentPosition");
  (match E.schema env "qrCodeRead" with
   | Some s ->
     Alcotest.(check bool) "percept" true s.E.s_percept;
     Alcotest.(check (list string)) "string = text (R1b)" ["qrCode: text"]
       (List.map (fun (x, t) -> x ^ ": " ^ Typing.Types.to_string t) s.E.s_slots)
   | None -> Alcotest.fail "qrCodeRead");
  match E.behaviour env "HandlePercepts" with
  | Some b ->
    Alcotest.(check (list string)) "sees RoboMe's ontology" ["RoboMeApplication"] b.E.b_visible;
    Alcotest.(check int) "three handlers" 3 (List.length (E.behaviour_handlers env "HandlePercepts"))
  | None -> Alcotest.fail "HandlePercepts"

(* ------------------------------------------------ ill-typed programs *)

let onto = {|ontology O
    concept position(x as double, y as double)
    predicate seen(p as position, label as text) extends percept with priority = 3
    proposition bump extends percept
    action move(dx as integer)
|}
(* [onto] is 5 lines: programs that use it start at line 6. *)

(* name, program, (line, text at the error's column), message fragment *)
let bad = [
  (* R5e revised, D43: ams's failure carries aid("NAME"), which a handler
     takes with on failure do but cannot match: a message's content is one
     of the ontology's propositions and predicates *)
  "a failure's content is not a pattern", {|ontology T
    proposition ping

agent C uses ontology T
    on create do
        activate behaviour Call

cyclic behaviour Call for agent C
    do
        send inform ping to aid("ghost")
    on failure when content matches aid(n) do
        log "no " + n
|}, (11, "aid(n)"), "unknown schema aid";
  "float op double", {|agent A
    property f as float = 1.5
    property d as double = 2.0
    on create do
        log f + d
|}, (5, "f + d"), "'+' on float and double: float does not widen to double";
  "integer property, text value", {|agent A
    property n as integer = "x"
|}, (2, "\"x\""), "the initial value of property n: expected integer, found text";
  "double does not narrow to integer", {|agent A
    property n as integer = 1.5
|}, (2, "1.5"), "expected integer, found double";
  "integer literal out of range", {|agent A
    property n = 2147483648
|}, (2, "2147483648"), "integer literal 2147483648 is out of range";
  "negative integer literal out of range", {|agent A
    property n = -2147483649
|}, (2, "2147483649"), "out of range";
  "unknown type", {|agent A
    property n as integr = 1
|}, (2, "integr"), "unknown type integr";
  "unknown name", {|agent A
    on create do
        log zz
|}, (3, "zz"), "unknown name zz";
  "unknown procedure", {|agent A
    on create do
        do fly
|}, (3, "fly"), "unknown procedure fly";
  "procedure arity", {|agent A
    procedure p with a as integer do
        log a
    on create do
        do p with 1, 2
|}, (5, "do p"), "procedure p expects 1 argument (a as integer), found 2";
  "procedure argument type", {|agent A
    procedure p with a as integer do
        log a
    on create do
        do p with "x"
|}, (5, "\"x\""), "argument a of procedure p: expected integer, found text";
  "procedure named argument unknown", {|agent A
    procedure p with a as integer do
        log a
    on create do
        do p with b = 1
|}, (5, "b = 1"), "procedure p has no parameter b";
  "function argument type", {|agent A
    function f(a as double) as double do
        return a
    on create do
        log f(true)
|}, (5, "true"), "argument a of function f: expected double, found boolean";
  "return type", {|agent A
    function f() as integer do
        return "x"
|}, (3, "\"x\""), "the value returned: expected integer, found text";
  "function without return on every path", {|agent A
    function f(a as integer) as integer do
        if a > 0 do
            return 1
|}, (2, "f("), "function f does not return a value on every path";
  "return with a value in a procedure", {|agent A
    procedure p do
        return 1
|}, (3, "return"), "only a function returns a value";
  "break outside a loop", {|agent A
    on create do
        break
|}, (3, "break"), "'break' is only allowed inside a loop";
  "continue outside a loop", {|agent A
    procedure p do
        if true do
            continue
|}, (4, "continue"), "'continue' is only allowed inside a loop";
  "constructor arity", onto ^ {|agent A uses ontology O
    property p = position(1)
|}, (7, "position"), "concept position expects 2 arguments (x as double, y as double), found 1";
  "constructor argument type", onto ^ {|agent A uses ontology O
    property p = position("a", 1)
|}, (7, "\"a\""), "argument x of concept position: expected double, found text";
  "invoke on a non-any", {|agent A
    on create do
        invoke "m" on 3
|}, (3, "3"), "invoke needs a host value of type any on the right of 'on', found integer";
  "any in arithmetic", {|agent A
    property h as any
    on create do
        log h + 1
|}, (4, "h + 1"), "'+' needs numbers (integer, float or double), found any and integer";
  "any converted to text", {|agent A
    property h as any
    on create do
        log "x" + h
|}, (4, "h"), "a value of type any cannot be converted to text";
  "the result of invoke is any", {|agent A
    property h as any
    property n as integer = invoke "read" on h
|}, (3, "invoke"), "the initial value of property n: expected integer, found any";
  "send to an integer", onto ^ {|agent A uses ontology O
    on create do
        send inform bump to 3
|}, (8, "3"), "a receiver of send: expected aid or list of aid, found integer";
  "request carries an action", onto ^ {|agent A uses ontology O
    on create do
        send request bump to aid("x")
|}, (8, "bump"), "the content of a request message: expected action, found bump";
  "inform carries a predicate or proposition", onto ^ {|agent A uses ontology O
    on create do
        send inform move(1) to aid("x")
|}, (8, "move"), "expected predicate or proposition, found move";
  "priority on a non-percept", {|ontology P
    predicate q(x as integer)
    predicate r(y as integer) extends q with priority = 1
|}, (3, "priority"), "'with priority' is only for percept types";
  "negative priority", {|ontology P
    proposition p extends percept with priority = -1
|}, (2, "-1"), "the priority of a percept type must be a natural number (0 or more) written as a literal, found -1";
  "duplicate ontology", {|ontology P
    concept a(x as integer)
ontology P
    concept b(x as integer)
|}, (3, "P"), "P is already declared at 1:10";
  "cyclic extends", {|ontology P
    concept a(x as integer) extends b
    concept b(y as integer) extends a
|}, (2, "b"), "schema a extends itself";
  "incompatible overriding slot", {|ontology P
    concept a(x as integer)
    concept b(x as text) extends a
|}, (3, "text"), "slot x overrides the slot of a with an incompatible type: expected integer (or a subtype), found text";
  "unknown slot type", {|ontology P
    concept a(x as blob)
|}, (2, "blob"), "unknown type blob";
  "concept extends percept", {|ontology P
    concept a(x as integer) extends percept
|}, (2, "percept"), "only predicates and propositions can extend percept";
  "with slot of the wrong type", {|ontology P
    concept a(x as integer)
    concept b extends a with x = "s"
|}, (3, "\"s\""), "the default of slot x: expected integer, found text";
  "schema not visible", onto ^ {|agent A
    property p as position
|}, (7, "position"), "schema position is not visible here";
  "unresolved empty map", {|agent A
    property m = {}
    on create do
        log size of m
|}, (2, "{}"), "cannot infer the type of this empty collection: nothing in the program decides its element type; write the type of property m (property m as map of K:V = ...)";
  "empty map used with two key types", {|agent A
    property m = {}
    on create do
        m["a"] = 1
        m[2] = 2
|}, (5, "2]"), "a map key: expected text, found integer";
  "matches binds only in the then branch", onto ^ {|agent A uses ontology O
    property p = position(1, 2)
    on create do
        if p matches position(a, b) do
            log a + b
        else do
            log a
|}, (12, "a"), "unknown name a";
  "matches under or binds nothing", onto ^ {|agent A uses ontology O
    property p = position(1, 2)
    on create do
        if p matches position(a, _) or true do
            log a
|}, (10, "a"), "unknown name a";
  "constructor pattern arity", onto ^ {|cyclic behaviour B uses ontology O
    on percept when content matches seen(a) do
        log a
|}, (7, "seen(a)"), "pattern seen(...) needs 2 sub-patterns, one per slot (p, label), found 1";
  "pattern that never matches", onto ^ {|cyclic behaviour B uses ontology O
    on percept when content matches move(n) do
        log n
|}, (7, "move"), "this pattern can never match: a value of type percept is never a move";
  "content outside a handler", {|agent A
    on create do
        log content
|}, (3, "content"), "'content' is only available in an 'on percept' or message handler";
  "message in a percept handler", {|cyclic behaviour B
    on percept do
        log sender of message
|}, (3, "message"), "'message' is only available in a message handler";
  "x of agent without for agent", {|agent A
    property n = 1
    on create do
        log n
cyclic behaviour B
    do
        log n of agent
|}, (7, "agent"), "'n of agent' needs to know the agent: add 'for agent A' to this behaviour";
  "agent property without for agent", {|agent A
    property n = 1
    on create do
        log n
cyclic behaviour B
    do
        log n
|}, (7, "n"), "unknown name n (a behaviour sees the properties of an agent only with 'for agent A')";
  "unknown for agent", {|cyclic behaviour B for agent Z
    do
        log 1
|}, (1, "Z"), "unknown agent Z";
  "activate: argument type", {|cyclic behaviour B
    on create with k as integer do
        log k
agent A
    on create do
        activate behaviour B with k = "x"
|}, (6, "\"x\""), "argument k of the on create of behaviour B: expected integer, found text";
  "activate: unknown parameter", {|cyclic behaviour B
    on create with k as integer do
        log k
agent A
    on create do
        activate behaviour B with k = 1, j = 2
|}, (6, "j = 2"), "the on create of behaviour B has no parameter j";
  "activate: missing parameter", {|cyclic behaviour B
    on create with k as integer do
        log k
agent A
    on create do
        activate behaviour B
|}, (6, "activate"), "missing argument k (as integer) of the on create of behaviour B";
  "activate by the wrong agent", {|agent A1
    on create do
        activate behaviour B
agent A2
    on create do
        activate behaviour B
cyclic behaviour B for agent A1
    do
        log 1
|}, (6, "B"), "behaviour B is for agent A1 and can be activated only by A1 agents, not by A2";
  "deactivate in an agent", {|agent A
    on create do
        deactivate this
|}, (3, "deactivate"), "'deactivate this' is only allowed in a behaviour";
  "condition not boolean", {|agent A
    on create do
        if 1 do
            log 1
|}, (3, "1"), "a condition: expected boolean, found integer";
  "while condition not boolean", {|agent A
    on create do
        while "x" do
            log 1
|}, (3, "\"x\""), "the condition of while: expected boolean, found text";
  "for over an integer", {|agent A
    on create do
        for i in 3 do
            log i
|}, (3, "3"), "'for' iterates over a list or a map, found integer";
  "comparing text with integer", {|agent A
    on create do
        log "a" < 1
|}, (3, "\"a\""), "'<' needs numbers (integer, float or double), found text and integer";
  "equality of unrelated types", {|agent A
    on create do
        log 1 = "a"
|}, (3, "1 ="), "'=' compares values of one type (one assignable to the other), found integer and text";
  "length of an integer", {|agent A
    on create do
        log length of 3
|}, (3, "length"), "integer has no 'length'";
  "unknown slot", onto ^ {|agent A uses ontology O
    property p = position(1, 2)
    on create do
        log z of p
|}, (9, "z of"), "concept position has no slot z";
  "read-only of", {|agent A
    property l = [1]
    on create do
        size of l = 3
|}, (4, "size"), "size of list of integer cannot be assigned: it is read-only";
  "local declared twice", {|agent A
    on create do
        x as integer = 1
        x as integer = 2
|}, (4, "x"), "local x is already declared at 3:9";
  "pattern variable shadows a local", onto ^ {|agent A uses ontology O
    property p = position(1, 2)
    on create do
        a = 1.0
        if p matches position(a, _) do
            log a
|}, (10, "a, _"), "pattern variable a would shadow the local a declared at 9:9";
  "unknown ontology", {|agent A uses ontology Nope
    on create do
        log 1
|}, (1, "Nope"), "unknown ontology Nope";
  "property redeclared in a subtype", {|agent A
    property n = 1
    on create do
        log n
agent B extends A
    property n = 2
|}, (6, "n"), "property n is already declared in A";
  "list elements of two types", {|agent A
    on create do
        log [1, "a"]
|}, (3, "\"a\""), "the elements of a list have one type: expected integer, found text";
  "modulo on text", {|agent A
    on create do
        log "a" % 2
|}, (3, "\"a\""), "'%' needs numbers";
  "indexing an integer", {|agent A
    on create do
        x = 3
        log x[0]
|}, (4, "x["), "only lists and maps can be indexed, and this is a integer";
  "activation by a behaviour without for agent", {|agent A
    on create do
        activate behaviour X
cyclic behaviour X
    do
        activate behaviour B
cyclic behaviour B for agent A
    do
        log 1
|}, (6, "B"), "but this behaviour does not say which agent runs it";
  "cyclic agents", {|agent A extends B
    on create do
        log 1
agent B extends A
    on create do
        log 2
|}, (1, "B"), "agent A extends itself";
  "property type depends on itself", {|agent A
    property a = b
    property b = a
|}, (2, "a"), "the type of property a depends on itself";
  "function called with do", {|agent A
    function f() as integer do
        return 1
    on create do
        do f
|}, (5, "f"), "f is a function: call it as f(...)";
  "procedure called as a function", {|agent A
    procedure p do
        log 1
    on create do
        log p()
|}, (5, "p("), "p is a procedure: call it with 'do p'";
  "aid of an integer", {|agent A
    on create do
        log aid(3)
|}, (3, "3"), "the argument of aid: expected text, found integer";
  "slot named priority in a percept", {|ontology P
    predicate p(priority as integer) extends percept
|}, (2, "priority"), "priority is the priority of every percept";
  "predicate extends concept", {|ontology P
    concept base(x as integer)
    predicate p(y as integer) extends base
|}, (3, "base"), "predicate p cannot extend concept base";
  "for agent of a subtype must agree", {|agent A
    on create do
        log 1
agent Other
    on create do
        log 2
cyclic behaviour B for agent A
    do
        log 1
cyclic behaviour C extends B for agent Other
    do
        log 2
|}, (10, "Other"), "behaviour C is for agent Other, but it extends B, which is for agent A";
  "type of a later-decided empty list used too early", {|agent A
    on create do
        xs = []
        log xs[0] + 1
        xs = [1]
|}, (4, "xs[0]"), "the type of this expression is not known here";
  "message content narrowed by when", onto ^ {|cyclic behaviour B uses ontology O
    on request when content matches move(d) do
        log label of content
|}, (8, "label"), "action move has no slot label";
  "assigning to an agent property through of", onto ^ {|agent A uses ontology O
    property n = 1
    on create do
        log n
        activate behaviour B
cyclic behaviour B for agent A
    on percept do
        n of agent = "x"
|}, (13, "\"x\""), "the value assigned to n of agent: expected integer, found text";
]

let line_col text (line, snippet) =
  let lines = String.split_on_char '\n' text in
  let l = List.nth lines (line - 1) in
  let n = String.length l and m = String.length snippet in
  let rec find i = if i + m > n then Alcotest.failf "test bug: %S not on line %d" snippet line
    else if String.sub l i m = snippet then i + 1 else find (i + 1) in
  (line, find 0)

let bad_case (name, text, where, fragment) =
  Alcotest.test_case ("rejects: " ^ name) `Quick (fun () ->
      let (line, col) = line_col text where in
      let ds = check_texts [("bad.jade", text)] in
      let hit = List.exists (fun d ->
          d.Diag.severity = Diag.Error && d.at.left.line = line && d.at.left.column = col
          && contains d.message fragment) ds in
      if not hit then
        Alcotest.failf "expected an error at %d:%d containing %S; got:\n%s" line col fragment (show ds))

(* ------------------------------------------------ well-typed programs *)

let good = [
  "Figure 4's 'x of agent' and direct use both check", onto ^ {|agent A uses ontology O
    property here as position
    on create do
        activate behaviour B
    procedure stop do
        log here
cyclic behaviour B for agent A
    on percept when content matches seen(p, l) do
        here of agent = p
        here = p
        do stop
|};
  "narrowing: content has the schema type in the body", onto ^ {|cyclic behaviour B uses ontology O
    on percept when content matches seen(p, _) and x of p > 0 do
        log label of content
        log priority of content + 1
    on percept do
        log priority of content
        if content matches bump do
            log "bump"
|};
  "integer widens to double and float, not the other way", {|agent A
    property d as double = 1
    property f as float = 2
    property g as float = 1.5
    on create do
        d = d + 1
        f = f * 2 + 0.5
        g = f
        log f * 0 + 0.5
        log d * 2 + 1
|};
  "empty collections typed by later use, maps and loops", {|agent A
    property m = {}
    property xs = []
    on create do
        m["a"] = [1, 2]
        xs = ["x"]
        for k in m do
            for v in m[k] do
                log k + v
        for s in xs do
            if s = "x" do
                break
        n = 0
        while n < 3 do
            n = n + 1
            continue
        log size of m + length of xs + size of keys of m + size of values of m
|};
  "messages, performatives and sender", onto ^ {|agent A uses ontology O
    property peers as list of aid = [aid("a"), aid("b")]
    on create do
        activate behaviour B
cyclic behaviour B for agent A
    on inform when content matches seen(p, l) do
        send inform seen(p, l + "!") to sender of message
        send request move(1) to peers
    on request do
        log "request"
    on message do
        deactivate this
|};
  "functions return on every path", {|agent A
    function sign(n as integer) as integer do
        if n > 0 do
            return 1
        else if n < 0 do
            return -1
        else do
            return 0
    function forever() as integer do
        while true do
            log 1
    on create do
        log sign(3) + forever()
|};
  "invoke and any", {|agent A
    property h as any
    property r = invoke "read" on h
    on create with iface as any do
        h = iface
        invoke "go" on h with 1, "x", 2.5
        log h = r
|};
  "-2147483648 is an integer", {|agent A
    property n = -2147483648
    on create do
        log n
|};
  "agent and behaviour inheritance", onto ^ {|agent Base uses ontology O
    property level = 1
    procedure up do
        level = level + 1
agent Robot extends Base
    on create do
        do up
        activate behaviour Watch with start = level
cyclic behaviour Watch for agent Base
    property seenCount as integer = 0
    on create with start as integer do
        seenCount = start
    on percept when content matches bump do
        seenCount = seenCount + seenCount of this
        do up
|};
  "string is text (R1b) and percept values are values (R1c)", onto ^ {|agent A uses ontology O
    property s as string = "x"
    property t as text = s
    property places = {position(0, 0): "origin"}
    on create do
        places[position(1, 2.5)] = t
        log seen(position(1, 1), s) = seen(position(1.0, 1.0), t)
|};
  "percept subtypes inherit priority (R1a)", {|ontology P
    predicate base(x as integer) extends percept with priority = 5
    predicate sub(y as integer) extends base
    proposition flag extends percept
cyclic behaviour B uses ontology P
    on percept when content matches sub(a, b) do
        log a + b + priority of content
    on percept when content matches base(a) do
        log a
|};
]

let good_case (name, text) =
  Alcotest.test_case ("accepts: " ^ name) `Quick (fun () ->
      let ds = errors (check_texts [("good.jade", text)]) in
      if ds <> [] then Alcotest.failf "%s" (show ds))

let priorities () =
  let env, _ = Typing.check [parse "p.jade" (List.assoc "percept subtypes inherit priority (R1a)" good)] in
  let module E = Typing.Tenv in
  let p s = match E.schema env s with Some s -> (s.E.s_priority, s.E.s_slots |> List.map fst) | None -> (-1, []) in
  Alcotest.(check (pair int (list string))) "sub inherits 5, slots inherited first" (5, ["x"; "y"]) (p "sub");
  Alcotest.(check int) "root default 0" 0 (fst (p "flag"))

(* ----------------------------------------------------------- warnings *)

let warnings_case () =
  let text = onto ^ {|agent A uses ontology O
    property unused = 1
    property used = 2
    on create do
        log used
cyclic behaviour B uses ontology O
    on inform do
        log 1
    on inform when content matches bump do
        log 2
    on request do
        log 3
|} in
  let ds = check_texts [("w.jade", text)] in
  Alcotest.(check string) "no errors" "" (show (errors ds));
  Alcotest.(check (list string)) "warnings, sorted"
    [ "w.jade:7:14: warning: property unused of A is never read";
      "w.jade:14:5: warning: this handler is unreachable: the handler at 12:5 takes every inform message first (R5b)" ]
    (List.map Diag.to_string (warnings ds))

let several_files () =
  let a = ("a.jade", onto) and b = ("b.jade", "agent A uses ontology O\n    property p = position(1, 2)\n    on create do\n        log p\n") in
  Alcotest.(check string) "declarations of one file visible in another" "" (show (errors (check_texts [a; b])));
  let ds = errors (check_texts [a; b; ("c.jade", "ontology O\n    concept z(x as integer)\n")]) in
  Alcotest.(check bool) "duplicate across files" true
    (List.exists (fun d -> contains (Diag.to_string d) "c.jade:1:10: error: O is already declared at a.jade:1:10") ds)

let sorted_all () =
  let text = {|agent A
    on create do
        log zz
        log 1 + "a" * 2
        break
|} in
  let ds = check_texts [("s.jade", text)] in
  Alcotest.(check (list string)) "every error, by position"
    [ "s.jade:3:13: error: unknown name zz";
      "s.jade:4:17: error: '*' needs numbers (integer, float or double), found text and integer";
      "s.jade:5:9: error: 'break' is only allowed inside a loop ('while' or 'for')" ]
    (List.map Diag.to_string ds)

(* ---------------------------------------------------------------- CLI *)

let tmp_file name text =
  let dir = Filename.concat (Filename.get_temp_dir_name ()) "jsref-typing" in
  (try Sys.mkdir dir 0o755 with Sys_error _ -> ());
  let p = Filename.concat dir name in
  let oc = open_out_bin p in output_string oc text; close_out oc; p

let cli () =
  let q = Filename.quote in
  let (st, _, err) = run_command (Printf.sprintf "%s check %s" (q exe)
                                    (String.concat " " (List.map q shapes))) in
  Alcotest.(check int) "figures 1-3 as printed: exit 1" 1 st;
  Alcotest.(check bool) "the diagnostic" true (contains err "fig3_shape_behaviours.jade:5:47: error: unknown agent ShapeProvider");
  let corrected = Filename.concat examples_dir "typing/shapes_corrected.jade" in
  let (st, _, err) = run_command (Printf.sprintf "%s check %s" (q exe) (q corrected)) in
  Alcotest.(check int) "corrected: exit 0 (warnings only)" 0 st;
  Alcotest.(check bool) "a warning" true (contains err "warning: property myShape of ShapeRequester is never read");
  let (st, _, err) = run_command (Printf.sprintf "%s check --no-warnings %s" (q exe) (q corrected)) in
  Alcotest.(check (pair int string)) "--no-warnings" (0, "") (st, err);
  let good = tmp_file "good.jade" "agent A\n    on create do\n        log 1\n" in
  let broken = tmp_file "broken.jade" "agent B\n    on create do\n        log (\n" in
  let bad = tmp_file "bad.jade" "agent C\n    on create do\n        log zz\n        log 1 + true\n" in
  let (st, out, err) = run_command (Printf.sprintf "%s check %s %s %s" (q exe) (q good) (q broken) (q bad)) in
  Alcotest.(check int) "exit 1" 1 st;
  Alcotest.(check string) "nothing on stdout" "" out;
  let lines = List.filter (( <> ) "") (String.split_on_char '\n' err) in
  Alcotest.(check int) "a syntax error and two type errors, one line each" 3 (List.length lines);
  Alcotest.(check bool) "the file that parses is still checked" true
    (List.exists (fun l -> contains l "bad.jade:3:13: error: unknown name zz") lines);
  Alcotest.(check bool) "no backtrace" false (contains err "Raised at")

(* ---------------------------------------------------- generated programs *)

let generated_check p =
  let ds = errors (snd (Typing.check [{ Parse.program = p; comments = [] }])) in
  if ds <> [] then QCheck.Test.fail_reportf "%s" (show ds) else true

let generated_round_trip p =
  let text = Print.program p in
  let r = match Parse.string ~file:"gen.jade" text with
    | r -> r
    | exception Diag.Failed d -> QCheck.Test.fail_reportf "does not parse: %s" (Diag.to_string d) in
  if Ast_util.strip r.program <> Ast_util.strip p then QCheck.Test.fail_report "parse (print p) <> p";
  let ds = errors (snd (Typing.check [r])) in
  if ds <> [] then QCheck.Test.fail_reportf "%s" (show ds) else true

let mutated (_, (m : Typed_gen.mutation)) =
  let text = Print.program m.program in
  let r = match Parse.string ~file:"mut.jade" text with
    | r -> r
    | exception Diag.Failed d -> QCheck.Test.fail_reportf "does not parse: %s" (Diag.to_string d) in
  let ds = errors (snd (Typing.check [r])) in
  if ds = [] then QCheck.Test.fail_report "the mutated program checks"
  else if not (List.exists (fun d -> contains d.Diag.message m.fragment) ds) then
    QCheck.Test.fail_reportf "no error contains %S:\n%s" m.fragment (show ds)
  else true

let every_mutation () =
  (* each mutation of the catalogue, on a few programs *)
  let rs = Random.State.make [| seed |] in
  for _ = 1 to 5 do
    let p = Typed_gen.program rs in
    List.iter (fun name ->
        let rec find k =
          let m = Typed_gen.mutate p rs in
          if m.name = name || k = 0 then m else find (k - 1) in
        let m = find 500 in
        ignore (mutated (p, m))) Typed_gen.mutation_names
  done

(* The constructs the generator makes so that five defects of the bug
   catalogue can show (conformance/README.md), counted over 200 programs
   and their hosts: a behaviour that extends another, with percept handlers
   in both (R4a); an integer literal or integer arithmetic given to a double
   or float slot, parameter, local or property (R1c: it widens); such an
   integer compared with a real (R1c); a schema value compared with one made
   by its constructor (R1c: structural equality); a host message with
   "during": "step" (D42). Found in the tree by the test's own reading of
   it: an expression counts as an integer or a real only when its literals
   say so. *)
let rec surely_int (e : Ast.expr) = match e.it with
  | Ast.Lit (Ast.Int _) -> true
  | Ast.Unop (Ast.Neg, a) -> surely_int a
  | Ast.Binop ((Ast.Add | Ast.Sub | Ast.Mul | Ast.Div | Ast.Mod), a, b) -> surely_int a && surely_int b
  | Ast.Of ({ it = "length" | "size"; _ }, _) -> true
  | _ -> false

let rec surely_real (e : Ast.expr) = match e.it with
  | Ast.Lit (Ast.Real _) -> true
  | Ast.Binop ((Ast.Add | Ast.Sub | Ast.Mul), a, b) ->
    (surely_real a && (surely_real b || surely_int b)) || (surely_int a && surely_real b)
  | _ -> false

let constructs (p : Ast.program) =
  let real (t : Ast.ty) = match t.it with Ast.TName ("double" | "float") -> true | _ -> false in
  (* the names whose arguments, by position, are real: schemas, functions,
     procedures, behaviours' on create; the real properties *)
  let real_args = Hashtbl.create 16 and real_props = Hashtbl.create 16 and percept_handlers = Hashtbl.create 4 in
  let feature_sigs owner (f : Ast.feature) = match f.it with
    | Ast.Function { name; params; _ } | Ast.Procedure { name; params; _ } ->
      Hashtbl.replace real_args name.it (List.map (fun (q : Ast.param) -> (q.pname.it, real q.pty)) params)
    | Ast.OnCreate { params; _ } ->
      Hashtbl.replace real_args owner (List.map (fun (q : Ast.param) -> (q.pname.it, real q.pty)) params)
    | Ast.Property { name; ty = Some t; _ } when real t -> Hashtbl.replace real_props name.it ()
    | Ast.OnPercept _ -> Hashtbl.replace percept_handlers owner ()
    | _ -> () in
  List.iter (fun (d : Ast.decl) -> match d.it with
      | Ast.DOntology o -> List.iter (fun (s : Ast.schema) ->
          Hashtbl.replace real_args s.it.sname.it
            (List.map (fun (sl : Ast.slot) -> (sl.slot_name.it, real sl.slot_ty)) s.it.slots)) o.schemas
      | Ast.DAgent a -> List.iter (feature_sigs a.aname.it) a.afeatures
      | Ast.DBehaviour b -> List.iter (feature_sigs b.bname.it) b.bfeatures) p.decls;
  (* slots of a schema that extends another come after the parent's: the
     generator's own q2 and q3 repeat q1's x, a double, first *)
  let schema_names = Hashtbl.create 8 in
  List.iter (fun (d : Ast.decl) -> match d.it with
      | Ast.DOntology o -> List.iter (fun (s : Ast.schema) -> Hashtbl.replace schema_names s.it.sname.it ()) o.schemas
      | _ -> ()) p.decls;
  let widened = ref false and int_real = ref false and schema_eq = ref false in
  let widen_into flags args =
    (* positional: flags and args in order *)
    let rec go fl ar = match fl, ar with
      | (_, true) :: fl, a :: ar -> if surely_int a then widened := true; go fl ar
      | _ :: fl, _ :: ar -> go fl ar
      | _ -> () in
    go flags args in
  let rec expr (e : Ast.expr) =
    (match e.it with
     | Ast.Call (f, args) ->
       (match Hashtbl.find_opt real_args f.it with Some fl -> widen_into fl args | None -> ())
     | Ast.Binop ((Ast.Eq | Ast.Neq | Ast.Lt | Ast.Gt | Ast.Le | Ast.Ge) as op, a, b) ->
       if (surely_int a && surely_real b) || (surely_real a && surely_int b) then int_real := true;
       let schema_value (x : Ast.expr) = match x.it with
         | Ast.Call (s, _) -> Hashtbl.mem schema_names s.it
         | Ast.Name s -> Hashtbl.mem schema_names s
         | _ -> false in
       if (op = Ast.Eq || op = Ast.Neq) && (schema_value a || schema_value b) then schema_eq := true
     | _ -> ());
    match e.it with
    | Ast.Lit _ | Ast.Name _ | Ast.This | Ast.Agent | Ast.Content | Ast.Message -> ()
    | Ast.List l -> List.iter expr l
    | Ast.Map l -> List.iter (fun (k, v) -> expr k; expr v) l
    | Ast.Call (_, l) -> List.iter expr l
    | Ast.Index (a, b) | Ast.Binop (_, a, b) -> expr a; expr b
    | Ast.Of (_, a) | Ast.Matches (a, _) | Ast.Unop (_, a) -> expr a
    | Ast.Invoke i -> expr i.target; List.iter expr i.args in
  let rec stmt (s : Ast.stmt) = match s.it with
    | Ast.Assign (lv, e) ->
      (match lv.it with
       | Ast.LName x when Hashtbl.mem real_props x && surely_int e -> widened := true
       | Ast.LName _ -> ()
       | Ast.LOf (_, a) -> expr a
       | Ast.LIndex (a, b) -> expr a; expr b);
      expr e
    | Ast.Local (_, t, e) -> if real t && surely_int e then widened := true; expr e
    | Ast.Do (pr, args) ->
      (match args, Hashtbl.find_opt real_args pr.it with
       | Ast.Positional l, Some fl -> widen_into fl l
       | Ast.Named l, Some fl ->
         List.iter (fun ((x : Ast.name), a) -> if List.assoc_opt x.it fl = Some true && surely_int a then widened := true) l
       | _ -> ());
      (match args with Ast.Positional l -> List.iter expr l | Ast.Named l -> List.iter (fun (_, a) -> expr a) l)
    | Ast.Activate (b, l) ->
      (match Hashtbl.find_opt real_args b.it with
       | Some fl -> List.iter (fun ((x : Ast.name), a) -> if List.assoc_opt x.it fl = Some true && surely_int a then widened := true) l
       | None -> ());
      List.iter (fun (_, a) -> expr a) l
    | Ast.InvokeS i -> expr i.target; List.iter expr i.args
    | Ast.Send (_, c, r) -> expr c; List.iter expr r
    | Ast.Log e | Ast.Return (Some e) -> expr e
    | Ast.If (bs, els) -> List.iter (fun (c, b) -> expr c; List.iter stmt b) bs; Option.iter (List.iter stmt) els
    | Ast.While (c, b) | Ast.For (_, c, b) -> expr c; List.iter stmt b
    | Ast.Nothing | Ast.Deactivate | Ast.Return None | Ast.Break | Ast.Continue -> () in
  let feature (f : Ast.feature) = match f.it with
    | Ast.Property { ty; init = Some e; _ } ->
      (match ty with Some t when real t && surely_int e -> widened := true | _ -> ());
      expr e
    | Ast.Property { init = None; _ } -> ()
    | Ast.Function { body; _ } | Ast.Procedure { body; _ } | Ast.OnCreate { body; _ } | Ast.OnDestroy body
    | Ast.ActionSection body -> List.iter stmt body
    | Ast.OnPercept { guard; body } | Ast.OnMessage { guard; body; _ } -> Option.iter expr guard; List.iter stmt body in
  List.iter (fun (d : Ast.decl) -> match d.it with
      | Ast.DOntology _ -> ()
      | Ast.DAgent a -> List.iter feature a.afeatures
      | Ast.DBehaviour b -> List.iter feature b.bfeatures) p.decls;
  let extends = List.exists (fun (d : Ast.decl) -> match d.it with
      | Ast.DBehaviour { bname; bextends = Some parent; _ } ->
        Hashtbl.mem percept_handlers bname.it && Hashtbl.mem percept_handlers parent.it
      | _ -> false) p.decls in
  [ ("a behaviour extending one, percept handlers in both (R4a)", extends);
    ("an integer widened into a real slot, parameter, local or property (R1c)", !widened);
    ("an integer compared with a real (R1c)", !int_real);
    ("a schema value compared with = or <> (R1c)", !schema_eq) ]

let generated_constructs () =
  let n = 200 in
  let counts = Hashtbl.create 8 in
  let bump k = Hashtbl.replace counts k (1 + Option.value (Hashtbl.find_opt counts k) ~default:0) in
  for k = 1 to n do
    let rs = Random.State.make [| 7; k |] in
    let p = Typed_gen.program rs in
    List.iter (fun (c, present) -> if present then bump c else Hashtbl.replace counts c
                   (Option.value (Hashtbl.find_opt counts c) ~default:0)) (constructs p);
    let env, _ = Typing.check [ Parse.string ~file:"gen.jade" (Print.program p) ] in
    let sc = Event_gen.scenario env ~agent_type:"Ag" rs in
    let during = List.exists (function
        | Interp.Events.Message_text { during_step; _ } -> during_step | _ -> false) sc.events in
    let c = "a host message during a step (D42)" in
    if during then bump c else Hashtbl.replace counts c (Option.value (Hashtbl.find_opt counts c) ~default:0)
  done;
  (* each in at least one program in ten: the defects run (conform
     --generated, 1,000 programs) then meets each many times *)
  Hashtbl.iter (fun c m -> Printf.printf "%s: %d of %d programs\n" c m n) counts;
  Hashtbl.iter (fun c m ->
      if m < n / 10 then Alcotest.failf "%s: in %d of %d generated programs, expected at least %d" c m n (n / 10))
    counts;
  Alcotest.(check int) "five constructs counted" 5 (Hashtbl.length counts)

let robust =
  (* random (mostly ill-typed) trees: the checker never raises, never crashes *)
  Support.qcheck ~count:300 "random trees: no exception, no crash" Ast_gen.arb_program (fun p ->
      let _, ds = Typing.check [{ Parse.program = p; comments = [] }] in
      not (List.exists (fun d -> d.Diag.kind = Diag.Crash) ds))

(* A tree deeper than the parser allows (D27) can still reach the checker
   from elsewhere (a generator, the playground): it never raises, and its
   diagnostic is located in the program's file, not at ":0:0". *)
let deep_tree_located () =
  let r = Parse.string ~file:"deep.jade" "agent A\n\ton create do\n\t\tlog true\n" in
  let rec deepen n (e : Ast.expr) = if n = 0 then e else deepen (n - 1) { e with it = Ast.Unop (Ast.Not, e) } in
  let rec map_stmt (st : Ast.stmt) = match st.it with
    | Ast.Log e -> { st with it = Ast.Log (deepen 1_000_000 e) }
    | _ -> st
  and map_feature (f : Ast.feature) = match f.it with
    | Ast.OnCreate c -> { f with it = Ast.OnCreate { c with body = List.map map_stmt c.body } }
    | _ -> f in
  let decls = List.map (fun (d : Ast.decl) -> match d.it with
      | Ast.DAgent a -> { d with it = Ast.DAgent { a with afeatures = List.map map_feature a.afeatures } }
      | _ -> d) r.program.decls in
  let r = { r with program = { r.program with decls } } in
  let _, ds = Typing.check [ r ] in
  Alcotest.(check int) "one diagnostic" 1 (List.length ds);
  List.iter (fun d ->
      let l = Diag.to_string d in
      Alcotest.(check bool) ("located in deep.jade: " ^ l) true
        (String.length l > 9 && String.sub l 0 9 = "deep.jade" && d.Diag.at.left.line > 0)) ds

let () =
  Alcotest.run "typing" [
    ("examples", example_cases @ [
        Alcotest.test_case "Figures 1-3 as printed do not check" `Quick figure3_as_printed;
        Alcotest.test_case "RoboMe's typed environment" `Quick robome_env ]);
    ("ill-typed", List.map bad_case bad);
    ("well-typed", List.map good_case good @ [
        Alcotest.test_case "percept priorities and slots" `Quick priorities;
        Alcotest.test_case "a tree too deep for the stack: a located line" `Quick deep_tree_located ]);
    ("diagnostics", [
        Alcotest.test_case "warnings" `Quick warnings_case;
        Alcotest.test_case "several files, one program" `Quick several_files;
        Alcotest.test_case "all errors, sorted" `Quick sorted_all;
        Alcotest.test_case "check command" `Quick cli ]);
    ("generated", [
        Support.qcheck ~count:200 "well-typed by construction: checks" Typed_gen.arb_program generated_check;
        Support.qcheck ~count:200 "print, parse back, check" Typed_gen.arb_program generated_round_trip;
        Support.qcheck ~count:300 "one mutation: rejected with its message" Typed_gen.arb_mutated mutated;
        Alcotest.test_case "every mutation of the catalogue" `Quick every_mutation;
        Alcotest.test_case "the constructs five defects need (R1c, R4a, D42)" `Quick generated_constructs;
        robust ]);
  ]
