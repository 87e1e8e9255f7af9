---------------------------- MODULE MCFloodNative -----------------------------------
(***************************************************************************)
(* Flood, native.                                                          *)
(***************************************************************************)
\* expect TypeOK holds
\* expect BehaviourProgress holds
\* expect MessageProgress violated lasso
\* expect NoLivelock holds
EXTENDS AgentLoop

MCVariant == "native"
MCTiePolicy == "Stable"
MCBudget == 1
MCPercepts == {"obstacle", "position"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2]
MCOverrides == {}
MCObjects == {}
MCMessages == {"inform"}
MCMaxNotify == 2
MCMaxPut == 0
MCMaxSend == 1
MCFlood == TRUE
MCO2ACapacity == 1
MCBehaviours == {"Main"}
MCKind == [Main |-> "cyclic"]
MCHasAction == [Main |-> FALSE]
MCActionEffects == [Main |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<>>],
                        [accepts |-> {"position"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"inform"}, effects |-> <<>>]>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 2
=============================================================================
