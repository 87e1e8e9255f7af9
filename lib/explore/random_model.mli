(** Small random models of AgentLoop.tla: variants, tie policies, percepts with
    priorities and overrides, objects, messages, behaviours (cyclic or one-shot,
    with or without an action block) whose handlers accept random percepts and
    messages and activate or deactivate behaviours, and small host bounds.

    A generated model is written once as an [MC*.tla]/[MC*.cfg] pair, in the
    format of spec/models, and both TLC and the explorer read that pair. *)

val constants : Random.State.t -> (string * Tla.t) list
(** The constant values of a random model. *)

val write : dir:string -> name:string -> (string * Tla.t) list -> string
(** Writes [dir/name.tla] and [dir/name.cfg]; returns the path of the [.tla]. *)
