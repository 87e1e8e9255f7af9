(** Messages sent by agents and not yet delivered, in the order in which
    they must reach their receivers.

    R5e: a message sent to an agent joins the end of what is owed to that
    receiver, and the messages reach it in the order of the sends. D47: on a
    platform of several containers (the trace header's [containers]), that
    order holds among the sends made in one container; sends from different
    containers are not ordered with each other. So the messages owed to a
    receiver form one queue per container of their senders, and a delivery
    from agent A must be the oldest message in the queue of A's container.
    With one container (a header without [containers]) there is one queue
    per receiver, as R5e says.

    One owner for the three readers that follow messages across agents:
    validate's checks between agents ([Explore.Trace_check]), its check of
    the ends of steps ([Explore.Trace_more]) and the judge ([Judge]); each
    keeps its own payload ['a] with a message. *)

type 'a t

val create : Trace.header -> 'a t
(** Nothing in flight; the agents' containers are the header's. *)

val container : 'a t -> string -> string
(** The container of an agent: the header's, else
    {!Trace.main_container}. *)

val containers : 'a t -> int
(** How many containers the header names, the main one included (1 for a
    header without [containers]). *)

val push : 'a t -> receiver:string -> sender:string -> 'a -> unit
(** A message of [sender] to [receiver], after every message sent before
    it. *)

val take : 'a t -> receiver:string -> sender:string -> (string * 'a) option
(** Takes out the message a delivery to [receiver] from [sender] must be:
    the oldest message to [receiver] sent from [sender]'s container, with
    its own sender (which may be another agent of that container: then the
    delivery is out of order, and the reader rejects the trace). [None]
    when that container owes [receiver] nothing. *)

val iter : 'a t -> (receiver:string -> sender:string -> 'a -> unit) -> unit
(** Every message still in flight, each receiver's and container's in the
    order of the sends (the order among receivers and containers is not
    specified). *)
