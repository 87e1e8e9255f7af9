--------------------------- MODULE MCBenchLarge ----------------------------
(***************************************************************************)
(* The explorer's bench model (bench.exe explorer, goal 4), not a test:   *)
(* MCReferenceFull with six notifications instead of four and four         *)
(* messages instead of two: 1,494,915 distinct states, 3,735,250           *)
(* transitions. It lives in bench/models so that neither make spec nor the *)
(* test suites, which take every model of spec/models, explore it. TLC     *)
(* runs it with the spec's modules copied beside it (Tlc.run_model).       *)
(***************************************************************************)
EXTENDS AgentLoop

MCVariant == "reference"
MCTiePolicy == "Stable"
MCBudget == 2
MCPercepts == {"obstacle", "position"}
MCDefaultPriority == [obstacle |-> 8, position |-> 2]
MCOverrides == {}
MCObjects == {"obj"}
MCMessages == {"inform"}
MCMaxNotify == 6
MCMaxPut == 1
MCMaxSend == 4
MCFlood == FALSE
MCO2ACapacity == 3
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
