#!/usr/bin/env bash
# JADE O2A percept-handling baseline (see README.md). Builds with Maven (fetches
# net.sf.ingenias:jade:4.3 from Maven Central by coordinates) and runs the
# scenarios, one JVM each. Result lines:
#   JADE steady percepts_per_second=<float> handled=<int> seconds=<float> peak_mb=<float> cpu_seconds=<float>
#   JADE flood percepts_per_second=<float> handled=<int> seconds=<float> peak_mb=<float> windows=<rates>
# Every other line is commentary (starts with '#') or a supplementary result
# (JADE flood_concurrent, JADE sweep, CONTROL ...).
#
# Usage: bench/jade/run.sh [--quick] [--steady-only]
#   FLOOD_CAP=<seconds>  stop a flood that has not drained after this long (default 60; --quick 10)
#   STEADY_N=<n>         percepts of the steady scenario (default 15000000; --quick 200000)
#   HEAP=<size>          -Xmx (default 8g)
set -euo pipefail
cd "$(dirname "$0")"

quick=0; steady_only=0
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    --steady-only) steady_only=1 ;;
    *) echo "usage: $0 [--quick] [--steady-only]" >&2; exit 2 ;;
  esac
done

if [ "$quick" = 1 ]; then
  steady_n=${STEADY_N:-200000}; flood_n=1000000; window=100000
  cap=${FLOOD_CAP:-10}; sweep=25000,50000,100000
else
  steady_n=${STEADY_N:-15000000}; flood_n=10000000; window=1000000
  cap=${FLOOD_CAP:-60}; sweep=25000,50000,100000,200000,400000
fi

command -v java >/dev/null || { echo "run.sh: java (17+) not found" >&2; exit 1; }
command -v mvn >/dev/null || { echo "run.sh: mvn not found" >&2; exit 1; }

# Build (idempotent): classes in target/classes, the JADE jar copied to target/lib.
mvn -q -B -Dstyle.color=never package 1>&2

bench() { java -Xmx"${HEAP:-8g}" -Xms1g -XX:+UseG1GC -cp "target/classes:target/lib/*" jsbench.Bench "$@"; }

echo "# jade-o2a-bench $(date -u +%FT%TZ) on $(nproc) cpus; load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# workload: 4 percept types (priorities 10,8,4,2), 1 handler updating a HashMap keyed by payload mod 1024,"
echo "#           a loop behaviour (drain O2A -> PriorityQueue, dispatch all) + 3 cyclic behaviours (JADE round robin)"

echo "# --- steady state: $steady_n percepts, 1,024 in flight (host notifies a batch of 1,024, waits until handled)"
bench steady "$steady_n" 1024 | grep -v '^# JADE JADE' || true
# --steady-only: the steady scenario alone (make bench interleaves such runs with its own)
[ "$steady_only" = 1 ] && exit 0
echo "# --- flood: $flood_n percepts notified by the host as fast as it can, agent transfer held until all are in"
echo "#     the O2A queue, then drained (stops after ${cap}s if not drained; windows of $window percepts)"
bench flood "$flood_n" before "$cap" "$window" | grep -v '^# flood t=.*[1-46-9]\.0s '
echo "# --- flood, concurrent variant: the agent drains while the host notifies"
bench flood "$flood_n" concurrent "$cap" "$window" name=flood_concurrent | grep -v '^# JADE JADE\|^# flood t=.*[1-46-9]\.0s '
echo "# --- drain time against backlog ('before' floods of growing size, drained to the end)"
bench sweep "$sweep" | grep -v '^# JADE JADE'
echo "# --- where the time goes: java.util.ArrayList.remove(0) alone, the call getO2AObject() makes"
bench listcost
echo "# --- control: same agent, JADE scheduler and loop, percepts through a ConcurrentLinkedQueue instead of O2A"
bench steady "$steady_n" 1024 put=control | grep '^CONTROL'
bench flood "$flood_n" before "$cap" "$window" put=control | grep '^CONTROL\|transfer (O2A\|host notified'
echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
