---------------------------- MODULE MCTiesStable ----------------------------
(***************************************************************************)
(* Ties under the stable policy (R3b).  Two percept types with the same    *)
(* priority, three notifications: the priority queue always hands out the  *)
(* smallest seq among the highest priority, so FifoAmongEquals holds.      *)
(***************************************************************************)
\* expect TypeOK holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect NoLoss holds
EXTENDS AgentLoop

MCVariant == "reference"
MCTiePolicy == "Stable"
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
