package jsref.runtime;

/** The agent loops of docs/semantics.md ("Variants"), chosen when the run starts. */
public enum Variant {
  /** R3 as ruled: transfer everything, dispatch everything, one behaviour step. */
  REFERENCE,
  /** Algorithm 1 as printed: element by element transfer, never idles (D4). */
  PRINTED,
  /** The reference loop dispatching at most {@code budget} percepts per iteration. */
  BUDGETED,
  /** Percepts moved into JADE's message queue and taken by behaviour steps. */
  NATIVE;

  /** The variant named as on the command line, or null.
      @param s {@code reference}, {@code printed}, {@code budgeted} or {@code native}
      @return the variant */
  public static Variant of(String s) {
    return switch (s) {
      case "reference" -> REFERENCE;
      case "printed" -> PRINTED;
      case "budgeted" -> BUDGETED;
      case "native" -> NATIVE;
      default -> null;
    };
  }

  /** The name used in traces. @return the lower-case name */
  public String traceName() { return name().toLowerCase(java.util.Locale.ROOT); }
}
