#!/usr/bin/env bash
# Benchmark: units/s of the ESS Monte Carlo on the shipped type-A config, for
# 1 and 2 threads (and the DSS config when present).  Speed is measured here,
# never asserted in a test.  Usage: scripts/bench.sh [build/sunmc] [UNITS]
set -euo pipefail
SUNMC=${1:-build/sunmc}
UNITS=${2:-1000}
for cfg in configs/ess_type_a.ini configs/ess_type_b.ini configs/dss.ini; do
  [ -f "$cfg" ] || continue
  for t in 1 2; do
    start=$(date +%s.%N)
    "$SUNMC" run "$cfg" --units "$UNITS" --threads "$t" --quiet > /dev/null
    end=$(date +%s.%N)
    awk -v c="$cfg" -v t="$t" -v n="$UNITS" -v s="$start" -v e="$end" \
      'BEGIN { printf "%-26s threads %d: %6d units in %6.2f s = %7.1f units/s\n", c, t, n, e - s, n / (e - s) }'
  done
done
