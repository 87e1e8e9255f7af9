/* setrlimit(2) for the fuzz driver's children (fuzz/fuzz.ml): a child that
   runs risky inputs gets a bound on its data size and CPU time, so that
   a runaway input ends as a recorded crash instead of exhausting the
   machine. OCaml's Unix library has no setrlimit. */
#include <sys/resource.h>
#include <caml/mlvalues.h>
#include <caml/memory.h>

/* fuzz_setrlimit(kind, value): kind 0 = RLIMIT_DATA (bytes: the heap and private mappings; unlike RLIMIT_AS it lets a JVM reserve its address space), 1 = RLIMIT_CPU
   (seconds), 2 = RLIMIT_CORE (bytes); the value -1 lifts the soft limit to the
   hard one. Returns true on success. */
value fuzz_setrlimit(value kind, value v)
{
  CAMLparam2(kind, v);
  int res;
  struct rlimit rl;
  switch (Int_val(kind)) {
  case 0: res = RLIMIT_DATA; break;
  case 1: res = RLIMIT_CPU; break;
  default: res = RLIMIT_CORE; break;
  }
  /* the soft limit only: the child may lift it again (-1: no limit) for a
     subprocess that needs more, such as TLC's JVM */
  if (getrlimit(res, &rl) != 0) CAMLreturn(Val_false);
  rl.rlim_cur = Long_val(v) < 0 ? rl.rlim_max : (rlim_t) Long_val(v);
  if (rl.rlim_max != RLIM_INFINITY && rl.rlim_cur > rl.rlim_max) rl.rlim_cur = rl.rlim_max;
  CAMLreturn(Val_bool(setrlimit(res, &rl) == 0));
}

#include <sys/prctl.h>
#include <signal.h>

/* fuzz_die_with_parent(): this process gets SIGKILL when its parent dies
   (the driver stopped by ^C or a signal leaves no child running). */
value fuzz_die_with_parent(value unit)
{
  CAMLparam1(unit);
  CAMLreturn(Val_bool(prctl(PR_SET_PDEATHSIG, SIGKILL) == 0));
}
