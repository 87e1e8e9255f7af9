----------------------------- MODULE MCPlatform -----------------------------
(***************************************************************************)
(* Two agents that message each other while a host notifies                *)
(* (spec/Platform.tla, reference loop), small: one notification. The robot *)
(* (Main) sends an alarm to the monitor on obstacle, and a report to       *)
(* station, an agent that is not on the platform, on position; it takes    *)
(* acks and failures. The monitor's Main answers each alarm with an ack to *)
(* the robot and a log message to df, which df takes and never answers     *)
(* (D44); its Watch takes nothing (it blocks, and every message wakes it). *)
(* Deliveries fall between any two rules of the receiver or during its     *)
(* behaviour steps (SendInStep). Everything holds, RoundRobinBound         *)
(* included: messages that arrive during the monitor's steps do not let a  *)
(* behaviour overtake the other; the one answer of the platform is ams's   *)
(* failure for the report (OnlyFailuresAnswer, PlatformAnswers).           *)
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
\* expect WaitBound holds
\* expect OnlyFailuresAnswer holds
\* expect NoLoss holds (full)
\* expect BehaviourProgress holds (full)
\* expect MessageProgress holds (full)
\* expect NoLivelock holds (full)
\* expect DeliveryProgress holds (full)
\* expect PlatformAnswers holds
\* expect MessagesConsumed holds (full)
EXTENDS Platform

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 2
MCNameA == "robot"
MCNameB == "monitor"
MCConfA == [percepts |-> {"obstacle", "position"},
            defaultPriority |-> [obstacle |-> 8, position |-> 2],
            overrides |-> {}, objects |-> {},
            messages |-> {"ack", "failure"},
            maxNotify |-> 1, maxPut |-> 0, o2aCapacity |-> 1,
            behaviours |-> {"Main"},
            kind |-> [Main |-> "cyclic"], hasAction |-> [Main |-> FALSE],
            actionEffects |-> [Main |-> <<>>],
            perceptHandlers |-> [Main |-> <<
                [accepts |-> {"obstacle"},
                 effects |-> <<[op |-> "send", to |-> "monitor", m |-> "alarm"]>>],
                [accepts |-> {"position"},
                 effects |-> <<[op |-> "send", to |-> "station", m |-> "report"]>>]>>],
            messageHandlers |-> [Main |-> <<
                [accepts |-> {"ack", "failure"}, effects |-> <<>>]>>],
            initialBehaviours |-> <<"Main">>,
            maxActive |-> 1, inversionBound |-> 1]
MCConfB == [percepts |-> {}, defaultPriority |-> [p \in {} |-> 0],
            overrides |-> {}, objects |-> {},
            messages |-> {"alarm"},
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
                                 Watch |-> <<>>],
            initialBehaviours |-> <<"Main", "Watch">>,
            maxActive |-> 2, inversionBound |-> 0]
MCMaxOut == 2
=============================================================================
