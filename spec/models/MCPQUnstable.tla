---------------------------- MODULE MCPQUnstable ----------------------------
(***************************************************************************)
(* The percept priority queue alone (PQSpec): two percept names, two       *)
(* priorities, up to four entries, producer and consumer interleaved.      *)
(* Unstable policy: FifoAmongEquals is violated (two entries of            *)
(* priority 1 enqueued with seqs 1 and 2; Dequeue returns seq 2 first).    *)
(***************************************************************************)
\* expect TypeOK holds
\* expect DequeueTakesHighest holds
\* expect FifoAmongEquals violated invariant
EXTENDS PQSpec

MCPercepts == {"obstacle", "position"}
MCPrios == {1, 2}
MCMaxSeq == 4
MCTiePolicy == "Unstable"
=============================================================================
