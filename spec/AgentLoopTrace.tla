--------------------------- MODULE AgentLoopTrace ---------------------------
(***************************************************************************)
(* Trace validation of one agent (`jadescript-ref validate`,               *)
(* docs/trace-format.md "How TLC checks one agent"): is the run an         *)
(* implementation wrote in its trace a behaviour of AgentLoop?             *)
(*                                                                         *)
(* The trace is data: TraceLog holds one record per step of the agent, in  *)
(* order, and a module that validate generates gives it, with the          *)
(* constants of AgentLoop read off the same trace.  Each record is the     *)
(* value of the variable `last` after that step (the action and its        *)
(* parameters), with the run's values named as the model names them: the   *)
(* percept notified with seq s is "n<s>", the message delivered with seq s *)
(* is "m<s>", the object put with index k is "o<k>".                       *)
(*                                                                         *)
(* Below, one predicate per kind of line of the trace                      *)
(* (docs/trace-format.md, "Events"): which action of AgentLoop the line    *)
(* is, with which parameters.  Each ends with  last' = l : the step the    *)
(* spec takes must write the line exactly.  Lines that are not steps of    *)
(* the agent loop have no record and no predicate: what happens inside a   *)
(* step (log, invoke, send, activate, deactivate, error: their effects on  *)
(* behaviours are the handlers' constants), and what the spec does not     *)
(* model (refused, undeliverable, destroy); validate checks those in OCaml *)
(* (lib/explore/trace_check.ml).                                           *)
(*                                                                         *)
(* TLC follows TraceLog from its first record (TraceInit) one record at a  *)
(* time (TraceNext) and stutters at its end (TraceAccepted): it accepts    *)
(* the trace, or deadlocks where the spec cannot take the next record's    *)
(* step; traceIndex then says how far it got.  (The layout follows the     *)
(* trace validation of EWD998 in the TLA+ Examples,                        *)
(* specifications/ewd998/EWD998ChanTrace.tla, which reads a log line by    *)
(* line with one predicate per kind of line.)                              *)
(***************************************************************************)
EXTENDS AgentLoop

CONSTANT TraceLog   \* Seq of records: the value of `last` after each step

VARIABLE traceIndex \* how many records of TraceLog the behaviour has matched

(***************************************************************************)
(* The first line of an agent.                                             *)
(***************************************************************************)

\* "create" (Init): the agent exists and its on create ran; the behaviours
\* it activated are the constant InitialBehaviours.
IsCreate(l) ==
    /\ l.act = "Init"
    /\ last = l

(***************************************************************************)
(* The host's steps.                                                       *)
(***************************************************************************)

\* "notify" with action Notify: notifyEvent(p), the default priority of p's
\* type (R1a, R2b).  Record: [act, p, prio, seq].
IsNotify(l) ==
    /\ l.act = "Notify"
    /\ l.p \in Percepts
    /\ Notify(l.p)
    /\ last' = l

\* "notify" with action NotifyWith: notifyEvent(p, k), the priority given by
\* the host (R2a).  Record: [act, p, prio, seq].
IsNotifyWith(l) ==
    /\ l.act = "NotifyWith"
    /\ l.p \in Percepts
    /\ l.prio \in Overrides
    /\ NotifyWith(l.p, l.prio)
    /\ last' = l

\* "put" (Put): an object into the O2A queue (R2c).  Record: [act, obj].
IsPut(l) ==
    /\ l.act = "Put"
    /\ l.obj \in Objects
    /\ Put(l.obj)
    /\ last' = l

\* "deliver" (Send): a message reached the agent (R5e); from another agent
\* or from the host, the spec's host sends it.  Record: [act, m, seq].
IsDeliver(l) ==
    /\ l.act = "Send"
    /\ l.m \in Messages
    /\ Send(l.m)
    /\ last' = l

\* "deliver" with action SendInStep (R5d revised): a message that reached
\* the agent during its last behaviour step, after that step's handlers
\* looked; the behaviour the step blocked is runnable again at its place.
\* Record: [act, m, seq].
IsSendInStep(l) ==
    /\ l.act = "SendInStep"
    /\ l.m \in Messages
    /\ SendInStep(l.m)
    /\ last' = l

(***************************************************************************)
(* The agent's steps: transfer.                                            *)
(***************************************************************************)

\* "transfer" (Transfer, R3a): every percept of the O2A queue moved at once.
\* Record: [act, moved].
IsTransfer(l) ==
    /\ l.act = "Transfer"
    /\ Transfer
    /\ last' = l

\* "transfer_one" (TransferOne, printed): the head of the O2A queue, a
\* percept, moved.  Record: [act, p, prio, seq].
IsTransferOne(l) ==
    /\ l.act = "TransferOne"
    /\ TransferOne
    /\ last' = l

\* "transfer_spin" (TransferSpin, printed): the head is an object; the loop
\* peeks at it again.  Record: [act, obj].
IsTransferSpin(l) ==
    /\ l.act = "TransferSpin"
    /\ TransferSpin
    /\ last' = l

\* "transfer_end" (TransferEnd, printed): the O2A queue is empty.
IsTransferEnd(l) ==
    /\ l.act = "TransferEnd"
    /\ TransferEnd
    /\ last' = l

(***************************************************************************)
(* The agent's steps: dispatch of percepts.                                *)
(***************************************************************************)

\* "dequeue" (Dequeue, R3b): the percept that leaves the priority queue
\* first.  Record: [act, e |-> [p, prio, seq]].
IsDequeue(l) ==
    /\ l.act = "Dequeue"
    /\ Dequeue
    /\ last' = l

\* "handle" (Handle, R3b, R4): the next registered handler applies and runs.
\* Record: [act, id, h, p, seq].
IsHandle(l) ==
    /\ l.act = "Handle"
    /\ Handle
    /\ last' = l

\* "skip" (Skip, R4b): the next registered handler does not apply, or its
\* instance was deactivated.  Record: [act, id, h].
IsSkip(l) ==
    /\ l.act = "Skip"
    /\ Skip
    /\ last' = l

\* "end_dispatch", or "discard" when no handler applied (EndDispatch, R3b).
\* Record: [act, seq, discarded].
IsEndDispatch(l) ==
    /\ l.act = "EndDispatch"
    /\ EndDispatch
    /\ last' = l

(***************************************************************************)
(* The agent's steps: behaviours and the end of an iteration.              *)
(***************************************************************************)

\* "behaviour_step" (BehaviourStep, R5a-R5d): the instance JADE's round
\* robin picks, and what it took from the message queue.  Record: [act, id,
\* msg], msg [kind |-> "none"], [kind |-> "message", m, seq] or (native)
\* [kind |-> "percept", p, prio, seq].
IsBehaviourStep(l) ==
    /\ l.act = "BehaviourStep"
    /\ BehaviourStep
    /\ last' = l

\* "next_iteration" (NextIteration): nothing to step; the loop goes round.
IsNextIteration(l) ==
    /\ l.act = "NextIteration"
    /\ NextIteration
    /\ last' = l

\* "idle" (Idle, R3e): nothing to do at all; the agent sleeps.
IsIdle(l) ==
    /\ l.act = "Idle"
    /\ Idle
    /\ last' = l

(***************************************************************************)
(* Following the trace.                                                    *)
(***************************************************************************)

\* The step of record l: exactly one of the predicates can hold, the one of
\* l.act.  (Every action of Next names itself in last.act, so this is
\* Next /\ last' = l, with the action and its parameters read off l.)
TraceStep(l) ==
    \/ IsNotify(l)
    \/ IsNotifyWith(l)
    \/ IsPut(l)
    \/ IsDeliver(l)
    \/ IsSendInStep(l)
    \/ IsTransfer(l)
    \/ IsTransferOne(l)
    \/ IsTransferSpin(l)
    \/ IsTransferEnd(l)
    \/ IsDequeue(l)
    \/ IsHandle(l)
    \/ IsSkip(l)
    \/ IsEndDispatch(l)
    \/ IsBehaviourStep(l)
    \/ IsNextIteration(l)
    \/ IsIdle(l)

TraceInit ==
    /\ traceIndex = 1
    /\ Init
    /\ IsCreate(TraceLog[1])

\* The next record, matched.
TraceAdvance ==
    /\ traceIndex < Len(TraceLog)
    /\ TraceStep(TraceLog[traceIndex + 1])
    /\ traceIndex' = traceIndex + 1

\* Every record matched: the whole trace is a behaviour of the spec.
TraceAccepted == traceIndex = Len(TraceLog)

\* Rejected: TLC finds a state where neither holds (a deadlock).
TraceNext ==
    \/ TraceAdvance
    \/ TraceAccepted /\ UNCHANGED <<vars, traceIndex>>

=============================================================================
