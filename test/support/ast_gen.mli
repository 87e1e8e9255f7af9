(** Random syntax trees, for the printer/parser round trip.

    Every tree generated is one the parser can produce: identifiers are not
    keywords, integer literals outside patterns are not negative, blocks are not
    empty, an [invoke] appears only where the grammar allows it (a statement, the
    right side of an assignment or a property), features sit where the parser
    accepts them. Regions are {!Source.no_region}. *)

val program : Syntax.Ast.program QCheck.Gen.t
val expr : Syntax.Ast.expr QCheck.Gen.t

val arb_program : Syntax.Ast.program QCheck.arbitrary
(** Printed with {!Syntax.Print.program} when a property fails. *)
