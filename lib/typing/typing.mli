(** The type checker of jadescript-ref (docs/typing.md).

    [check] takes the parsed files of one program (declarations of every file
    are visible in every other; module names do not create namespaces) and
    returns the typed environment with every diagnostic, errors and warnings,
    sorted by position. It never raises: an internal failure is reported as a
    [Crash] diagnostic. *)

module Types = Types
module Tenv = Tenv

val check : Syntax.Parse.result list -> Tenv.t * Syntax.Diag.t list

val performatives : string list
(** The FIPA performatives the language knows: a host message (an events
    file) may carry only these. *)

val has_errors : Syntax.Diag.t list -> bool
(** Some diagnostic is an error (not a warning). *)
