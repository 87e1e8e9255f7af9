(** The judge of the oracle ({!Judge}, docs/trace-format.md, "Judging a
    run") on the page: a trace judged against the program and agents of a
    playground session, the session's own trace as it grows (the
    Concurrency tab) or a trace pasted from another implementation.

    {!Judge.judge} reads its trace from a file; the page has js_of_ocaml's
    file system in memory, so each function here writes the lines to
    [path] first (a path under [/static/] in the browser, a temporary
    file natively) and judges that file. *)

val session : path:string -> Session.t -> Judge.verdict
(** The session's trace so far ({!Session.trace}), judged against its
    program and agents with its fuel: a run of the finer interleaving
    (R6 revised, D45) is always one the rulings allow, so the answer is
    [Accepted]; [complete] once {!Session.finish} ended the run. *)

val text : path:string -> Session.t -> string -> Judge.verdict
(** A trace given as text (JSON lines, docs/trace-format.md), judged
    against the session's program and agents, as [jadescript-ref judge]
    judges a file: the first line the program does not explain, or
    acceptance. *)

val to_json : Judge.verdict -> Yojson.Safe.t
(** [{"accepted": true, "lines": N, "complete": B, "cut": B, "level": L}]
    or [{"accepted": false, "line": N, "message": M}] (lines counted from
    1, the header). *)
