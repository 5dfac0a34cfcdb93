#!/usr/bin/env bash
# mutate.sh - mutation testing: does the test suite notice a wrong number?
#
#   scripts/dev/mutate.sh [--list FILE] [--only REGEX] [--tree DIR] [--timeout SECONDS] [--keep]
#                     [--check]
#
# Applies each mutant of FILE (default tests/mutants.txt; format in its
# header) one at a time to a copy of the tree DIR (default: this repository),
# builds incrementally there (`make mutate-build`: only the mutated object is
# recompiled, the binaries relinked), runs the suites `make mutate-tests`
# lists (fastest first, stopping at the first that fails, each under a
# timeout) and restores the file.  A mutant is
#   caught      some suite fails (or times out) with it,
#   survived    every suite passes: a test is missing, or the mutant is
#               equivalent (it cannot change any result) and must be marked so,
#   equivalent  it survived and carries an `equivalent:` mark,
#   error       its text is not found exactly once in its file (re-target it),
#               or the mutated tree does not build.
# Prints one line per mutant, then caught/survived per module (src/ folder and
# file) and in total, and the score = caught / (applied - equivalent).
# --only REGEX keeps the mutants whose id or file matches.  --keep leaves the
# copy in place.  --check only says which mutants no longer apply (no build,
# no tests: quick, after others moved code).  Exit status: 2 for an error (or a failing unmutated tree),
# 1 when an unmarked mutant survived, else 0.
set -u

list=""
only=""
tree=""
timeout_s=${MUTATE_TIMEOUT:-300}
keep=0
check=0
while [ $# -gt 0 ]; do
  case "$1" in
    --list) list=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    --tree) tree=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    --check) check=1; shift ;;
    -h|--help) sed -n '2,/^set -u/p' "$0" | sed -e '$d' -e 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "mutate.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$tree" ] || tree=$(cd "$(dirname "$0")/../.." && pwd)
tree=$(cd "$tree" && pwd) || exit 2
[ -n "$list" ] || list=$tree/tests/mutants.txt
[ -f "$list" ] || { echo "mutate.sh: $list: no such mutant list" >&2; exit 2; }
jobs=${MUTATE_JOBS:-2}

# ---- the list ---------------------------------------------------------------
ids=(); files=(); froms=(); tos=(); whys=(); equivs=(); lines=()
bad_list=0

unescape() { # "\n" -> newline, "\\" -> backslash
  local s=$1
  s=${s//\\\\/$'\001'}
  s=${s//\\n/$'\n'}
  s=${s//$'\001'/\\}
  printf '%s' "$s"
}

flush() {
  [ -n "$cur_id$cur_file$cur_from" ] || return 0
  if [ -z "$cur_id" ] || [ -z "$cur_file" ] || [ "$have_from" = 0 ] || [ "$have_to" = 0 ]; then
    echo "mutate.sh: $list:$cur_line: a mutant needs id:, file:, from: and to:" >&2
    bad_list=1
  else
    ids+=("$cur_id"); files+=("$cur_file"); froms+=("$(unescape "$cur_from")")
    tos+=("$(unescape "$cur_to")"); whys+=("$cur_why"); equivs+=("$cur_equiv")
    lines+=("$cur_line")
  fi
  cur_id=""; cur_file=""; cur_from=""; cur_to=""; cur_why=""; cur_equiv=""
  have_from=0; have_to=0
}

cur_id=""; cur_file=""; cur_from=""; cur_to=""; cur_why=""; cur_equiv=""
have_from=0; have_to=0; cur_line=0; n=0
while IFS= read -r line || [ -n "$line" ]; do
  n=$((n + 1))
  case "$line" in
    '#'*) continue ;;
    '') flush; continue ;;
  esac
  [ -n "$cur_id$cur_file$cur_from" ] || cur_line=$n
  key=${line%%:*}
  val=${line#*:}
  val=${val# }
  case "$key" in
    id) cur_id=$val ;;
    file) cur_file=$val ;;
    from) cur_from=$val; have_from=1 ;;
    to) cur_to=$val; have_to=1 ;;
    why) cur_why=$val ;;
    equivalent) cur_equiv=${val:-yes} ;;
    *) echo "mutate.sh: $list:$n: unknown field '$key'" >&2; bad_list=1 ;;
  esac
done < "$list"
flush
[ "$bad_list" = 0 ] || exit 2

dup=$(printf '%s\n' "${ids[@]}" | sort | uniq -d | head -1)
[ -z "$dup" ] || { echo "mutate.sh: $list: id '$dup' used twice" >&2; exit 2; }

sel=()
for i in "${!ids[@]}"; do
  if [ -z "$only" ] || [[ "${ids[$i]}" =~ $only ]] || [[ "${files[$i]}" =~ $only ]]; then
    sel+=("$i")
  fi
done
echo "mutate: ${#sel[@]} of ${#ids[@]} mutants from $list"
[ "${#sel[@]}" -gt 0 ] || exit 0

