#!/usr/bin/env bash
# claims.sh - check every numbered claim, table and figure of the two papers
# against sunmc and write the table docs/claims.md (make claims).
#
# Each row runs the command it shows (build/sunmc ... --out runs/claims/ID),
# reads the number from the files it wrote, and states the verdict with its
# reason.  A reason rests on a condition on those numbers (need below): when
# a change to sunmc breaks one, the script says which row and exits 1
# instead of writing a table that is no longer true.
#   bash scripts/claims.sh [OUT.md]     (default docs/claims.md)
# CLAIMS_RUNS=DIR writes the runs there instead of runs/claims (the table
# still shows runs/claims: tests/cli/test_claims_current.c regenerates the
# table in a temporary folder and compares it with docs/claims.md).
set -eu
cd "$(dirname "$0")/.."
SUNMC=${SUNMC:-build/sunmc}
OUTMD=${1:-docs/claims.md}
R=${CLAIMS_RUNS:-runs/claims}
mkdir -p $R
cmds=$(mktemp)
rows=$(mktemp)
trap 'rm -f "$cmds" "$rows"' EXIT
bad=0

# c ID ARGS...: run `sunmc ARGS --out runs/claims/ID --quiet`, keep the command.
c() {
  local id=$1; shift
  "$SUNMC" "$@" --out $R/$id --quiet >/dev/null 2>&1 || { echo "claims: $id failed: $*" >&2; exit 1; }
  echo "build/sunmc $* --out runs/claims/$id --quiet   # $id" >>"$cmds"
}
# need ROW COND: the awk condition COND (on numbers) must hold for ROW's reason.
need() {
  awk "BEGIN { exit !($2) }" || { echo "claims: row $1: its reason no longer holds ($2)" >&2; bad=1; }
}
# row ID PAPER CLAIM PAPERVALUE SUNMCVALUE CMDIDS VERDICT REASON
n=0
row() {
  n=$((n + 1))
  local ids
  ids=$(echo "$6" | sed 's/[^, ][^, ]*/`&`/g')
  printf '| %s | %s | %s | %s | %s | %s | **%s**: %s |\n' "$1" "$2" "$3" "$4" "$5" "$ids" "$7" "$8" >>"$rows"
  echo "$7" >>"$rows.v"
}
rm -f "$rows.v"
f() { printf "%.${2:-4}f" "$1"; }
# umax DIR COL [BETA]: max |COL| of curve.tsv (at beta BETA): "value alpha beta"
umax() {
  awk -F'\t' -v c="$2" -v b="${3:-}" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
    b == "" || $2 == b { v = $k < 0 ? -$k : $k; if (v > m) { m = v; a = $1; bb = $2 } }
    END { print m, a, bb }' "$1/curve.tsv"
}
# at DIR COL ALPHA BETA: COL of curve.tsv at (ALPHA, BETA)
at() { awk -F'\t' -v c="$2" -v a="$3" -v b="$4" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
    $1 == a && $2 == b { print $k }' "$1/curve.tsv"; }
# sm DIR BAND COL [ANGLE]: summary.tsv's COL in BAND
sm() { awk -F'\t' -v c="$3" -v band="$2" -v ang="${4:-alpha}" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
    $3 == ang && $4 == band { print $k }' "$1/summary.tsv"; }
# ucol DIR COL min|max|absmin|absmax: over units.tsv
ucol() { awk -F'\t' -v c="$2" -v op="$3" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
    { v = $k; if (op ~ /abs/ && v < 0) v = -v; if (NR == 2 || v < lo) lo = v; if (NR == 2 || v > hi) hi = v }
    END { print (op ~ /min/) ? lo : hi }' "$1/units.tsv"; }
first() { echo "$1" | cut -d' ' -f"${2:-1}"; }

ideal="--set design.harmonics=given --set design.a3_ratio=0 --set design.a5_ratio=0"
fine="--set validation.alpha_offset_deg=0 --set validation.alpha_step_deg=0.05"
A=configs/ess_type_a.ini
B=configs/ess_type_b.ini
D=configs/dss.ini

# ---------------------------------------------------------------- ESS sec. 3
c a_dH curve $A --only dH_um=2 $ideal $fine --set validation.beta_deg=0
c b_dH curve $B --only dH_um=2 $ideal $fine --set validation.beta_deg=0
m=$(umax $R/a_dH error_source_alpha_deg); mb=$(umax $R/b_dH error_source_alpha_deg)
e62=$(at $R/a_dH error_source_alpha_deg 62 0); e62=${e62#-}
need E1 "$(first "$m") < 0.015 && $(first "$m") > 0.0138 && ($(first "$m" 2)) ^ 2 == 2025"
row E1 "ESS 3.1 (2), Fig. 3" "type A, ΔH = ±2 µm: error exceeds 0.015°" "> 0.015°" \
  "$(f "$(first "$m")")° at α = ±45°" a_dH differs \
  "the error of a height alone is −(ΔH/2H) sin 2α, largest ΔH/2H = 0.0139° at 45° (closed form, tests/test_ess_closed_forms.c); 0.015° needs H ≈ 3.8 mm or ΔH ≈ 2.2 µm"
need E2 "$(first "$mb") > 0.008"
row E2 "ESS 3.1 (2)" "type B, ΔH = ±2 µm: error exceeds 0.008°" "> 0.008°" \
  "$(f "$(first "$mb")")° at α = ±45°" b_dH reproduced "ΔH/2H = 2 µm / 13.17 mm"
need E3 "$(first "$m") > $(first "$mb") && $e62 < $(first "$m")"
row E3 "ESS 3.1 (1)" "ΔH's error grows as H decreases and as incidence grows" "grows" \
  "A $(f "$(first "$m")")° > B $(f "$(first "$mb")")°; A: $(f "$(first "$m")")° at 45°, $(f "$e62")° at 62°" "a_dH, b_dH" qualitatively \
  "1/H: yes; incidence: sin 2α grows only to 45° and falls beyond"

c a_dd curve $A --only dd_um=1 $ideal $fine --set validation.beta_deg=0
m=$(umax $R/a_dd error_source_alpha_deg)
e0=$(at $R/a_dd error_source_alpha_deg 0 0); e0=${e0#-}
e60=$(at $R/a_dd error_source_alpha_deg 60 0); e60=${e60#-}
need E4 "$(first "$m") < 0.014 && $(first "$m") > 0.0135 && $(first "$m" 2) + 0 == 0"
row E4 "ESS 3.2 (2), Fig. 5" "type A, Δd = 1 µm: error exceeds 0.014°" "> 0.014°" \
  "$(f "$(first "$m")")° at α = $(first "$m" 2)°" a_dd qualitatively \
  "the size is Δd/H = 0.0139° (1 % short), but at normal incidence: a pure offset gives −(Δd/H) cos²α"
need E5 "$e60 < $e0 / 3"
row E5 "ESS 3.2 (1)" "offset's error grows with incidence" "grows" \
  "$(f "$e0")° at 0°, $(f "$e60")° at 60°" a_dd differs \
  "−(Δd/H) cos²α falls with incidence; an offset is a position error, turned into angle by cos²α/H"

c a_dphi curve $A --only dphi_deg=0.01 $ideal $fine --set validation.beta_deg=-30,0,30
c b_dphi curve $B --only dphi_deg=0.01 $ideal $fine --set validation.beta_deg=0
m0=$(umax $R/a_dphi error_source_alpha_deg 0); m30=$(umax $R/a_dphi error_source_alpha_deg 30)
mb=$(umax $R/b_dphi error_source_alpha_deg 0)
# mean error over |alpha| < 5 and over 55..62 at beta 0 (the curve's trend)
lohi=$(awk -F'\t' 'NR > 1 && $2 == 0 { a = $1 < 0 ? -$1 : $1; v = $5 < 0 ? -$5 : $5
  if (a < 5) { s0 += v; n0++ } if (a >= 55) { s1 += v; n1++ } } END { print s0 / n0, s1 / n1 }' $R/a_dphi/curve.tsv)
need E6 "$(first "$m0") < 0.005"
row E6 "ESS 3.2 (3), Fig. 6" "type A, Δφ = 0.01°: error under 0.005°" "< 0.005°" \
  "$(f "$(first "$m0")")° at β = 0; $(f "$(first "$m30")")° at β = 30°" a_dphi reproduced \
  "at β = 0, as the figure draws; at β = ±30° the tilt's cross-axis term tan β cos α Δφ adds up to 0.0058°"
c a_dphi_pivot curve $A --only dphi_deg=0.01 --set design.tilt_pivot_mm=1.5 $ideal $fine --set validation.beta_deg=0
lp=$(awk -F'\t' 'NR > 1 && $2 == 0 { a = $1 < 0 ? -$1 : $1; v = $5 < 0 ? -$5 : $5
  if (a < 5) { s0 += v; n0++ } if (a >= 55) { s1 += v; n1++ } } END { print s0 / n0, s1 / n1 }' $R/a_dphi_pivot/curve.tsv)
c a_dial curve $A --only dial_tilt_deg=0.01 $ideal $fine --set validation.beta_deg=0
ld=$(awk -F'\t' 'NR > 1 && $2 == 0 { a = $1 < 0 ? -$1 : $1; v = $5 < 0 ? -$5 : $5
  if (a < 5) { s0 += v; n0++ } if (a >= 55) { s1 += v; n1++ } } END { print s0 / n0, s1 / n1 }' $R/a_dial/curve.tsv)
need E7 "$(first "$ld" 2) > 2 * $(first "$ld") && $(first "$lohi" 2) < $(first "$lohi") / 2 && $(first "$lp" 2) < $(first "$lp") / 2"
row E7 "ESS 3.2 (1)" "tilt's error grows with incidence" "grows" \
  "dial tilt about the row axis (dial_tilt_deg = 0.01°): mean \|error\| $(f "$(first "$ld")" 5)° at \|α\| < 5°, $(f "$(first "$ld" 2)" 5)° at 55-62° (β = 0)" "a_dial, a_dphi, a_dphi_pivot" reproduced \
  "by the dial's tilt about the code-row axis (each row's height changes by x tan τ; docs/ess.md); the in-plane reading of Δφ alone falls instead ($(f "$(first "$lohi")")° → $(f "$(first "$lohi" 2)")°; at the fine rows' centre as pivot $(f "$(first "$lp")" 5)° → $(f "$(first "$lp" 2)" 5)°)"
need E8 "$(first "$mb") < $(first "$m0")"
row E8 "ESS 3.2 (3)" "type B's tilt error much less than A's" "much less" \
  "B $(f "$(first "$mb")")°, A $(f "$(first "$m0")")° (β = 0)" "a_dphi, b_dphi" qualitatively \
  "less by H_A/H_B (same rows, taller B), not much less"

# offset against tilt (3.2 (2)) and the offset's 1/H (3.2 (1)): a_dd's peak
# (the offset's, at 0°), a_dphi's at β = 0, b_dd's
c b_dd curve $B --only dd_um=1 $ideal $fine --set validation.beta_deg=0
mdd=$(umax $R/a_dd error_source_alpha_deg); mbd=$(umax $R/b_dd error_source_alpha_deg)
need E12 "$(first "$mdd") > 2 * $(first "$m0")"
row E12 "ESS 3.2 (2)" "errors of the slit's offset exceed those of its tilt" "offset > tilt" \
  "type A, largest: Δd = 1 µm $(f "$(first "$mdd")")°, Δφ = 0.01° $(f "$(first "$m0")")° (β = 0)" "a_dd, a_dphi" reproduced \
  "Δd/H against the tilt's read-position term (x − pivot) tan Δφ cos²α/H: the tolerances the paper names give 3 times"
need E13 "$(first "$mbd") < $(first "$mdd") && $(first "$mbd") > 0.6 * $(first "$mdd") * 4.124 / 6.584"
row E13 "ESS 3.2 (1)" "the offset's error grows as H falls" "grows" \
  "Δd = 1 µm: A (H 4.124 mm) $(f "$(first "$mdd")")°, B (6.584 mm) $(f "$(first "$mbd")")°" "a_dd, b_dd" reproduced \
  "Δd/H: the ratio of the two is H_B/H_A = 1.60"

# sec. 3.3: an odd harmonic a3 gives an error of size (θ0/2π)·|a3/a1| with
# a 0.5° period (eq. 7's 4α; eq. 5 prints the phase of a3 as 3α)
c a_h3 curve $A --only dH_um=0 --set design.harmonics=given --set design.a3_ratio=-0.1 --set design.a5_ratio=0 $fine --set validation.beta_deg=0
h3=$(awk -F'\t' 'NR > 1 { e[sprintf("%.2f", $1)] = $3; v = $3 < 0 ? -$3 : $3; if (v > m) m = v }
  END { for (k in e) { a = k + 0; if (a <= 0 && a >= -40) { k5 = sprintf("%.2f", a + 0.5); k25 = sprintf("%.2f", a + 0.25)
          d = e[k5] - e[k]; if (d < 0) d = -d; if (d > dp) dp = d; s = e[k25] + e[k]; if (s < 0) s = -s; if (s > sh) sh = s } }
        printf "%.5f %.1e %.5f\n", m, dp, sh }' $R/a_h3/curve.tsv)
need E14 "$(first "$h3") > 0.030 && $(first "$h3") < 0.0325 && $(first "$h3" 2) < 0.1 * $(first "$h3") && $(first "$h3" 3) < 0.25 * $(first "$h3")"
row E14 "ESS 3.3, eq. 5-7" "the fine-code's odd harmonics give an error of size (θ0/2π)·aₙ/a1 with a 0.5° period; even ones cancel" "(θ0/2π)·0.1 = 0.0318° for a3/a1 = −0.1; period 0.5°" \
  "a3/a1 = −0.1 alone: largest $(f "$(first "$h3")")°; α against α + 0.5° differs by at most $(first "$h3" 2)°, α + 0.25° nearly opposite (sum at most $(f "$(first "$h3" 3)" 5)°; the 2nd harmonic of eq. 7's arctangent)" a_h3 reproduced \
  "eq. 7 exactly (−atan(r sin 4x / (1 + r cos 4x)), largest asin r), the four-quadrant demodulation cancels the even harmonics by construction (no key sets one); eq. 5 prints a3's phase as −3α, which against a1's −α would give a 2α error term: eq. 7's 4α (the 0.5° period) needs +3α, the 3rd harmonic travelling against the 1st"

c a_dphi_0p5 curve $A --only dphi_deg=0.01 $ideal --set validation.alpha_offset_deg=0 --set validation.alpha_step_deg=0.5 --set validation.beta_deg=0
alt=$(awk -F'\t' 'NR > 1 { e[++k] = $5 } END { for (i = 2; i < k - 1; i++) { d1 = e[i] - (e[i-1] + e[i+1]) / 2
  d2 = e[i+1] - (e[i] + e[i+2]) / 2; n++; if (d1 * d2 < 0) s++ } print s, n }' $R/a_dphi_0p5/curve.tsv)
need E9 "$(first "$alt") >= 0.95 * $(first "$alt" 2)"
row E9 "ESS 3.2 (3), Fig. 7" "sampled every 0.5°, the tilt's error has a 1° period" "1° period" \
  "the error alternates sample to sample at $(first "$alt") of $(first "$alt" 2) points" a_dphi_0p5 reproduced \
  "the fine rows' offsets from the pivot alternate the demodulated phase; the same alternation is Fig. 6's band"
c a_dphi_rows curve $A --only dphi_deg=0.01 $ideal $fine --set validation.beta_deg=0 --set design.fine_rows_x_mm=1.5,1.5,1.5,1.5
band() { awk -F'\t' 'NR > 1 { w = int(($1 + 62) / 2); if (!(w in lo) || $5 < lo[w]) lo[w] = $5; if (!(w in hi) || $5 > hi[w]) hi[w] = $5 }
  END { for (w in lo) if (hi[w] - lo[w] > b) b = hi[w] - lo[w]; print b }' "$1/curve.tsv"; }
b1=$(band $R/a_dphi); b1=$(awk -F'\t' 'NR > 1 && $2 == 0 { w = int(($1 + 62) / 2); if (!(w in lo) || $5 < lo[w]) lo[w] = $5; if (!(w in hi) || $5 > hi[w]) hi[w] = $5 }
  END { for (w in lo) if (hi[w] - lo[w] > b) b = hi[w] - lo[w]; print b }' $R/a_dphi/curve.tsv)
b2=$(band $R/a_dphi_rows)
need E10 "$b2 < $b1 / 5"
row E10 "ESS Fig. 6" "the tilt's error is a band (sunmc's earlier reading: over the β lines)" "a band" \
  "width $(f "$b1" 5)° at β = 0 alone; $(f "$b2" 5)° with the four fine rows at one x" "a_dphi, a_dphi_rows" reproduced \
  "one β line is a band already: it comes from the fine rows' alternation (rows at 0.6-2.4 mm, different tilt offsets), not from β"

c a_budget budget $A --units 100 --seed 1 --set report.budget_units=50 --set report.budget_steps=1
sh() { awk -F'\t' -v s="$2" -v c="$3" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next } $3 == s { printf "%.1f", 100 * $k }' "$1/budget.tsv"; }
gb=$(sh $R/a_budget gain_pct share_before); eb=$(sh $R/a_budget etch_um share_before)
ga=$(sh $R/a_budget gain_pct share_after); ea=$(sh $R/a_budget etch_um share_after)
hb=$(sh $R/a_budget dH_um share_before); db=$(sh $R/a_budget dd_um share_before)
need E11 "$gb + $eb < 1 && $gb + $eb < ($hb + $db) / 4"
row E11 "ESS 3.4, 3.5 (3)" "etching and photocell errors (under ±1 %) are insignificant" "insignificant" \
  "type A, shares of the mean square before: gain 1 % $gb %, etching 0.2 µm $eb % (ΔH $hb %, Δd $db %); after: gain $ga %, etching $ea %" a_budget reproduced \
  "before calibration; after it the row gains' imbalance (a 1st-harmonic term eq. 9 has no place for) is a few per cent of what is left (calibration.model = extended fits it)"

# ---------------------------------------------------------------- ESS tables
c a_run run $A --units 100 --seed 1
c b_run run $B --units 100 --seed 1
# eq. 12-13: eq. 13 inverts eq. 12 exactly; (a, b, c, d) matter up to a
# common scale, so eq. 14's 18 parameters are not all identifiable
inv=$(awk 'BEGIN { a = 4.1289; b = -0.0003; c = -0.0003; d = 4.1191; pi = atan2(0, -1)
  for (x = -62; x <= 62; x += 0.5) { t = sin(x * pi / 180) / cos(x * pi / 180); td = (a * t + b) / (c * t + d)
    back = atan2(b - d * td, c * td - a); if (back > pi / 2) back -= pi; if (back < -pi / 2) back += pi
    e = back - x * pi / 180; if (e < 0) e = -e; if (e > m) m = e
    s = 3; td2 = (s * a * t + s * b) / (s * c * t + s * d); g = td2 - td; if (g < 0) g = -g; if (g > ms) ms = g }
  printf "%.1e %.1e\n", m, ms }')
model=$(sm $R/a_run 0:62 model)
need E15 "$(first "$inv") < 1e-12 && $(first "$inv" 2) < 1e-12"
case $model in *"d = 1"*) ;; *) echo "claims: row E15: the model no longer fixes d = 1 ($model)" >&2; bad=1 ;; esac
row E15 "ESS eq. 12-14" "eq. 13 compensates eq. 12; eq. 14 fits eighteen parameters" "eq. 13; 18 parameters" \
  "eq. 12 then eq. 13 with Table 3's (a, b, c, d), α over ±62°: back to $(first "$inv") rad; (a, b, c, d) × 3 moves eq. 12 by $(first "$inv" 2); sunmc fits: $model" "scripts/claims.sh, a_run" qualitatively \
  "eq. 13 is the exact inverse of eq. 12 (solve tan α_d (cT + d) = aT + b for T); but eq. 12 depends on (a, b, c, d) only up to a common scale and R_rs (r1-r9) is a rotation of 3 angles and V0 a direction of 2, so the 18 are 11 free (sunmc: d = 1, the roll fixed at its measurement; include/ess/ess_calib.h)"

for t in a b; do
  eval "i30_$t=\$(sm $R/${t}_run 0:30 improvement_mean); i60_$t=\$(sm $R/${t}_run 30:60 improvement_mean)"
  eval "i62_$t=\$(sm $R/${t}_run 0:62 improvement_mean); mx_$t=\$(sm $R/${t}_run 0:62 rms_after_max)"
  eval "mn_$t=\$(sm $R/${t}_run 0:62 rms_after_min)"
done
c a_run_np run $A --units 100 --seed 1 --set calibration.priors=off
c b_run_np run $B --units 100 --seed 1 --set calibration.priors=off
for t in a b; do
  eval "npx_$t=\$(sm $R/${t}_run_np 0:62 rms_after_max); npi_$t=\$(sm $R/${t}_run_np 0:62 improvement_min)"
  eval "ix_$t=\$(sm $R/${t}_run 0:62 improvement_max); in_$t=\$(sm $R/${t}_run 0:62 improvement_min)"
done
need T1 "$i62_a > 3 && $i62_b > 2.5 && $mx_a / $mn_a < 1.5 && $mx_b / $mn_b < 1.5 && $npx_a > $mx_a && $npi_a < $in_a"
row T1 "ESS Table 1, type A, ±62°" "RMS after max, min; improvement mean, max, min" "0.0245°, 0.0093°; 3.94, 5.17, 2.7" \
  "default mode: $(f "$mx_a")°, $(f "$mn_a")°; $(f "$i62_a" 2), $(f "$ix_a" 2), $(f "$in_a" 2) (±30°: $(f "$i30_a" 2), 30-60°: $(f "$i60_a" 2)); priors off: max $(f "$npx_a")°, improvement min $(f "$npi_a" 2)" "a_run, a_run_np" qualitatively \
  "the mean improvement is the paper's size, the spread is not (after max/min $(f "$(awk "BEGIN { print $mx_a / $mn_a }")" 2) against 2.63): the default's priors (calibration.priors = tolerances, which the paper does not have) pull every unit's fit toward the pilot's, and the after level is the assumed 1.5 % row-current noise, the same for every unit; one calibration over the field serves all three bands.  Cell by cell under the paper's protocol: rows T12, T13"
row T2 "ESS Table 1, type B, ±62°" "RMS after max, min; improvement mean, max, min" "0.157° (sic: 0.0157°, row T15), 0.0056°; 3.34, 4.27, 2.83" \
  "default mode: $(f "$mx_b")°, $(f "$mn_b")°; $(f "$i62_b" 2), $(f "$ix_b" 2), $(f "$in_b" 2) (±30°: $(f "$i30_b" 2), 30-60°: $(f "$i60_b" 2)); priors off: max $(f "$npx_b")°, improvement min $(f "$npi_b" 2)" "b_run, b_run_np" qualitatively \
  "as type A (after max/min $(f "$(awk "BEGIN { print $mx_b / $mn_b }")" 2) against 2.8)"
need T3 "$i62_a >= 3 && $i62_b >= 3"
row T3 "ESS abstract, 6 (4), 7" "three times better within ±60° on average" "3 times" \
  "A $(f "$i62_a" 2), B $(f "$i62_b" 2) times" "a_run, b_run" reproduced "mean improvement over ±62°"
c a_ripple run $A --units 100 --seed 1 --set design.harmonics=given --set design.a3_ratio=-0.1
c b_ripple run $B --units 100 --seed 1 --set design.harmonics=given --set design.a3_ratio=-0.1
r30a=$(sm $R/a_ripple 0:30 improvement_mean); r60a=$(sm $R/a_ripple 30:60 improvement_mean)
r30b=$(sm $R/b_ripple 0:30 improvement_mean); r60b=$(sm $R/b_ripple 30:60 improvement_mean)
need T4 "$i60_a > $i30_a && $i62_a > $i62_b && $r60a < $r30a && $r60b < $r30b"
row T4 "ESS 6 (1)" "improvement greater in 30-60° than ±30°, and for A than B, because structural errors grow as H falls and incidence grows" "A > B; 30-60° > ±30°" \
  "shipped: A $(f "$i30_a" 2) → $(f "$i60_a" 2), B $(f "$i30_b" 2) → $(f "$i60_b" 2) (±30° → 30-60°); the same ripple a3/a1 = −0.1 for both: A $(f "$r30a" 2) → $(f "$r60a" 2), B $(f "$r30b" 2) → $(f "$r60b" 2)" \
  "a_run, b_run, a_ripple, b_ripple" qualitatively \
  "the trend comes from the slit widths chosen for A (20 µm) and B (46 µm), which set the fine-code ripple; with the same ripple for both, 30-60° improves less than ±30° and A and B nearly agree"

grid="--set validation.alpha_min_deg=-61.95 --set validation.alpha_max_deg=61.95 --set validation.alpha_offset_deg=0 --set validation.beta_deg=-30,0,30"
for s in 1 0.25; do
  id=${s/./p}
  c a_t2_on_$id run $A --units 100 --seed 1 --set report.bands_deg=0:62 --set campaign.alpha_step_deg=$s --set validation.alpha_step_deg=$s $grid
  c a_t2_off_$id run $A --units 100 --seed 1 --set report.bands_deg=0:62 --set campaign.alpha_step_deg=$s
  c b_t2_on_$id run $B --units 100 --seed 1 --set report.bands_deg=0:62 --set campaign.alpha_step_deg=$s --set validation.alpha_step_deg=$s $grid
done
t2() { echo "$(f "$(sm $R/$1 0:62 rms_before_mean)") → $(f "$(sm $R/$1 0:62 rms_after_mean)")"; }
on1=$(sm $R/a_t2_on_1 0:62 rms_after_mean); on25=$(sm $R/a_t2_on_0p25 0:62 rms_after_mean)
off1=$(sm $R/a_t2_off_1 0:62 rms_after_mean); bf1=$(sm $R/a_t2_off_1 0:62 rms_before_mean)
bon1=$(sm $R/b_t2_on_1 0:62 rms_after_mean); bon25=$(sm $R/b_t2_on_0p25 0:62 rms_after_mean)
bon1b=$(sm $R/a_t2_on_1 0:62 rms_before_mean); bon25b=$(sm $R/a_t2_on_0p25 0:62 rms_before_mean)
wmin=$(awk "BEGIN { a = $(sm $R/a_t2_on_1 0:62 improvement_min); b = $(sm $R/a_t2_on_0p25 0:62 improvement_min); print a < b ? a : b }")
need T5 "$on1 < 0.5 * $bf1 && $on25 < $on1 && $off1 > $bf1 && $bon25b >= $bon1b && $wmin < 1"
row T5 "ESS Table 2, type A" "RMS before → after at steps 1°, 0.25° (±62°)" "1°: 0.0399° → 0.0141°; 0.25°: 0.0296° → 0.0102°" \
  "default mode, on the calibration grid: 1°: $(t2 a_t2_on_1)°, 0.25°: $(t2 a_t2_on_0p25)°, per-unit improvement down to $(f "$wmin" 2); off it: 1°: $(t2 a_t2_off_1)°, 0.25°: $(t2 a_t2_off_0p25)°" \
  "a_t2_on_1, a_t2_on_0p25, a_t2_off_1, a_t2_off_0p25" qualitatively \
  "validated on its calibration grid, as the paper's before changing with the step shows it was, the after is of the paper's size and better at 0.25°; but the paper's before falls with the step and sunmc's does not (row T14: one unit's phase, not a trend), and some units come out worse although the validation points are the calibration points; off the grid 1° and 0.5° alias the 0.5° fine-code term (docs/ess.md, Table 2 both ways)"
need T6 "$bon25 < $bon1"
row T6 "ESS Table 2, type B" "RMS before → after at steps 1°, 0.25°" "1°: 0.020° → 0.007°; 0.25°: 0.0191° → 0.0056°" \
  "on the calibration grid: 1°: $(t2 b_t2_on_1)°, 0.25°: $(t2 b_t2_on_0p25)°" "b_t2_on_1, b_t2_on_0p25" qualitatively \
  "improves at both steps, more at 0.25°, as the paper; sunmc's type B starts from a larger before (its 46 µm slit's ripple)"
need T7 "$on25 < $on1 && $bon25 < $bon1"
row T7 "ESS 6 (2a)" "0.25° compensates better than 1°, but the improvement is limited" "better, limited" \
  "A $(f "$on1")° → $(f "$on25")°, B $(f "$bon1")° → $(f "$bon25")° (on the grid)" "a_t2_on_*, b_t2_on_*" reproduced \
  "on the calibration grid; off it the reason is aliasing, not the period argument (0.25° samples two opposite phases)"

kmin_a=$(ucol $R/a_run fit_k_deg absmin); kmax_a=$(ucol $R/a_run fit_k_deg absmax)
kmin_b=$(ucol $R/b_run fit_k_deg absmin); kmax_b=$(ucol $R/b_run fit_k_deg absmax)
r3() { awk "BEGIN { printf \"%.2f\", $1 / (2 / (2 * atan2(0, -1))) }"; }
need K1 "$kmin_a > 0.03 && $kmin_b > 0.03"
row K1 "ESS 6 (2b)" "the solved k is generally less than 0.03" "< 0.03 (Table 3, type A: 0.016-0.023; Table 4, type B: 0.0357)" \
  "default mode: \|k\| A $(f "$kmin_a" 3)-$(f "$kmax_a" 3)°, B $(f "$kmin_b" 3)-$(f "$kmax_b" 3)°" "a_run, b_run" differs \
  "none below 0.03: k ≈ (θ0/2π)·\|a3/a1\| = 0.318°·\|a3/a1\|, so the shipped slit widths make \\|a3/a1\\| $(r3 $kmin_a)-$(r3 $kmax_a) (type A, 20 µm: about twice Table 3's type-A k) and $(r3 $kmin_b)-$(r3 $kmax_b) (type B, 46 µm: Table 4's k); the paper-protocol configs take type A's ripple from Table 3 (a3/a1 = −0.063, row T12) and keep type B's at Table 4's"
it=$(awk -F'\t' 'FNR == 1 { for (i = 1; i <= NF; i++) if ($i == "fit_iterations") k = i; next }
  { v = $k; if (NR == 2 || v < lo) lo = v; if (v > hi) hi = v; if (v >= 5 && v <= 10) w++; n++ }
  END { print lo, hi, w, n }' $R/a_run/units.tsv $R/b_run/units.tsv)
need K2 "$(first "$it" 2) <= 10 && $(first "$it" 3) >= 0.9 * $(first "$it" 4)"
row K2 "ESS 5" "the fit converges in five to ten iterations" "5-10" \
  "$(first "$it")-$(first "$it" 2); $(first "$it" 3) of $(first "$it" 4) units in 5-10" "a_run, b_run" reproduced \
  "Levenberg-Marquardt from the nominal model, a = 1, b = c = k = 0 (the paper: Gauss-Newton from k = 0.03)"

# Table 3: three installations; each run three times with the campaign's
# beta lines in another order, which gives every point another noise draw
# (the draws follow the point's index), so the spread is the noise's too.
t3="--units 3:4 --seed 1 --set calibration.priors=off --set tolerance.install_x_arcsec_dist=fixed --set tolerance.install_y_arcsec_dist=fixed --set tolerance.install_z_arcsec_dist=fixed"
i=0
for inst in "0 0 0" "0 300 38" "17 94 68"; do
  read -r ix iy iz <<<"$inst"
  j=0
  for bl in -30,0,30 0,30,-30 30,-30,0; do
    c a_t3_${i}_$j run $A $t3 --set tolerance.install_x_arcsec=$ix --set tolerance.install_y_arcsec=$iy --set tolerance.install_z_arcsec=$iz --set campaign.beta_deg=$bl
    j=$((j + 1))
  done
  i=$((i + 1))
done
spread=$(awk -F'\t' 'FNR == 1 { for (i = 1; i <= NF; i++) { if ($i == "fit_a") ca = i; if ($i == "fit_k_deg") ck = i; if ($i == "fit_t_rad") ct = i }; next }
  { a[++n] = $ca; k[n] = $ck; t[n] = $ct; st += $ct; stt += $ct * $ct }
  END { for (i = 1; i <= n; i++) { if (i == 1 || a[i] < a0) a0 = a[i]; if (a[i] > a1) a1 = a[i]; if (i == 1 || k[i] < k0) k0 = k[i]; if (i == 1 || k[i] > k1) k1 = k[i]
    if (i == 1 || t[i] < t0) t0 = t[i]; if (i == 1 || t[i] > t1) t1 = t[i] }
    sd = sqrt((stt - st * st / n) / (n - 1))
    printf "%.1e %.5f %.5f %.4f %.4f %d\n", (a1 - a0) / a0, k0, k1, t1 - t0, sd, n }' $R/a_t3_*_*/units.tsv)
need T8 "$(first "$spread") < 7e-5 && $(first "$spread" 4) < 0.084 && $(first "$spread" 6) == 9"
row T8 "ESS Table 3, 6 (3)" "one unit's parameters under installation deviations (0, 0, 0), (0, 5′, 38″), (17″, 1′34″, 1′8″): almost identical" \
  "a/a 7e-5, k −0.0225..−0.0164, t spread 0.084 rad" \
  "unit 3 of type A, plain least squares, 3 installations × 3 noise draws: a/a $(first "$spread"), k $(first "$spread" 2)..$(first "$spread" 3)°, t spread $(first "$spread" 4) rad (SD $(first "$spread" 5))" "a_t3_*" reproduced \
  "more stable than the paper's own, the noise redrawn included: the installation rotations are fitted (the roll held at its measurement); sunmc's \\|k\\| is type A's shipped 0.04 (row K1), not Table 3's 0.02"

amax_a=$(ucol $R/a_run fit_a absmax); amin_b=$(ucol $R/b_run fit_a min); amax_b=$(ucol $R/b_run fit_a max)
need T9 "$amax_a < 1.001 && $amax_b < 1.001"
row T9 "ESS Tables 3-4" "a/d: Table 3 4.1289/4.1191 = 1.0024 (type A), Table 4 6.5912/6.5759 = 1.0023 (type B)" \
  "1.0023-1.0024: an effective ΔH of 9.8 µm (A), 15.3 µm (B)" \
  "a (d = 1): A up to $(f "$amax_a" 5), B $(f "$amin_b" 5)-$(f "$amax_b" 5): ΔH ≤ 2 µm" "a_run, b_run" differs \
  "sunmc draws ΔH within the paper's simulated ±2 µm (sec. 3.1), so a − 1 = ΔH/H ≤ 5e-4; the paper's units sit five to seven times further (docs/papers.md, the paper's units); the paper-protocol configs take ΔH from these a/d (rows T12, T13)"
row T10 "ESS Table 4" "type-B unit: k 0.0357, t 2.4558; r (installation) within 0.0014, e1 −0.0066" \
  "k 0.0357; e1 = 23′ sun tilt toward X" \
  "\|k\| B $(f "$kmin_b" 3)-$(f "$kmax_b" 3)°; sun tilt drawn within ±60″" b_run qualitatively \
  "k of Table 4's size by construction (slit width); t follows the drawn harmonic phase; the simulator's tilt toward X is a β offset an α sensor cannot see (fixed at 0 in the fit)"

c b_paper_unit run $B --units 100 --seed 1 --set report.bands_deg=0:62 --set tolerance.dH_um=15.3 --set tolerance.dH_um_dist=fixed --set design.slit_width_um=43 --set noise.row_current_pct=4.2
pua=$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "fit_a") ca = i; if ($i == "fit_k_deg") ck = i }; next }
  { a += $ca; k += ($ck < 0 ? -$ck : $ck); n++ } END { printf "%.5f %.4f\n", a / n, k / n }' $R/b_paper_unit/units.tsv)
pub=$(sm $R/b_paper_unit 0:62 rms_before_mean); puf=$(sm $R/b_paper_unit 0:62 rms_after_mean)
pui=$(sm $R/b_paper_unit 0:62 improvement_mean)
need T11 "$pub > 0.055 && $pub < 0.0635 && $puf > 0.0147 && $puf < 0.0167 && $(first "$pua") > 1.0022 && $(first "$pua") < 1.0025"
row T11 "ESS Table 4 with Fig. 11" "one type-B unit: a/d 1.0023, k 0.0357 and RMS 0.0635° → 0.0157° at once" "1.0023, 0.0357°; 0.0635° → 0.0157° (4.0 times)" \
  "ΔH = 15.3 µm fixed, slit 43 µm, row noise 4.2 %: a $(first "$pua"), k $(first "$pua" 2)°; $(f "$pub")° → $(f "$puf")° ($(f "$pui" 2) times)" b_paper_unit qualitatively \
  "met together, the before 6 % short, only with a height 15 µm off (7.6 times the paper's simulated ±2 µm) and readings 2.8 times noisier than the shipped units' (docs/papers.md, the paper's units)"

U=32
c b_fig11 curve $B --unit $U --set validation.alpha_step_deg=0.05 --set validation.alpha_offset_deg=0 --set validation.beta_deg=-25,-15,-5,5,15,25
c b_fig11_r24 curve $B --unit $U --set design.harmonics=given --set design.a3_ratio=-0.24 --set design.a5_ratio=0 --set validation.alpha_step_deg=0.05 --set validation.alpha_offset_deg=0 --set validation.beta_deg=-25,-15,-5,5,15,25
rms() { awk -F'\t' 'NR > 1 && $3 == $3 + 0 && $4 == $4 + 0 { b += $3 * $3; a += $4 * $4; n++ } END { printf "%.4f %.4f %.2f\n", sqrt(b / n), sqrt(a / n), sqrt(b / a) }' "$1/curve.tsv"; }
s1=$(rms $R/b_fig11); s2=$(rms $R/b_fig11_r24)
need F11 "$(first "$s1") < 0.04 && $(first "$s2" 3) > 3 && $(first "$s2") > 0.045"
row F11 "ESS Fig. 11, 6" "one type-B unit: RMS 0.0635° before, 0.0157° after (4.0 times)" "0.0635° → 0.0157°" \
  "unit $U shipped: $(first "$s1")° → $(first "$s1" 2)° ($(first "$s1" 3) times); with a3/a1 = −0.24: $(first "$s2")° → $(first "$s2" 2)° ($(first "$s2" 3) times)" "b_fig11, b_fig11_r24" qualitatively \
  "the ratio is the paper's; its level needs a fine-code ripple about twice the shipped one, or the effective ΔH of Table 4 (docs/papers.md, the paper's units)"

# ---------------------------------------------------------------- the paper's protocol
# Table 1 cell by cell (scripts/paper-table1.sh): each range calibrated and
# validated on its own, 1000 units = 50 groups of twenty; and sunmc's
# default mode grouped the same way.
s1() {
  local id=$1; shift
  SUNMC=$SUNMC bash scripts/paper-table1.sh "$@" $R/$id >$R/$id.tsv 2>/dev/null || { echo "claims: $id failed: paper-table1.sh $*" >&2; exit 1; }
  echo "bash scripts/paper-table1.sh $* runs/claims/$id > runs/claims/$id.tsv   # $id" >>"$cmds"
}
s1 table1_paper 1000
s1 table1_default --default 1000
# cell TSV TYPE RANGE CELL: "median p5 p95 in"
cell() { awk -F'\t' -v t="$2" -v r="$3" -v c="$4" '$1 == t && $2 == r && $3 == c { print $5, $6, $7, $10 }' "$1"; }
hits() { awk -F'\t' -v t="$2" '$1 == t && $10 == "yes" { n++ } END { print n + 0 }' "$1"; }
misses() { awk -F'\t' -v t="$2" '$1 == t && $10 == "no" { sub(/^\+-/, "±", $2); sub(/improvement_/, "improvement ", $3); sub(/after_/, "after ", $3)
  printf "%s%s %s %s [%s, %s]", (n++ ? "; " : ""), $2, $3, $5, $6, $7 } END { print "" }' "$1"; }
ha=$(hits $R/table1_paper.tsv A); hb=$(hits $R/table1_paper.tsv B)
da=$(hits $R/table1_default.tsv A); db=$(hits $R/table1_default.tsv B)
fails=$(awk -F'\t' 'NR > 1 { s += $9 } END { print s + 0 }' $R/table1_paper.tsv)
need T12 "$ha >= 9 && $ha > $da && $fails == 0"
row T12 "ESS Table 1, type A, every cell" "after max, min; improvement mean, max, min, in each of ±30°, 30-60°, ±62°: 15 cells" "table below" \
  "paper protocol: $ha of 15 cells inside the 5-95 % range of fifty 20-unit groups (default mode: $da); outside: $(misses $R/table1_paper.tsv A)" "table1_paper, table1_default" qualitatively \
  "configs/ess_paper_a.ini: plain least squares, each range calibrated on its own, 0.25° on the grid, ΔH fixed at Table 3's 9.8 µm, a3/a1 from Table 3's k, row noise 2.5 % (docs/papers.md, Table 1 under the paper's protocol).  The paper's ±62° mean improvement (3.94) lies below both of its sub-bands' (4.76, 5.53); sunmc's ±62° range, calibrated on its own, fits nearly as well as its parts (after max $(first "$(cell $R/table1_paper.tsv A +-62 after_max)")° against the paper's 0.0245°), so its improvement lies between theirs: the paper's ±62° units are fitted worse at the field's edge than any modelled deviation makes them"
need T13 "$hb >= 6 && $hb >= $db && $fails == 0"
row T13 "ESS Table 1, type B, every cell" "the same 15 cells for type B" "table below" \
  "paper protocol: $hb of 15 cells inside the range (default mode: $db); outside: $(misses $R/table1_paper.tsv B)" "table1_paper, table1_default" qualitatively \
  "configs/ess_paper_b.ini: as type A, ΔH normal with σ 10 µm (Table 4's 15.3 µm at 1.5σ, Table 2's type-B before needs units near 0), Table 4's k by the 46 µm slit, row noise 1.5 %; the improvement's spread is wider than the paper's: a normal ΔH draws some units near 0 (little to remove: a low minimum) and some far out (a high maximum); a narrower spread of ΔH misses Table 2's type-B before instead"

# Table 2 under the paper's protocol, on the grid and off it (the shipped
# validation grid), and the per-unit change of the before with the step.
for t in a b; do
  for s in 1 0.25; do
    id=${s/./p}
    c ${t}_pp_on_$id run configs/ess_paper_$t.ini --units 100 --seed 1 --set report.bands_deg=0:62 --set campaign.alpha_step_deg=$s --set validation.alpha_step_deg=$s
    c ${t}_pp_off_$id run configs/ess_paper_$t.ini --units 100 --seed 1 --set report.bands_deg=0:62 --set campaign.alpha_step_deg=$s --set validation.alpha_step_deg=0.13 --set validation.alpha_offset_deg=0.05 --set validation.beta_deg=-25,-10,10,25
  done
done
# fall DIR1 DIR025 RATIO: per unit before(1°)/before(0.25°): share > 1, share >= RATIO, min, max
fall() { awk -F'\t' -v rt="$3" 'FNR == 1 { f++; for (i = 1; i <= NF; i++) if ($i == "rms_before_alpha_0_62_deg") c = i; next }
  f == 1 { b[$1] = $c; next } ($1 in b) { r = b[$1] / $c; n++; if (r > 1) u++; if (r >= rt) w++; if (n == 1 || r < lo) lo = r; if (r > hi) hi = r }
  END { printf "%.0f %.0f %.2f %.2f\n", 100 * u / n, 100 * w / n, lo, hi }' "$1/units.tsv" "$2/units.tsv"; }
fa=$(fall $R/a_pp_on_1 $R/a_pp_on_0p25 1.348); fb=$(fall $R/b_pp_on_1 $R/b_pp_on_0p25 1.047)
need T14 "$(first "$fa") > 20 && $(first "$fa") < 80 && $(first "$fa" 2) < 5 && $(first "$fb" 2) > 10"
row T14 "ESS Table 2, the paper's protocol" "before and after at 1° and 0.25°, and the before falls with the step (A 0.0399° → 0.0296°, B 0.020° → 0.0191°)" "A 0.0399 → 0.0141, 0.0296 → 0.0102; B 0.020 → 0.007, 0.0191 → 0.0056" \
  "on the grid: A 1°: $(t2 a_pp_on_1)°, 0.25°: $(t2 a_pp_on_0p25)°; B 1°: $(t2 b_pp_on_1)°, 0.25°: $(t2 b_pp_on_0p25)°; off it: A $(t2 a_pp_off_1)°, $(t2 a_pp_off_0p25)°; B $(t2 b_pp_off_1)°, $(t2 b_pp_off_0p25)°.  Per unit, before(1°)/before(0.25°) on the grid: A $(first "$fa" 3)-$(first "$fa" 4), above 1 for $(first "$fa") %, at the paper's 1.35 for $(first "$fa" 2) %; B $(first "$fb" 3)-$(first "$fb" 4), at the paper's 1.05 for $(first "$fb" 2) %" \
  "a_pp_on_*, a_pp_off_*, b_pp_on_*, b_pp_off_*" qualitatively \
  "the after is the paper's size on the grid; the before is ΔH's (Table 3's 9.8 µm makes type A's 0.055°, the paper's Table 2 unit sits lower).  On the grid the before of a unit is the error at the grid's phases of the fine-code terms: at 1° one phase of the 1° and 0.5° terms, at 0.25° four of the 1° term and two of the 0.5° term; so it moves with the step by the unit's harmonic phase, up for about half the units and down for the rest: a fall is one unit's phase, not a trend (type B's 5 % fall is common, type A's 35 % is met by none).  Off the grid 1° aliases the 0.5° term and the after grows"

# Fig. 11's unit against Table 1: type B's ±62° after max "0.157°"
f11=$(cell $R/table1_paper.tsv B +-62 after_max)
need T15 "0.0157 >= $(first "$f11" 2) && 0.0157 <= $(first "$f11" 3) && 0.157 > 5 * $(first "$f11" 3)"
row T15 "ESS Table 1 with Fig. 11" "type B's ±62° after max is 0.157°; Fig. 11's type-B unit ends at 0.0157°" "0.157° (Table 1), 0.0157° (Fig. 11)" \
  "paper protocol, type B ±62° after max over 20-unit groups: $(first "$f11") [$(first "$f11" 2), $(first "$f11" 3)]°" table1_paper reproduced \
  "0.0157° lies in the groups' range and 0.157° ten times beyond it: Table 1's cell is Fig. 11's unit with a dropped zero, the worst of twenty"

# The conclusion: structural errors "major factors" (sec. 7), against the
# fine-code ripple, shares of the mean square before (a_budget)
sb() { awk -F'\t' -v list="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "share_before") k = i; next }
  { n = split(list, L, ","); for (j = 1; j <= n; j++) if ($3 == L[j]) s += $k } END { printf "%.1f", 100 * s }' "$1/budget.tsv"; }
st=$(sb $R/a_budget dH_um,dd_um,dphi_deg,dial_tilt_deg); rp=$(sb $R/a_budget FLOOR,harmonic_phase_deg,slit_width_um)
need C1 "$st < 20 && $rp > 60"
row C1 "ESS 7" "the structural errors, with the fine-code's approximation error, are the major factors that limit the accuracy" "major factors" \
  "type A, shares of the mean square before: structural (ΔH, Δd, Δφ, dial tilt) $st %, the fine-code ripple (the nominal unit's, its phase, the slit width) $rp %" a_budget differs \
  "within the paper's own tolerances (±2 µm, ±1 µm, ±0.01°) the structural errors are a small part; the ripple dominates.  The paper's own units are further out (Tables 3-4's a/d: ΔH of 10-15 µm, row T9), where a height error alone makes 0.03-0.06°: the conclusion fits its units, not its simulated tolerances"

# Sec. 5: the calibration takes several beta lines
c a_beta1_np run $A --units 100 --seed 1 --set calibration.priors=off --set campaign.beta_deg=0 --set report.bands_deg=0:62
o1=$(sm $R/a_beta1_np 0:62 rms_after_mean); o3=$(sm $R/a_run_np 0:62 rms_after_mean); of=$(sm $R/a_beta1_np 0:62 fit_failures)
need S5 "$o1 > $o3 && $o1 < 2 * $o3 && $of == 0"
row S5 "ESS 5" "the calibration data are taken on several β lines (α_i, β_i)" "several lines" \
  "type A, plain least squares, mean RMS after (±62°): one line β = 0 $(f "$o1")°, three lines $(f "$o3")°; fit failures on one line: $of" "a_beta1_np, a_run_np" qualitatively \
  "one line still calibrates (the roll is fixed at its measurement, and the β dependence of eq. 12 is small), a little worse at the validation's β = ±25°: several lines help, they are not needed"

# ---------------------------------------------------------------- DSS
dgrid="--set validation.b_step_deg=2 --set validation.b_offset_deg=0"
c d_dh curve $D --only dh_px=0.2 $dgrid --set noise.s_curve=off
m=$(umax $R/d_dh error_source_alpha_arcsec 0)
dep=$(awk -F'\t' 'NR > 1 { v[$1 "," $2] = $5; a[$1] = 1; b[$2] = 1 } END { for (x in a) for (y in b) if ((x "," y) in v && (x ",0") in v) {
  d = v[x "," y] - v[x ",0"]; if (d < 0) d = -d; if (d > m) m = d } print m }' $R/d_dh/curve.tsv)
e60=$(at $R/d_dh error_source_alpha_arcsec 60 0); e60=${e60#-}
need D1 "$dep < 0.06 * $(first "$m") && ($(first "$m" 2)) ^ 2 >= 1600 && ($(first "$m" 2)) ^ 2 <= 2916 && $e60 < $(first "$m")"
row D1 "DSS Fig. 2" "dh = 0.2 px: α's error depends on α only, rises to a maximum, then falls" "rises, then falls" \
  "$(f "$(first "$m")" 1)″ at \|α\| = $(first "$m" 2 | tr -d -)°, $(f "$e60" 1)″ at 60°; β moves it by at most $(f "$dep" 1)″ (the glass)" d_dh reproduced \
  "the height scales tan α: (dh/h) sin α cos α seen through the glass"
c d_dx curve $D --only dx_px=0.1 $dgrid --set noise.s_curve=off
c d_dx_paper curve $D --only dx_px=0.1 $dgrid --set noise.s_curve=off --set design.principal_point=paper_eq6 --set campaign.mount=aligned
c d_dy_paper curve $D --only dy_px=0.1 $dgrid --set noise.s_curve=off --set design.principal_point=paper_eq6 --set campaign.mount=aligned
pa0=$(at $R/d_dx error_source_alpha_arcsec 0 0); pb=$(umax $R/d_dx error_source_beta_arcsec)
xa0=$(at $R/d_dx_paper error_source_alpha_arcsec 0 0); xa50=$(at $R/d_dx_paper error_source_alpha_arcsec 50 50)
xb50=$(at $R/d_dx_paper error_source_beta_arcsec 50 50)
ya=$(umax $R/d_dy_paper error_source_alpha_arcsec); yb0=$(at $R/d_dy_paper error_source_beta_arcsec 0 0)
yb=$(umax $R/d_dy_paper error_source_beta_arcsec)
need D2 "${pa0#-} > 30 && $(first "$pb") < 1"
row D2 "DSS Fig. 3, physical" "dx moves α and β; dy β only, less at the centre" "both; nil at the centre" \
  "design.principal_point = physical: dx: α $(f "${pa0#-}" 1)″ at the centre, β at most $(f "$(first "$pb")" 2)″" d_dx differs \
  "sunmc's default displaces the pinhole: (d/h) cos², largest at the centre, α only (docs/dss.md)"
need D3 "${xa0#-} < 0.1 && ${xa50#-} > 20 && ${xb50#-} > 20 && $(first "$ya") < 1 && ${yb0#-} < 0.1 && $(first "$yb") > 10"
row D3 "DSS Fig. 3, the paper's eq. 5-6" "dx moves α and β; dy β only, less at the centre than at the edge" "both; nil at the centre" \
  "design.principal_point = paper_eq6: dx: $(f "${xa0#-}" 2)″ at the centre, ($(f "${xa50#-}" 1)″, $(f "${xb50#-}" 1)″) at sun angles (50°, 50°); dy: α at most $(f "$(first "$ya")" 2)″, β $(f "${yb0#-}" 2)″ at the centre, $(f "$(first "$yb")" 1)″ at the edge" \
  "d_dx_paper, d_dy_paper" reproduced \
  "with the paper's own model (S_b0 = (dx, dy, −h) rotated with the table, eq. 9-10): (43.2″, 29.3″) at table angles (±50°, ±50°), tests/test_dss_paper_mode.c"
for k in c1 c2 c3; do
  c d_${k} curve $D --only ${k}_arcsec=10 $dgrid --set noise.s_curve=off --set campaign.mount=aligned
done
c d_c1_mounted curve $D --only c1_arcsec=10 $dgrid --set noise.s_curve=off
cen=0; edge=
for k in c1 c2 c3; do
  for a in alpha beta; do
    v=$(at $R/d_$k error_source_${a}_arcsec 0 0); v=${v#-}; cen=$(awk "BEGIN { print ($v > $cen) ? $v : $cen }")
  done
  ma=$(umax $R/d_$k error_source_alpha_arcsec); mb=$(umax $R/d_$k error_source_beta_arcsec)
  edge="$edge $k $(f "$(awk "BEGIN { print ($(first "$ma") > $(first "$mb")) ? $(first "$ma") : $(first "$mb") }")" 1)″,"
done
mc=$(at $R/d_c1_mounted error_source_beta_arcsec 0 0)
need D4 "$cen < 0.1"
row D4 "DSS Fig. 4" "installation errors of 10″: negligible at the centre, growing toward the edge" "negligible at the centre" \
  "campaign.mount = aligned: at most $(f "$cen" 2)″ at the centre; largest over the ±60° field${edge%,}; as mounted c1 adds $(f "${mc#-}" 1)″ at the centre" \
  "d_c1, d_c2, d_c3, d_c1_mounted" reproduced \
  "with the paper's lab (eq. 6: the table zeroed on the detector normal); as mounted the rotation is an offset everywhere"
c d_glass curve $D --only glass_index=0 $dgrid --set noise.s_curve=off --set design.onboard_refraction=ignored
mono=$(awk -F'\t' 'NR > 1 && $2 == 0 && $1 >= 0 { e[$1] = $3 < 0 ? -$3 : $3 } END { ok = 1; for (a = 2; a <= 60; a += 2) if (e[a] < e[a-2]) ok = 0; print ok, e[60] }' $R/d_glass/curve.tsv)
monb=$(awk -F'\t' 'NR > 1 && $1 == 0 && $2 >= 0 { e[$2] = $6 < 0 ? -$6 : $6 } END { ok = 1; for (b = 2; b <= 60; b += 2) if (e[b] < e[b-2]) ok = 0; print ok, e[60] }' $R/d_glass/curve.tsv)
need D5 "$(first "$mono") == 1 && $(first "$monb") == 1"
row D5 "DSS Fig. 5" "refraction: α's error grows with \|α\| at fixed β, β's with \|β\| at fixed α" "grows" \
  "monotone in \|α\| (β = 0) to $(f "$(first "$mono" 2)" 0)″ at 60°, in \|β\| (α = 0) to $(f "$(first "$monb" 2)" 0)″" d_glass reproduced \
  "Snell's law through 0.4 mm of glass, n = 1.52, which the paper's eq. 9-10 ignore"
c d_phys run $D --units 100 --seed 1 --set campaign.mount=aligned --set design.onboard_refraction=ignored
c d_poly run $D --units 100 --seed 1 --set campaign.mount=aligned --set design.onboard_refraction=ignored --set calibration.model=polynomial --set calibration.poly_order=3
c d_poly7 run $D --units 100 --seed 1 --set campaign.mount=aligned --set design.onboard_refraction=ignored --set calibration.model=polynomial --set calibration.poly_order=7
pp=$(sm $R/d_phys 0:60 rms_after_mean); pq=$(sm $R/d_poly 0:60 rms_after_mean); p0=$(sm $R/d_phys 0:60 rms_before_mean)
p7=$(sm $R/d_poly7 0:60 rms_after_mean)
need D6 "$pq > 10 * $pp && $p7 < 2 * $pp && $p7 > $pp"
row D6 "DSS 3, 4" "errors of the sources are coupled; polynomial fitting, which ignores refraction, cannot uncover them; all sources must be calibrated" "qualitative" \
  "mean RMS of α: $(f "$p0" 0)″ before; after: physical model $(f "$pp" 2)″, polynomial order 3 $(f "$pq" 0)″, order 7 $(f "$p7" 2)″" "d_phys, d_poly, d_poly7" qualitatively \
  "the on-board formula of the paper leaves the glass's refraction; order 3 cannot fit it, but order 7 comes within $(f "$(awk "BEGIN { print $p7 / $pp }")" 2) times of the physical model: the polynomial's limit is its order, and the physical model is better, not the only one that works"

# Fig. 4: "the pattern of alpha's error by c1 is similar to beta's by c2,
# alpha's by c2 to beta's by c1, alpha's by c3 to beta's by c3": the
# correlation of the two error maps over the grid, at the same point and
# with the axes swapped (alpha, beta) -> (beta, alpha)
corr() { awk -F'\t' -v tr="$3" 'FNR == 1 { f++; next } f == 1 { x[$1 "," $2] = $5; next }
  { k = tr ? $2 "," $1 : $1 "," $2; if (k in x) { u = x[k]; v = $8; n++; su += u; sv += v; suu += u * u; svv += v * v; suv += u * v } }
  END { printf "%.2f", (suv / n - su * sv / n / n) / sqrt((suu / n - (su / n) ^ 2) * (svv / n - (sv / n) ^ 2)) }' "$1/curve.tsv" "$2/curve.tsv"; }
r12=$(corr $R/d_c1 $R/d_c2 0); r12s=$(corr $R/d_c1 $R/d_c2 1); r21=$(corr $R/d_c2 $R/d_c1 0); r21s=$(corr $R/d_c2 $R/d_c1 1)
r33=$(corr $R/d_c3 $R/d_c3 0); r33s=$(corr $R/d_c3 $R/d_c3 1)
need D7 "$r12 > 0.9 && ($r21s > 0.9 || $r21s < -0.9) && ($r33s > 0.99 || $r33s < -0.99) && $r21 < 0.9 && $r21 > -0.9"
row D7 "DSS Fig. 4" "α's error pattern by c1 is like β's by c2, α's by c2 like β's by c1, α's by c3 like β's by c3" "similar patterns" \
  "correlation of the two maps over the ±60° grid, same point (axes swapped): α(c1)~β(c2) $r12 ($r12s), α(c2)~β(c1) $r21 ($r21s), α(c3)~β(c3) $r33 ($r33s)" "d_c1, d_c2, d_c3" qualitatively \
  "each pair is alike, but not by one mapping: c1/c2 at the same point, c2/c1 and c3 with α and β swapped (and c2/c1, c3 with the opposite sign): the paper's pairs are likenesses of shape, not one symmetry of the maps"

# Fig. 2: "dh is applied to both incident angles with the same tendency":
# beta's error against beta at alpha = 0, and how alpha moves it
bt=$(awk -F'\t' 'NR > 1 && $1 == 0 { v = $8 < 0 ? -$8 : $8; if (v > m) { m = v; b = $2 < 0 ? -$2 : $2 } if ($2 == 60) e = v }
  NR > 1 { w[$2] = w[$2] " " $8 } END { print m, b, e }' $R/d_dh/curve.tsv)
bdep=$(awk -F'\t' 'NR > 1 { v[$1 "," $2] = $8; a[$1] = 1; b[$2] = 1 } END { for (x in a) for (y in b) if ((x "," y) in v && ("0," y) in v) {
  d = v[x "," y] - v["0," y]; if (d < 0) d = -d; if (d > m) m = d } print m }' $R/d_dh/curve.tsv)
need D8 "($(first "$bt" 2)) ^ 2 >= 1600 && ($(first "$bt" 2)) ^ 2 <= 2916 && $(first "$bt" 3) < $(first "$bt") && $bdep < 0.06 * $(first "$bt")"
row D8 "DSS Fig. 2" "dh moves both angles with the same tendency (β's error rises, then falls, with \|β\|)" "the same tendency" \
  "β's error at α = 0: $(f "$(first "$bt")" 1)″ at \|β\| = $(first "$bt" 2)°, $(f "$(first "$bt" 3)" 1)″ at 60°; α moves it by at most $(f "$bdep" 1)″ (the glass)" d_dh reproduced \
  "β's error is α's mirrored (row D1): it depends on β alone and rises to its peak near 45°, then falls"

# Eq. 1 as printed: the zxy rotation matrix C10 at (10°, 20°, 30°)
orth=$(awk 'BEGIN { d = atan2(0, -1) / 180; s1 = sin(10 * d); c1 = cos(10 * d); s2 = sin(20 * d); c2 = cos(20 * d); s3 = sin(30 * d); c3 = cos(30 * d)
  m[1,1] = c2 * c3 - s1 * s2 * s3; m[1,2] = -c2 * s3 + s1 * s2 * c3; m[1,3] = c1 * s2
  m[2,1] = c1 * s3; m[2,2] = c1 * c3; m[2,3] = -s1
  m[3,1] = s1 * c2 + s1 * c2 * s3; m[3,2] = s2 * s3 - s1 * c2 * c3; m[3,3] = c1 * c2
  for (i = 1; i <= 3; i++) for (j = 1; j <= 3; j++) { g = -(i == j); for (k = 1; k <= 3; k++) g += m[i,k] * m[j,k]; if (g < 0) g = -g; if (g > e) e = g }
  # with m[1,2] = -c2 s3 ... kept, the entries (1,1), (3,1) corrected to c2 c3 + s1 s2 s3, s2 c3 - s1 c2 s3 (and (1,2), (3,2) to match)
  n[1,1] = c2 * c3 + s1 * s2 * s3; n[1,2] = -c2 * s3 + s1 * s2 * c3; n[1,3] = c1 * s2
  n[2,1] = c1 * s3; n[2,2] = c1 * c3; n[2,3] = -s1
  n[3,1] = -s2 * c3 + s1 * c2 * s3; n[3,2] = s2 * s3 + s1 * c2 * c3; n[3,3] = c1 * c2
  for (i = 1; i <= 3; i++) for (j = 1; j <= 3; j++) { g = -(i == j); for (k = 1; k <= 3; k++) g += n[i,k] * n[j,k]; if (g < 0) g = -g; if (g > f) f = g }
  printf "%.3f %.1e\n", e, f }')
need D9 "$(first "$orth") > 0.05 && $(first "$orth" 2) < 1e-12"
row D9 "DSS eq. 1" "the zxy rotation matrix C10" "as printed" \
  "printed, at (θ1, θ2, θ3) = (10°, 20°, 30°): \|C C^T − I\| up to $(first "$orth"); with (1,1) = C2C3 + S1S2S3, (3,1) = −S2C3 + S1C2S3, (3,2) = S2S3 + S1C2C3: $(first "$orth" 2)" scripts/claims.sh differs \
  "the printed matrix is not a rotation (three entries carry typos); sunmc builds the zxy rotation from its three factors (util/rotation.c, one passive convention; tests/unit/dss/test_dss_geometry.c checks it orthonormal)"

# Eq. 3-4 from eq. 2: the spot of the ray S through the pinhole at height h
# lies at -h (Sx/Sz, Sy/Sz); the angles it reads are atan(x/h), atan(y/h)
e34=$(awk 'BEGIN { d = atan2(0, -1) / 180
  for (b1 = -60; b1 <= 60; b1 += 5) for (b2 = -60; b2 <= 60; b2 += 5) { sx = cos(b1 * d) * sin(b2 * d); sy = -sin(b1 * d); sz = cos(b1 * d) * cos(b2 * d)
    a = atan2(-sx / sz, 1); b = atan2(-sy / sz, 1); a0 = -b2 * d; t = sin(b1 * d) / cos(b1 * d) / cos(b2 * d); b0 = atan2(t, 1)
    e = a - a0; if (e < 0) e = -e; if (e > m) m = e; e = b - b0; if (e < 0) e = -e; if (e > m) m = e }
  printf "%.1e\n", m }')
need D10 "$e34 < 1e-12"
row D10 "DSS eq. 2-4" "the table's (b1, b2) give the sun angles α0 = −b2, β0 = atan(tan b1 / cos b2)" "eq. 3-4" \
  "eq. 2's ray through the pinhole, read from its spot (atan(x/h), atan(y/h)), over b1, b2 in ±60°: eq. 3-4 to $e34 rad" scripts/claims.sh reproduced \
  "eq. 3-4 are exact, with the angles read from the spot (which moves against the ray: hence −b2); sunmc's table truth is these two formulas (util/rotation.c)"

# ---------------------------------------------------------------- write
nr=$(grep -c '^reproduced$' "$rows.v" || true); nq=$(grep -c '^qualitatively$' "$rows.v" || true)
nd=$(grep -c '^differs$' "$rows.v" || true); rm -f "$rows.v"
[ "$bad" -eq 0 ] || { echo "claims: $OUTMD not written: fix the rows above (their reason or sunmc)" >&2; exit 1; }
{
cat <<EOF
# The papers' claims, one by one

Generated by \`make claims\` (\`scripts/claims.sh\`): every number in the
sunmc column was read from the files the row's command wrote, and every
verdict rests on a condition on those numbers that the script checks: when
a change to sunmc breaks one, \`make claims\` fails naming the row instead
of writing this page.  Do not edit it by hand: \`make test\`
(tests/cli/test_claims_current.c) regenerates it and fails when the
committed page differs.  The papers:
[papers.md](papers.md) (where sunmc and the papers differ, and why), ESS =
Fan et al. 2013, DSS = Wei et al.

**$n rows: $nr reproduced, $nq qualitatively, $nd differ.**  Reproduced: the
number or the shape the paper states, under the paper's protocol where the
row says so; qualitatively: the trend or the size, not the value, or the
value for another reason than the paper's; differs: sunmc's physics gives
something else, and the reason says why.

| # | paper, where | claim | paper's value | sunmc's value | command | verdict |
|---|---|---|---|---|---|---|
EOF
cat "$rows"
cat <<EOF

## ESS Table 1 cell by cell

Each cell: the median over fifty groups of twenty units (1000 units, seed
1) and its 5-95 % range over the groups, under the paper's protocol
(\`configs/ess_paper_a.ini\`, \`configs/ess_paper_b.ini\`, each range
calibrated and validated on its own: \`scripts/paper-table1.sh\`) and in
sunmc's default mode (the shipped configs: priors on, one calibration over
the field); **in**: the paper's value lies in the range.  Rows T12, T13;
the inputs and their derivations: [papers.md](papers.md#table-1-under-the-papers-protocol).

| type | range | cell | paper | paper protocol | in | default mode | in |
|---|---|---|---|---|---|---|---|
EOF
paste $R/table1_paper.tsv $R/table1_default.tsv | awk -F'\t' 'NR > 1 { r = $2; sub(/^\+-/, "±", r); c = $3; sub(/_/, " ", c)
  printf "| %s | %s | %s | %s | %s [%s, %s] | %s | %s [%s, %s] | %s |\n", $1, r, c, $4, $5, $6, $7, $10, $15, $16, $17, $20 }'
cat <<EOF

The commands (each writes runs/claims/ID; \`make claims\` runs them all and
checks every row, in about half a minute):

\`\`\`
EOF
cat "$cmds"
echo '```'
} >"$OUTMD"
echo "claims: $n rows ($nr reproduced, $nq qualitatively, $nd differ) -> $OUTMD" >&2
