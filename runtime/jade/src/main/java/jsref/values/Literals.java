package jsref.values;

import java.util.ArrayList;
import java.util.List;
import jsref.runtime.ProgramInfo;

/** The host's Jadescript literals: creation arguments of agents
    ({@code --agent NAME:TYPE:ARGS}), and the {@code notify}, {@code put} and
    {@code message} lines of an events file. The rules and messages are those
    of the interpreter ({@code Eval.literal_value}, {@code Eval.percept_value},
    {@code split_args} of {@code bin/cmd_run.ml}); the syntax is that of
    Jadescript expressions, restricted to literals. */
public final class Literals {
  private Literals() {}

  // ------------------------------------------------------------- the tree

  private enum K { INT, REAL, TEXT, BOOL, NEG, LIST, MAP, CALL, NAME, OTHER }

  private static final class Node {
    final K k; final int col; final String s; final long n; final List<Node> kids;
    Node(K k, int col, String s, long n, List<Node> kids) { this.k = k; this.col = col; this.s = s; this.n = n; this.kids = kids; }
  }

  // ---------------------------------------------------------- the lexer

  private static final class Lexer {
    final String src;
    int pos = 0;
    Lexer(String src) { this.src = src; }

    void blanks() { while (pos < src.length() && (src.charAt(pos) == ' ' || src.charAt(pos) == '\t')) pos++; }
    int col() { return pos + 1; }
    boolean atEnd() { blanks(); return pos >= src.length(); }
    char peek() { blanks(); return pos < src.length() ? src.charAt(pos) : '\0'; }
    boolean eat(char c) { if (peek() == c && pos < src.length()) { pos++; return true; } return false; }
  }

