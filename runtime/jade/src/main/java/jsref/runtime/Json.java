package jsref.runtime;

import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;

/** A small JSON writer and reader, enough for traces and events files.

    <p>The writer prints what {@code Yojson.Safe.to_string} prints, so that the
    runtime's traces are byte for byte those of the OCaml runtime: no spaces,
    strings escaped as Yojson escapes them (quote, backslash, {@code \b \f \n
    \r \t}, other control characters and DEL as backslash-u00XX; everything
    else, including non-ASCII text, as is).

    <p>The reader parses one JSON value into {@link Map} (insertion order, the
    first binding of a key wins, as {@code List.assoc_opt}), {@link List},
    {@link String}, {@link Long} (integers), {@link Double} (other numbers),
    {@link Boolean} and {@link #NULL}. A syntax error is a {@link
    Json.Error} with the column of its first character (from 1). */
public final class Json {
  private Json() {}

  /** JSON's {@code null} as the reader returns it. */
  public static final Object NULL = new Object() {
    @Override public String toString() { return "null"; }
  };

  /** A syntax error in a JSON text. */
  public static final class Error extends Exception {
    private static final long serialVersionUID = 1L;
    /** Where, from 1. */
    public final int column;
    Error(int column, String message) { super(message); this.column = column; }
  }

  // ------------------------------------------------------------- writer

  /** Append {@code s} as a JSON string literal, escaped as Yojson does. */
  public static void string(StringBuilder b, String s) {
    b.append('"');
    for (int i = 0; i < s.length(); i++) {
      char c = s.charAt(i);
      switch (c) {
        case '"' -> b.append("\\\"");
        case '\\' -> b.append("\\\\");
        case '\b' -> b.append("\\b");
        case '\f' -> b.append("\\f");
        case '\n' -> b.append("\\n");
        case '\r' -> b.append("\\r");
        case '\t' -> b.append("\\t");
        default -> {
          if (c < 0x20 || c == 0x7f) {
            b.append("\\u00");
            b.append(Character.forDigit((c >> 4) & 0xf, 16));
            b.append(Character.forDigit(c & 0xf, 16));
          } else b.append(c);
        }
      }
    }
    b.append('"');
  }

  /** Append any value the writer knows: null, {@link #NULL}, strings, numbers,
      booleans, lists, maps (in their iteration order), and {@link Obj}. */
  public static void value(StringBuilder b, Object v) {
    if (v == null || v == NULL) b.append("null");
    else if (v instanceof String s) string(b, s);
    else if (v instanceof Integer || v instanceof Long) b.append(v);
    else if (v instanceof Boolean x) b.append(x ? "true" : "false");
    else if (v instanceof Obj o) o.write(b);
    else if (v instanceof List<?> l) {
      b.append('[');
      for (int i = 0; i < l.size(); i++) { if (i > 0) b.append(','); value(b, l.get(i)); }
      b.append(']');
    } else if (v instanceof Map<?, ?> m) {
      b.append('{');
      boolean first = true;
      for (Map.Entry<?, ?> e : m.entrySet()) {
        if (!first) b.append(',');
        first = false;
        string(b, (String) e.getKey());
        b.append(':');
        value(b, e.getValue());
      }
      b.append('}');
    } else throw new IllegalArgumentException("not a JSON value: " + v.getClass().getName());
  }

  /** A JSON object under construction, fields in the order they are added. */
  public static final class Obj {
    private final List<String> keys = new ArrayList<>();
    private final List<Object> values = new ArrayList<>();

    /** Add a field. @param k its name @param v its value @return this */
    public Obj put(String k, Object v) { keys.add(k); values.add(v); return this; }

    /** Append all fields of another object. @param o the other @return this */
    public Obj putAll(Obj o) { keys.addAll(o.keys); values.addAll(o.values); return this; }

    /** The value of a field, or null. @param k its name @return the value */
    public Object get(String k) { int i = keys.indexOf(k); return i < 0 ? null : values.get(i); }

    /** Replace the value of a field that is there. @param k name @param v value */
    public void set(String k, Object v) { int i = keys.indexOf(k); if (i >= 0) values.set(i, v); }

    void write(StringBuilder b) {
      b.append('{');
      for (int i = 0; i < keys.size(); i++) {
        if (i > 0) b.append(',');
        string(b, keys.get(i));
        b.append(':');
        value(b, values.get(i));
      }
      b.append('}');
    }

    /** The object as one line of JSON. */
    @Override public String toString() { StringBuilder b = new StringBuilder(); write(b); return b.toString(); }
  }

  // ------------------------------------------------------------- reader

