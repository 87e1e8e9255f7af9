-------------------------- MODULE MCPrintedObject ---------------------------
(***************************************************************************)
(* Algorithm 1 as printed, with one non-percept object put into O2A        *)
(* (R2c).  Once the object reaches the head of the O2A queue, the transfer *)
(* loop peeks at it forever (TransferSpin): percepts behind it are never   *)
(* transferred (NoLoss violated), no behaviour runs and no message is      *)
(* handled (BehaviourProgress, MessageProgress violated) and the agent does*)
(* no work although work is pending (NoLivelock violated).  All are lassos *)
(* ending in TransferSpin stuttering.  Safety properties still hold, and   *)
(* there is no deadlock (the spin is a step).                              *)
(***************************************************************************)
\* expect TypeOK holds
\* expect NoDuplication holds
\* expect PriorityOrder holds
\* expect NoLoss violated lasso
\* expect BehaviourProgress violated lasso
\* expect MessageProgress violated lasso
\* expect NoLivelock violated lasso
\* expect DeadlockFree holds
EXTENDS AgentLoop

MCVariant == "printed"
MCTiePolicy == "Stable"
MCBudget == 1
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
MCInversionBound == 2
=============================================================================
