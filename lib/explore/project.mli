(** The projection of a machine configuration onto the variables of
    [spec/AgentLoop.tla]: the bridge between the two state graphs.

    Every variable of the spec is computed from the configuration exactly as the
    spec defines it ([o2a] as a sequence of records, [pq] as a set, [cur] as
    [NoDispatch] outside a dispatch, [last] as the record of the last action with
    its parameters, ...), with indices turned back into the model's names. *)

val variables : string list
(** The spec's variables, in its order. *)

val state : Model.t -> Model.M.t -> Tla.t
(** The state as a canonical TLA+ record from variable names to values. *)

val label : Model.t -> (int, int, int) Semantics.Machine.label -> Tla.t
(** The value of [last] after a step with this label ([Send] is taken as
    Send: {!state} tells SendInStep from the configuration's [stepped]). *)
