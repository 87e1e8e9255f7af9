package jsref.values;

import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;

/** The operators of Jadescript on dynamic values, with the reference
    interpreter's semantics and error messages ({@code lib/interp/eval.ml},
    {@code lib/interp/value.ml}). Every operation that can fail takes first the
    source position {@code at} ({@code FILE:LINE:COL}) of the expression or
    statement the interpreter reports the error at, and throws a
    {@link JadescriptError} there.

    <p>Where the interpreter evaluates the right operand first (the comparisons:
    {@code =}, {@code !=}, {@code <}, {@code >}, {@code <=}, {@code >=}), the
    methods take the operands right first ({@code ...RL}), so that generated
    code, evaluating Java arguments left to right, evaluates them in the
    interpreter's order. */
public final class Ops {
  private Ops() {}

  // ---------------------------------------------------------------- errors

  /** Throws the error: usable as a statement that javac does not treat as
      the end of a block.
      @param at position
      @param msg message
      @return never returns */
  public static RuntimeException fail(String at, String msg) { throw new JadescriptError(at, msg); }

  /** {@code content} outside a handler.
      @param at position
      @return never returns */
  public static Object noContent(String at) { throw new JadescriptError(at, "no content here"); }

  /** {@code message} outside a message handler.
      @param at position
      @return never returns */
  public static Object noMessage(String at) { throw new JadescriptError(at, "no message here"); }

  /** A local variable's value, checked: null means the variable was never
      assigned on this run's path, and no property or proposition has the name.
      @param at position of the name
      @param name the name
      @param v the local's value or null
      @return v */
  public static Object local(String at, String name, Object v) {
    if (v == null) throw new JadescriptError(at, "unknown name " + name);
    return v;
  }

  /** A property's value, checked as {@link #local} (a property whose
      initialiser has not run yet, or failed, does not exist yet).
      @param at position of the name
      @param name the name
      @param v the value or null
      @return v */
  public static Object prop(String at, String name, Object v) { return local(at, name, v); }

  // ------------------------------------------------------- equality, order

  private static int tag(Object v) {
    if (v instanceof Boolean) return 0;
    if (v instanceof Integer || v instanceof Float || v instanceof Double) return 1;
    if (v instanceof String) return 2;
    if (v instanceof Aid) return 3;
    if (v instanceof JList) return 4;
    if (v instanceof JMap) return 5;
    if (v instanceof Schema) return 6;
    if (v instanceof AgentRef) return 8;
    if (v instanceof BehaviourRef) return 9;
    if (v instanceof Nothing || v == null) return 10;
    return 7;
  }

  private static double num(Object v) {
    if (v instanceof Integer) return (Integer) v;
    if (v instanceof Float) return (Float) v;
    return (Double) v;
  }

  /** OCaml's order on floats: NaN equals NaN and is below every number;
      0.0 and -0.0 are equal. */
  private static int compareFloats(double x, double y) {
    if (x < y) return -1;
    if (x > y) return 1;
    if (x == y) return 0;
    if (Double.isNaN(x)) return Double.isNaN(y) ? 0 : -1;
    return 1;
  }

  /** Texts in the order of their UTF-8 bytes (the order of code points). */
  private static int compareTexts(String a, String b) {
    int i = 0, j = 0;
    while (i < a.length() && j < b.length()) {
      int c = a.codePointAt(i), d = b.codePointAt(j);
      if (c != d) return c < d ? -1 : 1;
      i += Character.charCount(c); j += Character.charCount(d);
    }
    return Integer.compare(a.length() - i, b.length() - j);
  }

  /** The interpreter's structural order ({@code Value.compare}): numbers by
      value whatever their kind, texts by code point, lists and maps item by
      item (maps in insertion order), schema values by name then slots, host
      objects by identity.
      @param a a value
      @param b a value
      @return negative, zero or positive */
  public static int compare(Object a, Object b) { return compare(a, b, new int[1]); }

