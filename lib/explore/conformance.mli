(** The checks that the OCaml semantics and the TLA+ spec agree, beyond whole
    graphs on the models of spec/models:

    - {!mutant_table}: each deliberate mutant of the step function must make
      some model's graph differ from TLC's (the comparison can fail);
    - {!replay_simulation}: TLC's random behaviours of a model ([-simulate]),
      replayed step by step by the OCaml machine;
    - {!validate_runs}: random runs of the OCaml machine, checked by TLC as
      traces of the spec (trace validation, docs/trace-format.md,
      "Validating a trace against the spec"). *)

val models : ?full:bool -> unit -> string list
(** The AgentLoop models of spec/models (paths), without the [\* full] ones
    unless [full]. *)

val tlc_graph : Model.t -> Dot.graph
(** TLC's state graph of the model, computed once per process. *)

val check : ?mutant:Mutant.t -> Model.t -> Compare.report
(** The explorer (with the mutant, if any) against TLC. *)

type mutant_row = {
  mutant : string;
  caught_by : string option;   (** the first model whose graph differed *)
  witness_length : int;        (** steps to the first difference *)
}

val mutant_table : Model.t list -> mutant_row list

val replay_simulation : Model.t -> traces:int -> depth:int -> seed:int -> (int, string) result
(** [Ok n]: n behaviours, each replayed to the end (every step one the machine
    can take, reaching the same state). [Error] explains the first that is not. *)

val random_runs : Model.t -> runs:int -> depth:int -> seed:int -> Tla.t list list
(** Random behaviours of the OCaml machine (host and agent steps chosen at
    random), as sequences of projected states. *)

val trace_module : name:string -> model:Model.t -> Tla.t list list -> string
(** A TLA+ module [name] extending the model, holding the traces as a constant
    and a trace spec ([TraceInit], [TraceNext]) whose behaviours are exactly
    the behaviours of the spec that match one of the traces state by state. *)

val validate_runs : Model.t -> Tla.t list list -> (int, string) result
(** Asks TLC whether every trace is a behaviour of the spec: [Ok n] when all n
    are; [Error] names the first trace and position the spec rejects. *)
