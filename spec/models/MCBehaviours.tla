---------------------------- MODULE MCBehaviours ------------------------------------
(***************************************************************************)
(* Behaviours.                                                             *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect O2AOrderPreserved holds
\* expect NoLoss holds
\* expect BehaviourProgress holds
\* expect MessageProgress holds
\* expect NoLivelock holds
EXTENDS AgentLoop

MCVariant == "reference"
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
MCFlood == FALSE
MCO2ACapacity == 2
MCBehaviours == {"Main", "Once"}
MCKind == [Main |-> "cyclic", Once |-> "oneshot"]
MCHasAction == [Main |-> FALSE, Once |-> TRUE]
MCActionEffects == [Main |-> <<>>, Once |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<[op |-> "activate", b |-> "Once"]>>],
                              [accepts |-> {"position"}, effects |-> <<[op |-> "deactivate"]>>]>>,
                        Once |-> <<[accepts |-> {"obstacle"}, effects |-> <<[op |-> "deactivate"]>>]>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"inform"}, effects |-> <<>>]>>, Once |-> <<>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 2
MCInversionBound == 2
=============================================================================
