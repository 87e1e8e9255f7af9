package jsref.runtime;

import java.io.PrintStream;

/** How the agents of one run are run: the program, the loop variant and its
    parameters, the trace, where logs and errors go, and whether a host drives
    the agents in lock step (one loop iteration at a time, {@link
    JadescriptAgent#runIteration}) or they run freely on their JADE threads.
    Passed to each agent as the first of its JADE arguments. */
public final class RunConfig {
  /** The compiled program. */
  public final ProgramInfo program;
  /** The agent loop. */
  public final Variant variant;
  /** Percepts dispatched per iteration in {@link Variant#BUDGETED}. */
  public final int budget;
  /** The O2A capacity (R2d), or null for unbounded. */
  public final Integer o2aCapacity;
  /** Statements one body may execute (R7). */
  public final int fuel;
  /** The trace (never null; it may write nowhere). */
  public final Trace trace;
  /** Lock step (true) or free running (false). */
  public final boolean lockStep;
  private final PrintStream out;
  private final PrintStream err;
  private int errors;

  /** A configuration.
      @param program the program @param variant the loop @param budget the budget
      @param o2aCapacity the O2A capacity or null @param fuel the fuel
      @param trace the trace @param lockStep lock step or free running
      @param out where logs are printed (null: nowhere)
      @param err where run-time errors are reported (null: nowhere) */
  public RunConfig(ProgramInfo program, Variant variant, int budget, Integer o2aCapacity, int fuel,
                   Trace trace, boolean lockStep, PrintStream out, PrintStream err) {
    this.program = program; this.variant = variant; this.budget = budget;
    this.o2aCapacity = o2aCapacity; this.fuel = fuel;
    this.trace = trace == null ? new Trace(null) : trace;
    this.lockStep = lockStep; this.out = out; this.err = err;
  }

  /** A {@code log}: {@code NAME: text} on the output. @param agent the agent @param text the text */
  void log(String agent, String text) {
    if (out != null) out.print(agent + ": " + text + "\n");
  }

  /** A run-time error (R7, D15): {@code FILE:LINE:COL: error: message} on the
      error stream; an error with no place in the program is put at the start
      of the first file. @param at where @param message what */
  synchronized void error(String at, String message) {
    errors++;
    if (err == null) return;
    if (out != null) out.flush();
    String where = at;
    if (at == null || at.endsWith(":0:0") || at.isEmpty()) {
      String[] files = program.files();
      where = (files.length > 0 ? files[0] : "") + ":1:1";
    }
    err.println(where + ": error: " + message);
  }

  private final java.util.Map<String, JadescriptAgent> agents = new java.util.HashMap<>();

  /** An agent of the run registers itself when JADE has set it up.
      @param a the agent */
  synchronized void register(JadescriptAgent a) {
    agents.put(a.name(), a);
    notifyAll();
  }

  /** The names of every agent of the run, in this JVM or another (null:
      those set up in this JVM). */
  private java.util.Set<String> runAgents;

  /** The names of every agent of the run (two containers: in either JVM).
      @param names the names */
  public synchronized void runAgents(java.util.Collection<String> names) { runAgents = new java.util.HashSet<>(names); }

  /** Is this the name of an agent of the run (R5e: on the platform)?
      @param name a local name @return true if so */
  public synchronized boolean isRunAgent(String name) {
    return runAgents != null ? runAgents.contains(name) : agents.containsKey(name);
  }

  /** Is an agent of this name in this JVM? @param name the name @return true if it is */
  public synchronized boolean hasAgent(String name) { return agents.containsKey(name); }

  /** The agent of this name, once it is set up (waits at most the time given).
      @param name the agent's local name @param millis how long to wait
      @return the agent, or null @throws InterruptedException if interrupted */
  public synchronized JadescriptAgent awaitAgent(String name, long millis) throws InterruptedException {
    long end = System.currentTimeMillis() + millis;
    while (!agents.containsKey(name)) {
      long left = end - System.currentTimeMillis();
      if (left <= 0) return null;
      wait(left);
    }
    return agents.get(name);
  }

  /** Running freely: the rules all agents may still take together
      ({@code --max-steps}); an agent that finds none left stops for good. */
  final java.util.concurrent.atomic.AtomicLong freeSteps = new java.util.concurrent.atomic.AtomicLong(Long.MAX_VALUE);

  /** Running freely, stop every agent after this many rules in all ({@code --max-steps}).
      @param n the number of rules */
  public void limitFreeSteps(long n) { freeSteps.set(n); }

  private boolean holding;

  /** Running freely, messages sent by {@code on create} wait until {@link
      #allCreated} (D13); the harness calls this before creating the agents. */
  public synchronized void holdCreateMessages() { holding = true; }

  /** Every agent of the run exists: their {@code on create} messages may go. */
  public synchronized void allCreated() { holding = false; notifyAll(); }

  /** Wait until every agent exists (D13). @throws InterruptedException if interrupted */
  synchronized void awaitAllCreated() throws InterruptedException { while (holding) wait(); }

  /** @return how many run-time errors were reported */
  public synchronized int errors() { return errors; }
}
