package jsref.values;

/** SKELETON (to be filled in with the back end): declared types at run time. */
public final class Type {
  private final String name;
  private Type(String name) { this.name = name; }
  public static final Type INTEGER = new Type("integer");
  @Override public String toString() { return name; }
}
