/* The stack of jadescript-ref (bin/main.ml, "the stack"): the soft limit
   of RLIMIT_STACK raised before the program starts again with exec, so
   that the recursion the width of an input costs (a list of a million
   items walked by List.map) has room. OCaml's Unix library has no
   setrlimit. */
#include <sys/resource.h>
#include <caml/mlvalues.h>
#include <caml/memory.h>

/* jsref_raise_stack(bytes): the soft limit raised to [bytes] (or to the
   hard limit, if lower). True when it was raised (then the caller starts
   the program again, as a running process keeps the stack it began
   with); false when it was already that large or cannot be raised. */
value jsref_raise_stack(value bytes)
{
  CAMLparam1(bytes);
  struct rlimit rl;
  rlim_t want = (rlim_t) Long_val(bytes);
  if (getrlimit(RLIMIT_STACK, &rl) != 0) CAMLreturn(Val_false);
  if (rl.rlim_cur == RLIM_INFINITY || rl.rlim_cur >= want) CAMLreturn(Val_false);
  if (rl.rlim_max != RLIM_INFINITY && rl.rlim_max < want) want = rl.rlim_max;
  if (want <= rl.rlim_cur) CAMLreturn(Val_false);
  rl.rlim_cur = want;
  CAMLreturn(Val_bool(setrlimit(RLIMIT_STACK, &rl) == 0));
}
