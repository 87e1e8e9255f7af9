----------------------------- MODULE AgentLoop -----------------------------
(***************************************************************************)
(* One Jadescript agent: the loop of Algorithm 1 of the paper (Section 4), *)
(* its priority queue of percepts, its JADE behaviour scheduler and its    *)
(* message queue, driven by a host that notifies percepts, puts other      *)
(* objects into the O2A queue and sends messages.                          *)
(*                                                                         *)
(* Four variants of the loop are specified (constant Variant):             *)
(*  "printed"   Algorithm 1 exactly as printed: the transfer loop peeks at *)
(*              the head of the O2A queue, moves it if it is a percept and *)
(*              loops while the O2A queue is not empty; the agent never    *)
(*              sleeps (it busy-waits).                                    *)
(*  "reference" the semantics fixed by the rulings (R3): one atomic        *)
(*              Transfer of every O2A percept, then drain the priority     *)
(*              queue, then one behaviour step; idle when nothing to do.   *)
(*  "budgeted"  as reference, but at most Budget percepts are dispatched   *)
(*              per loop iteration; the rest wait in the priority queue    *)
(*              while one behaviour step runs.                             *)
(*  "native"    no priority queue: percepts are delivered into the JADE    *)
(*              message queue, in arrival order, and handled by the        *)
(*              behaviours like messages (percept handlers first).         *)
(*                                                                         *)
(* The state graph of this spec is the conformance oracle for the OCaml    *)
(* semantics: every step is one named action, `last` records the action    *)
(* and its parameters, and all values are canonical (sets, sequences,      *)
(* records) so that two implementations can be compared node by node.      *)
(*                                                                         *)
(* Decisions beyond the paper and the rulings are marked "DECISION".       *)
(* The rulings (R1a ... R8) are stated in docs/rulings.md.                 *)
(***************************************************************************)
EXTENDS Naturals, Sequences, FiniteSets, PerceptPriority

CONSTANTS
    Variant,            \* "printed", "reference", "budgeted" or "native"
    TiePolicy,          \* "Stable" (R3b) or "Unstable" (java PriorityQueue)
    Budget,             \* max dispatches per iteration in "budgeted" (>= 1)
    Percepts,           \* percept names (strings)
    DefaultPriority,    \* [Percepts -> Nat]: default priority of each (R1a)
    Overrides,          \* priorities the host may pass to notifyEvent(p, k) (R2a)
    Objects,            \* non-percept objects the host may put into O2A (R2c)
    Messages,           \* message contents the host may send (R5e)
    MaxNotify,          \* bound on percept notifications (ignored if Flood)
    MaxPut,             \* bound on objects put
    MaxSend,            \* bound on messages sent
    Flood,              \* TRUE: endless percept stream abstraction (see Notify)
    O2ACapacity,        \* capacity of the O2A queue (R2d), >= 1
    Behaviours,         \* behaviour type names (strings)
    Kind,               \* [Behaviours -> {"cyclic", "oneshot"}] (R5c)
    HasAction,          \* [Behaviours -> BOOLEAN]: has a `do` block (R5b, R5d)
    ActionEffects,      \* [Behaviours -> Seq(Effect)]: effects of the `do` block
    PerceptHandlers,    \* [Behaviours -> Seq([accepts, effects])], declaration order
    MessageHandlers,    \* [Behaviours -> Seq([accepts, effects])], declaration order
    InitialBehaviours,  \* Seq(Behaviours) activated by the agent's on create (R5g)
    MaxActive,          \* model bound: an activation when Len(active) = MaxActive is ignored
    InversionBound      \* bound checked by BoundedInversion

