#!/usr/bin/env bash
# The compiled Jadescript agent on JADE (make bench; docs/jade.md, "Speed"):
# bench/programs/percepts.jade compiled by `jadescript-ref compile --target
# jade`, run by CompiledBench.java on the runtime of runtime/jade, one JVM per
# scenario. Result lines:
#   COMPILED steady percepts_per_second=<f> handled=<n> seconds=<f>
#   COMPILED flood percepts_per_second=<f> handled=<n> seconds=<f> windows=<r1,...>
# Usage: bench/compiled/run.sh [--quick] [--steady-only|--flood-only]
#   STEADY_N (default 15000000; --quick 200000), FLOOD_N (10000000; --quick 1000000),
#   HEAP (-Xmx, default 8g)
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
quick=0; steady_only=0; flood_only=0
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    --steady-only) steady_only=1 ;;
    --flood-only) flood_only=1 ;;
    *) echo "usage: $0 [--quick] [--steady-only|--flood-only]" >&2; exit 2 ;;
  esac
done
if [ "$quick" = 1 ]; then steady_n=${STEADY_N:-200000}; flood_n=${FLOOD_N:-1000000}
else steady_n=${STEADY_N:-15000000}; flood_n=${FLOOD_N:-10000000}; fi

build="${DUNE_BUILD_DIR:-_build}"; case "$build" in /*) ;; *) build="$here/$build" ;; esac
exe="$build/default/bin/main.exe"
[ -x "$exe" ] || (cd "$here" && dune build bin/main.exe 1>&2)
(cd "$here/runtime/jade" && mvn -q -B package -DskipTests 1>&2)
rt="$here/runtime/jade/target"
cp="$rt/jadescript-runtime.jar:$rt/lib/jade-4.3.jar"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$exe" compile "$here/bench/programs/percepts.jade" --target jade --out "$work/src"
mkdir -p "$work/classes"
javac -encoding UTF-8 -d "$work/classes" -cp "$cp" $(find "$work/src" -name '*.java') "$here/bench/compiled/CompiledBench.java"

bench() { java -Xmx"${HEAP:-8g}" -Xms1g -XX:+UseG1GC -cp "$work/classes:$cp" CompiledBench "$@"; }
echo "# compiled percepts.jade on JADE 4.3 (runtime/jade), $(nproc) cpus; load average $(cut -d' ' -f1-3 /proc/loadavg)"
[ "$flood_only" = 1 ] || bench steady "$steady_n"
[ "$steady_only" = 1 ] && exit 0
bench flood "$flood_n"
