#!/usr/bin/env bash
# Runs each cmocka test binary given as an argument; prints their output and a
# closing line "N passed, N failed".  Exit status 1 if any test failed.
set -u
passed=0
failed=0
for t in "$@"; do
  echo "== $t"
  out=$("$t" 2>&1)
  rc=$?
  echo "$out"
  p=$(echo "$out" | sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' | awk '{s+=$1} END {print s+0}')
  f=$(echo "$out" | sed -n 's/^\[  FAILED  \] \([0-9]*\) test.*/\1/p' | awk '{s+=$1} END {print s+0}')
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
    echo "!! $t exited with status $rc"
    f=1
  fi
  passed=$((passed + p))
  failed=$((failed + f))
done
echo "suite: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