(***************************************************************************)
(* Effects of handler bodies and action blocks.  Only the effects that     *)
(* change the loop's state are modelled: activating a behaviour and        *)
(* `deactivate this`; and `send m to r` (R5e), which changes nothing in    *)
(* the sending agent's loop: the platform of several agents               *)
(* (spec/Platform.tla) takes it from the effects of the body that ran      *)
(* (HandleBodyEffects, StepBodyEffects) and delivers it.                   *)
(***************************************************************************)
Effect == [op : {"activate"}, b : Behaviours] \cup [op : {"deactivate"}]
          \cup [op : {"send"}, to : STRING, m : STRING]

\* A handler: the percepts (or messages) it accepts and the effects of its body.
HandlerSet(Accepted) == [accepts : SUBSET Accepted, effects : Seq(Effect)]

\* The effects of handler h's body when it runs for the percept or message x.
\* A handler record may carry an optional field byValue, a function from the
\* values it accepts to effect sequences, for bodies whose effects depend on
\* the value (an `if` around an `activate`).  The models of spec/models do not
\* use it; the trace-validation models that jadescript-ref generates from an
\* interpreter trace do, since there every percept and message is its own
\* value ("n3", "m1").
HandlerEffects(h, x) == IF "byValue" \in DOMAIN h THEN h.byValue[x] ELSE h.effects

\* Every priority a percept can get: defaults and host overrides.
Prios == {DefaultPriority[p] : p \in Percepts} \cup Overrides

ASSUME
    /\ Variant \in {"printed", "reference", "budgeted", "native"}
    /\ TiePolicy \in TiePolicies
    /\ Budget \in Nat \ {0}
    /\ DefaultPriority \in [Percepts -> Nat]
    /\ Overrides \subseteq Nat
    /\ {MaxNotify, MaxPut, MaxSend, MaxActive, InversionBound} \subseteq Nat
    /\ Flood \in BOOLEAN
    /\ O2ACapacity \in Nat \ {0}
    /\ Kind \in [Behaviours -> {"cyclic", "oneshot"}]
    /\ HasAction \in [Behaviours -> BOOLEAN]
    /\ \A b \in Behaviours : \A i \in DOMAIN ActionEffects[b] :
            ActionEffects[b][i] \in Effect
    /\ \A b \in Behaviours : \A i \in DOMAIN PerceptHandlers[b] :
            PerceptHandlers[b][i].accepts \subseteq Percepts
    /\ \A b \in Behaviours : \A i \in DOMAIN MessageHandlers[b] :
            MessageHandlers[b][i].accepts \subseteq Messages
    /\ \A i \in DOMAIN InitialBehaviours : InitialBehaviours[i] \in Behaviours
    /\ Len(InitialBehaviours) <= MaxActive

VARIABLES
    o2a,        \* the O2A queue: Seq of percept entries
                \*   [kind |-> "percept", p, prio, seq] and object entries
                \*   [kind |-> "object", obj]
    pq,         \* the priority queue: a SET of [p, prio, seq] (PerceptPriority)
    msgq,       \* the message queue: Seq of [kind |-> "message", m, seq];
                \*   in "native" also percept entries [kind |-> "percept", p, prio, seq]
    nextSeq,    \* seq of the last notified percept (R2b: the first gets 1)
    msgSeq,     \* seq of the last message sent (a separate counter)
    puts,       \* number of objects put so far
    active,     \* active instances [id, b] in activation order (R4a, R5a)
    ready,      \* Seq of ids: JADE's ready list (R5f)
    blocked,    \* Seq of ids: blocked instances in blocking order (R5d)
    pos,        \* 1-based index in ready of the next instance to run
                \*   (1 when ready is empty)
    phase,      \* "transfer", "dispatch", "handle" or "idle"
    cur,        \* the dispatch in progress [e, todo, applied] (NoDispatch
                \*   when phase # "handle")
    dispatched, \* percepts dequeued since the last Transfer (TransferEnd in
                \*   "printed"); always 0 in "native"
    done,       \* seqs that left the system (dispatched or discarded/consumed)
    waits,      \* ghost: <<seq, n>> for every percept still waiting, n = number
                \*   of dispatches of lower-priority percepts since its notification
    last,       \* the last action and its parameters
    stepped     \* R5d revised: is a message that arrives now one that came during
                \*   the agent's last behaviour step?  NoStep: no, the agent took
                \*   another rule since (or a Send came after the step);
                \*   [kind |-> "kept"]: yes, and the step did not block its
                \*   behaviour; [kind |-> "blocked", bs |-> S]: yes, and the step
                \*   blocked it; S is the behaviour state just before the block
                \*   (S2 of BehaviourStep)

vars == <<o2a, pq, msgq, nextSeq, msgSeq, puts, active, ready, blocked, pos,
          phase, cur, dispatched, done, waits, last, stepped>>

\* The variables describing the behaviours, changed together by effects.
behVars == <<active, ready, blocked, pos>>

-----------------------------------------------------------------------------
(***************************************************************************)
(* Helpers                                                                 *)
(***************************************************************************)

\* The largest number of instance ids that can be in use at once: the
\* active instances plus the instances of a dispatch snapshot (R4b) that
\* were deactivated meanwhile, plus the instance running.  Ids never exceed
\* IdBound (see NewId).
IdBound == 2 * MaxActive + 1

\* The instance ids that can occur.
Ids == 1..IdBound

\* Priority entries (the elements of pq).
PQEntry == EntrySet(Percepts, Prios, Nat)

\* O2A / native message-queue percept entries.
PerceptEntry == [kind : {"percept"}, p : Percepts, prio : Prios, seq : Nat]

\* O2A object entries.
ObjectEntry == [kind : {"object"}, obj : Objects]

\* Message-queue message entries.
MessageEntry == [kind : {"message"}, m : Messages, seq : Nat]

\* The value of cur when no dispatch is in progress.
NoDispatch == [e |-> [p |-> "", prio |-> 0, seq |-> 0], todo |-> <<>>,
               applied |-> FALSE]

\* The value of last.msg when a behaviour step consumed nothing.
NoMsg == [kind |-> "none"]

\* The value of stepped outside the window of a behaviour step (R5d).
NoStep == [kind |-> "none"]

\* Is x a percept entry (of o2a or msgq)?
IsPercept(x) == x.kind = "percept"

\* The priority-queue entry made from an O2A percept entry.
ToPQ(x) == [p |-> x.p, prio |-> x.prio, seq |-> x.seq]

\* The native message-queue entry made from an O2A percept entry (same shape).
ToMsg(x) == x

\* The range of a sequence.
Range(s) == {s[i] : i \in DOMAIN s}

\* Sequence s without its i-th element.
RemoveAt(s, i) == SubSeq(s, 1, i - 1) \o SubSeq(s, i + 1, Len(s))

\* The index of the first element of s equal to x (0 if none).
IndexOf(s, x) == IF \E i \in DOMAIN s : s[i] = x
                 THEN CHOOSE i \in DOMAIN s : s[i] = x /\ \A j \in 1..(i-1) : s[j] # x
                 ELSE 0

\* Is there a percept in the O2A queue?
PerceptInO2A == \E i \in DOMAIN o2a : IsPercept(o2a[i])

\* Number of percepts waiting in the native message queue.
MsgqPercepts == Len(SelectSeq(msgq, IsPercept))

\* Space used in the O2A queue.  DECISION: in "native" the percepts waiting in
\* the message queue count too (they are the O2A percepts, only moved); without
\* this the native flood models are infinite.
O2AUsed == Len(o2a) + (IF Variant = "native" THEN MsgqPercepts ELSE 0)

\* The behaviour type of the active instance id.
BOf(id) == (CHOOSE a \in Range(active) : a.id = id).b

\* Is the instance id active?
IsActive(id) == \E a \in Range(active) : a.id = id

\* Is the instance id in the ready list?
InReady(id) == \E i \in DOMAIN ready : ready[i] = id

(***************************************************************************)
(* Behaviour-state transformers.  A behaviour state S is a record          *)
(* [active, ready, blocked, pos]; effects are applied to it in order.      *)
(***************************************************************************)

\* The current behaviour state.
BS == [active |-> active, ready |-> ready, blocked |-> blocked, pos |-> pos]

\* Remove id from the ready list of S, adjusting pos as JADE's
\* Scheduler.remove does (R5f): an entry before pos shifts pos back by one;
\* a pos past the end wraps to 1.  No remaining instance is skipped or run
\* twice because of the removal.
RemoveReady(S, id) ==
    LET k == IndexOf(S.ready, id)
        r == RemoveAt(S.ready, k)
        p1 == IF k < S.pos THEN S.pos - 1 ELSE S.pos
    IN IF k = 0 THEN S
       ELSE [S EXCEPT !.ready = r, !.pos = IF p1 > Len(r) THEN 1 ELSE p1]

\* Deactivate instance id (R5h): it leaves active, ready and blocked at once.
\* Deactivating an inactive instance does nothing.
Deactivate(S, id) ==
    IF ~\E a \in Range(S.active) : a.id = id THEN S
    ELSE LET S1 == RemoveReady(S, id)
         IN [S1 EXCEPT !.active = SelectSeq(S.active, LAMBDA a : a.id # id),
                       !.blocked = SelectSeq(S.blocked, LAMBDA x : x # id)]

\* Block instance id (R5d): it leaves ready and joins the end of blocked.
Block(S, id) ==
    LET S1 == RemoveReady(S, id)
    IN [S1 EXCEPT !.blocked = Append(S.blocked, id)]

\* The id of a new instance: the smallest positive integer used neither by an
\* active instance nor in `reserved` (DECISION: reserved = the running
\* instance and every instance of the pending dispatch snapshot, so that an
\* id in the snapshot or the id of "this" never denotes a new instance).
NewId(S, reserved) ==
    LET used == {a.id : a \in Range(S.active)} \cup reserved
    IN CHOOSE n \in 1..(Cardinality(used) + 1) :
          n \notin used /\ \A m \in 1..(n - 1) : m \in used

\* Apply one effect of instance this to S.  Activation (R5g) appends the new
\* instance to active and to ready; it is ignored when MaxActive instances are
\* active (a model bound, not a language rule).
ApplyEffect(S, this, eff, reserved) ==
    IF eff.op = "activate"
    THEN IF Len(S.active) >= MaxActive THEN S
         ELSE LET n == NewId(S, reserved)
              IN [S EXCEPT !.active = Append(S.active, [id |-> n, b |-> eff.b]),
                           !.ready = Append(S.ready, n)]
    ELSE IF eff.op = "deactivate" THEN Deactivate(S, this)
    ELSE S      \* a send: the behaviours do not change

\* Apply the effects effs of instance this to S, in order.
RECURSIVE ApplyEffects(_, _, _, _)
ApplyEffects(S, this, effs, reserved) ==
    IF effs = <<>> THEN S
    ELSE ApplyEffects(ApplyEffect(S, this, Head(effs), reserved),
                      this, Tail(effs), reserved)

\* Make S the next behaviour state.
SetBS(S) == /\ active' = S.active
            /\ ready' = S.ready
            /\ blocked' = S.blocked
            /\ pos' = S.pos

(***************************************************************************)
(* Registered handlers (R4a): the percept handlers of the active instances *)
(* in activation order, then declaration order: a Seq of [id, h].          *)
(***************************************************************************)
RECURSIVE HandlersOf(_)
HandlersOf(s) ==
    IF s = <<>> THEN <<>>
    ELSE [j \in 1..Len(PerceptHandlers[Head(s).b]) |-> [id |-> Head(s).id, h |-> j]]
         \o HandlersOf(Tail(s))

\* The ids in a dispatch snapshot.
TodoIds(todo) == {t.id : t \in Range(todo)}

(***************************************************************************)
(* The inversion ghost.  PrioOfSeq(s) is the priority of the waiting       *)
(* percept with seq s.  After a dispatch of a percept with priority k and  *)
(* seq s, every other waiting percept with a priority above k counts one   *)
(* more inversion, and s stops waiting.                                    *)
(***************************************************************************)
\* The percepts still waiting (O2A, pq, native message queue) as pq entries.
WaitingEntries == {ToPQ(x) : x \in {y \in Range(o2a) : IsPercept(y)}}
                  \cup pq
                  \cup {ToPQ(x) : x \in {y \in Range(msgq) : IsPercept(y)}}

\* The priority of the waiting percept with seq s.
PrioOfSeq(s) == (CHOOSE x \in WaitingEntries : x.seq = s).prio

\* The waits ghost after the dispatch of entry e.
BumpWaits(e) ==
    IF Flood THEN waits
    ELSE {IF PrioOfSeq(w[1]) > e.prio THEN <<w[1], w[2] + 1>> ELSE w :
             w \in {v \in waits : v[1] # e.seq}}

-----------------------------------------------------------------------------
(***************************************************************************)
(* Initial state: the agent's on create has activated InitialBehaviours    *)
(* (R5g), instances 1..n, all ready; the first iteration starts with a     *)
(* transfer.                                                               *)
(***************************************************************************)
Init ==
    /\ o2a = <<>>
    /\ pq = EmptyQueue
    /\ msgq = <<>>
    /\ nextSeq = 0
    /\ msgSeq = 0
    /\ puts = 0
    /\ active = [i \in 1..Len(InitialBehaviours) |->
                    [id |-> i, b |-> InitialBehaviours[i]]]
    /\ ready = [i \in 1..Len(InitialBehaviours) |-> i]
    /\ blocked = <<>>
    /\ pos = 1
    /\ phase = "transfer"
    /\ cur = NoDispatch
    /\ dispatched = 0
    /\ done = {}
    /\ waits = {}
    /\ last = [act |-> "Init"]
    /\ stepped = NoStep

-----------------------------------------------------------------------------
(***************************************************************************)
(* Host actions (not fair: the host may stop at any time).                 *)
(***************************************************************************)

\* Can one more entry enter the O2A queue (R2d: refused when full; a
\* refusal changes no state, so it is simply a disabled action)?
O2AHasRoom == O2AUsed < O2ACapacity

\* Can one more percept be notified?
CanNotify == (Flood \/ nextSeq < MaxNotify) /\ O2AHasRoom

\* The effect of notifying percept p with priority k (R2b): append it to
\* O2A with the next seq.  Under Flood, seqs are not tracked: every seq is 0
\* and nextSeq, done, waits never change.  A notification wakes an idle agent
\* (R3e).  (A helper, not an action: Notify and NotifyWith below are the
\* actions, so that TLC names the DOT edges after them.)
NotifyEffect(p, k, actName) ==
    LET s == IF Flood THEN 0 ELSE nextSeq + 1
    IN /\ o2a' = Append(o2a, [kind |-> "percept", p |-> p, prio |-> k, seq |-> s])
       /\ nextSeq' = s
       /\ waits' = IF Flood THEN waits ELSE waits \cup {<<s, 0>>}
       /\ phase' = IF phase = "idle" THEN "transfer" ELSE phase
       /\ last' = [act |-> actName, p |-> p, prio |-> k, seq |-> s]
       /\ UNCHANGED <<pq, msgq, msgSeq, puts, behVars, cur, dispatched, done,
                      stepped>>

\* notifyEvent(p): the percept's default priority (R1a, R2b).
Notify(p) ==
    /\ CanNotify
    /\ NotifyEffect(p, DefaultPriority[p], "Notify")

\* notifyEvent(p, k): the priority overridden by k (R2a).
NotifyWith(p, k) ==
    /\ CanNotify
    /\ NotifyEffect(p, k, "NotifyWith")

\* putO2AObject(o): a non-percept object (R2c).  Does not wake an idle agent.
Put(o) ==
    /\ puts < MaxPut
    /\ O2AHasRoom
    /\ o2a' = Append(o2a, [kind |-> "object", obj |-> o])
    /\ puts' = puts + 1
    /\ last' = [act |-> "Put", obj |-> o]
    /\ UNCHANGED <<pq, msgq, nextSeq, msgSeq, behVars, phase, cur, dispatched,
                   done, waits, stepped>>

\* A message with content m reaches the agent (R5e).  It wakes every blocked
\* instance (R5d: they join the end of ready in blocking order) and an idle
\* agent (R3e).  It came after the agent's last behaviour step, if any: a
\* message that comes later cannot have come during that step (deliveries
\* to one agent keep their order, R6), so the step's window closes.
Send(m) ==
    /\ msgSeq < MaxSend
    /\ msgq' = Append(msgq, [kind |-> "message", m |-> m, seq |-> msgSeq + 1])
    /\ msgSeq' = msgSeq + 1
    /\ ready' = ready \o blocked
    /\ blocked' = <<>>
    /\ phase' = IF phase = "idle" THEN "transfer" ELSE phase
    /\ last' = [act |-> "Send", m |-> m, seq |-> msgSeq + 1]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, nextSeq, puts, active, pos, cur, dispatched, done,
                   waits>>

(***************************************************************************)
(* A message with content m reaches the agent during its last behaviour    *)
(* step, after that step's handlers looked for messages (R5d revised,      *)
(* D42).  Enabled from a BehaviourStep until the agent's next rule: host   *)
(* notifications and puts, and other messages that came during the step,  *)
(* may come in between; a Send closes the window (above).  A message that  *)
(* came during the step before its handlers looked is a Send before the    *)
(* step.  The effect is Send's, and in addition, if the step blocked its   *)
(* behaviour, the behaviour stays runnable at its place in the ready list, *)
(* as JADE's restart counter has it: the behaviour state becomes the one   *)
(* the step had just before the block (S2 of BehaviourStep), with the      *)
(* other blocked instances woken to the end of ready.  After it the window *)
(* stays open, as for a step that blocked nothing: a further message that  *)
(* came during the step is exactly a Send.  The phase is "transfer" in the *)
(* window (the step ends the iteration), so an idle agent is not woken.    *)
(***************************************************************************)
SendInStep(m) ==
    /\ stepped.kind # "none"
    /\ msgSeq < MaxSend
    /\ msgq' = Append(msgq, [kind |-> "message", m |-> m, seq |-> msgSeq + 1])
    /\ msgSeq' = msgSeq + 1
    /\ IF stepped.kind = "blocked"
       THEN /\ active' = stepped.bs.active
            /\ ready' = stepped.bs.ready \o stepped.bs.blocked
            /\ pos' = stepped.bs.pos
       ELSE /\ ready' = ready \o blocked
            /\ UNCHANGED <<active, pos>>
    /\ blocked' = <<>>
    /\ last' = [act |-> "SendInStep", m |-> m, seq |-> msgSeq + 1]
    /\ stepped' = [kind |-> "kept"]
    /\ UNCHANGED <<o2a, pq, nextSeq, puts, phase, cur, dispatched, done, waits>>

\* All host actions.
HostStep ==
    \/ \E p \in Percepts : Notify(p)
    \/ \E p \in Percepts, k \in Overrides : NotifyWith(p, k)
    \/ \E o \in Objects : Put(o)
    \/ \E m \in Messages : Send(m)
    \/ \E m \in Messages : SendInStep(m)

-----------------------------------------------------------------------------
(***************************************************************************)
(* Agent actions: transfer.                                                *)
(***************************************************************************)

\* reference / budgeted (R3a): every O2A percept moves to pq in one atomic
\* step; objects stay in O2A, in order.
\* native: every O2A percept moves to the end of the message queue, in
\* order; if any moved, blocked instances wake up as for a message (R5d).
\* last.moved is the number of percepts moved.
Transfer ==
    /\ Variant \in {"reference", "budgeted", "native"}
    /\ phase = "transfer"
    /\ LET moving == SelectSeq(o2a, IsPercept)
       IN /\ o2a' = SelectSeq(o2a, LAMBDA x : ~IsPercept(x))
          /\ IF Variant = "native"
             THEN /\ msgq' = msgq \o [i \in DOMAIN moving |-> ToMsg(moving[i])]
                  /\ IF moving # <<>>
                     THEN /\ ready' = ready \o blocked
                          /\ blocked' = <<>>
                     ELSE UNCHANGED <<ready, blocked>>
                  /\ UNCHANGED pq
             ELSE /\ pq' = pq \cup {ToPQ(moving[i]) : i \in DOMAIN moving}
                  /\ UNCHANGED <<msgq, ready, blocked>>
          /\ last' = [act |-> "Transfer", moved |-> Len(moving)]
    /\ phase' = "dispatch"
    /\ dispatched' = 0
    /\ stepped' = NoStep
    /\ UNCHANGED <<nextSeq, msgSeq, puts, active, pos, cur, done, waits>>

\* printed: the head of O2A is a percept: dequeue it into pq; the while loop
\* goes on.
TransferOne ==
    /\ Variant = "printed"
    /\ phase = "transfer"
    /\ o2a # <<>>
    /\ IsPercept(Head(o2a))
    /\ pq' = Enqueue(pq, ToPQ(Head(o2a)))
    /\ o2a' = Tail(o2a)
    /\ last' = [act |-> "TransferOne", p |-> Head(o2a).p,
                prio |-> Head(o2a).prio, seq |-> Head(o2a).seq]
    /\ stepped' = NoStep
    /\ UNCHANGED <<msgq, nextSeq, msgSeq, puts, behVars, phase, cur,
                   dispatched, done, waits>>

\* printed: the head of O2A is not a percept: the loop peeks at it again and
\* again and never leaves (only `last` changes, once).
TransferSpin ==
    /\ Variant = "printed"
    /\ phase = "transfer"
    /\ o2a # <<>>
    /\ ~IsPercept(Head(o2a))
    /\ last' = [act |-> "TransferSpin", obj |-> Head(o2a).obj]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, behVars, phase, cur,
                   dispatched, done, waits>>

\* printed: the O2A queue is empty: the transfer loop ends.
TransferEnd ==
    /\ Variant = "printed"
    /\ phase = "transfer"
    /\ o2a = <<>>
    /\ phase' = "dispatch"
    /\ dispatched' = 0
    /\ last' = [act |-> "TransferEnd"]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, behVars, cur, done,
                   waits>>

(***************************************************************************)
(* Agent actions: percept dispatch (all variants but native).              *)
(***************************************************************************)

\* Has the budgeted variant used up this iteration's dispatches?
BudgetSpent == Variant = "budgeted" /\ dispatched >= Budget

\* Take the next percept out of pq (R3b, tie policy) and snapshot the
\* registered handlers (R4a, R4b).
Dequeue ==
    /\ Variant # "native"
    /\ phase = "dispatch"
    /\ pq # EmptyQueue
    /\ ~BudgetSpent
    /\ \E e \in Candidates(pq, TiePolicy) :
          /\ pq' = DequeueMax(pq, e)
          /\ cur' = [e |-> e, todo |-> HandlersOf(active), applied |-> FALSE]
          /\ waits' = BumpWaits(e)
          /\ last' = [act |-> "Dequeue", e |-> e]
    /\ phase' = "handle"
    /\ dispatched' = dispatched + 1
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, msgq, nextSeq, msgSeq, puts, behVars, done>>

\* Is the snapshot entry t applicable to the current percept: its instance
\* is still active (R4b) and the handler accepts the percept (R3b)?
Applicable(t) ==
    /\ IsActive(t.id)
    /\ cur.e.p \in PerceptHandlers[BOf(t.id)][t.h].accepts

\* Run the next handler of the snapshot: its effects, in order.
Handle ==
    /\ phase = "handle"
    /\ cur.todo # <<>>
    /\ LET t == Head(cur.todo)
       IN /\ Applicable(t)
          /\ SetBS(ApplyEffects(BS, t.id, HandlerEffects(PerceptHandlers[BOf(t.id)][t.h], cur.e.p),
                                TodoIds(cur.todo)))
          /\ last' = [act |-> "Handle", id |-> t.id, h |-> t.h,
                      p |-> cur.e.p, seq |-> cur.e.seq]
    /\ cur' = [cur EXCEPT !.todo = Tail(cur.todo), !.applied = TRUE]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, phase, dispatched,
                   done, waits>>

\* Pass over the next handler of the snapshot: it does not accept the
\* percept, or its instance was deactivated earlier in this dispatch (R4b).
Skip ==
    /\ phase = "handle"
    /\ cur.todo # <<>>
    /\ LET t == Head(cur.todo)
       IN /\ ~Applicable(t)
          /\ last' = [act |-> "Skip", id |-> t.id, h |-> t.h]
    /\ cur' = [cur EXCEPT !.todo = Tail(cur.todo)]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, behVars, phase,
                   dispatched, done, waits>>

\* The snapshot is exhausted: the percept leaves the system; if no handler
\* applied it is discarded (R3b) and last says so.
EndDispatch ==
    /\ phase = "handle"
    /\ cur.todo = <<>>
    /\ done' = IF Flood THEN done ELSE done \cup {cur.e.seq}
    /\ last' = [act |-> "EndDispatch", seq |-> cur.e.seq,
                discarded |-> ~cur.applied]
    /\ cur' = NoDispatch
    /\ phase' = "dispatch"
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, behVars, dispatched,
                   waits>>

(***************************************************************************)
(* Agent actions: behaviour step and end of iteration.                     *)
(***************************************************************************)

\* Nothing (more) to dispatch in this iteration.
DispatchOver == pq = EmptyQueue \/ BudgetSpent

\* The handlers a behaviour step tries, in order: message handlers (R5b);
\* in native the percept handlers first, then the message handlers.
\* Each is [accepts, handler, isPercept].
StepHandlers(b) ==
    LET ph == [j \in DOMAIN PerceptHandlers[b] |->
                  [accepts |-> PerceptHandlers[b][j].accepts,
                   handler |-> PerceptHandlers[b][j], isPercept |-> TRUE]]
        mh == [j \in DOMAIN MessageHandlers[b] |->
                  [accepts |-> MessageHandlers[b][j].accepts,
                   handler |-> MessageHandlers[b][j], isPercept |-> FALSE]]
    IN IF Variant = "native" THEN ph \o mh ELSE mh

\* Does message-queue entry x match handler h?
Matches(h, x) ==
    IF h.isPercept THEN IsPercept(x) /\ x.p \in h.accepts
    ELSE x.kind = "message" /\ x.m \in h.accepts

\* Does handler h have a matching entry in the message queue?
HasMatch(h) == \E i \in DOMAIN msgq : Matches(h, msgq[i])

\* The index in hs of the first handler with a matching entry (0 if none).
FirstHandler(hs) ==
    IF \E j \in DOMAIN hs : HasMatch(hs[j])
    THEN CHOOSE j \in DOMAIN hs : HasMatch(hs[j]) /\ \A i \in 1..(j-1) : ~HasMatch(hs[i])
    ELSE 0

\* The index in msgq of the first entry matching handler h.
FirstEntry(h) ==
    CHOOSE i \in DOMAIN msgq : Matches(h, msgq[i]) /\ \A j \in 1..(i-1) : ~Matches(h, msgq[j])

(***************************************************************************)
(* What the step of the instance at ready[pos] finds (R5b): the handlers   *)
(* it tries, the first with a matching entry (0 if none), the index of the *)
(* entry it takes in msgq (0 if none) and the percept or message taken.    *)
(* Meaningful only when ready # <<>>.                                      *)
(***************************************************************************)
StepId == ready[pos]
StepHs == StepHandlers(BOf(StepId))
StepJ == FirstHandler(StepHs)
StepK == IF StepJ = 0 THEN 0 ELSE FirstEntry(StepHs[StepJ])
StepX == IF StepK = 0 THEN ""
         ELSE IF IsPercept(msgq[StepK]) THEN msgq[StepK].p ELSE msgq[StepK].m

\* The effects of the bodies that the step runs, in order: the action block,
\* then the handler that took an entry (R5b).
StepBodyEffects ==
    LET b == BOf(StepId)
    IN (IF HasAction[b] THEN ActionEffects[b] ELSE <<>>)
       \o (IF StepJ = 0 THEN <<>> ELSE HandlerEffects(StepHs[StepJ].handler, StepX))

\* The effects of the body that Handle runs: the head of the snapshot, for
\* the percept being dispatched.
HandleBodyEffects ==
    LET t == Head(cur.todo)
    IN HandlerEffects(PerceptHandlers[BOf(t.id)][t.h], cur.e.p)

(***************************************************************************)
(* One step of the instance at ready[pos], as JADE schedules it (R5f):     *)
(* pos advances first; the action block runs (if any); then the first      *)
(* handler with a matching entry takes the first such entry and runs       *)
(* (R5b: at most one entry per step).  With no action block and nothing    *)
(* consumed the instance blocks (R5d) unless it was deactivated during the *)
(* step.  A one-shot instance is deactivated after its step (R5c);         *)
(* DECISION: this wins over blocking (JADE removes a finished one-shot).   *)
(* Activations append to active and ready (R5g); `deactivate this` takes   *)
(* effect at once and the rest of the step still runs (R5h).  The step     *)
(* opens the window of SendInStep (R5d revised): stepped remembers S2, the *)
(* behaviour state before the block, when the step blocked its instance.   *)
(***************************************************************************)
BehaviourStep ==
    /\ phase = "dispatch"
    /\ DispatchOver
    /\ ready # <<>>
    /\ LET id == StepId
           b == BOf(id)
           S0 == [BS EXCEPT !.pos = (pos % Len(ready)) + 1]
           S1 == IF HasAction[b] THEN ApplyEffects(S0, id, ActionEffects[b], {id})
                 ELSE S0
           hs == StepHs
           j == StepJ
           k == StepK
           S2 == IF j = 0 THEN S1 ELSE ApplyEffects(S1, id, HandlerEffects(hs[j].handler, StepX), {id})
           stillActive == \E a \in Range(S2.active) : a.id = id
           blocks == Kind[b] # "oneshot" /\ ~HasAction[b] /\ j = 0 /\ stillActive
           S3 == IF Kind[b] = "oneshot" THEN Deactivate(S2, id)
                 ELSE IF blocks THEN Block(S2, id)
                 ELSE S2
       IN /\ SetBS(S3)
          /\ msgq' = IF k = 0 THEN msgq ELSE RemoveAt(msgq, k)
          /\ IF k # 0 /\ IsPercept(msgq[k])
             THEN /\ done' = IF Flood THEN done ELSE done \cup {msgq[k].seq}
                  /\ waits' = BumpWaits(ToPQ(msgq[k]))
             ELSE UNCHANGED <<done, waits>>
          /\ last' = [act |-> "BehaviourStep", id |-> id,
                      msg |-> IF k = 0 THEN NoMsg ELSE msgq[k]]
          /\ stepped' = IF blocks THEN [kind |-> "blocked", bs |-> S2]
                        ELSE [kind |-> "kept"]
    /\ phase' = "transfer"
    /\ UNCHANGED <<o2a, pq, nextSeq, msgSeq, puts, cur, dispatched>>

\* Would the agent go idle (R3e): nothing to step, no percept anywhere to
\* transfer or dispatch?
IdleCondition == ready = <<>> /\ ~PerceptInO2A /\ pq = EmptyQueue

\* Nothing to step in this iteration: start the next one.  DECISION: in the
\* variants that can idle, NextIteration is taken only when the agent would
\* not idle, so the agent is deterministic up to the tie policy.  The printed
\* loop never idles: it busy-waits with NextIteration / TransferEnd.
NextIteration ==
    /\ phase = "dispatch"
    /\ DispatchOver
    /\ ready = <<>>
    /\ (Variant = "printed" \/ ~IdleCondition)
    /\ phase' = "transfer"
    /\ last' = [act |-> "NextIteration"]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, behVars, cur,
                   dispatched, done, waits>>

\* Nothing to do at all: sleep until a notification or a message (R3e).
Idle ==
    /\ Variant # "printed"
    /\ phase = "dispatch"
    /\ DispatchOver
    /\ IdleCondition
    /\ phase' = "idle"
    /\ last' = [act |-> "Idle"]
    /\ stepped' = NoStep
    /\ UNCHANGED <<o2a, pq, msgq, nextSeq, msgSeq, puts, behVars, cur,
                   dispatched, done, waits>>

\* All agent actions.
AgentStep ==
    \/ Transfer \/ TransferOne \/ TransferSpin \/ TransferEnd
    \/ Dequeue \/ Handle \/ Skip \/ EndDispatch
    \/ BehaviourStep \/ NextIteration \/ Idle

\* The next-state relation.
Next == HostStep \/ AgentStep

\* The agent is weakly fair as a whole; the host is not fair at all.
Spec == Init /\ [][Next]_vars /\ WF_vars(AgentStep)

-----------------------------------------------------------------------------
(***************************************************************************)
(* Properties.                                                             *)
(***************************************************************************)

\* Action names, as in DOT labels and last.act.
ActNames == {"Init", "Notify", "NotifyWith", "Put", "Send", "SendInStep",
             "Transfer", "TransferOne", "TransferSpin", "TransferEnd",
             "Dequeue", "Handle", "Skip", "EndDispatch", "BehaviourStep",
             "NextIteration", "Idle"}

\* Seqs a percept may carry.
SeqRange == IF Flood THEN {0} ELSE 0..MaxNotify

\* Every variable has the expected shape.
TypeOK ==
    /\ o2a \in Seq(PerceptEntry \cup ObjectEntry)
    /\ Len(o2a) <= O2ACapacity
    /\ pq \subseteq EntrySet(Percepts, Prios, SeqRange)
    /\ msgq \in Seq(MessageEntry \cup PerceptEntry)
    /\ nextSeq \in SeqRange
    /\ msgSeq \in 0..MaxSend
    /\ puts \in 0..MaxPut
    /\ active \in Seq([id : Ids, b : Behaviours])
    /\ Len(active) <= MaxActive
    /\ ready \in Seq(Ids)
    /\ blocked \in Seq(Ids)
    /\ pos \in 1..(Len(ready) + 1)
    /\ (ready = <<>> => pos = 1) /\ (ready # <<>> => pos <= Len(ready))
    /\ phase \in {"transfer", "dispatch", "handle", "idle"}
    /\ (phase # "handle" => cur = NoDispatch)
    /\ (phase = "handle" => cur.e \in EntrySet(Percepts, Prios, SeqRange)
                            /\ cur.todo \in Seq([id : Ids, h : Nat])
                            /\ cur.applied \in BOOLEAN)
    /\ dispatched \in Nat
    /\ done \subseteq 1..MaxNotify
    /\ waits \subseteq (1..MaxNotify) \X Nat
    /\ last.act \in ActNames
    /\ stepped.kind \in {"none", "kept", "blocked"}
    /\ (stepped.kind # "none" => phase = "transfer")
    /\ (stepped.kind = "blocked" =>
            /\ stepped.bs.active = active
            /\ stepped.bs.ready \in Seq(Ids)
            /\ stepped.bs.blocked \in Seq(Ids)
            /\ stepped.bs.pos \in 1..Len(stepped.bs.ready))

\* Every ready or blocked instance is active, none twice, never both.
ReadyBlockedConsistent ==
    /\ \A i \in Range(ready) \cup Range(blocked) : IsActive(i)
    /\ Cardinality(Range(ready)) = Len(ready)
    /\ Cardinality(Range(blocked)) = Len(blocked)
    /\ Range(ready) \cap Range(blocked) = {}
    /\ Cardinality({a.id : a \in Range(active)}) = Len(active)

\* The percept just dispatched (a Dequeue, or a native behaviour step that
\* consumed a percept).
JustDispatched ==
    \/ last.act = "Dequeue"
    \/ last.act = "BehaviourStep" /\ last.msg.kind = "percept"

\* Its entry.
DispatchedEntry == IF last.act = "Dequeue" THEN last.e ELSE ToPQ(last.msg)

\* The entries still waiting in the dispatch source (pq; native: the
\* percepts of the message queue).
SourceEntries ==
    IF Variant = "native"
    THEN {ToPQ(x) : x \in {y \in Range(msgq) : IsPercept(y)}}
    ELSE pq

\* After a dispatch, nothing left in the source has a higher priority.
PriorityOrder ==
    JustDispatched => \A f \in SourceEntries : f.prio <= DispatchedEntry.prio

\* After a dispatch, nothing left in the source with the same priority
\* arrived earlier (R3b).
FifoAmongEquals ==
    JustDispatched =>
        \A f \in SourceEntries :
            f.prio = DispatchedEntry.prio => ~(f.seq < DispatchedEntry.seq)

\* The seqs of the percepts in the O2A queue,
SeqsO2A == {x.seq : x \in {y \in Range(o2a) : IsPercept(y)}}
\* ... in the priority queue,
SeqsPQ == {e.seq : e \in pq}
\* ... in the dispatch in progress,
SeqsCur == IF phase = "handle" THEN {cur.e.seq} ELSE {}
\* ... and in the native message queue.
SeqsMsgq == {x.seq : x \in {y \in Range(msgq) : IsPercept(y)}}

\* Every notified percept is in exactly one place (not meaningful under Flood).
NoDuplication ==
    Flood \/
    /\ Cardinality(SeqsO2A) = Len(SelectSeq(o2a, IsPercept))
    /\ Cardinality(SeqsMsgq) = MsgqPercepts
    /\ SeqsO2A \cap SeqsPQ = {}   /\ SeqsO2A \cap SeqsCur = {}
    /\ SeqsO2A \cap SeqsMsgq = {} /\ SeqsO2A \cap done = {}
    /\ SeqsPQ \cap SeqsCur = {}   /\ SeqsPQ \cap SeqsMsgq = {}
    /\ SeqsPQ \cap done = {}      /\ SeqsCur \cap SeqsMsgq = {}
    /\ SeqsCur \cap done = {}     /\ SeqsMsgq \cap done = {}
    /\ SeqsO2A \cup SeqsPQ \cup SeqsCur \cup SeqsMsgq \cup done = 1..nextSeq

\* Is the sequence of numbers s strictly increasing?
Increasing(s) == \A i, j \in DOMAIN s : i < j => s[i] < s[j]

\* The O2A queue keeps notification order, and every percept that left it
\* (pq, cur, native message queue) arrived before every percept still in it;
\* the native message queue keeps notification order too.
O2AOrderPreserved ==
    Flood \/
    /\ Increasing(LET ps == SelectSeq(o2a, IsPercept)
                  IN [i \in DOMAIN ps |-> ps[i].seq])
    /\ Increasing(LET ps == SelectSeq(msgq, IsPercept)
                  IN [i \in DOMAIN ps |-> ps[i].seq])
    /\ \A s \in SeqsPQ \cup SeqsCur \cup SeqsMsgq, t \in SeqsO2A : s < t

\* No percept waits behind more than InversionBound dispatches of
\* lower-priority percepts.
BoundedInversion == \A w \in waits : w[2] <= InversionBound

\* At most Budget percepts are dispatched in one loop iteration, i.e.
\* between two transfers (and hence between two behaviour steps).  True by
\* construction in "budgeted"; checked for the other variants to measure how
\* many percepts one iteration may dispatch.
DispatchesWithinBudget == dispatched <= Budget

\* Every notified percept eventually leaves the system (not under Flood).
NoLoss == \A s \in (IF Flood THEN {} ELSE 1..MaxNotify) : (s <= nextSeq) ~> (s \in done)

\* Did instance i just step?
Stepped(i) == last.act = "BehaviourStep" /\ last.id = i

\* A ready instance eventually steps or leaves the ready list.
BehaviourProgress == \A i \in Ids : InReady(i) ~> (Stepped(i) \/ ~InReady(i))

\* Message s is in the queue and some active instance has a handler for it.
MsgAccepted(s) ==
    \E k \in DOMAIN msgq :
        /\ msgq[k].kind = "message" /\ msgq[k].seq = s
        /\ \E a \in Range(active) : \E j \in DOMAIN MessageHandlers[a.b] :
               msgq[k].m \in MessageHandlers[a.b][j].accepts

\* A message that some active handler accepts is eventually consumed or
\* stops being accepted.
MessageProgress == \A s \in 1..MaxSend : MsgAccepted(s) ~> ~MsgAccepted(s)

\* Message s is in the queue.
MsgWaiting(s) == \E k \in DOMAIN msgq : msgq[k].kind = "message" /\ msgq[k].seq = s

\* Every message that reaches the agent is eventually taken by a behaviour
\* step, whether or not a handler accepts it.  It fails as soon as a message
\* that no handler takes can arrive: that message stays in the queue for
\* good, as in JADE (checked in spec/Platform.tla, for the failures).
EveryMessageConsumed == \A s \in 1..MaxSend : MsgWaiting(s) ~> ~MsgWaiting(s)

\* There is work: a percept to transfer, a percept to dispatch, or a ready
\* behaviour.
PendingWork == PerceptInO2A \/ pq # EmptyQueue \/ ready # <<>>

\* The last step did work: moved a percept, dispatched one, or ran a behaviour.
WorkStep ==
    \/ last.act = "Transfer" /\ last.moved > 0
    \/ last.act \in {"TransferOne", "Dequeue", "BehaviourStep"}

\* Pending work always leads to a work step (or disappears, e.g. the only
\* ready instance is deactivated by a percept handler): the agent never
\* spins while there is something to do.
NoLivelock == PendingWork ~> (WorkStep \/ ~PendingWork)

=============================================================================
