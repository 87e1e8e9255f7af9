-------------------------- MODULE MCFloodReference --------------------------
(***************************************************************************)
(* Endless percepts, reference variant.                                    *)
(* Flood abstraction: the host may notify percepts forever (seqs are not   *)
(* tracked, every seq is 0, and identical entries merge in the priority    *)
(* queue, so the graph is finite).  Only TypeOK and the liveness of        *)
(* behaviours and messages (and NoLivelock) are meaningful.  One cyclic    *)
(* behaviour Main handles both percept types and the message; O2A capacity *)
(* 1, so a notification is possible whenever the O2A queue is empty.       *)
(* The atomic Transfer (R3a) takes a snapshot: percepts notified during the*)
(* dispatch wait for the next iteration, so every iteration dispatches at  *)
(* most what O2A held at its Transfer and then runs a behaviour step.      *)
(* Behaviours and messages are not starved (in the liveness sense); the    *)
(* price is an unbounded number of dispatches per iteration when the O2A   *)
(* capacity is unbounded (see MCInversion, DispatchesWithinBudget).        *)
(***************************************************************************)
\* expect TypeOK holds
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
