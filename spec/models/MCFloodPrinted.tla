--------------------------- MODULE MCFloodPrinted ---------------------------
(***************************************************************************)
(* Endless percepts, printed variant.                                      *)
(* Flood abstraction: the host may notify percepts forever (seqs are not   *)
(* tracked, every seq is 0, and identical entries merge in the priority    *)
(* queue, so the graph is finite).  Only TypeOK and the liveness of        *)
(* behaviours and messages (and NoLivelock) are meaningful.  One cyclic    *)
(* behaviour Main handles both percept types and the message; O2A capacity *)
(* 1, so a notification is possible whenever the O2A queue is empty.       *)
(* The printed transfer loop runs while the O2A queue is not empty: the    *)
(* host refills it after every TransferOne, so the loop never ends and     *)
(* neither Main nor the message is ever served (lassos Notify,             *)
(* TransferOne, Notify, ...).  The agent is busy (TransferOne is work):    *)
(* NoLivelock holds.                                                       *)
(***************************************************************************)
\* expect TypeOK holds
\* expect BehaviourProgress violated lasso
\* expect MessageProgress violated lasso
\* expect NoLivelock holds
EXTENDS AgentLoop

MCVariant == "printed"
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
