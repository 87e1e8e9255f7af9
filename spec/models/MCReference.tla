---------------------------- MODULE MCReference -----------------------------
(***************************************************************************)
(* Reference loop (R3), small.  Two percept types of the case study        *)
(* (obstacle 8, position 2), one non-percept O2A object, one message, one  *)
(* cyclic behaviour Main (no action block) with a percept handler for each *)
(* percept type and a message handler.  Every property holds: percepts are *)
(* dispatched by priority, ties by seq, none is lost or duplicated, the    *)
(* object does not block the transfer (R3a), behaviours and messages make  *)
(* progress, and one iteration never dispatches more than Budget = 2 = the *)
(* O2A capacity.  BoundedInversion with bound 1: a percept notified during *)
(* a dispatch waits for at most the one lower-priority percept already in  *)
(* the priority queue (MaxNotify = 2).                                     *)
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
