#!/usr/bin/env bash
# proofs/check.sh: check every proof of proofs/*.v with coqc, in dependency
# order, in a fresh temporary folder (nothing is reused from an earlier
# check), then write what the build uses:
#   proved_loop.ml, proved_loop.mli  the machine of Loop.v extracted (Extract.v)
#   audit.txt                        coqc's answer to Audit.v: each theorem's
#                                    statement as Coq states it, and the
#                                    axioms it rests on
# into the folder given as $1 (default: the current folder). Any proof that
# fails stops the check with coqc's message and exit status 1.
#
# dune runs it at build time (proofs/dune); `make proofs` runs it directly
# with --time: the seconds of each file, and its lines of specification and
# of proof (sizes.awk).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(pwd)
time_it=false
for a in "$@"; do
  case "$a" in
    --time) time_it=true ;;
    *) out=$(cd "$a" && pwd) ;;
  esac
done
case "$here" in
  */_build/*) ;;
  *) [ "$out" != "$here" ] || { echo "proofs: error: give a folder for the outputs (the source folder would shadow dune's rule)" >&2; exit 1; } ;;
esac
command -v coqc >/dev/null || { echo "proofs: error: coqc not found (scripts/setup installs Coq)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# in $work/proofs, so that coqc's messages name proofs/FILE.v
mkdir "$work/proofs"
cp "$here"/*.v "$work/proofs/"
cd "$work"
order=$(coqdep -Q proofs Jsref -sort proofs/*.v)
ms() { echo $(( $(date +%s%N) / 1000000 )); }
secs() { local d=$(( $(ms) - $1 )); printf '%d.%d' $((d / 1000)) $(((d % 1000) / 100)); }
total_start=$(ms)
for f in $order; do
  start=$(ms)
  if [ "$f" = proofs/Audit.v ]; then
    coqc -q -Q proofs Jsref "$f" > audit.txt
  else
    coqc -q -Q proofs Jsref "$f"
  fi
  if $time_it; then
    printf '  %-20s %6s s\n' "$f" "$(secs "$start")"
  fi
done
cp proved_loop.ml proved_loop.mli audit.txt "$out"/
if $time_it; then
  echo "  lines of specification and of proof (proofs/sizes.awk):"
  for f in $order; do awk -f "$here/sizes.awk" "$f"; done |
    awk '{ printf "  %-20s %5d %5d\n", $1, $2, $3; s += $2; p += $3 }
         END { printf "  %-20s %5d %5d\n", "total", s, p }'
  printf 'proofs: every proof checked in %s s (coqc %s)\n' \
    "$(secs "$total_start")" "$(coqc -print-version | cut -d' ' -f1)"
fi
