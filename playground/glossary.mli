(** The words the page shows and explains: every ruling (R1a ... R8) and
    decision (D1 ...), in the one line docs/rulings.md gives each; every
    property of the TLA+ spec in the plain words of docs/spec.md; the spec's
    ghost variables; the TLC models that the counterexample replays name.
    The page links each occurrence of a term to its entry (a tooltip with
    the line, and the link to the docs). *)

type entry = {
  term : string;        (** as it appears on the page: ["R3b"], ["NoLoss"], ["ghosts"] *)
  kind : string;        (** ["ruling"], ["decision"], ["property (liveness)"], ... *)
  text : string;        (** one line, from the docs *)
  doc : string;         (** the docs page and anchor, relative to docs/: ["rulings.md#r3b"] *)
}

val all : entry list
(** Rulings, decisions, properties, ghosts, models, in that order; no term
    twice. *)

val to_json : unit -> Yojson.Safe.t
(** [[{"term", "kind", "text", "doc"}]]. *)