  /** D37: a comparison or a hash visits at most this many values
      ({@code Value.max_visits}): every value reached counts one, each time
      it is reached; each call has a budget of its own. */
  public static final int MAX_VISITS = 10_000_000;

  /** Past {@link #MAX_VISITS}: turned into an exhaustion error at the
      operator by the callers that know the position. */
  public static final class TooLarge extends RuntimeException {
    private static final long serialVersionUID = 1L;
    TooLarge() { super("too large to compare", null, false, false); }
  }

  private static final TooLarge TOO_LARGE = new TooLarge();

  private static void visit(int[] visits) { if (++visits[0] > MAX_VISITS) throw TOO_LARGE; }

  /** The error of D37 at a position.
      @param at position
      @return the error */
  public static JadescriptError tooLargeToCompare(String at) {
    return new JadescriptError(at, "value too large: comparing or hashing it would visit more than "
        + MAX_VISITS + " values");
  }

  private static int compare(Object a, Object b, int[] visits) {
    visit(visits);
    if (a == b) return 0;
    int ta = tag(a), tb = tag(b);
    if (ta != tb) return Integer.compare(ta, tb);
    switch (ta) {
      case 0: return Boolean.compare((Boolean) a, (Boolean) b);
      case 1:
        if (a instanceof Integer && b instanceof Integer) return Integer.compare((Integer) a, (Integer) b);
        return compareFloats(num(a), num(b));
      case 2: return compareTexts((String) a, (String) b);
      case 3: return compareTexts(((Aid) a).name(), ((Aid) b).name());
      case 4: {
        JList x = (JList) a, y = (JList) b;
        int n = Math.min(x.size(), y.size());
        for (int i = 0; i < n; i++) { int c = compare(x.get(i), y.get(i), visits); if (c != 0) return c; }
        return Integer.compare(x.size(), y.size());
      }
      case 5: {
        List<Map.Entry<Object, Object>> x = ((JMap) a).entries(), y = ((JMap) b).entries();
        int n = Math.min(x.size(), y.size());
        for (int i = 0; i < n; i++) {
          int c = compare(x.get(i).getKey(), y.get(i).getKey(), visits);
          if (c != 0) return c;
          c = compare(x.get(i).getValue(), y.get(i).getValue(), visits);
          if (c != 0) return c;
        }
        return Integer.compare(x.size(), y.size());
      }
      case 6: {
        Schema x = (Schema) a, y = (Schema) b;
        int c = x.schemaName().compareTo(y.schemaName());
        if (c != 0) return c;
        Object[] u = x.slotValues(), v = y.slotValues();
        int n = Math.min(u.length, v.length);
        for (int i = 0; i < n; i++) { c = compare(u[i], v[i], visits); if (c != 0) return c; }
        return Integer.compare(u.length, v.length);
      }
      case 8: return compareTexts(((AgentRef) a).name(), ((AgentRef) b).name());
      case 9: return Integer.compare(((BehaviourRef) a).uid(), ((BehaviourRef) b).uid());
      case 10: return 0;
      default: {
        int c = Integer.compare(System.identityHashCode(a), System.identityHashCode(b));
        return c != 0 ? c : 1;
      }
    }
  }

  /** Structural equality ({@code Value.equal}): {@code 1 = 1.0}, schema values
      and collections compared slot by slot and item by item.
      @param a a value
      @param b a value
      @return true if equal */
  public static boolean equal(Object a, Object b) { return compare(a, b) == 0; }

  private static int hashLong(long l) { return (int) (l ^ (l >>> 32)); }

  /** A hash consistent with {@link #equal} (equal values hash equal, 1 and
      1.0 included).
      @param v a value
      @return the hash */
  public static int hash(Object v) { return hash(v, new int[1]); }

