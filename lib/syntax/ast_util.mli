(** Operations on whole trees. *)

val strip : Ast.program -> Ast.program
(** The same tree with every region replaced by {!Source.no_region}: two programs
    that differ only in layout and comments strip to equal trees. *)

val strip_expr : Ast.expr -> Ast.expr

val dump : Ast.program -> string
(** The tree as an S-expression, one node per line with its [LINE:COL]
    ([jadescript-ref parse --ast]). *)
