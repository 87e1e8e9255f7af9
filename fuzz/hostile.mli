(** The hostile classes of the fuzz campaign (fuzz/README.md, "The
    hostile classes"): inputs at and past every documented limit, hostile
    names, big flat programs, pipes, FIFOs and paths that are not UTF-8,
    all through the command line; the JADE back end's Java through javac;
    and the interpreter against JADE on generated programs.

    Targets:
    - [hostile]: in turn, programs whose names are Java keywords, names of
      JADE's classes and members or the back end's own generated names
      ([check], [run], [compile --target jade]); expressions nested about
      the parser's 1,000 and the back end's 100; big flat programs (1,000
      behaviours and more, bodies of 20,000 statements, texts about Java's
      65,535 bytes and the interpreter's 1,000,000, 250 slots and more, names
      of 200 bytes and more); events files, traces for [validate],
      [vector.json] for [conform], scenarios for [sim] and TLA+ models for
      [explore], nested at and past the JSON reader's 1,000 or at and past
      their size limits (an events line of 16 MB, 2,000,000 sensor samples,
      a 1,000,000-percept flood, [--max-states]); the program or the events
      given as a pipe, a FIFO, or a path that is not UTF-8. The oracle is the
      command line's: exit 0 or 1, no signal, every line of standard error
      located, within the target's time; a trace written must be valid.
    - [jade]: a program of those names, a big flat one or one of
      {!Test_support.Typed_gen}: when [check] accepts it, [compile --target
      jade] either refuses it with a located line or writes Java that javac
      compiles against the runtime jar.
    - [differential]: a program of {!Test_support.Typed_gen} with a host of
      {!Test_support.Event_gen} run by the interpreter and by
      [scripts/jade-run] (JADE, lock step), judged by conform's oracle
      ({!Interp.Oracle.run_vector}): equal traces, [step] aside. *)

val targets : Inputs.target list
