(** The page's entry point: installs [window.jsref], the playground engine
    ({!Playground_core.Session}, {!Playground_core.Examples},
    {!Playground_core.Replays}) for the page's script (playground/ui.js).
    Every function takes and returns strings (JSON where structured) and never
    throws: an OCaml exception becomes an error message. *)
