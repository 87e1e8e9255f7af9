-------------------------- MODULE MCPlatformFlood ---------------------------
(***************************************************************************)
(* Failures from the platform (spec/Platform.tla, reference loop): the     *)
(* robot's Retry has an action block that sends a report to station, an    *)
(* agent that is not on the platform, at every step, so ams answers every  *)
(* step with a failure (up to MaxOut = 2 sends, a model bound). Meanwhile  *)
(* the robot's Main sends an alarm to the monitor on obstacle and the      *)
(* monitor answers with an ack. No handler takes a failure: the failures   *)
(* stay in the robot's message queue for good (MessagesConsumed violated), *)
(* and each one wakes the blocked Main for nothing; but they starve        *)
(* nothing: percepts, behaviours and the ack are all handled, and round    *)
(* robin keeps its bound.                                                  *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect NoDuplication holds
\* expect RoundRobinBound holds
\* expect WaitBound holds
\* expect OnlyFailuresAnswer holds
\* expect NoLoss holds (full)
\* expect BehaviourProgress holds (full)
\* expect MessageProgress holds (full)
\* expect NoLivelock holds (full)
\* expect DeliveryProgress holds (full)
\* expect PlatformAnswers holds (full)
\* expect MessagesConsumed violated lasso (full)
EXTENDS Platform

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 1
MCNameA == "robot"
MCNameB == "monitor"
MCConfA == [percepts |-> {"obstacle"},
            defaultPriority |-> [obstacle |-> 8],
            overrides |-> {}, objects |-> {},
            messages |-> {"ack", "failure"},
            maxNotify |-> 1, maxPut |-> 0, o2aCapacity |-> 1,
            behaviours |-> {"Main", "Retry"},
            kind |-> [Main |-> "cyclic", Retry |-> "cyclic"],
            hasAction |-> [Main |-> FALSE, Retry |-> TRUE],
            actionEffects |-> [Main |-> <<>>,
                               Retry |-> <<[op |-> "send", to |-> "station", m |-> "report"]>>],
            perceptHandlers |-> [Main |-> <<
                [accepts |-> {"obstacle"},
                 effects |-> <<[op |-> "send", to |-> "monitor", m |-> "alarm"]>>]>>,
                                 Retry |-> <<>>],
            messageHandlers |-> [Main |-> <<[accepts |-> {"ack"}, effects |-> <<>>]>>,
                                 Retry |-> <<>>],
            initialBehaviours |-> <<"Main", "Retry">>,
            maxActive |-> 2, inversionBound |-> 0]
MCConfB == [percepts |-> {}, defaultPriority |-> [p \in {} |-> 0],
            overrides |-> {}, objects |-> {},
            messages |-> {"alarm"},
            maxNotify |-> 0, maxPut |-> 0, o2aCapacity |-> 1,
            behaviours |-> {"Main"},
            kind |-> [Main |-> "cyclic"], hasAction |-> [Main |-> FALSE],
            actionEffects |-> [Main |-> <<>>],
            perceptHandlers |-> [Main |-> <<>>],
            messageHandlers |-> [Main |-> <<
                [accepts |-> {"alarm"},
                 effects |-> <<[op |-> "send", to |-> "robot", m |-> "ack"]>>]>>],
            initialBehaviours |-> <<"Main">>,
            maxActive |-> 1, inversionBound |-> 0]
MCMaxOut == 2
=============================================================================
