---------------------------- MODULE MCBehaviours ----------------------------
(***************************************************************************)
(* Behaviour life cycle inside percept handlers (reference variant).  Main *)
(* (cyclic, no action) activates a one-shot Once on obstacle and           *)
(* deactivates itself on position; Once (one-shot, with an action block)   *)
(* also handles obstacle by deactivating itself.  Exercises R4b (snapshot  *)
(* of registered handlers; a deactivated instance's handler is skipped),   *)
(* R5c (one-shot ends after its step), R5d (blocking and waking by a       *)
(* message), R5g/R5h and the id reuse rule.  Everything holds.             *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect O2AOrderPreserved holds
\* expect NoLoss holds
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
MCFlood == FALSE
MCO2ACapacity == 2
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