  private static int hash(Object v, int[] visits) {
    visit(visits);
    if (v instanceof Boolean) return ((Boolean) v) ? 1 : 0;
    if (v instanceof Integer) return hashLong((Integer) v);
    if (v instanceof Float || v instanceof Double) {
      double f = num(v);
      if (f == Math.rint(f) && Math.abs(f) < 4e18) return hashLong((long) f);
      if (Double.isNaN(f)) return 0x7ff80000;
      return Double.hashCode(f);
    }
    if (v instanceof String) return v.hashCode();
    if (v instanceof Aid) return ((Aid) v).name().hashCode();
    if (v instanceof AgentRef) return ((AgentRef) v).name().hashCode();
    if (v instanceof BehaviourRef) return ((BehaviourRef) v).uid();
    if (v instanceof JList) {
      JList l = (JList) v;
      int h = 7;
      for (int i = 0; i < l.size(); i++) h = h * 31 + hash(l.get(i), visits);
      return h;
    }
    if (v instanceof JMap) {
      int h = 11;
      for (Map.Entry<Object, Object> e : ((JMap) v).entries()) h = h * 31 + hash(e.getKey(), visits) * 17 + hash(e.getValue(), visits);
      return h;
    }
    if (v instanceof Schema) {
      Schema s = (Schema) v;
      int h = s.schemaName().hashCode();
      for (Object x : s.slotValues()) h = h * 31 + hash(x, visits);
      return h;
    }
    if (v instanceof Nothing || v == null) return 0;
    return System.identityHashCode(v);
  }

  // ------------------------------------------------------------ arithmetic

  private static boolean numeric(Object v) { return v instanceof Integer || v instanceof Float || v instanceof Double; }

  private static final int ADD = 0, SUB = 1, MUL = 2, DIV = 3, MOD = 4;

  private static Object arith(String at, int op, Object a, Object b) {
    // as_float_pair: a double next to a float counts as a float
    if (a instanceof Float && b instanceof Double) b = (float) (double) (Double) b;
    else if (a instanceof Double && b instanceof Float) a = (float) (double) (Double) a;
    if (!numeric(a) || !numeric(b))
      throw new JadescriptError(at, "cannot apply an arithmetic operator to " + Text.typeName(a) + " and " + Text.typeName(b));
    if (a instanceof Integer && b instanceof Integer) {
      int x = (Integer) a, y = (Integer) b;
      switch (op) {
        case ADD: return x + y;
        case SUB: return x - y;
        case MUL: return x * y;
        case DIV: if (y == 0) throw new JadescriptError(at, "division by zero"); return x / y;
        default: if (y == 0) throw new JadescriptError(at, "division by zero (%)"); return x % y;
      }
    }
    double x = num(a), y = num(b), r;
    switch (op) {
      case ADD: r = x + y; break;
      case SUB: r = x - y; break;
      case MUL: r = x * y; break;
      case DIV: r = x / y; break;
      default: r = x % y; break;
    }
    if (a instanceof Float || b instanceof Float) return (float) r;
    return r;
  }

  /** {@code a + b}: text concatenation when either is a text (their
      {@link Text#text}), else arithmetic.
      @param at position
      @param a left
      @param b right
      @return the sum */
  public static Object add(String at, Object a, Object b) {
    if (a instanceof String || b instanceof String) {
      String x = Text.text(a), y = Text.text(b);
      // D21: lengths in UTF-8 bytes, as the interpreter counts them
      if (utf8Length(x) + utf8Length(y) > MAX_TEXT) throw tooBig(at, "the text would be too long");
      return x + y;
    }
    return arith(at, ADD, a, b);
  }

  /** D21: the largest text (UTF-8 bytes) and map (entries) a run may build
      ({@code Eval.max_text}, {@code Eval.max_map_size}). */
  public static final int MAX_TEXT = 1_000_000, MAX_MAP_SIZE = 1_000_000;

  private static JadescriptError tooBig(String at, String what) {
    return new JadescriptError(at, "value too large: " + what + " (at most " + MAX_TEXT
        + " bytes in a text, " + MAX_MAP_SIZE + " entries in a map)");
  }

