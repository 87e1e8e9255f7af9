(** The nesting limit of the syntax (decision D27, docs/syntax.md).

    Every stage after the parser (the printer, the type checker, the
    interpreter, the JADE back end) walks expressions, patterns and types by
    recursion, one stack frame or more per level. So that none of them can
    overflow the stack, the parser rejects a program whose expressions, patterns
    or types are nested more than {!max_depth} deep, with one located error at
    the first node that is too deep. Brackets and blocks have their own, smaller
    limit (200, in {!Layout}). *)

val max_depth : int
(** 1,000 levels (D27): [1 + 1 + ... + 1] with 1,000 operators, or
    [not not ... true] with 1,000 [not]s, is the most that is accepted. *)

val check_program : Ast.program -> unit
(** @raise Diag.Failed ([Syntax]) located at the start of the first expression,
    pattern or type that is nested more than {!max_depth} deep. The walk
    itself goes at most {!max_depth} levels down, so it cannot overflow. *)

val check_expr : Ast.expr -> unit
(** The same for one expression. *)
