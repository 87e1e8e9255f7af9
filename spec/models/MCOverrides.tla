---------------------------- MODULE MCOverrides -----------------------------
(***************************************************************************)
(* Priority overrides (R2a): the host may call notifyEvent(p, k) with      *)
(* k in {0, 9}, so a position can overtake an obstacle and an obstacle can *)
(* sink below a position.  Dispatch follows the effective priority: the    *)
(* order properties hold.                                                  *)
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
MCPercepts == {"obstacle", "position"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2]
MCOverrides == {0, 9}
MCObjects == {}
MCMessages == {}
MCMaxNotify == 2
MCMaxPut == 0
MCMaxSend == 0
MCFlood == FALSE
MCO2ACapacity == 2
MCBehaviours == {"Main"}
MCKind == [Main |-> "cyclic"]
MCHasAction == [Main |-> FALSE]
MCActionEffects == [Main |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<>>],
                        [accepts |-> {"position"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 2
=============================================================================
