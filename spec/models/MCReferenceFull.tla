-------------------------- MODULE MCReferenceFull ---------------------------
(***************************************************************************)
(* Reference variant, larger (run by spec-full only): four                 *)
(* notifications, O2A capacity 3, one object, two messages, and the        *)
(* behaviours of MCBehaviours.                                             *)
(* Every property holds except the two bounds, which the O2A capacity (3)  *)
(* exceeds: three positions can be transferred in one batch, so an         *)
(* iteration dispatches 3 > Budget = 2 percepts and an obstacle notified   *)
(* after the Transfer waits behind 3 > InversionBound = 2 dispatches.      *)
(***************************************************************************)
\* full
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect O2AOrderPreserved holds
\* expect BoundedInversion violated invariant
\* expect DispatchesWithinBudget violated invariant
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
