#!/usr/bin/env bash
# The studies engineers wait for, at their defaults on ESS type A with
# --threads 2, timed as CPU seconds (user + system of the process, which a
# busy machine disturbs far less than wall time): budget, sensitivity and
# design, each with its unit-run count.  With a second binary, the two run
# in turn (pairs) and the table gives both and the ratio of the medians.
# Usage: scripts/dev/bench-studies.sh [build/sunmc [BEFORE_BINARY [PAIRS]]]
set -euo pipefail
AFTER=${1:-build/sunmc}
BEFORE=${2:-}
PAIRS=${3:-1}
CFG=${CFG:-configs/ess_type_a.ini}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# CPU seconds of one study; its stdout kept in $tmp/out.
cpu() {
  local t
  t=$( { TIMEFORMAT='%U %S'; time "$1" "$2" "$CFG" --threads 2 --out "$tmp/o" \
           > "$tmp/out" 2> /dev/null; } 2>&1 )
  rm -rf "$tmp/o"
  awk -v t="$t" 'BEGIN { split(t, a, " "); printf "%.2f\n", a[1] + a[2] }'
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
runs() { { grep -Eo '[0-9,]+ unit runs' "$tmp/out" || true; } | head -1 | tr -d ',' | awk '{print $1}'; }

if [ -n "$BEFORE" ]; then
  echo "| study | unit runs before | unit runs after | CPU s before | CPU s after | after / before |"
  echo "|---|---|---|---|---|---|"
else
  echo "| study | unit runs | CPU s |"
  echo "|---|---|---|"
fi
for study in budget sensitivity design; do
  : > "$tmp/a"; : > "$tmp/b"; ra=-; rb=-
  for ((i = 0; i < PAIRS; i++)); do
    if [ -n "$BEFORE" ]; then cpu "$BEFORE" "$study" >> "$tmp/b"; rb=$(runs); fi
    cpu "$AFTER" "$study" >> "$tmp/a"; ra=$(runs)
  done
  a=$(median < "$tmp/a")
  if [ -n "$BEFORE" ]; then
    b=$(median < "$tmp/b")
    echo "| $study | ${rb:--} | ${ra:--} | $b | $a | $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", a / b }') |"
  else
    echo "| $study | ${ra:--} | $a |"
  fi
done
