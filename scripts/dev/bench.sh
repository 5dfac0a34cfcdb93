#!/usr/bin/env bash
# Benchmark the shipped configs (ESS type A, ESS type B, DSS): milliseconds
# per unit per core on one thread (wall, and the CPU time the kernel
# accounts to the process, which a busy machine disturbs far less), units/s
# on every core, the speed-up, and where a unit's time goes (campaign, fit,
# validation, in ms per unit and in % of the unit) from `run --profile`.
# Speed is measured here, never asserted in a test; on a shared machine run
# it twice and compare, and read the CPU column (wall figures and the
# speed-up need an idle machine).  Usage: scripts/dev/bench.sh [build/sunmc] [UNITS]
set -euo pipefail
SUNMC=${1:-build/sunmc}
UNITS=${2:-1000}
ALL=$(nproc 2>/dev/null || echo 1)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# "wall cpu" seconds of one run (cpu = user + system of the process); its
# --profile lines are left in $tmp/prof.
run() {
  local cfg=$1 threads=$2 t
  t=$( { TIMEFORMAT='%R %U %S'
         time "$SUNMC" run "$cfg" --units "$UNITS" --threads "$threads" --quiet --profile \
           > /dev/null 2> "$tmp/prof"; } 2>&1 )
  awk -v t="$t" 'BEGIN { split(t, a, " "); printf "%.4f %.4f\n", a[1], a[2] + a[3] }'
}

printf '%-24s %6s %9s %9s %10s %8s   %s\n' config units "ms/unit" "cpu ms" "units/s" speedup \
  "split on 1 thread, ms per unit: campaign fit validation"
for cfg in configs/ess_type_a.ini configs/ess_type_b.ini configs/dss.ini; do
  [ -f "$cfg" ] || continue
  read -r t1 c1 < <(run "$cfg" 1)
  split=$(awk '/^profile: campaign/ { printf "%s %s %s %s %s %s", $3, $5, $7, $9, $11, $13 }' \
    "$tmp/prof")
  read -r tn cn < <(run "$cfg" "$ALL")
  awk -v c="$cfg" -v n="$UNITS" -v t1="$t1" -v c1="$c1" -v tn="$tn" -v all="$ALL" \
    -v parts="$split" \
    'BEGIN { split(parts, p, " ");
             printf "%-24s %6d %9.3f %9.3f %10.1f %7.2fx   %s %s  %s %s  %s %s (threads: %d)\n",
             c, n, 1e3 * t1 / n, 1e3 * c1 / n, n / tn, t1 / tn,
             p[1], p[2], p[3], p[4], p[5], p[6], all }'
done
