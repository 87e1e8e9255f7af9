(** The examples the page offers, compiled in at build time
    ([examples_data.ml], written by [gen/embed.ml]): the paper's RoboMe agent,
    the Shapes example, and every conformance vector with its host events. *)

type t = {
  id : string;                      (** unique: ["robome"], ["shapes"], a vector's folder *)
  title : string;
  about : string;                   (** one or two sentences *)
  files : (string * string) list;   (** the program: names and texts *)
  agents : string list;             (** [NAME:TYPE[:ARG,...]] *)
  o2a_capacity : int option;
  fuel : int option;
  seed : int option;
  variant : string option;          (** the agent loop, when the vector fixes it (072, 074) *)
  max_steps : int option;           (** the step limit, when the vector gives one *)
  events : string list;             (** the host's events, JSON lines as in an
                                        events file (comments dropped) *)
}

val all : t list
(** RoboMe, Shapes, then the vectors by name. *)

val find : string -> t option

val to_json : t -> Yojson.Safe.t
(** [{"id", "title", "about", "files": [{"name", "text"}], "agents",
    "o2a_capacity", "fuel", "seed", "variant", "max_steps", "events"}]. *)
