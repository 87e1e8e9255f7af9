(** The constants of [spec/AgentLoop.tla], named once: every model the OCaml
    side writes (random models, the models of validated traces and of the
    corridor simulator's runs) is built as this record. *)

type t = {
  variant : string;                         (** Variant *)
  tie_policy : string;                      (** TiePolicy: ["Stable"] or ["Unstable"] *)
  budget : int;                             (** Budget *)
  percepts : string list;                   (** Percepts *)
  default_priority : (string * int) list;   (** DefaultPriority *)
  overrides : int list;                     (** Overrides *)
  objects : string list;                    (** Objects *)
  messages : string list;                   (** Messages *)
  max_notify : int;                         (** MaxNotify *)
  max_put : int;                            (** MaxPut *)
  max_send : int;                           (** MaxSend *)
  flood : bool;                             (** Flood *)
  o2a_capacity : int;                       (** O2ACapacity *)
  behaviours : string list;                 (** Behaviours *)
  kind : string -> string;                  (** Kind: ["cyclic"] or ["oneshot"] *)
  has_action : string -> bool;              (** HasAction *)
  action_effects : string -> Tla.t;         (** ActionEffects: a sequence of effects *)
  percept_handlers : string -> Tla.t;       (** PerceptHandlers: a sequence of handlers *)
  message_handlers : string -> Tla.t;       (** MessageHandlers *)
  initial : string list;                    (** InitialBehaviours *)
  max_active : int;                         (** MaxActive *)
  inversion_bound : int;                    (** InversionBound *)
}

val constants : t -> (string * Tla.t) list
(** The constants by name, in the order AgentLoop.tla declares them. *)

val activate : string -> Tla.t
val deactivate : Tla.t
(** The two effects ([Effect] of the spec). *)

val handler : accepts:Tla.t list -> effects:Tla.t list -> Tla.t
(** A handler record [[accepts, effects]]. *)
