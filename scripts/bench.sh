#!/usr/bin/env bash
# Benchmark the shipped configs (ESS type A, ESS type B, DSS): milliseconds
# per unit per core on one thread, units/s on every core, the speed-up, and
# where a unit's time goes (campaign, fit, validation) from `run --profile`.
# Speed is measured here, never asserted in a test; on a shared machine run
# it twice and compare.  Usage: scripts/bench.sh [build/sunmc] [UNITS]
set -euo pipefail
SUNMC=${1:-build/sunmc}
UNITS=${2:-1000}
ALL=$(nproc 2>/dev/null || echo 1)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Wall seconds of one run; its --profile lines are left in $tmp/prof.
run() {
  local cfg=$1 threads=$2 start end
  start=$(date +%s.%N)
  "$SUNMC" run "$cfg" --units "$UNITS" --threads "$threads" --quiet --profile \
    > /dev/null 2> "$tmp/prof"
  end=$(date +%s.%N)
  awk -v s="$start" -v e="$end" 'BEGIN { printf "%.4f", e - s }'
}

printf '%-24s %8s %14s %12s %8s   %s\n' config units "ms/unit/core" "units/s" speedup \
  "split on 1 thread (ms per unit): campaign fit validation"
for cfg in configs/ess_type_a.ini configs/ess_type_b.ini configs/dss.ini; do
  [ -f "$cfg" ] || continue
  t1=$(run "$cfg" 1)
  split=$(awk '/^profile: campaign/ { printf "%s %s %s", $3, $7, $11 }' "$tmp/prof")
  tn=$(run "$cfg" "$ALL")
  awk -v c="$cfg" -v n="$UNITS" -v t1="$t1" -v tn="$tn" -v all="$ALL" -v parts="$split" \
    'BEGIN { printf "%-24s %8d %14.3f %12.1f %7.2fx   %s (threads: %d)\n",
             c, n, 1e3 * t1 / n, n / tn, t1 / tn, parts, all }'
done
