(** The type checker: the rules of docs/typing.md, one function per syntactic
    category (the rule names of docs/typing.md appear in comments in check.ml).

    Phases: collect the declarations of every file ({!Tenv}); resolve
    ontologies, schemas (slots, supers, percept priorities), agent and
    behaviour headers (extends, for agent, visible ontologies) and signatures;
    check every feature of every agent and behaviour, inferring property types
    lazily (so a property may be used before its declaration is checked);
    finally report the empty collections whose type was never decided, and warn
    about unused properties and unreachable handlers. *)

val program : Syntax.Parse.result list -> Tenv.t * Syntax.Diag.t list
(** Checks the files as one program. Diagnostics are sorted by position.
    May raise only on a bug: {!Typing.check} catches that. *)

val performative_names : string list
(** The FIPA performatives the language knows ([inform], [request], ...),
    the only ones a message may carry. *)
