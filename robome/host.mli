(** The host object the agent receives [as any] in its [on create]
    (the paper's [roboMeInterface]): a table of named methods, the paper's
    names, that the agent calls with [invoke "name" on roboMeInterface].

    - [startListening]: start delivering percepts from every source;
    - [callStop], [callMoveForward], [callMoveBackward], [callTurnLeft],
      [callTurnRight], [callHeadTiltUp], [callHeadTiltDown], [callHeadReset]:
      queue the corresponding RoboMe command on the sound channel.

    The methods take no argument, as in the paper; which speed level or turn
    the argument-less calls play is fixed by a {!mapping} (the Java part of
    the paper's application made the same choice). *)

type mapping = {
  forward_level : int;    (** [callMoveForward] plays [Forward forward_level] *)
  backward_level : int;   (** [callMoveBackward] plays [Backward backward_level] *)
  turn : Command.turn;    (** [callTurnLeft] / [callTurnRight] play this turn *)
}

val default_mapping : mapping
(** Forward and backward at level 3, turns by 90 degrees. *)

type t = (string * (unit -> unit)) list
(** The methods, by name. *)

val method_names : string list
(** The nine names above, in that order. *)

val make : mapping -> enqueue:(Command.t -> unit) -> start_listening:(unit -> unit) -> t
(** The host object whose call methods pass their command to [enqueue] (the
    simulation puts it on the sound channel at the right time). *)

val command_of : mapping -> string -> Command.t option
(** The command a [call...] method plays ([None] for [startListening] and
    unknown names). *)

val call : t -> string -> (unit, string) result
(** [call h name] invokes the method; [Error] for an unknown name (an
    "unknown native method", R7). *)
