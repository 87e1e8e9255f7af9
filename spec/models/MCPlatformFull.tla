--------------------------- MODULE MCPlatformFull ---------------------------
(***************************************************************************)
(* MCPlatform with the budgeted loop (Budget 1), two notifications and an  *)
(* O2A capacity of 2 (run by spec-full only): the budget's bounds under    *)
(* the finer interleaving of two agents, deliveries between any two rules  *)
(* and during behaviour steps. The robot (Main) sends an alarm to the      *)
(* monitor on obstacle, and a report to station, an agent that is not on   *)
(* the platform, on position; it takes acks and failures. The monitor's    *)
(* Main answers each alarm with an ack to the robot and a log message to   *)
(* df, which is never answered (D44); its Watch takes nothing. Every       *)
(* invariant holds, the two bounds of the budget included (one dispatch    *)
(* per iteration; a late obstacle waits behind at most one position). Only *)
(* invariants (9,821 states): the liveness of two agents takes TLC far     *)
(* too long at this size; MCPlatform checks it.                            *)
(***************************************************************************)
\* full
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
EXTENDS Platform

MCVariant == "budgeted"
MCTiePolicy == "Stable"
MCBudget == 1
MCNameA == "robot"
MCNameB == "monitor"
MCConfA == [percepts |-> {"obstacle", "position"},
            defaultPriority |-> [obstacle |-> 8, position |-> 2],
            overrides |-> {}, objects |-> {},
            messages |-> {"ack", "failure"},
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
MCMaxOut == 4
=============================================================================