  private static long utf8Length(String s) {
    long n = 0;
    for (int i = 0; i < s.length(); i++) {
      char c = s.charAt(i);
      if (c < 0x80) n += 1;
      else if (c < 0x800) n += 2;
      else if (Character.isHighSurrogate(c) && i + 1 < s.length() && Character.isLowSurrogate(s.charAt(i + 1))) { n += 4; i++; }
      else n += 3;
    }
    return n;
  }

  /** {@code a - b}.
      @param at position
      @param a left
      @param b right
      @return the result */
  public static Object sub(String at, Object a, Object b) { return arith(at, SUB, a, b); }

  /** {@code a * b}.
      @param at position
      @param a left
      @param b right
      @return the result */
  public static Object mul(String at, Object a, Object b) { return arith(at, MUL, a, b); }

  /** {@code a / b}: integers truncate, {@code division by zero} for an
      integer 0.
      @param at position
      @param a left
      @param b right
      @return the result */
  public static Object div(String at, Object a, Object b) { return arith(at, DIV, a, b); }

  /** {@code a % b}: {@code division by zero (%)} for an integer 0.
      @param at position
      @param a left
      @param b right
      @return the result */
  public static Object mod(String at, Object a, Object b) { return arith(at, MOD, a, b); }

  /** {@code -v}.
      @param at position
      @param v operand
      @return the result */
  public static Object neg(String at, Object v) {
    if (v instanceof Integer) return -(Integer) v;
    if (v instanceof Float) return -(Float) v;
    if (v instanceof Double) return -(Double) v;
    throw new JadescriptError(at, "cannot negate a " + Text.typeName(v));
  }

  /** {@code not v}.
      @param at position
      @param v operand
      @return the result */
  public static Object not(String at, Object v) {
    if (v instanceof Boolean) return !(Boolean) v;
    throw new JadescriptError(at, "not needs a boolean, not a " + Text.typeName(v));
  }

  /** The left operand of {@code and} or {@code or} (the right one is returned
      as it is, unchecked, as the interpreter does).
      @param at position of the whole expression
      @param what {@code "and"} or {@code "or"}
      @param v the left operand's value
      @return its truth */
  public static boolean truth(String at, String what, Object v) {
    if (v instanceof Boolean) return (Boolean) v;
    throw new JadescriptError(at, what + " needs booleans, not a " + Text.typeName(v));
  }

  /** A double beside a float counts as a float ({@code as_float_pair}). */
  private static Object asFloatBeside(Object x, Object other) {
    return (x instanceof Double && other instanceof Float) ? (Object) (float) (double) (Double) x : x;
  }

  /** {@code l = r}, operands given right first.
      @param r right
      @param l left
      @return the result */
  public static Object eqRL(Object r, Object l) { return equal(asFloatBeside(l, r), asFloatBeside(r, l)); }

  /** {@code l = r} at a position, operands given right first (D37).
      @param at position of the operator
      @param r right
      @param l left
      @return the result */
  public static Object eqRL(String at, Object r, Object l) {
    try { return equal(asFloatBeside(l, r), asFloatBeside(r, l)); }
    catch (TooLarge e) { throw tooLargeToCompare(at); }
  }

  /** {@code l != r}, operands given right first.
      @param r right
      @param l left
      @return the result */
  public static Object neqRL(Object r, Object l) { return !equal(asFloatBeside(l, r), asFloatBeside(r, l)); }

  /** {@code l != r} at a position, operands given right first (D37).
      @param at position of the operator
      @param r right
      @param l left
      @return the result */
  public static Object neqRL(String at, Object r, Object l) {
    try { return !equal(asFloatBeside(l, r), asFloatBeside(r, l)); }
    catch (TooLarge e) { throw tooLargeToCompare(at); }
  }

