------------------------------- MODULE PQSpec -------------------------------
(***************************************************************************)
(* A tiny standalone specification of the percept priority queue alone:   *)
(* a producer enqueues percepts with a priority, a consumer dequeues.  It  *)
(* checks that the operators of PerceptPriority do what R3b says, before   *)
(* AgentLoop relies on them.                                               *)
(***************************************************************************)
EXTENDS PerceptPriority, Naturals

CONSTANTS
    Percepts,   \* percept names (strings)
    Prios,      \* priorities a producer may use (a finite set of Nat)
    MaxSeq,     \* how many entries may be enqueued in total
    TiePolicy   \* "Stable" or "Unstable"

ASSUME /\ Prios \subseteq Nat
       /\ MaxSeq \in Nat
       /\ TiePolicy \in TiePolicies

VARIABLES
    pq,       \* the queue: a set of entries [p, prio, seq]
    nextSeq,  \* the seq of the last enqueued entry (the first one gets 1)
    lastOut   \* the entry returned by the last step if it was a Dequeue,
              \* otherwise NoEntry (an Enqueue resets it)

vars == <<pq, nextSeq, lastOut>>

\* The value of lastOut when the last step was not a Dequeue.
NoEntry == [p |-> "", prio |-> 0, seq |-> 0]

\* Every variable has the expected shape.
TypeOK == /\ pq \subseteq EntrySet(Percepts, Prios, 1..MaxSeq)
          /\ nextSeq \in 0..MaxSeq
          /\ lastOut \in EntrySet(Percepts, Prios, 1..MaxSeq) \cup {NoEntry}

\* Empty queue, nothing enqueued yet.
Init == /\ pq = EmptyQueue
        /\ nextSeq = 0
        /\ lastOut = NoEntry

\* Enqueue percept p with priority k; it gets the next seq.
EnqueueAction(p, k) ==
    /\ nextSeq < MaxSeq
    /\ pq' = Enqueue(pq, [p |-> p, prio |-> k, seq |-> nextSeq + 1])
    /\ nextSeq' = nextSeq + 1
    /\ lastOut' = NoEntry

\* Dequeue one of the candidates allowed by the tie policy.
DequeueAction ==
    /\ pq # EmptyQueue
    /\ \E e \in Candidates(pq, TiePolicy) :
          /\ pq' = DequeueMax(pq, e)
          /\ lastOut' = e
    /\ UNCHANGED nextSeq

\* Either side may move.
Next == \/ \E p \in Percepts, k \in Prios : EnqueueAction(p, k)
        \/ DequeueAction

\* Safety only: no fairness needed.
Spec == Init /\ [][Next]_vars

\* The entry just dequeued has a priority at least as high as everything
\* still in the queue.
DequeueTakesHighest ==
    lastOut # NoEntry => \A e \in pq : e.prio <= lastOut.prio

\* Among equal priorities the entry just dequeued was the first to arrive:
\* no entry of the same priority with a smaller seq is still queued (R3b).
FifoAmongEquals ==
    lastOut # NoEntry =>
        \A e \in pq : e.prio = lastOut.prio => ~(e.seq < lastOut.seq)

=============================================================================
