(** The [sim] command's logic, as library functions: one run with its
    outputs, a batch of seeds with a table, and the benchmark. The agent is
    a parameter (default: {!Reference_controller}). *)

type outcome = { result : Sim.result; metrics : Metrics.t }

val run : ?agent:(module Agent.AGENT) -> ?trace:bool -> Scenario.t -> seed:int -> out_dir:string option -> outcome
(** Simulate the scenario with this seed. With [Some dir] (created if
    needed), write [dir/report.json], [dir/map.svg], [dir/timeline.svg] and,
    if [trace] (default true when writing), [dir/trace.txt]. *)

type stats = { name : string; mean : float; min : float; max : float; n : int }

val batch : ?agent:(module Agent.AGENT) -> ?progress:bool -> Scenario.t -> first_seed:int -> runs:int -> stats list * outcome list
(** Run the seeds [first_seed .. first_seed + runs - 1]; with [progress]
    (default true) draw a progress bar on stderr. The statistics cover
    {!Metrics.summary_fields} (nan values left out; [n] counts the rest). *)

val table : Scenario.t -> first_seed:int -> runs:int -> stats list -> string
(** The statistics as a text table (metric, mean, min, max). *)

val bench : ?agent:(module Agent.AGENT) -> ?scenario:string -> ?position_rate:float -> unit -> float * float
(** Run the paper scenario ([scenarios/paper.json], found from the current
    directory upwards, unless [scenario] is given) with [position_rate]
    position percepts per second (default 50) and the agent (default the
    reference controller);
    return (simulated seconds, wall-clock seconds). *)

val tune_gc : unit -> unit
(** The garbage collector's settings for single runs ([jadescript-ref sim]
    without [--batch], and [bench.exe sim]): a space overhead of 1000 and
    the default minor heap of 256k words, whatever was set before in the
    process. A run's results do not depend on them. Not for [--batch], which
    keeps every run's outcome: there the heap could grow to ten times what
    it keeps. *)

val find_scenario : string -> string
(** [find_scenario "paper"]: the path of [scenarios/paper.json] from the
    current directory or one of its parents; a path that exists is returned
    unchanged. @raise Scenario.Error if there is none. *)