  private static boolean identStart(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
  private static boolean identChar(char c) { return identStart(c) || (c >= '0' && c <= '9'); }
  private static boolean digit(char c) { return c >= '0' && c <= '9'; }

  private static final String[] NOT_VALUES = { "this", "agent", "content", "message" };

  private static Node primary(Lexer l) throws LiteralError {
    char c = l.peek();
    int col = l.col();
    if (l.atEnd()) throw new LiteralError(col, "a value is expected here");
    if (c == '-') { l.pos++; Node x = unary(l); return new Node(K.NEG, col, null, 0, List.of(x)); }
    if (digit(c)) {
      int start = l.pos;
      while (l.pos < l.src.length() && digit(l.src.charAt(l.pos))) l.pos++;
      boolean real = false;
      if (l.pos < l.src.length() && l.src.charAt(l.pos) == '.') {
        l.pos++;
        if (l.pos >= l.src.length() || !digit(l.src.charAt(l.pos)))
          throw new LiteralError(col, "a decimal number needs digits after the '.'");
        while (l.pos < l.src.length() && digit(l.src.charAt(l.pos))) l.pos++;
        real = true;
      }
      if (l.pos < l.src.length() && (l.src.charAt(l.pos) == 'e' || l.src.charAt(l.pos) == 'E')) {
        int save = l.pos;
        l.pos++;
        if (l.pos < l.src.length() && (l.src.charAt(l.pos) == '+' || l.src.charAt(l.pos) == '-')) l.pos++;
        if (l.pos < l.src.length() && digit(l.src.charAt(l.pos))) {
          while (l.pos < l.src.length() && digit(l.src.charAt(l.pos))) l.pos++;
          real = true;
        } else l.pos = save;
      }
      String t = l.src.substring(start, l.pos);
      if (real) return new Node(K.REAL, col, t, 0, null);
      long n;
      try { n = Long.parseLong(t); } catch (NumberFormatException e) { n = Long.MAX_VALUE; }
      if (n > 4611686018427387903L) throw new LiteralError(col, "integer literal " + t + " is too large");
      return new Node(K.INT, col, t, n, null);
    }
    if (c == '"') { l.pos++; return new Node(K.TEXT, col, text(l, col), 0, null); }
    if (c == '[') {
      l.pos++;
      List<Node> items = new ArrayList<>();
      if (!l.eat(']')) {
        do items.add(expr(l)); while (l.eat(','));
        if (!l.eat(']')) throw new LiteralError(l.col(), "',' or ']' is expected here");
      }
      return new Node(K.LIST, col, null, 0, items);
    }
    if (c == '{') {
      l.pos++;
      List<Node> items = new ArrayList<>();
      if (!l.eat('}')) {
        do {
          items.add(expr(l));
          if (!l.eat(':')) throw new LiteralError(l.col(), "':' is expected here");
          items.add(expr(l));
        } while (l.eat(','));
        if (!l.eat('}')) throw new LiteralError(l.col(), "',' or '}' is expected here");
      }
      return new Node(K.MAP, col, null, 0, items);
    }
    if (c == '(') {
      l.pos++;
      Node x = expr(l);
      if (!l.eat(')')) throw new LiteralError(l.col(), "')' is expected here");
      return x;
    }
    if (identStart(c)) {
      int start = l.pos;
      while (l.pos < l.src.length() && identChar(l.src.charAt(l.pos))) l.pos++;
      String id = l.src.substring(start, l.pos);
      if (id.equals("true") || id.equals("false")) return new Node(K.BOOL, col, id, 0, null);
      for (String k : NOT_VALUES) if (k.equals(id)) return new Node(K.OTHER, col, id, 0, null);
      if (l.eat('(')) {
        List<Node> args = new ArrayList<>();
        if (!l.eat(')')) {
          do args.add(expr(l)); while (l.eat(','));
          if (!l.eat(')')) throw new LiteralError(l.col(), "',' or ')' is expected here");
        }
        return new Node(K.CALL, col, id, 0, args);
      }
      return new Node(K.NAME, col, id, 0, null);
    }
    throw new LiteralError(col, "unexpected character '" + c + "'");
  }

  private static String text(Lexer l, int col) throws LiteralError {
    StringBuilder b = new StringBuilder();
    String s = l.src;
    while (true) {
      if (l.pos >= s.length())
        throw new LiteralError(col, "this text literal is never closed: a '\"' is missing before the end of the line");
      char c = s.charAt(l.pos++);
      if (c == '"') return b.toString();
      if (c == '\\') {
        if (l.pos >= s.length())
          throw new LiteralError(col, "this text literal is never closed: a '\"' is missing before the end of the line");
        char e = s.charAt(l.pos++);
        switch (e) {
          case '"': b.append('"'); break;
          case '\\': b.append('\\'); break;
          case 'n': b.append('\n'); break;
          case 't': b.append('\t'); break;
          case 'r': b.append('\r'); break;
          case '\'': b.append('\''); break;
          case 'u': {
            if (l.pos + 4 > s.length() || !s.substring(l.pos, l.pos + 4).matches("[0-9a-fA-F]{4}"))
              throw new LiteralError(l.pos, "unknown escape '\\u' in text (known: \\\" \\\\ \\n \\t \\r \\' \\uXXXX)");
            int code = Integer.parseInt(s.substring(l.pos, l.pos + 4), 16);
            if (code >= 0xD800 && code <= 0xDFFF)
              throw new LiteralError(l.pos - 1, "\\u" + s.substring(l.pos, l.pos + 4) + " is a surrogate, not a character");
            b.append((char) code);
            l.pos += 4;
            break;
          }
          default:
            throw new LiteralError(l.pos - 1, "unknown escape '\\" + e + "' in text (known: \\\" \\\\ \\n \\t \\r \\' \\uXXXX)");
        }
      } else if (c < ' ' && c != '\t' || c == '\u007f') {
        throw new LiteralError(l.pos, String.format("control character '\\x%02X' inside a text literal", (int) c));
      } else b.append(c);
    }
  }

  private static Node unary(Lexer l) throws LiteralError { return primary(l); }

  private static final String OPERATORS = "+-*/%<>=!";

  /** A literal, possibly followed by an operator: then it is not a literal. */
  private static Node expr(Lexer l) throws LiteralError {
    int col = l.col();
    l.blanks();
    col = l.col();
    Node x = primary(l);
    char c = l.peek();
    boolean op = !l.atEnd() && OPERATORS.indexOf(c) >= 0;
    if (!op && !l.atEnd() && identStart(c)) {
      int start = l.pos;
      int p = l.pos;
      while (p < l.src.length() && identChar(l.src.charAt(p))) p++;
      String w = l.src.substring(start, p);
      op = w.equals("and") || w.equals("or") || w.equals("matches") || w.equals("of");
      if (op) l.pos = p;
    } else if (op) {
      l.pos++;
    }
    if (op || c == '[' && !l.atEnd()) {
      // an operation: parse the rest loosely, the interpreter rejects it as a whole
      skipExpression(l);
      return new Node(K.OTHER, col, null, 0, null);
    }
    return x;
  }

  private static void skipExpression(Lexer l) {
    int depth = 0;
    boolean quoted = false;
    while (l.pos < l.src.length()) {
      char c = l.src.charAt(l.pos);
      if (quoted) { if (c == '\\') l.pos++; else if (c == '"') quoted = false; }
      else if (c == '"') quoted = true;
      else if (c == '(' || c == '[' || c == '{') depth++;
      else if (c == ')' || c == ']' || c == '}') { if (depth == 0) return; depth--; }
      else if ((c == ',' || c == ':') && depth == 0) return;
      l.pos++;
    }
  }

  private static Node parseAll(String src) throws LiteralError {
    Lexer l = new Lexer(src);
    Node x = expr(l);
    if (!l.atEnd()) throw new LiteralError(l.col(), "unexpected '" + l.peek() + "' after the value");
    return x;
  }

  // ---------------------------------------------------------- evaluation

  private static Object value(Node e, ProgramInfo program, String file) throws LiteralError {
    switch (e.k) {
      case INT:
        // D8: integers are 32-bit, as Eval.literal_value and the type checker say
        if (e.n > Integer.MAX_VALUE)
          throw new LiteralError(e.col, "integer literal " + e.n + " is out of range: integer is 32-bit (-2147483648..2147483647)");
        return (int) e.n;
      case REAL: return Double.parseDouble(e.s);
      case TEXT: return e.s;
      case BOOL: return e.s.equals("true");
      case NEG: {
        // -2147483648: the least int, as the checker reads it
        if (e.kids.get(0).k == K.INT && e.kids.get(0).n == 2147483648L) return Integer.MIN_VALUE;
        Object v = value(e.kids.get(0), program, file);
        if (v instanceof Integer) return -(Integer) v;
        if (v instanceof Double) return -(Double) v;
        if (v instanceof Float) return -(Float) v;
        if (e.kids.get(0).k == K.INT) return (int) -e.kids.get(0).n;
        throw new LiteralError(e.col, "only numbers can be negated");
      }
      case LIST: {
        JList l = new JList();
        for (Node x : e.kids) l.add(value(x, program, file));
        return l;
      }
      case MAP: {
        JMap m = new JMap();
        for (int i = 0; i + 1 < e.kids.size(); i += 2) {
          Object v = value(e.kids.get(i + 1), program, file);   // the value first, as the interpreter
          Object k = value(e.kids.get(i), program, file);
          try { m.put(k, v); }
          catch (Ops.TooLarge x) {   // D37
            throw new LiteralError(e.col, "value too large: comparing or hashing it would visit more than "
                + Ops.MAX_VISITS + " values");
          }
        }
        return m;
      }
      case CALL: {
        if (e.s.equals("aid") && e.kids.size() == 1) {
          Object a = value(e.kids.get(0), program, file);
          if (a instanceof String) return new Aid((String) a);
          throw new LiteralError(e.col, "aid takes a text");
        }
        List<Object> args = new ArrayList<>();
        for (Node x : e.kids) args.add(value(x, program, file));
        try {
          return program.construct(file + ":1:" + e.col, e.s, args);
        } catch (JadescriptError err) {
          throw new LiteralError(e.col, err.message());
        }
      }
      case NAME:
        if (program.isSchema(e.s) && program.slotCount(e.s) == 0) {
          try {
            return program.construct(file + ":1:" + e.col, e.s, new ArrayList<>());
          } catch (JadescriptError err) {
            throw new LiteralError(e.col, err.message());
          }
        }
        throw new LiteralError(e.col, e.s + " is not a value the host can give (a literal, aid(\"name\") or a schema construction)");
      default:
        throw new LiteralError(e.col, "only literal values can be given here");
    }
  }

  /** A value given by the host, written as a Jadescript literal
      ({@code Eval.literal_value}): integers, decimals (a double), texts,
      booleans, {@code -} before a number, lists {@code [a, b]}, maps
      {@code {k: v}}, {@code aid("name")}, schema constructions
      {@code position(1, 2)} (arguments converted to the slots' types) and
      proposition names. Anything else (an operation, a variable) is refused.
      @param src the literal's text
      @param program the compiled program (its schemas)
      @param file the name to put in positions of construction errors
      @return the value (see CONTRACT.md for the Java classes)
      @throws LiteralError with the column in {@code src} and the interpreter's message */
  public static Object parse(String src, ProgramInfo program, String file) throws LiteralError {
    return value(parseAll(src), program, file);
  }

  /** A percept given by the host ({@code Eval.percept_value}): a literal that
      constructs a percept type visible to the agent type (in an ontology the
      agent uses). Its default priority (R1a) is
      {@link Schema#defaultPriority} of the result.
      @param src the literal's text
      @param program the compiled program
      @param agentType the receiving agent's type
      @param file the name to put in positions of construction errors
      @return the percept, a {@link Schema}
      @throws LiteralError with the column in {@code src} and the interpreter's message */
  public static Schema percept(String src, ProgramInfo program, String agentType, String file) throws LiteralError {
    Node e = parseAll(src);
    Object v = value(e, program, file);
    if (v instanceof Schema) {
      Schema s = (Schema) v;
      if (program.isSchema(s.schemaName()) && program.isPercept(s.schemaName())) {
        if (!program.visibleTo(agentType, s.schemaName()))
          throw new LiteralError(e.col, "percept type " + s.schemaName() + " is not in an ontology that agent type " + agentType + " uses");
        return s;
      }
      throw new LiteralError(e.col, s.schemaName() + " is not a percept type (it does not extend percept)");
    }
    throw new LiteralError(e.col, "a percept is a construction of a percept type, such as qrCodeRead(\"A7\")");
  }

  /** Splits the arguments of {@code --agent NAME:TYPE:ARGS} at the commas
      outside brackets and quotes ({@code split_args} of the command line):
      {@code a,b(1, 2),"x,y"} gives {@code a}, {@code b(1, 2)}, {@code "x,y"},
      each trimmed; an empty text gives no argument.
      @param s the arguments' text
      @return the arguments, in order */
  public static List<String> split(String s) {
    List<String> parts = new ArrayList<>();
    StringBuilder b = new StringBuilder();
    int depth = 0;
    boolean quoted = false;
    for (int i = 0; i < s.length(); i++) {
      char c = s.charAt(i);
      if (quoted) {
        b.append(c);
        if (c == '"' && (i == 0 || s.charAt(i - 1) != '\\')) quoted = false;
      } else if (c == '"') { quoted = true; b.append(c); }
      else if (c == '(' || c == '[' || c == '{') { depth++; b.append(c); }
      else if (c == ')' || c == ']' || c == '}') { depth--; b.append(c); }
      else if (c == ',' && depth == 0) { parts.add(b.toString().trim()); b.setLength(0); }
      else b.append(c);
    }
    if (b.length() > 0 || !parts.isEmpty()) parts.add(b.toString().trim());
    return parts;
  }
}
