package jsref.runtime;

/** One behaviour type as the trace header lists it (docs/trace-format.md). */
public record BehaviourInfo(String name, String kind, boolean action,
                            int perceptHandlers, int messageHandlers) {}
