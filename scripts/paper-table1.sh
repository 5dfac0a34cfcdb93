#!/usr/bin/env bash
# paper-table1.sh - the ESS paper's Table 1 under its own protocol, cell by
# cell, with each cell's sampling interval over 20-unit groups.
#
# The paper calibrates twenty units and "tests them within different ranges
# of incident angles": each range is calibrated and validated on its own.
# sunmc runs one calibration per range and type (configs/ess_paper_a.ini,
# configs/ess_paper_b.ini, with the campaign and validation narrowed to the
# range), N units each (default 1000 = 50 groups of 20); for every group of
# 20 consecutive units with a fit (a unit whose fit failed is counted in
# fit_failures and skipped) it takes the five statistics of Table 1 (RMS after
# max and min, improvement mean, max and min), and prints, per cell, the
# median over the groups and the 5-95 % range, the paper's value and
# whether the paper's value lies in that range.
#   bash scripts/paper-table1.sh [--default] [UNITS [OUTDIR [--set KEY=VALUE ...]]]   (TSV on stdout)
# --default: sunmc's default mode instead (configs/ess_type_{a,b}.ini: the
# priors on, one calibration over the field for all three bands), grouped
# the same way, for the side-by-side of docs/papers.md.
# (the --set pairs go to every run, e.g. to try another input)
# The 30-60 range is calibrated on +30..+60 only: a campaign is one alpha
# interval (campaign.alpha_min_deg..alpha_max_deg), so "+-30..+-60" is the
# one side (docs/papers.md, Table 1 under the paper's protocol).
set -eu
cd "$(dirname "$0")/.."
SUNMC=${SUNMC:-build/sunmc}
MODE=paper
if [ "${1:-}" = --default ]; then MODE=default; shift; fi
N=${1:-1000}
OUT=${2:-runs/paper_table1}
shift $(($# < 2 ? $# : 2))
GROUP=20
[ "$N" -ge "$GROUP" ] || { echo "paper-table1: UNITS must be at least $GROUP" >&2; exit 2; }
mkdir -p "$OUT"

# range ID: campaign/validation alpha interval and the band it reports
range_sets() {
  case $1 in
    30) echo "-30 30 0:30" ;;
    60) echo "-60 60 30:60" ;;
    62) echo "-62 62 0:62" ;;
  esac
}
# paper's Table 1: type range after_max after_min impr_mean impr_max impr_min
paper() {
  case $1$2 in
    a30) echo "0.0113 0.0071 4.76 6.04 3.25" ;;
    a60) echo "0.0229 0.0099 5.526 6.8 3.96" ;;
    a62) echo "0.0245 0.0093 3.94 5.17 2.7" ;;
    b30) echo "0.010 0.005 2.88 4.5 1.49" ;;
    b60) echo "0.0143 0.0073 4.47 5.18 3.07" ;;
    b62) echo "0.0157 0.0056 3.34 4.27 2.83" ;;
  esac
}

printf 'type\trange\tcell\tpaper\tmedian\tp5\tp95\tgroups\tfit_failures\tpaper_in_range\n'
for t in a b; do
  for r in 30 60 62; do
    read -r lo hi band <<<"$(range_sets $r)"
    id=${t}_$r
    if [ $MODE = default ]; then
      id=${t}_default
      [ -s "$OUT/$id/units.tsv" ] && [ $r != 30 ] ||
        "$SUNMC" run configs/ess_type_$t.ini --units "$N" --seed 1 "$@" --out "$OUT/$id" --quiet >/dev/null ||
        { echo "paper-table1: run $id failed" >&2; exit 1; }
    else
    "$SUNMC" run configs/ess_paper_$t.ini --units "$N" --seed 1 \
      --set campaign.alpha_min_deg="$lo" --set campaign.alpha_max_deg="$hi" \
      --set validation.alpha_min_deg="$lo" --set validation.alpha_max_deg="$hi" \
      --set report.bands_deg="$band" "$@" --out "$OUT/$id" --quiet >/dev/null ||
      { echo "paper-table1: run $id failed" >&2; exit 1; }
    fi
    col=${band/:/_}
    awk -F'\t' -v g=$GROUP -v ty=$t -v rg=$r -v pp="$(paper $t $r)" -v col="$col" '
      function q(a, n, p,   h, i) { h = (n - 1) * p; i = int(h); return (i + 1 < n) ? a[i] + (h - i) * (a[i + 1] - a[i]) : a[i] }
      function sortn(a, n,   i, j, v) { for (i = 1; i < n; i++) { v = a[i]; for (j = i - 1; j >= 0 && a[j] > v; j--) a[j + 1] = a[j]; a[j + 1] = v } }
      NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "rms_before_alpha_" col "_deg") cb = i; if ($i == "rms_after_alpha_" col "_deg") ca = i }
                if (!cb || !ca) { print "paper-table1: no column for band " col > "/dev/stderr"; exit 1 }; next }
      { b = $cb; a = $ca
        if (!(a > 0) || !(b > 0)) { bad++; next }
        k = (NR - 2 - bad) % g
        im = b / a
        if (k == 0) { mx = a; mn = a; is = 0; ix = im; in_ = im }
        if (a > mx) mx = a; if (a < mn) mn = a; is += im; if (im > ix) ix = im; if (im < in_) in_ = im
        if (k == g - 1) { s[0, G] = mx; s[1, G] = mn; s[2, G] = is / g; s[3, G] = ix; s[4, G] = in_; G++ } }
      END { if (G < 1) { print "paper-table1: fewer than " g " units with a fit in " ty rg > "/dev/stderr"; exit 1 }
        split(pp, P, " "); split("after_max after_min improvement_mean improvement_max improvement_min", name, " ")
        for (c = 0; c < 5; c++) { for (i = 0; i < G; i++) v[i] = s[c, i]; sortn(v, G)
          lo = q(v, G, 0.05); hi = q(v, G, 0.95)
          printf "%s\t%s\t%s\t%s\t%.4g\t%.4g\t%.4g\t%d\t%d\t%s\n", toupper(ty), (rg == 30 ? "+-30" : rg == 60 ? "30-60" : "+-62"),
            name[c + 1], P[c + 1], q(v, G, 0.5), lo, hi, G, bad, (P[c + 1] >= lo && P[c + 1] <= hi) ? "yes" : "no" } }
    ' "$OUT/$id/units.tsv"
  done
done
