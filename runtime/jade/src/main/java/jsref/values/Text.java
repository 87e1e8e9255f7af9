package jsref.values;

import java.math.BigDecimal;
import java.math.MathContext;
import java.math.RoundingMode;
import java.util.List;
import java.util.Map;

/** How values are shown: {@link #text} is what {@code log} prints and what
    text concatenation uses ({@code Value.to_text}), {@link #literal} is a
    Jadescript literal, as traces show values ({@code Value.to_literal}).
    Numbers are written as Java writes them ({@code Double.toString},
    {@code Float.toString}) in the interpreter's reading of that format: the
    shortest digits that read back as the same value. */
public final class Text {
  private Text() {}

  /** As {@code log} shows a value: texts without quotes, the rest as
      {@link #literal}: {@code 3}, {@code 2.5}, {@code A7},
      {@code position(1.0, 2.0)}, {@code [1, 2]}, {@code {"a": 1}},
      {@code aid("r")}, {@code nothing}.
      @param v a Jadescript value
      @return its text */
  public static String text(Object v) {
    if (v instanceof String) return (String) v;
    StringBuilder b = new StringBuilder();
    show(b, v, false);
    return b.toString();
  }

  /** As a Jadescript literal (texts quoted and escaped as the printer does).
      @param v a Jadescript value
      @return the literal */
  public static String literal(Object v) {
    StringBuilder b = new StringBuilder();
    show(b, v, true);
    return b.toString();
  }

  private static void show(StringBuilder b, Object v, boolean quote) {
    if (v instanceof Boolean) b.append(((Boolean) v) ? "true" : "false");
    else if (v instanceof Integer) b.append(((Integer) v).intValue());
    else if (v instanceof Float) b.append(floatText((Float) v));
    else if (v instanceof Double) b.append(doubleText((Double) v));
    else if (v instanceof String) { if (quote) quote(b, (String) v); else b.append((String) v); }
    else if (v instanceof Aid) { b.append("aid("); quote(b, ((Aid) v).name()); b.append(')'); }
    else if (v instanceof JList) {
      b.append('[');
      JList l = (JList) v;
      for (int i = 0; i < l.size(); i++) { if (i > 0) b.append(", "); show(b, l.get(i), true); }
      b.append(']');
    } else if (v instanceof JMap) {
      b.append('{');
      boolean first = true;
      for (Map.Entry<Object, Object> e : ((JMap) v).entries()) {
        if (!first) b.append(", ");
        first = false;
        show(b, e.getKey(), true); b.append(": "); show(b, e.getValue(), true);
      }
      b.append('}');
    } else if (v instanceof Schema) {
      Schema s = (Schema) v;
      Object[] slots = s.slotValues();
      b.append(s.schemaName());
      if (slots.length > 0) {
        b.append('(');
        for (int i = 0; i < slots.length; i++) { if (i > 0) b.append(", "); show(b, slots[i], true); }
        b.append(')');
      }
    } else if (v instanceof AgentRef || v instanceof BehaviourRef || v instanceof Nothing) b.append(v.toString());
    else if (v == null) b.append("nothing");
    else b.append('<').append(hostClass(v)).append('>');
  }

  /** The class name shown for a host object ({@code <RoboMe>}): the simple
      name of its Java class.
      @param v a host object
      @return the name */
  public static String hostClass(Object v) { return v.getClass().getSimpleName(); }

  /** A text as a Jadescript text literal ({@code Print.text_literal}): quoted,
      with {@code \" \\ \n \t \r} escaped and other control characters as
      {@code \}{@code uXXXX}.
      @param s the text
      @return the literal */
  public static String quote(String s) {
    StringBuilder b = new StringBuilder(s.length() + 2);
    quote(b, s);
    return b.toString();
  }

