---------------------------- MODULE MCInversion -------------------------------------
(***************************************************************************)
(* Reference inversion.                                                    *)
(***************************************************************************)
\* expect TypeOK holds
\* expect PriorityOrder holds
\* expect BoundedInversion violated invariant
\* expect DispatchesWithinBudget violated invariant
EXTENDS AgentLoop

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 1
MCPercepts == {"obstacle", "position"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2]
MCOverrides == {}
MCObjects == {}
MCMessages == {"inform"}
MCMaxNotify == 3
MCMaxPut == 0
MCMaxSend == 1
MCFlood == FALSE
MCO2ACapacity == 3
MCBehaviours == {"Main"}
MCKind == [Main |-> "cyclic"]
MCHasAction == [Main |-> FALSE]
MCActionEffects == [Main |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<>>],
                        [accepts |-> {"position"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"inform"}, effects |-> <<>>]>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 1
=============================================================================