  private static int order(String at, Object l, Object r) {
    Object a = asFloatBeside(l, r), b = asFloatBeside(r, l);
    if (numeric(a) && numeric(b)) return compareFloats(num(a), num(b));
    if (a instanceof String && b instanceof String) return compareTexts((String) a, (String) b);
    throw new JadescriptError(at, "cannot compare " + Text.typeName(a) + " with " + Text.typeName(b));
  }

  /** {@code l < r}, operands given right first.
      @param at position
      @param r right
      @param l left
      @return the result */
  public static Object ltRL(String at, Object r, Object l) { return order(at, l, r) < 0; }
  /** {@code l > r}, operands given right first.
      @param at position
      @param r right
      @param l left
      @return the result */
  public static Object gtRL(String at, Object r, Object l) { return order(at, l, r) > 0; }
  /** {@code l <= r}, operands given right first.
      @param at position
      @param r right
      @param l left
      @return the result */
  public static Object leRL(String at, Object r, Object l) { return order(at, l, r) <= 0; }
  /** {@code l >= r}, operands given right first.
      @param at position
      @param r right
      @param l left
      @return the result */
  public static Object geRL(String at, Object r, Object l) { return order(at, l, r) >= 0; }

  /** The condition of an {@code if} or a {@code while}.
      @param at the condition's
      position
      @param v its value
      @return its truth */
  public static boolean cond(String at, Object v) {
    if (v instanceof Boolean) return (Boolean) v;
    throw new JadescriptError(at, "a condition is a boolean, not a " + Text.typeName(v));
  }

  /** The value of a handler's {@code when} condition.
      @param at the condition's
      position
      @param v its value
      @return its truth */
  public static boolean whenCond(String at, Object v) {
    if (v instanceof Boolean) return (Boolean) v;
    throw new JadescriptError(at, "a when condition is a boolean, not a " + Text.typeName(v));
  }

  // ----------------------------------------------------------- collections

  /** {@code m[k]}: a list by integer index, a map by key.
      @param at position
      @param m the collection
      @param k the index or key
      @return the item */
  public static Object index(String at, Object m, Object k) {
    if (m instanceof JList && k instanceof Integer) {
      JList l = (JList) m;
      int i = (Integer) k;
      if (i < 0 || i >= l.size())
        throw new JadescriptError(at, "index " + i + " is out of bounds (the list has " + l.size() + " elements)");
      return l.get(i);
    }
    if (m instanceof JMap) {
      Object v;
      try { v = ((JMap) m).get(k); } catch (TooLarge e) { throw tooLargeToCompare(at); }
      if (v == null) throw new JadescriptError(at, "the map has no key " + Text.literal(k));
      return v;
    }
    throw new JadescriptError(at, "cannot index a " + Text.typeName(m));
  }

  /** {@code m[k] = v}.
      @param at position of the left side
      @param m the collection
      @param k the index or key
      @param v the value */
  public static void setIndex(String at, Object m, Object k, Object v) {
    if (m instanceof JList && k instanceof Integer) {
      JList l = (JList) m;
      int i = (Integer) k;
      if (i < 0 || i >= l.size())
        throw new JadescriptError(at, "index " + i + " is out of bounds (the list has " + l.size() + " elements)");
      l.set(i, v);
      return;
    }
    if (m instanceof JMap) {
      JMap jm = (JMap) m;
      try {
        if (jm.size() >= MAX_MAP_SIZE && !jm.containsKey(k)) throw tooBig(at, "the map would have too many entries");
        jm.put(k, v);
      } catch (TooLarge e) { throw tooLargeToCompare(at); }
      return;
    }
    throw new JadescriptError(at, "cannot index a " + Text.typeName(m));
  }

  /** The items of a list, or the keys of a map, copied (for {@code for}).
      @param at position of the iterated expression
      @param v its value
      @return the items */
  public static List<Object> iter(String at, Object v) {
    if (v instanceof JList) return ((JList) v).items();
    if (v instanceof JMap) return ((JMap) v).keys();
    throw new JadescriptError(at, "cannot iterate over a " + Text.typeName(v));
  }

