--------------------------- MODULE MCFloodNative ----------------------------
(***************************************************************************)
(* Endless percepts, native variant (percepts are messages).               *)
(* Flood abstraction: the host may notify percepts forever (seqs are not   *)
(* tracked, every seq is 0, and identical entries merge in the priority    *)
(* queue, so the graph is finite).  Only TypeOK and the liveness of        *)
(* behaviours and messages (and NoLivelock) are meaningful.  One cyclic    *)
(* behaviour Main handles both percept types and the message; O2A capacity *)
(* 1, so a notification is possible whenever the O2A queue is empty.       *)
(* Behaviours keep running (round robin), but Main tries its percept       *)
(* handlers before its message handlers (they come first in its handler    *)
(* list) and there is always a percept in the message queue: the message is*)
(* never consumed (MessageProgress violated, lasso).  Priority between     *)
(* percepts and messages moved from the loop into each behaviour.          *)
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
