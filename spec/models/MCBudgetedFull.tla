--------------------------- MODULE MCBudgetedFull ---------------------------
(***************************************************************************)
(* Budgeted variant, larger (run by spec-full only): the constants of      *)
(* MCReferenceFull with Budget = 2.  Every property holds: the budget      *)
(* bounds both the dispatches per iteration and the inversion.             *)
(***************************************************************************)
\* full
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect O2AOrderPreserved holds
\* expect BoundedInversion holds
\* expect DispatchesWithinBudget holds
\* expect NoLoss holds
\* expect BehaviourProgress holds
\* expect MessageProgress holds
\* expect NoLivelock holds
EXTENDS AgentLoop

MCVariant == "budgeted"
MCTiePolicy == "Stable"
MCBudget == 2
MCPercepts == {"obstacle", "position"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2]
MCOverrides == {}
MCObjects == {"obj"}
MCMessages == {"inform"}
MCMaxNotify == 4
MCMaxPut == 1
MCMaxSend == 2
MCFlood == FALSE
MCO2ACapacity == 3
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
