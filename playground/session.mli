(** A playground session: a checked program, its agents and the host, run on
    the project's machine ({!Semantics.Machine}, {!Semantics.Platform}) and
    evaluator ({!Interp.Eval}) one rule at a time, with its trace and with
    every step undoable.

    The run is the one [jadescript-ref run] makes: the same agent creation,
    host rules, rounds (R6: round-robin in creation order, or a seeded order)
    and loop iterations, and the trace written line for line as
    [jadescript-ref run --trace] writes it (docs/trace-format.md), except that
    nothing runs on its own: the student takes each rule ({!step}), a whole
    iteration ({!iteration}) or runs until every agent is idle ({!run_idle}),
    and may act as the host between any two rules. The test
    [test/browser/test_playground_engine.ml] holds the trace to the
    command line's on every conformance vector.

    Stepping back ({!back}) replays the session from its start without its
    last command: the agents' state is mutable (properties, lists, maps), so a
    replay is the one faithful undo. *)

(** {1 Setting up} *)

type setup = {
  files : (string * string) list;   (** the program: file names and texts *)
  agents : string list;             (** [NAME:TYPE[:ARG,...]], as [run --agent] *)
  variant : Semantics.Machine.variant;
  tie : Semantics.Machine.tie_policy;
  budget : int;                     (** dispatches per iteration of [budgeted] *)
  o2a_capacity : int option;        (** R2d *)
  seed : int option;                (** [None]: round-robin (R6) *)
  fuel : int;                       (** statements per handler or step (R7) *)
  max_steps : int;                  (** agent rules in the whole session *)
  interleave : int option;
      (** [Some seed]: the finer interleaving of R6 revised (D45), for the
          page's Concurrency tab: the student gives any agent its next rule
          ({!rule_of}), a message between agents stays in flight until it is
          made to arrive ({!arrival}), possibly during its receiver's
          behaviour step (SendInStep, R5d revised), and {!draw} draws one
          of these from the seed. [None]: run's schedule (the rest of this
          interface) *)
}

val default_setup : setup
(** No files, no agents, the reference loop, stable ties, budget 1, unbounded
    O2A, round-robin, [run]'s fuel (100,000) and step limit (1,000,000), run's
    schedule (no [interleave]). *)

val check : (string * string) list -> string list
(** The program's diagnostics, errors and warnings, sorted, one line each as
    [jadescript-ref check] prints them ([FILE:LINE:COL: error: message]). *)

(** {1 A session} *)

type t

val create : setup -> (t, string list) result
(** Checks the program and creates the agents in order (R5g), writing the
    trace header and the [create] events. [Error] with the diagnostics (as
    {!check} gives them, errors only) or the problem with an agent's
    specification ([--agent NAME:TYPE: error: ...]); never raises. *)

val setup : t -> setup

(** {1 The host} *)

type host_action =
  | Notify of { agent : string; percept : string; priority : int option }
      (** [notifyEvent(p)], or [notifyEvent(p, k)] with a priority (R2) *)
  | Put of { agent : string; obj : string }    (** an object into O2A (R2c) *)
  | Message of { agent : string; perf : string; content : string; during : bool }
      (** a message from the host (R5e); [during]: it arrives during the
          agent's next behaviour step, after its handlers looked (an events
          file's ["during": "step"], D42): with SendInStep (R5d revised) *)

val host : t -> host_action -> (unit, string) result
(** Does the host action between two rules. Percepts, objects and contents
    are Jadescript, as in an events file. [Error] (nothing done, nothing
    recorded) for a text that does not parse or does not fit
    ([notify:1:COL: error: message]), an unknown agent, a negative priority or
    a full O2A queue (R2d: the refusal is in the trace, as [run] records it). *)

(** {1 The agents} *)

type outcome =
  | Stepped            (** a rule was taken *)
  | All_idle           (** nothing to do: every agent is idle *)
  | Limit              (** [max_steps] rules were taken *)

val next_agent : t -> int option
(** The agent whose rule {!step} takes next (the one in the middle of an
    iteration, else the next of the round that is not idle), [None] when all
    are idle. Draws nothing from the seed. *)

val choices : t -> string list
(** The rules enabled for {!next_agent}, described; more than one only for a
    Dequeue under unstable ties. *)

val step : ?choice:int -> t -> outcome
(** One rule of the next agent: [choice] (from 0, default 0) picks among
    {!choices}; an index out of range takes the first. *)

val iteration : t -> outcome
(** Rules until the current (or next) agent's iteration ends: its
    BehaviourStep, NextIteration or Idle. *)

val run_idle : ?limit:int -> t -> int * outcome
(** Rules until every agent is idle, [max_steps], or [limit] rules in this
    call (default 5,000: the printed loop never idles, D4). Returns the
    number of rules taken and why it stopped ([Stepped] when the limit
    stopped it). *)

val run_rounds : t -> int -> unit
(** [n] rounds, as [{"run": n}] of an events file: in each, every agent that
    is not idle runs one iteration (the iteration in progress is finished
    first). D20, as [run]: the rounds stop when every agent is idle, at the
    step limit, or after a round that took no step. *)

val run_rules : t -> int -> unit
(** [n] single rules, as [{"run": {"rules": n}}] of an events file (D23):
    each by the first agent in creation order that is not idle; fewer when
    every agent is idle. *)

val back : t -> bool
(** Undoes the last command (a rule or a host action) by replaying the
    session from its start; [false] when there is nothing to undo. *)

val history_length : t -> int
(** Commands done so far (rules and host actions). *)

val steps : t -> int
(** Agent rules taken so far. *)

(** {1 The finer interleaving}

    With [interleave] (D45): the rules of different agents in any order and
    each message between agents arriving when asked for, in the order of
    the sends to its receiver (R5e), as [jadescript-ref run --interleave]
    draws them. Every run made this way is one the rulings allow, so the
    judge ({!Judging}) accepts its trace. In run's schedule (no
    [interleave]) nothing is ever in flight. *)

