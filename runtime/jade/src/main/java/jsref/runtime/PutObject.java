package jsref.runtime;

/** A non-percept object put into an agent's O2A queue by the host (R2c),
    with its index (1 for the agent's first). It stays in the O2A queue (R3a).
    @param value the object @param index its index */
public record PutObject(Object value, int index) {}
