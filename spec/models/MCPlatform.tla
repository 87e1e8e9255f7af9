----------------------------- MODULE MCPlatform -----------------------------
(***************************************************************************)
(* Two agents that message each other while a host notifies (Platform,     *)
(* reference loop).  The robot (Main) sends an alarm to the monitor on     *)
(* obstacle, and a report to station, an agent that is not on the          *)
(* platform, on position; it takes acks, failures and not_understoods.     *)
(* The monitor's Main answers each alarm with an ack to the robot and a    *)
(* log message to df, whose not_understood its Watch takes.  Deliveries    *)
(* fall between any two rules of the receiver or during its behaviour      *)
(* steps (SendInStep).                                                     *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect PriorityOrder holds
\* expect FifoAmongEquals holds
\* expect NoDuplication holds
\* expect O2AOrderPreserved holds
\* expect BoundedInversion holds
\* expect DispatchesWithinBudget holds
\* expect RoundRobinBound holds
\* expect NoLoss holds
\* expect BehaviourProgress holds
\* expect MessageProgress holds
\* expect NoLivelock holds
\* expect DeliveryProgress holds
\* expect PlatformAnswers holds
\* expect MessagesConsumed holds
EXTENDS Platform

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 2
MCNameA == "robot"
MCNameB == "monitor"
MCConfA == [percepts |-> {"obstacle", "position"},
            defaultPriority |-> [obstacle |-> 8, position |-> 2],
            overrides |-> {}, objects |-> {},
            messages |-> {"ack", "failure", "not_understood"},
            maxNotify |-> 2, maxPut |-> 0, o2aCapacity |-> 2,
            behaviours |-> {"Main"},
            kind |-> [Main |-> "cyclic"], hasAction |-> [Main |-> FALSE],
            actionEffects |-> [Main |-> <<>>],
            perceptHandlers |-> [Main |-> <<
                [accepts |-> {"obstacle"},
                 effects |-> <<[op |-> "send", to |-> "monitor", m |-> "alarm"]>>],
                [accepts |-> {"position"},
                 effects |-> <<[op |-> "send", to |-> "station", m |-> "report"]>>]>>],
            messageHandlers |-> [Main |-> <<
                [accepts |-> {"ack", "failure", "not_understood"}, effects |-> <<>>]>>],
            initialBehaviours |-> <<"Main">>,
            maxActive |-> 1, inversionBound |-> 1]
MCConfB == [percepts |-> {}, defaultPriority |-> [p \in {} |-> 0],
            overrides |-> {}, objects |-> {},
            messages |-> {"alarm", "not_understood"},
            maxNotify |-> 0, maxPut |-> 0, o2aCapacity |-> 1,
            behaviours |-> {"Main", "Watch"},
            kind |-> [Main |-> "cyclic", Watch |-> "cyclic"],
            hasAction |-> [Main |-> FALSE, Watch |-> FALSE],
            actionEffects |-> [Main |-> <<>>, Watch |-> <<>>],
            perceptHandlers |-> [Main |-> <<>>, Watch |-> <<>>],
            messageHandlers |-> [Main |-> <<
                [accepts |-> {"alarm"},
                 effects |-> <<[op |-> "send", to |-> "robot", m |-> "ack"],
                               [op |-> "send", to |-> "df", m |-> "log"]>>]>>,
                                 Watch |-> <<[accepts |-> {"not_understood"}, effects |-> <<>>]>>],
            initialBehaviours |-> <<"Main", "Watch">>,
            maxActive |-> 2, inversionBound |-> 0]
MCMaxOut == 4
=============================================================================
