(** The exercises of the page: each a task with a starting program, its
    agents and loop settings, the host's events, hints, a solution, and a
    check that the page runs. Checking an attempt runs it as
    [jadescript-ref run] would (the events in order, then until every agent
    is idle, at most 5,000 rules: the printed loop never idles, D4) and
    judges the trace and the agents' state. The checks read the trace, not
    the page: test/browser/test_playground_engine.ml holds every solution
    to passing and every starting program to failing. *)

type verdict = {
  solved : bool;
  says : string;   (** what the check saw, in a sentence or two *)
}

type t = {
  id : string;
  title : string;
  task : string;              (** what to do, and what must stay *)
  hints : string list;        (** the first hint is the gentlest *)
  start : Session.setup;      (** the program, agents and settings to begin with *)
  events : string list;       (** the host's events, lines of an events file *)
  solution : Session.setup;   (** one setup that passes the check *)
  why : string;               (** what the solution shows, said once it passes *)
}

val all : t list
(** At least six, in the order of the menu. *)

val find : string -> t option

val attempt : t -> Session.setup -> (Session.t * verdict, string list) result
(** Creates the session from the setup ([Error]: the diagnostics, as
    {!Session.create}), does the exercise's events, runs until every agent is
    idle, and judges. An event the program cannot take (a percept type that
    is gone) fails the attempt. Never raises. *)

val to_json : unit -> Yojson.Safe.t
(** Every exercise, for the page: id, title, task, hints, why, the events,
    and the start and the solution as setups (files, agents, variant, tie,
    budget, o2a_capacity). *)
