package jsref.runtime;

/** A percept notified to an agent (R2b): the percept, its effective priority
    (its type's default, R1a, or the host's override, R2a) and its arrival
    number, from 1 per agent. This is the object that travels through JADE's
    O2A queue. @param percept the percept value @param priority effective priority
    @param seq arrival number */
public record PerceptEntry(Object percept, int priority, int seq) {}
