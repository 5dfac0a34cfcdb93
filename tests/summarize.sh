#!/usr/bin/env bash
# Adds up the closing lines of the plain and sanitizer runs into one line.
set -u
passed=0
failed=0
for log in "$@"; do
  line=$(grep '^suite: ' "$log" | tail -n 1)
  p=$(echo "$line" | sed -n 's/^suite: \([0-9]*\) passed, \([0-9]*\) failed/\1/p')
  f=$(echo "$line" | sed -n 's/^suite: \([0-9]*\) passed, \([0-9]*\) failed/\2/p')
  passed=$((passed + ${p:-0}))
  failed=$((failed + ${f:-1}))
done
echo
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