count_in() { # file text -> occurrences of text in file
  local text rest
  IFS= read -r -d '' text < "$1"
  rest=${text//"$2"/}
  if [ -z "$2" ]; then echo 0; else echo $(( (${#text} - ${#rest}) / ${#2} )); fi
}

if [ "$check" = 1 ]; then
  bad=0
  for i in "${sel[@]}"; do
    f=$tree/${files[$i]}
    if [ ! -f "$f" ]; then
      echo "ERROR     ${ids[$i]}: ${files[$i]}: no such file (line ${lines[$i]} of the list)"
      bad=$((bad + 1))
    elif c=$(count_in "$f" "${froms[$i]}") && [ "$c" != 1 ]; then
      echo "ERROR     ${ids[$i]}: ${files[$i]}: the text is found $c times, not once" \
        "(line ${lines[$i]} of the list)"
      bad=$((bad + 1))
    fi
  done
  echo "mutate: $((${#sel[@]} - bad)) of ${#sel[@]} mutants apply"
  [ "$bad" = 0 ] || exit 2
  exit 0
fi

# ---- the copy -----------------------------------------------------------------
work=$(mktemp -d "${TMPDIR:-/tmp}/sunmc_mutate.XXXXXX") || exit 2
copy=$work/tree
cleanup() { [ "$keep" = 1 ] && echo "mutate: copy kept in $copy" || rm -rf "$work"; }
trap cleanup EXIT
trap 'exit 130' INT TERM
mkdir -p "$copy"
# The build directory comes along (timestamps kept) so the first build is
# incremental too; the sanitizer build and run outputs are left behind.
(cd "$tree" && tar --exclude=./.git --exclude=./build/asan --exclude=./runs -cf - .) |
  (cd "$copy" && tar -xf -) || exit 2
cd "$copy" || exit 2

# Without debug information: faster to compile and link, same numbers.
build() { make -s -j"$jobs" CFLAGS="${MUTATE_CFLAGS--g0}" mutate-build > "$work/build.log" 2>&1; }

# The object a source compiles to (this tree's Makefile: src/X.c ->
# build/obj/X.o); saved and put back with the source, so restoring costs no
# compilation.  Other files (headers) are touched instead: rebuilt.
object_of() {
  case "$1" in
    src/*.c) local o=${1#src/}; printf 'build/obj/%s.o' "${o%.c}" ;;
  esac
}

if ! build; then
  echo "mutate: the unmutated tree does not build:" >&2
  tail -20 "$work/build.log" >&2
  exit 2
fi
read -r -a suites <<< "$(make -s --no-print-directory mutate-tests)"
[ "${#suites[@]}" -gt 0 ] || { echo "mutate: make mutate-tests lists no suite" >&2; exit 2; }

run_suite() { # suite seconds -> exit status (124 on timeout)
  SUNMC=build/sunmc timeout -k 5 "$2" "./$1" > "$work/suite.log" 2>&1
}

# Baseline: every suite passes unmutated; order them by their time.  A
# mutated suite gets ten times its time (at least 30 s, at most --timeout).
timed=()
declare -A limit
for s in "${suites[@]}"; do
  t0=$(date +%s%N)
  if ! run_suite "$s" "$timeout_s"; then
    echo "mutate: $s fails on the unmutated tree:" >&2
    tail -20 "$work/suite.log" >&2
    exit 2
  fi
  t1=$(date +%s%N)
  ms=$(( (t1 - t0) / 1000000 ))
  timed+=("$ms $s")
  lim=$(( ms / 100 ))
  [ "$lim" -ge 30 ] || lim=30
  [ "$lim" -le "$timeout_s" ] || lim=$timeout_s
  limit[$s]=$lim
done
mapfile -t suites < <(printf '%s\n' "${timed[@]}" | sort -n | cut -d' ' -f2-)
echo "mutate: baseline passes; suites, fastest first: ${suites[*]##*/}"

# ---- the mutants --------------------------------------------------------------
declare -A m_total m_caught m_surv m_equiv m_err kills
results=()
n_caught=0; n_surv=0; n_equiv=0; n_err=0; n_equiv_caught=0
started=$(date +%s)

module_of() { # src/core/report.c -> src/core
  local d=${1%/*}
  [ "$d" = "$1" ] && d=.
  printf '%s' "$d"
}

tally() { # kind file
  local f=$2 m
  m=$(module_of "$f")
  for k in "$f" "$m"; do
    m_total[$k]=$(( ${m_total[$k]:-0} + 1 ))
    case "$1" in
      caught) m_caught[$k]=$(( ${m_caught[$k]:-0} + 1 )) ;;
      survived) m_surv[$k]=$(( ${m_surv[$k]:-0} + 1 )) ;;
      equivalent) m_equiv[$k]=$(( ${m_equiv[$k]:-0} + 1 )) ;;
      error) m_err[$k]=$(( ${m_err[$k]:-0} + 1 )) ;;
    esac
  done
}

for i in "${sel[@]}"; do
  id=${ids[$i]}; f=${files[$i]}; from=${froms[$i]}; to=${tos[$i]}
  if [ ! -f "$f" ]; then
    echo "ERROR     $id: $f: no such file (line ${lines[$i]} of the list)"
    n_err=$((n_err + 1)); tally error "$f"; continue
  fi
  count=$(count_in "$f" "$from")
  if [ "$count" != 1 ]; then
    echo "ERROR     $id: $f: the text is found $count times, not once (line ${lines[$i]} of the list)"
    n_err=$((n_err + 1)); tally error "$f"; continue
  fi
  cp -p "$f" "$work/original"
  obj=$(object_of "$f")
  [ -n "$obj" ] && [ -f "$obj" ] && [ "$obj" -nt "$f" ] && cp -p "$obj" "$work/original.o" || obj=""
  IFS= read -r -d '' text < "$f"
  printf '%s' "${text/"$from"/"$to"}" > "$f"
  verdict=""
  if ! build; then
    verdict=error
    echo "ERROR     $id: $f: the mutated tree does not build: $(grep -m1 -i 'error' "$work/build.log")"
  else
    # Suites that caught mutants of this folder before go first.
    mod=$(module_of "$f")
    mapfile -t order < <(for k in "${!suites[@]}"; do
      s=${suites[$k]}
      printf '%d %d %s\n' "$(( -${kills[$mod|$s]:-0} ))" "$k" "$s"
    done | sort -n -k1,1 -k2,2 | cut -d' ' -f3-)
    for s in "${order[@]}"; do
      run_suite "$s" "${limit[$s]}"
      rc=$?
      if [ "$rc" != 0 ]; then
        verdict=caught
        by=${s##*/}
        kills[$mod|$s]=$(( ${kills[$mod|$s]:-0} + 1 ))
        [ "$rc" = 124 ] && by="$by (timeout)"
        break
      fi
    done
    [ -n "$verdict" ] || verdict=survived
  fi
  # Restore the source with its time stamp and its object with a new one,
  # so the next build re-archives it; without a saved object the source
  # gets a new time stamp and is recompiled.
  if [ -n "$obj" ]; then
    cp -p "$work/original" "$f"
    cp "$work/original.o" "$obj"
  else
    cat "$work/original" > "$f"
  fi
  case "$verdict" in
    caught)
      if [ -n "${equivs[$i]}" ]; then
        echo "CAUGHT    $id by $by  -- but marked equivalent: drop the mark"
        n_equiv_caught=$((n_equiv_caught + 1))
      else
        echo "caught    $id by $by"
      fi
      n_caught=$((n_caught + 1)); tally caught "$f" ;;
    survived)
      if [ -n "${equivs[$i]}" ]; then
        echo "equiv     $id: ${equivs[$i]}"
        n_equiv=$((n_equiv + 1)); tally equivalent "$f"
      else
        echo "SURVIVED  $id: $f: ${whys[$i]}"
        n_surv=$((n_surv + 1)); tally survived "$f"
      fi ;;
    error) n_err=$((n_err + 1)); tally error "$f" ;;
  esac
done
# Leave the copy's build as the tree is (for --keep).
build || true

# ---- the report -----------------------------------------------------------------
pct() { # a b -> "a/b = p %"
  if [ "$2" -gt 0 ]; then awk -v a="$1" -v b="$2" 'BEGIN { printf "%5.1f %%", 100 * a / b }'
  else printf '    - '; fi
}
echo
printf '%-34s %6s %6s %8s %10s %6s  %s\n' "module" "total" "caught" "survived" "equivalent" \
  "error" "score"
for k in $(printf '%s\n' "${!m_total[@]}" | sort); do
  c=${m_caught[$k]:-0}; s=${m_surv[$k]:-0}; e=${m_equiv[$k]:-0}; r=${m_err[$k]:-0}
  label=$k
  [ -f "$k" ] && label="  ${k##*/}"
  printf '%-34s %6d %6d %8d %10d %6d  %s\n' "$label" "${m_total[$k]}" "$c" "$s" "$e" "$r" \
    "$(pct "$c" $((c + s)))"
done
applied=$((n_caught + n_surv + n_equiv))
printf '%-34s %6d %6d %8d %10d %6d  %s\n' "total" $((applied + n_err)) "$n_caught" "$n_surv" \
  "$n_equiv" "$n_err" "$(pct "$n_caught" $((n_caught + n_surv)))"
echo "score: $n_caught caught of $((n_caught + n_surv)) non-equivalent mutants ($(pct "$n_caught" \
$((n_caught + n_surv)) | sed 's/^ *//')); $n_equiv marked equivalent; $n_err not applied;" \
  "$(( $(date +%s) - started )) s"
[ "$n_equiv_caught" = 0 ] || echo "$n_equiv_caught mutants marked equivalent were caught: drop their marks"
[ "$n_err" = 0 ] || exit 2
[ "$n_surv" = 0 ] || exit 1
exit 0
