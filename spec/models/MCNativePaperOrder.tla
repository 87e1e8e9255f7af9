------------------------- MODULE MCNativePaperOrder -------------------------
(***************************************************************************)
(* Native variant with the handlers declared in the paper's order          *)
(* (obstacle before position, as in HandlePercepts of the case study).     *)
(* With a single behaviour, the first matching handler in declaration order*)
(* takes its first percept, so an obstacle present in the message queue is *)
(* always taken before a position: PriorityOrder holds here, but only      *)
(* because declaration order happens to follow priority (see MCNative).    *)
(***************************************************************************)
\* expect TypeOK holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
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
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<>>],
                        [accepts |-> {"position"}, effects |-> <<>>]>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"inform"}, effects |-> <<>>]>>]
MCInitialBehaviours == <<"Main">>
MCMaxActive == 1
MCInversionBound == 0
=============================================================================
