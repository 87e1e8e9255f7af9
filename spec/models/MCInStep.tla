------------------------------ MODULE MCInStep ------------------------------
(***************************************************************************)
(* Messages that arrive during a behaviour step (R5d revised: SendInStep), *)
(* reference loop, one agent.  Two cyclic behaviours without action        *)
(* blocks, each with one message handler: Main takes ping, Aux takes pong; *)
(* the host sends up to three messages, between rules or during a step,    *)
(* and notifies one obstacle.  A step that takes nothing blocks its        *)
(* behaviour; a message that came during that step leaves it runnable at   *)
(* its place in the ready list, with the other blocked behaviour woken to  *)
(* the end.  Everything holds: the restart in place starves nobody, and    *)
(* every message is taken.                                                 *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect NoDuplication holds
\* expect NoLoss holds
\* expect BehaviourProgress holds
\* expect MessageProgress holds
\* expect EveryMessageConsumed holds
\* expect NoLivelock holds
EXTENDS AgentLoop

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 1
MCPercepts == {"obstacle"}
MCDefaultPriority == [obstacle |-> 8]
MCOverrides == {}
MCObjects == {}
MCMessages == {"ping", "pong"}
MCMaxNotify == 1
MCMaxPut == 0
MCMaxSend == 3
MCFlood == FALSE
MCO2ACapacity == 1
MCBehaviours == {"Main", "Aux"}
MCKind == [Main |-> "cyclic", Aux |-> "cyclic"]
MCHasAction == [Main |-> FALSE, Aux |-> FALSE]
MCActionEffects == [Main |-> <<>>, Aux |-> <<>>]
MCPerceptHandlers == [Main |-> <<[accepts |-> {"obstacle"}, effects |-> <<>>]>>, Aux |-> <<>>]
MCMessageHandlers == [Main |-> <<[accepts |-> {"ping"}, effects |-> <<>>]>>,
                      Aux |-> <<[accepts |-> {"pong"}, effects |-> <<>>]>>]
MCInitialBehaviours == <<"Main", "Aux">>
MCMaxActive == 2
MCInversionBound == 0
=============================================================================