val rule_of : t -> string -> (outcome, string) result
(** The next rule of the named agent, whatever the other agents are doing
    (R6 revised); [All_idle] when that agent has no rule to take. The host's
    messages held for its behaviour step (D42) arrive during that step. *)

val arrival : t -> receiver:string -> during:bool -> (unit, string) result
(** The oldest message in flight to [receiver] arrives now: between two
    rules ([during = false]), or during the receiver's last behaviour step
    ([during = true], SendInStep, R5d revised), which is allowed only in the
    step's window (between the step and the agent's next rule). A message
    to an agent that is not on the platform is reported undeliverable and
    [ams]'s failure goes in flight to its sender (R5e, D43). [Error]
    (nothing done) when nothing is in flight to [receiver] or its window is
    closed. *)

val draw : t -> (string, string) result
(** One event drawn from the seed, as [run --interleave] draws them (D45):
    a rule of an agent that is not idle, or the arrival of the oldest
    message in flight to a receiver (during its step, by a coin, when its
    window is open); the answer says what was drawn. [Error] when nothing
    can happen. Drawn again the same on a replay ({!back}, {!restore}). *)

val finish : t -> bool
(** Ends the run as [run] does: every message in flight arrives, then the
    host's held messages (D42), then every agent is destroyed; no rule or
    host action follows. [false] when it had ended already. *)

val finished : t -> bool

val env : t -> Typing.Tenv.t
(** The checked program. *)

val agent_specs : t -> (string * string * Interp.Value.t list) list
(** The agents as created: name, agent type, arguments, in creation order
    (what the judge needs with the program). *)

(** {1 What a student sees} *)

val trace : t -> string list
(** The trace so far: the header, then one JSON line per event, exactly as
    [jadescript-ref run --trace] writes them. *)

val output : t -> string list
(** What [run] would print so far: [NAME: text] for each [log], and
    [FILE:LINE:COL: error: message] for each run-time error (R7). *)

val view : t -> Yojson.Safe.t
(** The state of every agent, for the page: queues (the priority queue in
    dispatch order), behaviours, JADE's ready list and position, the dispatch
    in progress with the handlers still to try, the properties, the ghosts
    ([dispatched], [waits]), the enabled rules, and where the program code
    that the next rule runs is written ([run_at]: the file and line of the
    handler tried next, or of the behaviour that steps next; [null] for a
    rule that runs no code). A rule's label names its behaviour also when
    the instance has left since (a one-shot after its step, R5c). With
    [interleave]: no agent is the next ([next] is [null]); each agent tells
    whether it is [idle] and whether its [window] is open (R5d); the
    messages [in_flight] (receiver, sender, performative, content, the
    receiver's window) and those [held] for a step, and [finished]. *)

(** {1 Saving and restoring}

    What the page keeps across reloads and puts into a shared link. *)

val export : t -> Yojson.Safe.t
(** The commands done so far, oldest first, as a JSON list: each host
    action as the line of an events file says it
    ([{"agent": A, "notify": P, "priority": K}], [{"agent": A, "put": O}],
    [{"agent": A, "message": C, "performative": F}]), and the rules as
    [{"rules": N}] (N single rules, the first choice), [{"choice": K}] (one
    rule, choice K), [{"round": N}] (a round of {!run_rounds} and its N
    rules) and [{"single": I, "n": N}] (N rules of agent I, {!run_rules},
    or {!rule_of}); in the finer interleaving, also
    [{"arrive": R, "in_step": B}] ({!arrival}), [{"draw": N}] (N draws) and
    [{"finish": true}]. *)

val restore : setup -> Yojson.Safe.t -> (t, string list) result
(** A session created from [setup] with the commands of an {!export} done
    again: the same trace, the same view, and {!back} undoes them one by
    one. [Error] as {!create}, or for a list that {!export} could not have
    written; never raises. *)
