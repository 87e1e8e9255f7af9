---------------------------- MODULE MCReference -------------------------------------
(***************************************************************************)
(* Reference loop (R3), small: two percepts of different priority,         *)
(* one object, one message, one cyclic behaviour handling both percepts    *)
(* and the message.  Every property holds.                                 *)
(***************************************************************************)
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

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 2
MCPercepts == {"obstacle", "position"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2]
MCOverrides == {}
MCObjects == {"obj"}
MCMessages == {"inform"}
MCMaxNotify == 2
MCMaxPut == 1
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
MCInversionBound == 1
=============================================================================