  /** Parse a whole text as one JSON value. @param s the text @return the value
      @throws Error on a syntax error */
  public static Object parse(String s) throws Error {
    Reader r = new Reader(s);
    r.ws();
    Object v = r.value(0);
    r.ws();
    if (r.i < s.length()) throw new Error(r.i + 1, "unexpected text after the value");
    return v;
  }

  private static final class Reader {
    final String s;
    int i;
    Reader(String s) { this.s = s; }

    void ws() { while (i < s.length() && " \t\r\n".indexOf(s.charAt(i)) >= 0) i++; }

    Error err(String m) { return new Error(i + 1, m); }

    Object value(int depth) throws Error {
      if (depth > 512) throw err("nested too deeply");
      if (i >= s.length()) throw err("unexpected end of input");
      char c = s.charAt(i);
      switch (c) {
        case '{': {
          i++;
          Map<String, Object> m = new LinkedHashMap<>();
          ws();
          if (i < s.length() && s.charAt(i) == '}') { i++; return m; }
          while (true) {
            ws();
            if (i >= s.length() || s.charAt(i) != '"') throw err("expected a string (an object key)");
            String k = str();
            ws();
            if (i >= s.length() || s.charAt(i) != ':') throw err("expected ':'");
            i++;
            ws();
            Object v = value(depth + 1);
            m.putIfAbsent(k, v);
            ws();
            if (i < s.length() && s.charAt(i) == ',') { i++; continue; }
            if (i < s.length() && s.charAt(i) == '}') { i++; return m; }
            throw err("expected ',' or '}'");
          }
        }
        case '[': {
          i++;
          List<Object> l = new ArrayList<>();
          ws();
          if (i < s.length() && s.charAt(i) == ']') { i++; return l; }
          while (true) {
            ws();
            l.add(value(depth + 1));
            ws();
            if (i < s.length() && s.charAt(i) == ',') { i++; continue; }
            if (i < s.length() && s.charAt(i) == ']') { i++; return l; }
            throw err("expected ',' or ']'");
          }
        }
        case '"': return str();
        case 't': return word("true", Boolean.TRUE);
        case 'f': return word("false", Boolean.FALSE);
        case 'n': return word("null", NULL);
        default:
          if (c == '-' || (c >= '0' && c <= '9')) return number();
          throw err("invalid token");
      }
    }

    Object word(String w, Object v) throws Error {
      if (!s.startsWith(w, i)) throw err("invalid token");
      i += w.length();
      return v;
    }

    Object number() throws Error {
      int start = i;
      if (s.charAt(i) == '-') i++;
      int digits = i;
      while (i < s.length() && Character.isDigit(s.charAt(i))) i++;
      if (i == digits) throw err("invalid number");
      boolean integral = true;
      if (i < s.length() && s.charAt(i) == '.') {
        integral = false; i++;
        int d = i;
        while (i < s.length() && Character.isDigit(s.charAt(i))) i++;
        if (i == d) throw err("invalid number");
      }
      if (i < s.length() && (s.charAt(i) == 'e' || s.charAt(i) == 'E')) {
        integral = false; i++;
        if (i < s.length() && (s.charAt(i) == '+' || s.charAt(i) == '-')) i++;
        int d = i;
        while (i < s.length() && Character.isDigit(s.charAt(i))) i++;
        if (i == d) throw err("invalid number");
      }
      String t = s.substring(start, i);
      if (integral) {
        try { return Long.parseLong(t); } catch (NumberFormatException e) { return Double.parseDouble(t); }
      }
      return Double.parseDouble(t);
    }

    String str() throws Error {
      i++; // the opening quote
      StringBuilder b = new StringBuilder();
      while (true) {
        if (i >= s.length()) throw err("unterminated string");
        char c = s.charAt(i++);
        if (c == '"') return b.toString();
        if (c == '\\') {
          if (i >= s.length()) throw err("unterminated string");
          char e = s.charAt(i++);
          switch (e) {
            case '"' -> b.append('"');
            case '\\' -> b.append('\\');
            case '/' -> b.append('/');
            case 'b' -> b.append('\b');
            case 'f' -> b.append('\f');
            case 'n' -> b.append('\n');
            case 'r' -> b.append('\r');
            case 't' -> b.append('\t');
            case 'u' -> {
              if (i + 4 > s.length()) throw err("invalid escape");
              try { b.append((char) Integer.parseInt(s.substring(i, i + 4), 16)); }
              catch (NumberFormatException x) { throw err("invalid escape"); }
              i += 4;
            }
            default -> { i--; throw err("invalid escape"); }
          }
        } else if (c < 0x20) { i--; throw err("control character in a string"); }
        else b.append(c);
      }
    }
  }
}
