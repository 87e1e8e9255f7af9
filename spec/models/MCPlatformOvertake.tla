------------------------- MODULE MCPlatformOvertake -------------------------
(***************************************************************************)
(* Round robin under messages (spec/Platform.tla, reference loop). The     *)
(* monitor has three cyclic behaviours, in this order: Log (an action      *)
(* block: it never blocks), Main (takes the robot's alarm) and Watch       *)
(* (takes nothing); the robot sends an alarm on obstacle. Main steps       *)
(* before the alarm is there and blocks. If the alarm arrives during that  *)
(* step (SendInStep), Main keeps its place: Watch, then Log, then Main. If *)
(* it arrives just after the step (Send), Main goes to the end of the      *)
(* ready list, behind Watch but before Log, which then waits for Main,     *)
(* Watch and Main again: three steps of others, one more than the exact    *)
(* round robin allows (RoundRobinBound violated, also before R5d's         *)
(* revision); never more than twice each (WaitBound holds).                *)
(***************************************************************************)
\* expect TypeOK holds
\* expect ReadyBlockedConsistent holds
\* expect WaitBound holds
\* expect RoundRobinBound violated invariant
EXTENDS Platform

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 1
MCNameA == "robot"
MCNameB == "monitor"
MCConfA == [percepts |-> {"obstacle"},
            defaultPriority |-> [obstacle |-> 8],
            overrides |-> {}, objects |-> {}, messages |-> {},
            maxNotify |-> 1, maxPut |-> 0, o2aCapacity |-> 1,
            behaviours |-> {"Main"},
            kind |-> [Main |-> "cyclic"], hasAction |-> [Main |-> FALSE],
            actionEffects |-> [Main |-> <<>>],
            perceptHandlers |-> [Main |-> <<
                [accepts |-> {"obstacle"},
                 effects |-> <<[op |-> "send", to |-> "monitor", m |-> "alarm"]>>]>>],
            messageHandlers |-> [Main |-> <<>>],
            initialBehaviours |-> <<"Main">>,
            maxActive |-> 1, inversionBound |-> 0]
MCConfB == [percepts |-> {}, defaultPriority |-> [p \in {} |-> 0],
            overrides |-> {}, objects |-> {}, messages |-> {"alarm"},
            maxNotify |-> 0, maxPut |-> 0, o2aCapacity |-> 1,
            behaviours |-> {"Log", "Main", "Watch"},
            kind |-> [Log |-> "cyclic", Main |-> "cyclic", Watch |-> "cyclic"],
            hasAction |-> [Log |-> TRUE, Main |-> FALSE, Watch |-> FALSE],
            actionEffects |-> [Log |-> <<>>, Main |-> <<>>, Watch |-> <<>>],
            perceptHandlers |-> [Log |-> <<>>, Main |-> <<>>, Watch |-> <<>>],
            messageHandlers |-> [Log |-> <<>>,
                                 Main |-> <<[accepts |-> {"alarm"}, effects |-> <<>>]>>,
                                 Watch |-> <<>>],
            initialBehaviours |-> <<"Log", "Main", "Watch">>,
            maxActive |-> 3, inversionBound |-> 0]
MCMaxOut == 1
=============================================================================
