--------------------------- MODULE MCTiesUnstable ---------------------------
(***************************************************************************)
(* Ties under the unstable policy (java.util.PriorityQueue: any entry of   *)
(* the highest priority may come out).  Same model as MCTiesStable.        *)
(* FifoAmongEquals is violated: notify a (seq 1), notify b (seq 2),        *)
(* Transfer, Dequeue takes seq 2 while seq 1 (same priority) still waits.  *)
(* Priority order itself still holds, and nothing is lost.                 *)
(***************************************************************************)
\* expect TypeOK holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals violated invariant
\* expect NoDuplication holds
\* expect NoLoss holds
EXTENDS AgentLoop

MCVariant == "reference"
MCTiePolicy == "Unstable"
MCBudget == 1
MCPercepts == {"a", "b"}
MCDefaultPriority == [a |-> 1, b |-> 1]
MCOverrides == {}
MCObjects == {}
MCMessages == {}
MCMaxNotify == 3
MCMaxPut == 0
MCMaxSend == 0
MCFlood == FALSE
MCO2ACapacity == 3
MCBehaviours == {"Main"}
MCKind == [Main |-> "cyclic"]
MCHasAction == [Main |-> FALSE]
MCActionEffects == [Main |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"a", "b"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 2
=============================================================================
