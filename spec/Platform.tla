------------------------------ MODULE Platform ------------------------------
(***************************************************************************)
(* Two Jadescript agents on one JADE platform, as JADE runs them (R6       *)
(* revised).  Each agent is an instance of AgentLoop with variables of its *)
(* own (A and B).  The rules of the two agents interleave in any order,    *)
(* each rule atomic.  A message that a body sends (a send effect of        *)
(* AgentLoop, R5e) travels in a channel to its receiver and reaches it at  *)
(* any later moment, in the order of the sends to that receiver: between   *)
(* any two rules of the receiver (Send) or during its last behaviour step  *)
(* (SendInStep, R5d revised).  A host notifies percepts to both agents at  *)
(* any moment (R2).                                                        *)
(*                                                                         *)
(* The platform's own agents (R5e revised, D44): every platform has ams    *)
(* and df; no program agent takes their names.  A message to ams or df is  *)
(* taken by them and never answered: on JADE 4.3 they read only messages   *)
(* of their own ontologies, which a program's message never carries.  A   *)
(* message to an agent that is not on the platform is not delivered: ams   *)
(* answers the sender with a failure (D43: its content names the receiver  *)
(* that could not be reached).  That failure is a message to the sender,   *)
(* sent at some moment after the message that caused it (the platform's   *)
(* queue `pending`) and delivered like any message (it wakes blocked       *)
(* behaviours, a handler may take it).                                     *)
(*                                                                         *)
(* Model bounds, not language rules: an agent sends at most MaxOut         *)
(* messages (later sends are dropped), so that the state graph is finite;  *)
(* each agent's MaxSend is 2 * MaxOut, which no run reaches (the messages  *)
(* to an agent are the other agent's and the answers to its own).          *)
(*                                                                         *)
(* Properties: AgentLoop's, for both agents, under this finer              *)
(* interleaving, and the platform's own (docs/spec.md, "Several agents").  *)
(***************************************************************************)
EXTENDS Naturals, Sequences, FiniteSets

CONSTANTS
    Variant,    \* the loop of both agents (AgentLoop's Variant)
    TiePolicy,  \* AgentLoop's TiePolicy
    Budget,     \* AgentLoop's Budget
    NameA,      \* the name of agent A (a string)
    NameB,      \* the name of agent B
    ConfA,      \* agent A: a record of AgentLoop's other constants, fields
                \*   percepts, defaultPriority, overrides, objects, messages,
                \*   maxNotify, maxPut, o2aCapacity, behaviours, kind,
                \*   hasAction, actionEffects, perceptHandlers,
                \*   messageHandlers, initialBehaviours, maxActive,
                \*   inversionBound
    ConfB,      \* agent B, the same
    MaxOut      \* model bound: messages each agent may send

\* The program's agents, and the platform's own (R5e revised).
Agents == {NameA, NameB}
PlatformAgents == {"ams", "df"}

\* The name of the platform's one answer: ams's failure to the sender of a
\* message to an agent not on the platform (D43).
Failure == "failure"

ASSUME
    /\ NameA # NameB
    /\ Agents \cap (PlatformAgents \cup {"host"}) = {}
    /\ MaxOut \in Nat

VARIABLES
    \* agent A: AgentLoop's variables
    o2aA, pqA, msgqA, nextSeqA, msgSeqA, putsA, activeA, readyA, blockedA,
    posA, phaseA, curA, dispatchedA, doneA, waitsA, lastA, steppedA,
    \* agent B: the same
    o2aB, pqB, msgqB, nextSeqB, msgSeqB, putsB, activeB, readyB, blockedB,
    posB, phaseB, curB, dispatchedB, doneB, waitsB, lastB, steppedB,
    chan,       \* [Agents -> Seq(message name)]: sent, not yet delivered, in
                \*   the order of the sends to that receiver
    pending,    \* Seq([from, to, m]): sent to an agent not on the platform,
                \*   not yet answered, in send order
    out,        \* [Agents -> Nat]: messages each agent has sent (MaxOut)
    absent,     \* ghost: [Agents -> Nat]: messages each agent has sent to
                \*   agents not on the platform
    failures,   \* ghost: [Agents -> Nat]: failures ams has sent each agent
    overA,      \* ghost: [instance id -> Nat] for A: behaviour steps of other
                \*   instances since the instance joined the ready list or last
                \*   stepped (0 when it is not ready)
    overB       \* ghost: the same for B

A == INSTANCE AgentLoop WITH
        Percepts <- ConfA.percepts, DefaultPriority <- ConfA.defaultPriority,
        Overrides <- ConfA.overrides, Objects <- ConfA.objects,
        Messages <- ConfA.messages, MaxNotify <- ConfA.maxNotify,
        MaxPut <- ConfA.maxPut, MaxSend <- 2 * MaxOut, Flood <- FALSE,
        O2ACapacity <- ConfA.o2aCapacity, Behaviours <- ConfA.behaviours,
        Kind <- ConfA.kind, HasAction <- ConfA.hasAction,
        ActionEffects <- ConfA.actionEffects,
        PerceptHandlers <- ConfA.perceptHandlers,
        MessageHandlers <- ConfA.messageHandlers,
        InitialBehaviours <- ConfA.initialBehaviours,
        MaxActive <- ConfA.maxActive, InversionBound <- ConfA.inversionBound,
        o2a <- o2aA, pq <- pqA, msgq <- msgqA, nextSeq <- nextSeqA,
        msgSeq <- msgSeqA, puts <- putsA, active <- activeA, ready <- readyA,
        blocked <- blockedA, pos <- posA, phase <- phaseA, cur <- curA,
        dispatched <- dispatchedA, done <- doneA, waits <- waitsA,
        last <- lastA, stepped <- steppedA

B == INSTANCE AgentLoop WITH
        Percepts <- ConfB.percepts, DefaultPriority <- ConfB.defaultPriority,
        Overrides <- ConfB.overrides, Objects <- ConfB.objects,
        Messages <- ConfB.messages, MaxNotify <- ConfB.maxNotify,
        MaxPut <- ConfB.maxPut, MaxSend <- 2 * MaxOut, Flood <- FALSE,
        O2ACapacity <- ConfB.o2aCapacity, Behaviours <- ConfB.behaviours,
        Kind <- ConfB.kind, HasAction <- ConfB.hasAction,
        ActionEffects <- ConfB.actionEffects,
        PerceptHandlers <- ConfB.perceptHandlers,
        MessageHandlers <- ConfB.messageHandlers,
        InitialBehaviours <- ConfB.initialBehaviours,
        MaxActive <- ConfB.maxActive, InversionBound <- ConfB.inversionBound,
        o2a <- o2aB, pq <- pqB, msgq <- msgqB, nextSeq <- nextSeqB,
        msgSeq <- msgSeqB, puts <- putsB, active <- activeB, ready <- readyB,
        blocked <- blockedB, pos <- posB, phase <- phaseB, cur <- curB,
        dispatched <- dispatchedB, done <- doneB, waits <- waitsB,
        last <- lastB, stepped <- steppedB

\* The variables of each agent (A!vars and B!vars written out: TLC 2.18
\* cannot take UNCHANGED of an instance's tuple), and of the platform.
varsA == <<o2aA, pqA, msgqA, nextSeqA, msgSeqA, putsA, activeA, readyA, blockedA,
           posA, phaseA, curA, dispatchedA, doneA, waitsA, lastA, steppedA>>
varsB == <<o2aB, pqB, msgqB, nextSeqB, msgSeqB, putsB, activeB, readyB, blockedB,
           posB, phaseB, curB, dispatchedB, doneB, waitsB, lastB, steppedB>>
platformVars == <<chan, pending, out, absent, failures>>
vars == <<varsA, varsB, platformVars, overA, overB>>

-----------------------------------------------------------------------------
(***************************************************************************)
(* Sending (R5e).                                                          *)
(***************************************************************************)

\* The messages a body sends: the send effects among its effects, in order.
SendsIn(effs) == SelectSeq(effs, LAMBDA e : e.op = "send")

\* The channels, the platform's queue and the count n of agent from, after
\* it sent the messages ss: to an agent of the program, into its channel;
\* to ams or df, taken by them (nothing more happens, D44); to an agent not
\* on the platform, into the platform's queue.  Each counts against MaxOut;
\* from then on sends are dropped (a model bound).  The result is
\* <<chan, pending, n>>.
RECURSIVE Post(_, _, _, _, _)
Post(from, ss, ch, pd, n) ==
    IF ss = <<>> \/ n >= MaxOut THEN <<ch, pd, n>>
    ELSE LET e == Head(ss)
         IN IF e.to \in Agents
            THEN Post(from, Tail(ss), [ch EXCEPT ![e.to] = Append(@, e.m)], pd, n + 1)
            ELSE IF e.to \in PlatformAgents
            THEN Post(from, Tail(ss), ch, pd, n + 1)
            ELSE Post(from, Tail(ss), ch,
                      Append(pd, [from |-> from, to |-> e.to, m |-> e.m]), n + 1)

\* The ghost absent, counted apart from Post's routing: of the first k
\* messages of ss (those posted), the ones to an agent not on the platform.
ToAbsent(ss, k) ==
    Len(SelectSeq(SubSeq(ss, 1, k), LAMBDA e : e.to \notin Agents \cup PlatformAgents))

\* The messages sent by the rule an agent just took: the bodies of a Handle
\* or of a BehaviourStep send; no other rule runs a body.  (AgentLoop's
\* HandleBodyEffects and StepBodyEffects are evaluated in the state before
\* the rule, where they are defined; last' says which rule it was.)
BodySendsA == IF lastA'.act = "Handle" THEN SendsIn(A!HandleBodyEffects)
              ELSE IF lastA'.act = "BehaviourStep" THEN SendsIn(A!StepBodyEffects)
              ELSE <<>>
BodySendsB == IF lastB'.act = "Handle" THEN SendsIn(B!HandleBodyEffects)
              ELSE IF lastB'.act = "BehaviourStep" THEN SendsIn(B!StepBodyEffects)
              ELSE <<>>

(***************************************************************************)
(* The overtaking ghost.  After a rule of an agent, an instance that is    *)
(* not ready counts 0; the instance that just stepped counts 0; every      *)
(* other instance that was ready and still is counts one more if the rule  *)
(* was a behaviour step.                                                   *)
(***************************************************************************)
InSeq(s, x) == \E k \in DOMAIN s : s[k] = x

Overtake(ov, ready, ready2, last2) ==
    [i \in DOMAIN ov |->
        IF ~InSeq(ready2, i) THEN 0
        ELSE IF last2.act # "BehaviourStep" THEN ov[i]
        ELSE IF i = last2.id THEN 0
        ELSE IF InSeq(ready, i) THEN ov[i] + 1
        ELSE ov[i]]

-----------------------------------------------------------------------------
(***************************************************************************)
(* Initial state: both agents created (R5g), nothing in flight.            *)
(***************************************************************************)
Init ==
    /\ A!Init
    /\ B!Init
    /\ chan = [n \in Agents |-> <<>>]
    /\ pending = <<>>
    /\ out = [n \in Agents |-> 0]
    /\ absent = [n \in Agents |-> 0]
    /\ failures = [n \in Agents |-> 0]
    /\ overA = [i \in A!Ids |-> 0]
    /\ overB = [i \in B!Ids |-> 0]

(***************************************************************************)
(* The host (not fair): notifications and puts to either agent (R2).       *)
(***************************************************************************)
HostA ==
    /\ \/ \E p \in ConfA.percepts : A!Notify(p)
       \/ \E p \in ConfA.percepts, k \in ConfA.overrides : A!NotifyWith(p, k)
       \/ \E o \in ConfA.objects : A!Put(o)
    /\ UNCHANGED <<varsB, platformVars, overA, overB>>

HostB ==
    /\ \/ \E p \in ConfB.percepts : B!Notify(p)
       \/ \E p \in ConfB.percepts, k \in ConfB.overrides : B!NotifyWith(p, k)
       \/ \E o \in ConfB.objects : B!Put(o)
    /\ UNCHANGED <<varsA, platformVars, overA, overB>>

(***************************************************************************)
(* One rule of an agent's loop (R6 revised: atomic; the other agent's      *)
(* rules, deliveries and the host come in between); what its bodies sent   *)
(* is posted.                                                              *)
(***************************************************************************)
StepA ==
    /\ A!AgentStep
    /\ LET r == Post(NameA, BodySendsA, chan, pending, out[NameA])
       IN /\ chan' = r[1]
          /\ pending' = r[2]
          /\ out' = [out EXCEPT ![NameA] = r[3]]
          /\ absent' = [absent EXCEPT ![NameA] =
                           @ + ToAbsent(BodySendsA, r[3] - out[NameA])]
          /\ UNCHANGED failures
    /\ overA' = Overtake(overA, readyA, readyA', lastA')
    /\ UNCHANGED <<varsB, overB>>

StepB ==
    /\ B!AgentStep
    /\ LET r == Post(NameB, BodySendsB, chan, pending, out[NameB])
       IN /\ chan' = r[1]
          /\ pending' = r[2]
          /\ out' = [out EXCEPT ![NameB] = r[3]]
          /\ absent' = [absent EXCEPT ![NameB] =
                           @ + ToAbsent(BodySendsB, r[3] - out[NameB])]
          /\ UNCHANGED failures
    /\ overB' = Overtake(overB, readyB, readyB', lastB')
    /\ UNCHANGED <<varsA, overA>>

(***************************************************************************)
(* The oldest message in flight to an agent reaches it (R5e, R6 revised):  *)
(* between two of its rules (Send), or during its last behaviour step      *)
(* (SendInStep, R5d revised), when that step's window is open.             *)
(***************************************************************************)
DeliverA ==
    /\ chan[NameA] # <<>>
    /\ \/ A!Send(Head(chan[NameA]))
       \/ A!SendInStep(Head(chan[NameA]))
    /\ chan' = [chan EXCEPT ![NameA] = Tail(@)]
    /\ overA' = Overtake(overA, readyA, readyA', lastA')
    /\ UNCHANGED <<varsB, pending, out, absent, failures, overB>>

DeliverB ==
    /\ chan[NameB] # <<>>
    /\ \/ B!Send(Head(chan[NameB]))
       \/ B!SendInStep(Head(chan[NameB]))
    /\ chan' = [chan EXCEPT ![NameB] = Tail(@)]
    /\ overB' = Overtake(overB, readyB, readyB', lastB')
    /\ UNCHANGED <<varsA, pending, out, absent, failures, overA>>

(***************************************************************************)
(* The platform answers the oldest message sent to an agent that is not   *)
(* on the platform (R5e revised, D43): a failure from ams, into the        *)
(* sender's channel.  Messages to ams and df never come here (D44).        *)
(***************************************************************************)
Answer ==
    /\ pending # <<>>
    /\ LET x == Head(pending)
       IN /\ chan' = [chan EXCEPT ![x.from] = Append(@, Failure)]
          /\ failures' = [failures EXCEPT ![x.from] = @ + 1]
    /\ pending' = Tail(pending)
    /\ UNCHANGED <<varsA, varsB, out, absent, overA, overB>>

Next == HostA \/ HostB \/ StepA \/ StepB \/ DeliverA \/ DeliverB \/ Answer

\* The platform's deliveries and answers.
Deliver == DeliverA \/ DeliverB \/ Answer

\* Each agent is weakly fair (its thread runs), and so is the platform's
\* delivery as a whole: while a message is in flight, some delivery or
\* answer happens.  (As each agent sends finitely many messages, this
\* delivers every message, as fairness for each channel would, and it is
\* one fairness condition for TLC to check instead of three.)  The host is
\* not fair.
Spec == /\ Init /\ [][Next]_vars
        /\ WF_vars(StepA) /\ WF_vars(StepB) /\ WF_vars(Deliver)

-----------------------------------------------------------------------------
(***************************************************************************)
(* Properties: AgentLoop's, for both agents (docs/spec.md, "Properties").  *)
(***************************************************************************)
TypeOK ==
    /\ A!TypeOK /\ B!TypeOK
    /\ chan[NameA] \in Seq(ConfA.messages)
    /\ chan[NameB] \in Seq(ConfB.messages)
    /\ \A n \in Agents : out[n] \in 0..MaxOut
    /\ \A n \in Agents : absent[n] \in 0..MaxOut /\ failures[n] \in 0..MaxOut
    /\ \A k \in DOMAIN pending :
          pending[k].from \in Agents /\ pending[k].to \notin Agents \cup PlatformAgents

ReadyBlockedConsistent == A!ReadyBlockedConsistent /\ B!ReadyBlockedConsistent
PriorityOrder == A!PriorityOrder /\ B!PriorityOrder
FifoAmongEquals == A!FifoAmongEquals /\ B!FifoAmongEquals
NoDuplication == A!NoDuplication /\ B!NoDuplication
O2AOrderPreserved == A!O2AOrderPreserved /\ B!O2AOrderPreserved
BoundedInversion == A!BoundedInversion /\ B!BoundedInversion
DispatchesWithinBudget == A!DispatchesWithinBudget /\ B!DispatchesWithinBudget
NoLoss == A!NoLoss /\ B!NoLoss
BehaviourProgress == A!BehaviourProgress /\ B!BehaviourProgress
MessageProgress == A!MessageProgress /\ B!MessageProgress
NoLivelock == A!NoLivelock /\ B!NoLivelock

(***************************************************************************)
(* The platform's properties.                                              *)
(***************************************************************************)

\* Exact round robin: between two steps of a ready behaviour (or from when
\* it became ready), at most MaxActive - 1 steps of other behaviours of its
\* agent, each of the others at most once.
RoundRobinBound ==
    /\ \A i \in DOMAIN overA : overA[i] <= ConfA.maxActive - 1
    /\ \A i \in DOMAIN overB : overB[i] <= ConfB.maxActive - 1

\* No starvation, with a bound: at most 2 * (MaxActive - 1) steps of other
\* behaviours, each of the others at most twice.  (A behaviour woken by a
\* message that came after its step goes to the end of the ready list
\* (R5d), which may come before the behaviours it had passed; one woken by a
\* message that came during its step keeps its place.)
WaitBound ==
    /\ \A i \in DOMAIN overA : overA[i] <= 2 * (ConfA.maxActive - 1)
    /\ \A i \in DOMAIN overB : overB[i] <= 2 * (ConfB.maxActive - 1)

\* Every message sent to an agent of the program reaches it.  (Each agent
\* sends at most MaxOut messages, so a channel that empties again and
\* again cannot hold a message for ever: "eventually empty" is "every
\* message delivered", in one temporal formula per agent instead of one per
\* message, which TLC checks much faster.)
DeliveryProgress == \A n \in Agents : chan[n] # <<>> ~> chan[n] = <<>>

\* The platform's answers are exactly ams's failures for the messages to
\* agents not on the platform (D43, D44): each agent has had one failure
\* for each such message it sent, but for those still waiting in the
\* platform's queue, and none for its messages to ams or df, which are
\* never answered.
PendingFrom(n) == Len(SelectSeq(pending, LAMBDA x : x.from = n))
OnlyFailuresAnswer == \A n \in Agents : failures[n] + PendingFrom(n) = absent[n]

\* Every message to an agent not on the platform is answered by ams's
\* failure, and no message to ams or df is ever answered.
PlatformAnswers == /\ [](OnlyFailuresAnswer)
                   /\ (pending # <<>> ~> pending = <<>>)

\* Every message that reaches an agent is eventually taken by a handler,
\* whether or not one accepts it (AgentLoop's EveryMessageConsumed, in the
\* same one-formula form as DeliveryProgress: finitely many messages).
MessageWaitingA == \E k \in DOMAIN msgqA : msgqA[k].kind = "message"
MessageWaitingB == \E k \in DOMAIN msgqB : msgqB[k].kind = "message"
MessagesConsumed == /\ MessageWaitingA ~> ~MessageWaitingA
                    /\ MessageWaitingB ~> ~MessageWaitingB

=============================================================================
