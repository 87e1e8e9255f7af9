(** Random Jadescript programs that are well typed by construction, and single
    type-breaking mutations of them.

    A generated program has one ontology (concepts, percept predicates and a
    percept proposition with priorities, a percept subtype that inherits its
    priority, an action), one agent [Ag] using it (typed and inferred properties,
    an empty map whose type a later use decides, functions that return on every
    path, procedures, an [on create] that activates a behaviour), a cyclic
    behaviour [B for agent Ag] (percept handlers whose [when] is a [matches],
    message handlers, agent properties read directly and as [x of agent]),
    half the time extending a cyclic behaviour [BP] with percept handlers of
    its own (inherited handlers run first, R4a), and a one-shot behaviour
    [C] without [for agent]. Bodies
    declare locals by first assignment, loop over lists and maps, branch on
    [matches], call procedures and functions (only earlier ones: no
    recursion), send messages. Integers are given to [double] and [float]
    slots, parameters, typed locals and properties (they widen, R1c) and
    logged after; integers are compared with reals and schema values with
    copies made by their constructors (R1c), the outcomes logged.

    The programs are meant to run too (the interpreter reuses this generator):
    every loop terminates, nothing divides by anything but a non-zero literal,
    no map is read by key and no list by index. Regions are
    {!Syntax.Source.no_region}; {!Syntax.Print.program} prints them and the
    text parses back to the same tree. *)

val program : Syntax.Ast.program QCheck.Gen.t

val arb_program : Syntax.Ast.program QCheck.arbitrary
(** Printed with {!Syntax.Print.program}. *)

type mutation = {
  name : string;        (** what was broken, e.g. ["float op double"] *)
  fragment : string;    (** a fragment of the error message it must cause *)
  program : Syntax.Ast.program;
}

val mutate : Syntax.Ast.program -> mutation QCheck.Gen.t
(** One type-breaking change to a program made by {!program}: a wrong
    initialiser, a negative priority, a wrong or missing or extra argument, a
    [break] outside a loop, a missing [return], [invoke] on a non-[any], an
    unknown name, a message content of the wrong kind, a constructor pattern of
    the wrong arity, [float] op [double], a wrong assignment, [deactivate] or
    [content] in an agent, an empty list whose type nothing decides, a
    duplicate schema, an integer literal out of range. *)

val arb_mutated : (Syntax.Ast.program * mutation) QCheck.arbitrary

val mutation_names : string list

(** {1 Programs that hit the limits}

    Small well-typed programs whose percept handler (for [tick(n)], a
    percept of priority 3, handled by the cyclic behaviour [Work] of agent
    [Ag]) drives the interpreter to one of its limits: a recursion without
    end, a long mutual recursion, a long loop or loops nested three deep, a
    text that doubles, a map that grows, or a map of ever longer texts, hundreds of
    activations in one handler, an expression thousands of operators long or
    nested in parentheses up to the parser's bound, or
    simply many percepts, or a text literal holding invalid UTF-8 and control
    bytes (refused at the source, or escaped in the trace). A run must end each of them with a located
    exhaustion error (R7, D18) or normally, never with a crash, a signal
    or an exhausted machine. *)

type limit = {
  kind : string;   (** one of {!limit_kinds} *)
  size : int;      (** iterations, depth or growth steps *)
  text : string;   (** the program, Jadescript source *)
}

val limit_kinds : string list

val limit : limit QCheck.Gen.t
