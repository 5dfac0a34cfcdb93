#!/usr/bin/env bash
# Benchmark the shipped configs (ESS type A, ESS type B, DSS, PSD): for each,
# milliseconds per unit on one thread (wall, and the CPU time the kernel
# accounts to the process, which a busy machine disturbs far less), units/s
# on every core, the speed-up, and where a unit's time goes (campaign, fit,
# validation, in % of the unit) from `run --profile`; then the floor ratio:
# ESS type A's one-thread CPU time per unit over that of bench-floor
# (scripts/dev/bench-floor.c: the 250,968 vector math calls a unit made before issue 27
# and nothing else).  The output is a Markdown table, the one
# docs/performance.md quotes.  Speed is measured here, never asserted in a
# test; on a shared machine run it twice and read the CPU columns (wall
# figures and the speed-up need an idle machine).
# Usage: scripts/dev/bench.sh [build/sunmc] [UNITS]
set -euo pipefail
SUNMC=${1:-build/sunmc}
UNITS=${2:-1000}
FLOOR=${FLOOR:-$(dirname "$SUNMC")/bench-floor}
ALL=$(nproc 2>/dev/null || echo 1)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# "wall cpu" seconds of one command (cpu = user + system of the process).
timed() {
  local t
  t=$( { TIMEFORMAT='%R %U %S'; time "$@" > /dev/null 2> "$tmp/prof"; } 2>&1 )
  awk -v t="$t" 'BEGIN { split(t, a, " "); printf "%.4f %.4f\n", a[1], a[2] + a[3] }'
}
run() {
  timed "$SUNMC" run "$1" --units "$UNITS" --threads "$2" --quiet --profile
}

echo "| config | units | ms/unit (1 thread, wall) | CPU ms/unit | units/s ($ALL threads) | speed-up |" \
     "campaign | fit | validation |"
echo "|---|---|---|---|---|---|---|---|---|"
ess_cpu=
for cfg in configs/ess_type_a.ini configs/ess_type_b.ini configs/dss.ini configs/psd.ini; do
  [ -f "$cfg" ] || continue
  read -r t1 c1 < <(run "$cfg" 1)
  split=$(awk '/^profile: campaign/ { gsub(/[()]/, ""); printf "%s ms, %s;%s ms, %s;%s ms, %s", $3, $5, $7, $9, $11, $13 }' \
    "$tmp/prof")
  read -r tn _ < <(run "$cfg" "$ALL")
  [ "$cfg" = configs/ess_type_a.ini ] && ess_cpu=$c1
  awk -v c="$cfg" -v n="$UNITS" -v t1="$t1" -v c1="$c1" -v tn="$tn" -v parts="$split" \
    'BEGIN { split(parts, p, ";");
             printf "| %s | %d | %.3f | %.3f | %.0f | %.2fx | %s | %s | %s |\n",
             c, n, 1e3 * t1 / n, 1e3 * c1 / n, n / tn, t1 / tn, p[1], p[2], p[3] }'
done
if [ -n "$ess_cpu" ] && [ -x "$FLOOR" ]; then
  read -r _ cf < <(timed "$FLOOR" "$UNITS")
  awk -v n="$UNITS" -v s="$ess_cpu" -v f="$cf" \
    'BEGIN { printf "\nfloor (bench-floor, 250,968 vector calls a unit): %.3f CPU ms/unit; " \
             "ESS type A one thread: %.3f CPU ms/unit = %.2fx the floor\n",
             1e3 * f / n, 1e3 * s / n, s / f }'
fi
