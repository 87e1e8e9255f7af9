(** Trace validation of the reference controller by TLC: a run of the
    agent's loop, recorded as machine labels
    ({!Reference_controller.enable_log}), is checked to be a behaviour of
    [spec/AgentLoop.tla].

    The run is abstracted to a model of the spec: the four percept types of
    the ontology with their default priorities, one cyclic behaviour
    [HandlePercepts] without action block whose four percept handlers
    accept [falling], [obstacle], [qrCodeRead] and [position] respectively,
    the run's loop variant, and host bounds equal to what the run did. The
    labels are replayed on the abstract machine ({!Explore.Model.M}), each
    agent step being required to be the one the run took, and the projected
    states are handed to TLC ({!Explore.Conformance.validate_runs}). *)

val model_constants : Agent.loop -> Reference_controller.label list -> (string * Explore.Tla.t) list
(** The constants of the model for this run. *)

val replay : Explore.Model.t -> Reference_controller.label list -> (Explore.Tla.t list, string) result
(** The projected states of the replay, or where the abstract machine could
    not follow the run. *)

val check : ?dir:string -> Agent.loop -> Reference_controller.label list -> (int, string) result
(** Write the model (into [dir], default a fresh temporary folder), replay,
    and ask TLC: [Ok n] when TLC accepts the trace of [n] states.
    @raise Explore.Tlc.Error when TLC is not available. *)
