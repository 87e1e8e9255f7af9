package jsref.runtime;

import java.util.concurrent.atomic.AtomicInteger;
import jsref.values.Schema;

/** The host's rules on JADE's O2A queue (R2, docs/semantics.md "Host
    rules"): Notify and NotifyWith put a percept entry with its seq (R2b)
    and wake an idle agent (R3e); Put puts another object, which wakes
    nobody (R2c, D3); either is refused when the queue is full (R2d, D24),
    the percepts a {@code native} Transfer moved to the message queue still
    counting (D6). Safe from any thread: the host's calls are serialized on
    one lock; each one's line, its put and its wake-up are atomic with
    respect to the loop. */
final class HostRules {
  private final JadescriptAgent agent;
  private final Object hostLock = new Object();
  private int nextSeq;                 // under hostLock
  private int puts;                    // under hostLock
  /** {@code native}: percepts moved to the message queue and not yet taken
      by a behaviour step (D6). */
  final AtomicInteger nativePercepts = new AtomicInteger();

  HostRules(JadescriptAgent agent) { this.agent = agent; }

  /** {@code notifyEvent(p)} (R2b): the percept with its type's default
      priority (R1a). @param p a percept value @return false when refused (R2d) */
  boolean notifyEvent(Object p) {
    int prio = p instanceof Schema s ? s.defaultPriority() : 0;
    return notify(p, prio, false);
  }

  /** {@code notifyEvent(p, k)} (R2a): the percept with priority k.
      @param p a percept value @param k a natural number @return false when refused (R2d) */
  boolean notifyEvent(Object p, int k) {
    if (k < 0) throw new IllegalArgumentException("priority " + k + " is negative (R2a)");
    return notify(p, k, true);
  }

  private boolean notify(Object p, int prio, boolean with) {
    SchedulerHooks hooks = agent.hooks;
    Trace trace = agent.cfg.trace;
    synchronized (hostLock) {
      // the check, the line, the put and the wake-up at once (R2b, R2d,
      // R3e): a loop running meanwhile sees all of the notify or none of
      // it, and a refusal is written while the queue is full
      synchronized (hooks.sched) {
        synchronized (hooks.o2a) {
          if (!o2aHasRoom()) {
            trace.refused(agent.name(), p);
            return false;
          }
          int seq = ++nextSeq;
          PerceptEntry e = new PerceptEntry(p, prio, seq);
          trace.notify(agent.name(), e, with);
          try {
            agent.putO2AObject(e, false);
          } catch (InterruptedException x) {
            Thread.currentThread().interrupt();
          }
        }
        hooks.wakeUp();
      }
      return true;
    }
  }

  /** Put a non-percept object into the O2A queue (R2c); it does not wake an
      idle agent (D3). @param o the object @return false when refused (R2d) */
  boolean put(Object o) {
    jade.util.leap.List o2a = agent.hooks.o2a;
    Trace trace = agent.cfg.trace;
    synchronized (hostLock) {
      synchronized (o2a) {
        if (!o2aHasRoom()) {
          // R2d, D24: a refused put is in the trace, with its object
          trace.refusedPut(agent.name(), o);
          return false;
        }
        int k = ++puts;
        trace.put(agent.name(), o, k);
        try {
          agent.putO2AObject(new PutObject(o, k), false);
        } catch (InterruptedException x) {
          Thread.currentThread().interrupt();
        }
      }
      return true;
    }
  }

  /** O2AHasRoom (R2d, D6). */
  private boolean o2aHasRoom() {
    RunConfig cfg = agent.cfg;
    if (cfg.o2aCapacity == null) return true;
    int used;
    synchronized (agent.hooks.o2a) { used = agent.hooks.o2a.size(); }
    if (cfg.variant == Variant.NATIVE) used += nativePercepts.get();   // D6
    return used < cfg.o2aCapacity;
  }
}
