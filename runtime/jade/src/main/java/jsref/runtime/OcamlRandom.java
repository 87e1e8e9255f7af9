package jsref.runtime;

import java.nio.charset.StandardCharsets;
import java.security.MessageDigest;
import java.security.NoSuchAlgorithmException;

/** OCaml 4.13's {@code Random.State}: the lagged-Fibonacci generator of the
    standard library (55 words of 30 bits), seeded as
    {@code Random.State.make [| seed |]} seeds it (MD5 digests of the seed),
    drawing as {@code Random.State.bits} and {@code Random.State.int} draw.
    The seeded agent order of {@code jadescript-ref run --seed N} (R6, D17)
    comes from it, so a run on JADE interleaves the agents exactly as the
    reference does. */
public final class OcamlRandom {
  private static final long MASK30 = 0x3FFFFFFFL;
  private final long[] st = new long[55];
  private int idx;

  /** {@code Random.State.make seed}. @param seed the seed array (empty: [|0|]) */
  public OcamlRandom(long... seed) {
    if (seed.length == 0) seed = new long[] { 0 };
    MessageDigest md5;
    try { md5 = MessageDigest.getInstance("MD5"); }
    catch (NoSuchAlgorithmException e) { throw new IllegalStateException(e); }
    for (int i = 0; i < 55; i++) st[i] = i;
    byte[] accu = "x".getBytes(StandardCharsets.ISO_8859_1);
    int l = seed.length;
    for (int i = 0; i <= 54 + Math.max(55, l); i++) {
      int j = i % 55;
      int k = i % l;
      // combine accu x = Digest.string (accu ^ Int.to_string x)
      byte[] x = Long.toString(seed[k]).getBytes(StandardCharsets.ISO_8859_1);
      md5.reset();
      md5.update(accu);
      md5.update(x);
      accu = md5.digest();
      long extract = (accu[0] & 0xffL) | ((accu[1] & 0xffL) << 8) | ((accu[2] & 0xffL) << 16)
          | ((accu[3] & 0xffL) << 24);
      st[j] = (st[j] ^ extract) & MASK30;
    }
    idx = 0;
  }

  /** {@code Random.State.bits}: 30 random bits. @return 0 &lt;= n &lt; 2^30 */
  public int bits() {
    idx = (idx + 1) % 55;
    long cur = st[idx];
    long nv = st[(idx + 24) % 55] + (cur ^ ((cur >>> 25) & 0x1F));
    long nv30 = nv & MASK30;
    st[idx] = nv30;
    return (int) nv30;
  }

  /** {@code Random.State.int bound}. @param bound 0 &lt; bound &lt;= 2^30 - 1
      @return 0 &lt;= n &lt; bound */
  public int nextInt(int bound) {
    if (bound > MASK30 || bound <= 0) throw new IllegalArgumentException("Random.int");
    while (true) {
      int r = bits();
      int v = r % bound;
      if (r - v > MASK30 - bound + 1) continue;
      return v;
    }
  }

  /** The agent order of one round under a seed, as {@code Runtime.order}:
      a Fisher-Yates shuffle from the last index down to 1.
      @param n how many agents @return a permutation of 0..n-1 */
  public int[] order(int n) {
    int[] a = new int[n];
    for (int i = 0; i < n; i++) a[i] = i;
    for (int k = n - 1; k >= 1; k--) {
      int j = nextInt(k + 1);
      int x = a[k]; a[k] = a[j]; a[j] = x;
    }
    return a;
  }
}