  private static void quote(StringBuilder b, String s) {
    b.append('"');
    for (int i = 0; i < s.length(); i++) {
      char c = s.charAt(i);
      switch (c) {
        case '"': b.append("\\\""); break;
        case '\\': b.append("\\\\"); break;
        case '\n': b.append("\\n"); break;
        case '\t': b.append("\\t"); break;
        case '\r': b.append("\\r"); break;
        default:
          if (c < ' ' || c == '\u007f') b.append(String.format("\\u%04X", (int) c));
          else b.append(c);
      }
    }
    b.append('"');
  }

  /** A double as the interpreter writes it ({@code Double.toString}'s format
      with the shortest digits that read back as the same double).
      @param d the number
      @return its text */
  public static String doubleText(double d) { return javaText(d, false); }

  /** A float as the interpreter writes it ({@code Float.toString}'s format
      with the shortest digits that read back as the same float).
      @param f the number
      @return its text */
  public static String floatText(float f) { return javaText(f, true); }

  private static String javaText(double f, boolean single) {
    if (Double.isNaN(f)) return "NaN";
    if (f == Double.POSITIVE_INFINITY) return "Infinity";
    if (f == Double.NEGATIVE_INFINITY) return "-Infinity";
    if (f == 0.0) return (1.0 / f < 0) ? "-0.0" : "0.0";
    // the shortest digits d.ddd x 10^exp that read back as f
    BigDecimal exact = new BigDecimal(f);
    String mant = null;
    int exp = 0;
    for (int p = 1; p <= 18; p++) {
      BigDecimal r = exact.round(new MathContext(p, RoundingMode.HALF_EVEN));
      double back = r.doubleValue();
      boolean same = single ? ((float) back == (float) f) : back == f;
      if (same || p == 18) {
        BigDecimal u = r.abs();
        String digits = u.unscaledValue().toString();
        // value = digits x 10^-scale; exponent of the first digit:
        exp = digits.length() - 1 - u.scale();
        mant = digits;
        break;
      }
    }
    int n = mant.length();
    while (n > 1 && mant.charAt(n - 1) == '0') n--;
    mant = mant.substring(0, n);
    double a = Math.abs(f);
    StringBuilder b = new StringBuilder();
    if (f < 0) b.append('-');
    if (a >= 1e-3 && a < 1e7) {
      if (exp >= 0) {
        if (mant.length() > exp + 1) b.append(mant, 0, exp + 1).append('.').append(mant.substring(exp + 1));
        else { b.append(mant); for (int i = mant.length(); i < exp + 1; i++) b.append('0'); b.append(".0"); }
      } else {
        b.append("0.");
        for (int i = 0; i < -exp - 1; i++) b.append('0');
        b.append(mant);
      }
    } else {
      b.append(mant.charAt(0)).append('.').append(mant.length() > 1 ? mant.substring(1) : "0").append('E').append(exp);
    }
    return b.toString();
  }

  /** The type of a value for error messages ({@code Value.type_name}):
      {@code integer}, {@code text}, a schema's name, {@code any} for a host
      object, ...
      @param v a value
      @return its type's name */
  public static String typeName(Object v) {
    if (v instanceof Boolean) return "boolean";
    if (v instanceof Integer) return "integer";
    if (v instanceof Float) return "float";
    if (v instanceof Double) return "double";
    if (v instanceof String) return "text";
    if (v instanceof Aid) return "aid";
    if (v instanceof JList) return "list";
    if (v instanceof JMap) return "map";
    if (v instanceof Schema) return ((Schema) v).schemaName();
    if (v instanceof AgentRef) return "agent";
    if (v instanceof BehaviourRef) return "behaviour";
    if (v instanceof Nothing || v == null) return "nothing";
    return "any";
  }

  /** Joins texts of values (for host code and tests).
      @param vs values
      @return their texts, comma separated */
  public static String texts(List<?> vs) {
    StringBuilder b = new StringBuilder();
    for (Object v : vs) { if (b.length() > 0) b.append(", "); b.append(text(v)); }
    return b.toString();
  }
}