  /** Adds the receivers one {@code send} target denotes (an aid, or a list of aids).
      @param at position of the target
      @param v its value
      @param out the receivers' names */
  public static void addReceivers(String at, Object v, List<String> out) {
    if (v instanceof Aid) { out.add(((Aid) v).name()); return; }
    if (v instanceof JList) {
      for (Object x : ((JList) v).items()) {
        if (x instanceof Aid) out.add(((Aid) x).name());
        else throw new JadescriptError(at, "a receiver is an aid, not a " + Text.typeName(x));
      }
      return;
    }
    throw new JadescriptError(at, "a receiver is an aid, not a " + Text.typeName(v));
  }

  /** A new empty list for {@code send} receivers.
      @return the list */
  public static List<String> names() { return new ArrayList<>(); }

  // ------------------------------------------------------------ properties

  /** {@code p of v}: {@code length} of a text (its UTF-8 bytes) or list,
      {@code size} of a list or map, {@code keys}/{@code values} of a map,
      {@code priority} of a percept (R1a, D11), a slot of a schema value, a
      property of the agent or of the running behaviour.
      @param at position
      @param p the property
      @param v the value
      @param scope the running code's agent and behaviour
      @return the property's value */
  public static Object of(String at, String p, Object v, Scope scope) {
    if (v instanceof String && p.equals("length")) return ((String) v).getBytes(StandardCharsets.UTF_8).length;
    if (v instanceof JList && (p.equals("length") || p.equals("size"))) return ((JList) v).size();
    if (v instanceof JMap) {
      JMap m = (JMap) v;
      if (p.equals("size")) return m.size();
      if (p.equals("keys")) return JList.copyOf(m.keys());
      if (p.equals("values")) return JList.copyOf(m.values());
    }
    if (v instanceof Schema) {
      Schema s = (Schema) v;
      if (p.equals("priority") && s.get("priority") == null) {
        if (s.isPercept()) return s.defaultPriority();
        throw new JadescriptError(at, s.schemaName() + " has no priority");
      }
      Object x = s.get(p);
      if (x == null) throw new JadescriptError(at, s.schemaName() + " has no slot " + p);
      return x;
    }
    if (v instanceof AgentRef) {
      Object x = scope.jsAgentProperty(p);
      if (x == null) throw new JadescriptError(at, "the agent has no property " + p);
      return x;
    }
    if (v instanceof BehaviourRef) {
      if (scope.jsBehaviourUid() == ((BehaviourRef) v).uid()) {
        Object x = scope.jsBehaviourProperty(p);
        if (x == null) throw new JadescriptError(at, "the behaviour has no property " + p);
        return x;
      }
      throw new JadescriptError(at, "no such behaviour property " + p);
    }
    throw new JadescriptError(at, "a " + Text.typeName(v) + " has no property " + p);
  }

  /** {@code p of target = v}: a slot (stored as given), a property of the
      agent or of the running behaviour (converted to its type).
      @param at position of the left side
      @param p the slot or property
      @param target the value it belongs to
      @param v the new value
      @param scope the running code */
  public static void setOf(String at, String p, Object target, Object v, Scope scope) {
    if (target instanceof Schema) {
      Schema s = (Schema) target;
      if (!s.set(p, v)) throw new JadescriptError(at, s.schemaName() + " has no slot " + p);
      return;
    }
    if (target instanceof AgentRef) {
      if (!scope.jsSetAgentProperty(p, v)) throw new JadescriptError(at, "cannot set " + p + " of a agent");
      return;
    }
    if (target instanceof BehaviourRef) {
      if (scope.jsBehaviourUid() == ((BehaviourRef) target).uid() && scope.jsSetBehaviourProperty(p, v)) return;
      throw new JadescriptError(at, "no such behaviour property " + p);
    }
    throw new JadescriptError(at, "cannot set " + p + " of a " + Text.typeName(target));
  }

  // ------------------------------------------------------------ conversions

