(** The page's entry point: installs [window.jsref], the playground engine
    ({!Playground_core.Session}, {!Playground_core.Judging}, {!Playground_core.Examples},
    {!Playground_core.Replays}, {!Playground_core.Exercises},
    {!Playground_core.Glossary}) for the page's scripts (playground/ui.js and
    the scripts beside it). One session per slot ([use]): each tab of the
    page keeps its own.
    Every function takes and returns strings (JSON where structured) and never
    throws: an OCaml exception becomes an error message. *)
