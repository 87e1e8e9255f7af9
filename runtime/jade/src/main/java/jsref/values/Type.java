package jsref.values;

import java.util.Objects;

/** A declared Jadescript type, as the running code needs it: for the
    conversions of assignments, parameters and slots ({@link Ops#coerce},
    {@link Ops#coerceParam}, the interpreter's {@code Eval.coerce_param}) and
    for error messages ({@link #toString} is {@code Types.to_string}).
    Instances are immutable and compared structurally. */
public final class Type implements java.io.Serializable {
  /** The version of the serial form. */
  private static final long serialVersionUID = 1L;

  /** The kinds of types. {@code OTHER} stands for the types the checker leaves
      only after an error (a variable, the error type): every value fits it. */
  public enum Kind {
    /** {@code integer} */ INTEGER,
    /** {@code float} */ FLOAT,
    /** {@code double} */ DOUBLE,
    /** {@code boolean} */ BOOLEAN,
    /** {@code text} (and its synonym {@code string}) */ TEXT,
    /** {@code aid} */ AID,
    /** {@code any} */ ANY,
    /** {@code list of T} */ LIST,
    /** {@code map of K:V} */ MAP,
    /** a schema, by name */ SCHEMA,
    /** some ontology value of given kinds (an unnarrowed message content) */ ONTO,
    /** an agent type (name null: some agent) */ AGENT,
    /** a behaviour type */ BEHAVIOUR,
    /** the message being handled */ MESSAGE,
    /** not known (after an error) */ OTHER
  }

  /** The kind. */
  private final Kind kind;
  /** The name of a schema, agent or behaviour type, or an ontology type's description. */
  private final String name;
  /** The element type of a list, the key type of a map. */
  private final Type a;
  /** The value type of a map. */
  private final Type b;

  private Type(Kind kind, String name, Type a, Type b) {
    this.kind = kind; this.name = name; this.a = a; this.b = b;
  }

  /** {@code integer} */ public static final Type INTEGER = new Type(Kind.INTEGER, null, null, null);
  /** {@code float} */ public static final Type FLOAT = new Type(Kind.FLOAT, null, null, null);
  /** {@code double} */ public static final Type DOUBLE = new Type(Kind.DOUBLE, null, null, null);
  /** {@code boolean} */ public static final Type BOOLEAN = new Type(Kind.BOOLEAN, null, null, null);
  /** {@code text} */ public static final Type TEXT = new Type(Kind.TEXT, null, null, null);
  /** {@code aid} */ public static final Type AID = new Type(Kind.AID, null, null, null);
  /** {@code any} */ public static final Type ANY = new Type(Kind.ANY, null, null, null);
  /** The message being handled. */ public static final Type MESSAGE = new Type(Kind.MESSAGE, null, null, null);
  /** A type left unknown by an error: every value fits. */
  public static final Type OTHER = new Type(Kind.OTHER, null, null, null);

  /** {@code list of element}.
      @param element the element type
      @return the type */
  public static Type list(Type element) { return new Type(Kind.LIST, null, element, null); }

  /** {@code map of key:value}.
      @param key the key type
      @param value the value type
      @return the type */
  public static Type map(Type key, Type value) { return new Type(Kind.MAP, null, key, value); }

  /** A schema type.
      @param name the schema's name ({@code "percept"} is the root of percept types)
      @return the type */
  public static Type schema(String name) { return new Type(Kind.SCHEMA, name, null, null); }

  /** Some ontology value of the kinds given, as the checker prints it.
      @param description {@code "ontology value"} or e.g. {@code "concept or predicate"}
      @return the type */
  public static Type onto(String description) { return new Type(Kind.ONTO, description, null, null); }

  /** An agent type.
      @param name its name, or null for an agent of unknown type
      @return the type */
  public static Type agent(String name) { return new Type(Kind.AGENT, name, null, null); }

  /** A behaviour type.
      @param name its name
      @return the type */
  public static Type behaviour(String name) { return new Type(Kind.BEHAVIOUR, name, null, null); }

  /** The kind of this type.
      @return the kind */
  public Kind kind() { return kind; }

  /** The name of a schema, agent or behaviour type (null otherwise).
      @return the name */
  public String name() { return name; }

  /** The element type of a list, the key type of a map (null otherwise).
      @return the type */
  public Type element() { return a; }

  /** The value type of a map (null otherwise).
      @return the type */
  public Type value() { return b; }

  /** As Jadescript writes it, exactly as {@code Types.to_string}:
      {@code map of (list of integer):text}, {@code position}. */
  @Override public String toString() {
    switch (kind) {
      case INTEGER: return "integer";
      case FLOAT: return "float";
      case DOUBLE: return "double";
      case BOOLEAN: return "boolean";
      case TEXT: return "text";
      case AID: return "aid";
      case ANY: return "any";
      case LIST: return "list of " + a;
      case MAP: {
        String k = (a.kind == Kind.LIST || a.kind == Kind.MAP) ? "(" + a + ")" : a.toString();
        return "map of " + k + ":" + b;
      }
      case SCHEMA: case BEHAVIOUR: case ONTO: return name;
      case AGENT: return name == null ? "agent" : name;
      case MESSAGE: return "message";
      default: return "?";
    }
  }

  /** Structural equality. */
  @Override public boolean equals(Object o) {
    if (!(o instanceof Type)) return false;
    Type t = (Type) o;
    return kind == t.kind && Objects.equals(name, t.name) && Objects.equals(a, t.a) && Objects.equals(b, t.b);
  }

  /** Consistent with {@link #equals}. */
  @Override public int hashCode() { return Objects.hash(kind, name, a, b); }
}