  /** The value converted to a parameter or slot type ({@code Eval.coerce_param}):
      an integer to float or double, a double to float; null when it does not fit.
      @param t the type
      @param v the value
      @return the converted value, or null */
  public static Object coerceParam(Type t, Object v) {
    switch (t.kind()) {
      case INTEGER: return v instanceof Integer ? v : null;
      case DOUBLE:
        if (v instanceof Integer) return (double) (Integer) v;
        return v instanceof Double ? v : null;
      case FLOAT:
        if (v instanceof Integer) return (float) (int) (Integer) v;
        if (v instanceof Float) return v;
        if (v instanceof Double) return (float) (double) (Double) v;
        return null;
      case TEXT: return v instanceof String ? v : null;
      case BOOLEAN: return v instanceof Boolean ? v : null;
      case AID: return v instanceof Aid ? v : null;
      case LIST: return v instanceof JList ? v : null;
      case MAP: return v instanceof JMap ? v : null;
      case SCHEMA: case ONTO: return v instanceof Schema ? v : null;
      default: return v;
    }
  }

  /** The value converted to a declared type where it fits, else unchanged
      ({@code Eval.coerce}: assignments to properties, parameters, {@code x as float = e}).
      @param t the type
      @param v the value
      @return the value */
  public static Object coerce(Type t, Object v) {
    Object c = coerceParam(t, v);
    return c == null ? v : c;
  }

  /** A slot's argument in a construction ({@code Eval.construct}), converted
      to the slot's type.
      @param at position of the construction
      @param schema
      the schema's name
      @param slot the slot's name
      @param t the slot's type
      @param v the argument
      @return the converted value */
  public static Object slot(String at, String schema, String slot, Type t, Object v) {
    Object c = coerceParam(t, v);
    if (c == null)
      throw new JadescriptError(at, "slot " + slot + " of " + schema + " is a " + t + ", not a " + Text.typeName(v));
    return c;
  }

  /** Checks a construction's number of arguments.
      @param at position
      @param schema the schema
      @param slots its number of slots
      @param given the arguments given */
  public static void arity(String at, String schema, int slots, int given) {
    if (slots != given)
      throw new JadescriptError(at, schema + " takes " + slots + " argument" + (slots == 1 ? "" : "s") + ", not " + given);
  }

  /** {@code aid(v)}: an aid from a text (or an aid).
      @param at position
      @param v the argument
      @return the aid */
  public static Object aid(String at, Object v) {
    if (v instanceof String) return new Aid((String) v);
    if (v instanceof Aid) return v;
    throw new JadescriptError(at, "unknown schema aid");
  }

  // -------------------------------------------------------------- patterns

  /** Records a pattern variable's binding (made only if the whole pattern
      matches).
      @param binds the bindings
      @param i the variable's slot
      @param v the value
      @return true */
  public static boolean bind(Object[] binds, int i, Object v) { binds[i] = v; return true; }

  /** {@code true}, after its arguments (the bindings of a match) are evaluated.
      @param ignored assignments made for their effect
      @return {@code Boolean.TRUE} */
  public static Object yes(Object... ignored) { return Boolean.TRUE; }

  /** Evaluates and drops a value ({@code return e} where no value is returned).
      @param v the value */
  public static void ignore(Object v) {}

  /** A named argument of {@code activate behaviour B with x = e} for the
      parameter {@code name} of B's {@code on create}: the first given.
      @param at position of the activation
      @param name the parameter
      @param names the names given
      @param values their values
      @return the value */
  public static Object named(String at, String name, String[] names, Object[] values) {
    for (int i = 0; i < names.length; i++) if (names[i].equals(name)) return values[i];
    throw new JadescriptError(at, "missing argument " + name);
  }

  /** Literal pattern: structural equality of the literal with the value.
      @param lit the literal
      @param v the value
      @return true if equal */
  public static boolean same(Object lit, Object v) { return equal(lit, v); }
}
