(** What the host gives agents on the command line ([run --agent
    NAME:TYPE:ARGS], and the playground's agents box): the host objects
    offered by name, and the splitting of an argument list. *)

val objects : unit -> (string * Value.t) list
(** The host objects by name: [@robome] records the RoboMe SDK commands the
    paper's agent invokes (each method takes any arguments and returns
    nothing); the simulation offers a real one instead. *)

val split_args : string -> string list
(** ["a,b(1, 2),\"x,y\""] split at the commas outside brackets and quotes,
    each part trimmed: [["a"; "b(1, 2)"; "\"x,y\""]]; [""] gives [[]]. *)
