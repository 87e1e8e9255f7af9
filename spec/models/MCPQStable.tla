----------------------------- MODULE MCPQStable -----------------------------
(***************************************************************************)
(* The percept priority queue alone (PQSpec): two percept names, two       *)
(* priorities, up to four entries, producer and consumer interleaved.      *)
(* Stable policy (R3b): both order invariants hold.                        *)
(***************************************************************************)
\* expect TypeOK holds
\* expect DequeueTakesHighest holds
\* expect FifoAmongEquals holds
EXTENDS PQSpec

MCPercepts == {"obstacle", "position"}
MCPrios == {1, 2}
MCMaxSeq == 4
MCTiePolicy == "Stable"
=============================================================================
