package jsref.values;

/** The value of {@code message} in a message handler: a schema value named
    {@code message} with the slots {@code performative} (a text),
    {@code content} and {@code sender} (an aid), as the interpreter builds it. */
public final class MessageValue extends Schema {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;
  private static final String[] SLOTS = { "performative", "content", "sender" };
  /** The performative, as written in the program (lower case). */
  public Object performative;
  /** The content. */
  public Object content;
  /** The sender's identifier. */
  public Object sender;

  /** The message value.
      @param performative the performative
      @param content
      the content
      @param sender the sender's name ({@code "host"} for the host) */
  public MessageValue(String performative, Object content, String sender) {
    this.performative = performative; this.content = content; this.sender = new Aid(sender);
  }

  /** {@code message}. */
  @Override public String schemaName() { return "message"; }
  /** performative, content, sender. */
  @Override public String[] slotNames() { return SLOTS.clone(); }
  /** The three slots' values. */
  @Override public Object[] slotValues() { return new Object[] { performative, content, sender }; }
  /** A slot by name. */
  @Override public Object get(String slot) {
    switch (slot) {
      case "performative": return performative;
      case "content": return content;
      case "sender": return sender;
      default: return null;
    }
  }
  /** Sets a slot by name. */
  @Override public boolean set(String slot, Object v) {
    switch (slot) {
      case "performative": performative = v; return true;
      case "content": content = v; return true;
      case "sender": sender = v; return true;
      default: return false;
    }
  }
}
