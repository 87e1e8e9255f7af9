---------------------------- MODULE MCInversion -----------------------------
(***************************************************************************)
(* Reference variant with the constants of MCBudgeted (Budget = 1,         *)
(* InversionBound = 1, three notifications, O2A capacity 3).  The atomic   *)
(* Transfer moves the whole O2A batch into the priority queue and the      *)
(* iteration drains it: two dispatches in one iteration                    *)
(* (DispatchesWithinBudget violated: position, position, Transfer, Dequeue,*)
(* Dequeue), and an obstacle notified after the Transfer waits behind both *)
(* (BoundedInversion violated).  The dispatches per iteration, and the     *)
(* inversion, grow with the O2A capacity: bounded only by it.              *)
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
