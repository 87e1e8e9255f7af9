type t = {
  variant : string; tie_policy : string; budget : int;
  percepts : string list; default_priority : (string * int) list; overrides : int list;
  objects : string list; messages : string list;
  max_notify : int; max_put : int; max_send : int; flood : bool; o2a_capacity : int;
  behaviours : string list; kind : string -> string; has_action : string -> bool;
  action_effects : string -> Tla.t; percept_handlers : string -> Tla.t; message_handlers : string -> Tla.t;
  initial : string list; max_active : int; inversion_bound : int;
}

let str s = Tla.Str s
let int i = Tla.Int i

let constants c =
  (* A function of the behaviours; with none, the empty function <<>> (an
     empty record [] is not TLA+: an agent without behaviours failed). *)
  let per f = if c.behaviours = [] then Tla.Fn [] else Tla.record (List.map (fun b -> (b, f b)) c.behaviours) in
  [ "Variant", str c.variant;
    "TiePolicy", str c.tie_policy;
    "Budget", int c.budget;
    "Percepts", Tla.set (List.map str c.percepts);
    "DefaultPriority", Tla.record (List.map (fun (p, k) -> (p, int k)) c.default_priority);
    "Overrides", Tla.set (List.map int c.overrides);
    "Objects", Tla.set (List.map str c.objects);
    "Messages", Tla.set (List.map str c.messages);
    "MaxNotify", int c.max_notify;
    "MaxPut", int c.max_put;
    "MaxSend", int c.max_send;
    "Flood", Tla.Bool c.flood;
    "O2ACapacity", int c.o2a_capacity;
    "Behaviours", Tla.set (List.map str c.behaviours);
    "Kind", per (fun b -> str (c.kind b));
    "HasAction", per (fun b -> Tla.Bool (c.has_action b));
    "ActionEffects", per c.action_effects;
    "PerceptHandlers", per c.percept_handlers;
    "MessageHandlers", per c.message_handlers;
    "InitialBehaviours", Tla.Seq (List.map str c.initial);
    "MaxActive", int c.max_active;
    "InversionBound", int c.inversion_bound ]

let activate b = Tla.record [ "op", str "activate"; "b", str b ]
let deactivate = Tla.record [ "op", str "deactivate" ]
let handler ~accepts ~effects = Tla.record [ "accepts", Tla.set accepts; "effects", Tla.Seq effects ]
