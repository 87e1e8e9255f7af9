(** The reference controller: the paper's [RoboMe] agent
    ([examples/paper/robome_completed.jade]) written in OCaml on top of the
    executable semantics {!Semantics.Machine}, so that its loop follows the
    rulings (R2-R5) step by step and its runs can be checked against the
    TLA+ spec.

    - [on create]: [invoke "startListening"], activate [HandlePercepts],
      [do moveForward] ([callMoveForward]);
    - [HandlePercepts] (cyclic, no action block, no message handler), its
      percept handlers in declaration order:
      {ol
      {- [falling]: [callStop], [callMoveBackward], [callHeadTiltDown];}
      {- [obstacle]: [callStop], [callTurnLeft], [callMoveForward];}
      {- [qrCodeRead(qrCode)]: [worldMap[currentPosition] = qrCode];}
      {- [position(x, y)]: [currentPosition = position(x, y)].}}

    [currentPosition] starts at [position(0, 0)], as in the program. *)

include Agent.AGENT

type label = (Agent.percept, unit, unit) Semantics.Machine.label

val enable_log : t -> unit
(** Start recording the machine's labels (host notifications and agent
    steps), for trace validation ({!Trace_check}). Off by default. *)

val log : t -> label list
(** The labels recorded since {!enable_log}, in order. *)

val current_position : t -> float * float
