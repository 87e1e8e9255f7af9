package jade.core;

import jade.lang.acl.ACLMessage;
import jsref.runtime.JadeHooks;

/** JADE's own message queue of an agent ({@link InternalMessageQueue}), with
    one hook: every message that arrives is shown to the runtime first
    ({@link JadeHooks#arriving}), which numbers it (the per-receiver seq of
    R5e), records its delivery in the trace and wakes an idle agent, and which
    keeps out of the queue the AMS's FAILURE answers to the runtime's own sends
    to unknown agents (recorded as {@code undeliverable}). Storage, order,
    {@code receive(MessageTemplate)} and the wake-up of blocked behaviours
    ({@code Agent.postMessage}, {@code restartAll}) are JADE's. */
public class JsrefMessageQueue extends InternalMessageQueue {
  private final transient JadeHooks hooks;

  /** A queue for an agent. @param a the agent @param hooks its runtime */
  public JsrefMessageQueue(Agent a, JadeHooks hooks) {
    super(0, a);
    this.hooks = hooks;
  }

  @Override
  public void addLast(ACLMessage m) {
    if (hooks.arriving(m)) {
      super.addLast(m);
      hooks.arrived(m);
    }
  }
}
