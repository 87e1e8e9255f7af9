------------------------------ MODULE MCNative ------------------------------
(***************************************************************************)
(* Native variant: percepts go through the JADE message queue in arrival   *)
(* order.  Main declares its position handler BEFORE its obstacle handler, *)
(* and no handler accepts noise.  PriorityOrder is violated (a position is *)
(* consumed while an obstacle waits in the message queue: the handler      *)
(* order, not the priority, decides), noise percepts stay in the message   *)
(* queue forever (NoLoss violated, lasso), and BoundedInversion with bound *)
(* 0 is violated.  Behaviours and messages make progress.                  *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder violated invariant
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
MCPerceptHandlers == [Main |-> <<[accepts |-> {"position"}, effects |-> <<>>],
                        [accepts |-> {"obstacle"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"inform"}, effects |-> <<>>]>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 0
=============================================================================
