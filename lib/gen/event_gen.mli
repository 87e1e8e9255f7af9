(** Random host scenarios for a checked program: the agents the host creates,
    the events file it feeds them (docs/trace-format.md, written with
    {!Interp.Events.source_to_line}) and the run's options. Used by the fuzz
    campaign (fuzz/) on the programs of {!Typed_gen}.

    Every event is well formed for the program: a notify constructs one of
    the program's percept types (subtypes included) with literals of the
    slots' types (integers where a [double] is expected: widening, R1c),
    sometimes with a priority override (R2a: 0 included); a put carries a
    literal of any kind (R2c); a message from the host has one of the 22
    performatives of Jadescript (or none: [inform]), its content a schema
    value of a kind that performative carries (an action for [request],
    [cfp], ...; a predicate or proposition for [inform], [agree], ...), half of
    them arriving during the agent's next behaviour step
    (["during": "step"], D42, R5d revised). Runs are rounds ([{"run": K}]), single rules
    ([{"run": {"rules": K}}], D23) or until idle.
    Agents are one to three of ["g"], ["Bob"], ["provider"] (the names the
    programs of {!Typed_gen} send messages to), of the program's agent type;
    a parameter of type [any] gets the host object [@robome] or a literal.
    The options cover every loop variant, both tie policies, bounded and
    unbounded O2A capacities (R2d), round-robin and seeded schedules (R6),
    and fuel and step limits from tiny to generous. *)

type scenario = {
  agents : (string * string * string list) list;
      (** name, agent type, creation arguments as the command line writes
          them (Jadescript literals or [@robome]) *)
  events : Interp.Events.source list;
  variant : Semantics.Machine.variant;
  tie : Semantics.Machine.tie_policy;
  budget : int;
  capacity : int option;
  seed : int option;
  fuel : int;
  max_steps : int;
}

val performatives : string list
(** The performatives of Jadescript (lib/syntax/parser.mly), which the
    host's messages use. *)

val literal : Random.State.t -> Typing.Tenv.t -> Typing.Types.t -> string
(** A Jadescript literal of the type (schemas by their constructors, [aid]
    as [aid("…")]), in source form. *)

val scenario : Typing.Tenv.t -> agent_type:string -> scenario QCheck.Gen.t

val events_file : scenario -> string
(** The events file's text: one {!Interp.Events.to_line} per event. *)

val agent_args : scenario -> string list
(** The [--agent NAME:TYPE[:ARG,...]] values of [run]. *)

val run_args : scenario -> string list
(** The options of [run] the scenario sets ([--seed], [--variant], [--fuel],
    [--max-steps], [--o2a-capacity]; the tie policy and budget have no
    command-line option and are the defaults there). *)

val small_literal : Random.State.t -> Typing.Types.t -> string
(** A literal of the type from a few values (integers 0-4, decimals 0.5-4.5,
    texts "t0"-"t2", booleans, one-element lists; ["0"] otherwise), in
    Jadescript syntax: the random hosts of the test suites. *)

val percept_types : Typing.Tenv.t -> Typing.Tenv.schema list
(** The program's percept types. *)
