package jsref.runtime;

import java.nio.charset.StandardCharsets;

/** Agent names as Jadescript compares them, and as JADE holds them (D48).

    A Jadescript agent's name is compared as written: {@code Bob} and
    {@code bob} are two agents, and {@code AMS} is not the platform's
    {@code ams}. JADE compares names ignoring case ({@code AID.equals}), so
    the runtime never gives JADE a Jadescript name as it is: {@link #jade}
    maps each name to a JADE local name, one to one, such that two names
    that differ only in case stay apart and none is {@code ams} or
    {@code df}, and {@link #jadescript} maps it back. Traces, values and
    messages carry the Jadescript name; only an {@code AID} and JADE's
    agent creation see the other (docs/jade.md, section 4, item 6). */
final class Names {
  private Names() { }

  /** Hex-encoded names start with this, which no name kept as it is has. */
  private static final char ENCODED = '_';

  /** Kept as it is: lower-case ASCII letters, digits and '-', not a name of
      the platform's own agents. @param name a name @return is it so */
  private static boolean plain(String name) {
    if (name.isEmpty() || name.equals(Messaging.AMS) || name.equals(Messaging.DF)) return false;
    for (int i = 0; i < name.length(); i++) {
      char c = name.charAt(i);
      if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-')) return false;
    }
    return true;
  }

  /** The JADE local name of a Jadescript agent name: the name itself when
      it is {@link #plain}, else {@code _} and the lower-case hex of its
      UTF-8 bytes ({@code Bob} is {@code _426f62}). @param name as written
      @return the JADE local name */
  static String jade(String name) {
    if (plain(name)) return name;
    StringBuilder b = new StringBuilder().append(ENCODED);
    for (byte x : name.getBytes(StandardCharsets.UTF_8)) b.append(String.format("%02x", x & 0xff));
    return b.toString();
  }

  /** The Jadescript name of a JADE local name made by {@link #jade}.
      @param local JADE's local name @return the name as written */
  static String jadescript(String local) {
    if (local.isEmpty() || local.charAt(0) != ENCODED) return local;
    byte[] bytes = new byte[(local.length() - 1) / 2];
    for (int i = 0; i < bytes.length; i++)
      bytes[i] = (byte) Integer.parseInt(local.substring(1 + 2 * i, 3 + 2 * i), 16);
    return new String(bytes, StandardCharsets.UTF_8);
  }
}
