-------------------------- MODULE PerceptPriority --------------------------
(***************************************************************************)
(* The priority queue of percepts of a Jadescript agent, as an abstract    *)
(* data type.  Algorithm 1 of the paper ("priorityQueue") only says that   *)
(* percepts leave the queue "in decreasing order of priority" (Section 4). *)
(* Ruling R3b adds that ties go to the smallest arrival number (seq): the  *)
(* first percept notified is the first handled.  A java.util.PriorityQueue *)
(* does not promise that; the "Unstable" policy models it.                 *)
(*                                                                         *)
(* An entry is a record [p |-> percept name, prio |-> Nat, seq |-> Nat].   *)
(* The queue is a SET of entries: it has no internal order, so two queues  *)
(* holding the same entries are the same value (canonical for TLC and for  *)
(* the OCaml reproduction of the state graph).                             *)
(*                                                                         *)
(* This module has no variables; it is EXTENDed / INSTANCEd by PQSpec and  *)
(* AgentLoop.                                                              *)
(***************************************************************************)
EXTENDS Naturals, FiniteSets

\* The set of all entries over percept names P, priorities K, seqs S.
EntrySet(P, K, S) == [p : P, prio : K, seq : S]

\* The two tie policies (R3b).
TiePolicies == {"Stable", "Unstable"}

\* The empty queue.
EmptyQueue == {}

\* Add entry e to queue Q.  Identical entries merge (Q is a set); outside
\* the flood abstraction of AgentLoop every entry has its own seq, so no two
\* entries are ever identical.
Enqueue(Q, e) == Q \cup {e}

\* The highest priority present in the non-empty queue Q.
MaxPrio(Q) == CHOOSE k \in {e.prio : e \in Q} : \A e \in Q : e.prio <= k

\* The entries of the non-empty queue Q that carry the highest priority.
Top(Q) == {e \in Q : e.prio = MaxPrio(Q)}

\* The smallest seq among the entries of the non-empty set T.
MinSeq(T) == CHOOSE s \in {e.seq : e \in T} : \A e \in T : s <= e.seq

(***************************************************************************)
(* The entries that a dequeue may return from the non-empty queue Q.       *)
(*  - "Stable" (R3b): the entry with the highest priority and, among      *)
(*    those, the smallest seq.  When seqs are distinct this is exactly one *)
(*    entry.  (Only the flood abstraction of AgentLoop, where every seq is *)
(*    0, can make it several; then any of them may be taken: TLA+ cannot  *)
(*    order strings, and a CHOOSE would fix a TLC-internal order that an  *)
(*    implementation could not reproduce.)                                 *)
(*  - "Unstable": any entry with the highest priority, as the heap of     *)
(*    java.util.PriorityQueue may return any of them.                      *)
(***************************************************************************)
Candidates(Q, TiePolicy) ==
    IF TiePolicy = "Stable"
    THEN {e \in Top(Q) : e.seq = MinSeq(Top(Q))}
    ELSE Top(Q)

\* The queue left after the candidate e has been taken out of Q.
DequeueMax(Q, e) == Q \ {e}

=============================================================================
