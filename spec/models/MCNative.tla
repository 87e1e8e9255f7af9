---------------------------- MODULE MCNative ----------------------------------------
(***************************************************************************)
(* Native.                                                                 *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect O2AOrderPreserved holds
\* expect BoundedInversion violated invariant
\* expect NoLoss violated lasso
\* expect BehaviourProgress holds
\* expect MessageProgress holds
\* expect NoLivelock holds
EXTENDS AgentLoop

MCVariant == "native"
MCTiePolicy == "Stable"
MCBudget == 1
MCPercepts == {"obstacle", "position", "noise"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2, noise |-> 1]
MCOverrides == {}
MCObjects == {}
MCMessages == {"inform"}
MCMaxNotify == 2
MCMaxPut == 0
MCMaxSend == 1
MCFlood == FALSE
MCO2ACapacity == 2
MCBehaviours == {"Main"}
MCKind == [Main |-> "cyclic"]
MCHasAction == [Main |-> FALSE]
MCActionEffects == [Main |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<>>],
                        [accepts |-> {"position"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"inform"}, effects |-> <<>>]>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 0
=============================================================================
