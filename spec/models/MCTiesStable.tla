---------------------------- MODULE MCTiesStable ------------------------------------
(***************************************************************************)
(* Ties, stable policy (R3b): two percept types with the same priority.    *)
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
