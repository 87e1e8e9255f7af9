(** A TLA+ model of [spec/models/], read by the OCaml side.

    A model is described once, in its [MC*.tla] (constant definitions
    [MC<Name> == <literal value>]) and [MC*.cfg] ([CONSTANT X <- MCX]); this
    module reads those files, so the explorer and TLC check the very same model
    and nothing is maintained twice. It also builds the abstract bodies of the
    model: handlers and action blocks that accept the percepts and messages of
    their tables and have the activate/deactivate effects of their lists (a
    [send] effect, which changes nothing in one agent's loop, is left out),
    exactly as AgentLoop.tla interprets the constants. *)

type effect = E_activate of int | E_deactivate
(** Behaviour types are numbered by their index in {!t.behaviours}. *)

type handler = { accepts : int list; effects : effect list }
(** Accepted percepts or messages, by index. *)

type beh = {
  bidx : int;
  bname : string;
  cyclic : bool;
  has_action : bool;
  action_effects : effect list;
  percept_handlers : handler array;
  message_handlers : handler array;
  all : beh array Lazy.t;        (** every behaviour type of the model *)
}

type t = {
  name : string;                 (** e.g. ["MCReference"] *)
  dir : string;                  (** the folder holding the MC files *)
  constants : (string * Tla.t) list;   (** AgentLoop's constant names *)
  params : Semantics.Machine.params;
  percepts : string array;       (** sorted; a percept is its index *)
  default_priority : int array;
  overrides : int list;          (** sorted *)
  objects : string array;
  messages : string array;
  max_notify : int;
  max_put : int;
  max_send : int;
  behaviours : beh array;        (** sorted by name *)
  initial : int list;
  inversion_bound : int;
}

exception Error of string

val load : string -> t
(** [load path] reads [path] ([.../MCName.tla], [.../MCName.cfg] or
    [.../MCName]); both files must exist. @raise Error with a readable reason. *)

val of_constants : name:string -> dir:string -> (string * Tla.t) list -> t
(** A model from constant values given directly (random models in tests).
    @raise Error *)

val check_explorable : t -> unit
(** The upper bounds of the model constants (docs/spec.md, "Model constants"):
    Budget 1-16, MaxActive 1-8, O2ACapacity 1-16, MaxNotify, MaxPut and
    MaxSend 0-8, InversionBound 0-64, at most 8 percepts, objects, messages and
    behaviours. [load] and [of_constants] check only the lower bounds (and
    priorities: 0 to 2{^31}-1), since validate generates models from traces
    with one percept name per notification. @raise Error naming the constant. *)

val is_agent_loop_model : string -> bool
(** Does this MC file instantiate AgentLoop (rather than PQSpec)? *)

module Bodies : Semantics.Machine.BODIES
  with type percept = int and type message = int and type obj = int
   and type beh = beh and type world = unit

module M : module type of Semantics.Machine.Make (Bodies)
(** The machine with the abstract bodies. *)
