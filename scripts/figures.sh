#!/usr/bin/env bash
# figures.sh - regenerate the papers' figures from scratch into build/figures/
# (make figures).  Each figure's data are kept in build/figures/data/NAME/.
#
# ESS paper (Fan et al. 2013):
#   ess_fig3_dH.png      error caused by dH = +-2 um alone, type A        (Fig. 3)
#   ess_fig5_dd.png      error caused by dd = +-1 um alone                (Fig. 5)
#   ess_fig6_dphi.png    error caused by dphi = +-0.01 deg alone          (Fig. 6)
#   ess_fig6_dphi_pivot.png  the same, the tilt pivoting at the fine rows (Fig. 6)
#   ess_fig7_dphi_0p5.png  the same sampled every 0.5 deg: the 1-deg period (Fig. 7)
#   ess_fig11a_typeB.png one type-B unit before/after, every beta         (Fig. 11a)
#   ess_fig11a_typeB_zoom.png  the same over alpha 0-6 deg: the ripple as lines
#   ess_fig11b_typeB.png the same unit, two representative betas, 40-50 deg (Fig. 11b)
#   ess_table2_step_A.png, ess_table2_step_B.png  campaign step sweep     (Table 2)
#   ess_budget_A.png, ess_yield_A.png, ess_hist_A.png  budget, yield, improvement
# DSS paper (Wei et al.), when the dss family offers curves:
#   dss_fig2_dh.png, dss_fig3_dx.png, dss_fig3_dy.png (physical), dss_fig3_d[xy]_paper.png (paper_eq6), dss_fig4_c1..c3.png,
#   dss_fig5_refraction.png, dss_unit3_after.png   error maps over (alpha, beta)
#
# Figs. 3, 5-7 isolate one geometric error as the paper's section 3 does: every
# other tolerance 0 and an ideal fine code (pure sinusoid: design.harmonics =
# given, a3 = a5 = 0), so the curve is the error that deviation alone causes.
# Unit counts are small (the machine is shared); SUNMC and UNITS override.
set -eu
cd "$(dirname "$0")/.."
SUNMC=${SUNMC:-build/sunmc}
UNITS=${UNITS:-150}
out=build/figures
data=$out/data
rm -rf "$out"
mkdir -p "$data"
q=--quiet
n=0
say() { n=$((n + 1)); echo "figures: [$n] $1" >&2; }
A=configs/ess_type_a.ini
B=configs/ess_type_b.ini
ideal="--set design.harmonics=given --set design.a3_ratio=0 --set design.a5_ratio=0"
fine="--set validation.alpha_offset_deg=0 --set validation.beta_deg=0"

pair() { # NAME KEY VALUE STEP_DEG TITLE [--set ...]
  local name=$1 key=$2 v=$3 step=$4 title=$5
  shift 5
  say "$name.png ($key = +-$v)"
  "$SUNMC" curve $A --only "$key=$v" $ideal $fine --set validation.alpha_step_deg=$step "$@" \
    --out $data/${name}_plus $q >/dev/null
  "$SUNMC" curve $A --only "$key=-$v" $ideal $fine --set validation.alpha_step_deg=$step "$@" \
    --out $data/${name}_minus $q >/dev/null
  gnuplot -e "run='$data/${name}_plus'; run2='$data/${name}_minus'; what='source'; \
    label='$key = +$v, '; label2='$key = -$v, '; title=\"$title\"; out='$out/$name.png'" \
    scripts/curve.gp
}
pair ess_fig3_dH dH_um 2 0.05 "ESS paper Fig. 3: error caused by dH = +-2 um (type A, H = 4.124 mm)\\nsunmc: peak 0.0139 deg at 45 deg = dH/2H, not the paper's > 0.015 deg"
pair ess_fig5_dd dd_um 1 0.05 "ESS paper Fig. 5: error caused by the slit offset dd = +-1 um (type A)\\nsunmc: -(dd/H) cos^2(alpha), largest at 0 deg, where the paper says it grows"
pair ess_fig6_dphi dphi_deg 0.01 0.05 "ESS paper Fig. 6: slit tilt dphi = +-0.01 deg, type A, beta = 0, tilt pivot x = 0 (default)\\nmean: fine rows (0.6-2.4 mm) read 1.5 mm tan(dphi) off; band: their alternation"
pair ess_fig6_dphi_pivot dphi_deg 0.01 0.05 "ESS paper Fig. 6, tilt pivot at the fine rows' centre (tilt_pivot_mm = 1.5), beta = 0\\nonly their alternation is left: < 0.005 deg as the paper says, falling with incidence" \
  --set design.tilt_pivot_mm=1.5
pair ess_fig7_dphi_0p5 dphi_deg 0.01 0.5 "ESS paper Fig. 7: dphi = +-0.01 deg sampled every 0.5 deg: a 1-deg period"
say "ess_fig7_dphi_0p5_zoom.png (0 to 10 deg)"
gnuplot -e "run='$data/ess_fig7_dphi_0p5_plus'; run2='$data/ess_fig7_dphi_0p5_minus'; what='source'; xmin=0; xmax=10; \
  label='dphi_deg = +0.01, '; label2='dphi_deg = -0.01, '; out='$out/ess_fig7_dphi_0p5_zoom.png'; \
  title='ESS paper Fig. 7 zoomed on 0 to 10 deg: the error alternates sample to sample, a 1-deg period'" scripts/curve.gp

# Fig. 11: one type-B unit (the unit of the largest error before of the
# first 40), before and after its own calibration, at the paper's size.
# With the shipped derived harmonics this unit goes only 0.027 -> 0.0067
# deg (its error before is mostly the fine-code ripple, which the
# tolerances barely move).  A given third harmonic a3/a1 = -0.24 makes the
# ripple the paper's size: 0.055 -> 0.015 deg RMS where the paper's unit
# goes 0.0635 -> 0.0157.  -0.245 is about the largest the model's
# fine-code term can undo on the shipped 0.7-deg campaign: at -0.25 its
# fitted amplitude k reaches 1/omega (0.08 deg), the term has no inverse
# and curve flags every point.
U=32
paper="--set design.harmonics=given --set design.a3_ratio=-0.24 --set design.a5_ratio=0"
f11="ESS paper Fig. 11(a): type-B unit $U before and after compensation, every beta\\n"
f11="${f11}sunmc: given a3/a1 = -0.24 (shipped: derived, 0.027 -> 0.0067 deg) for a ripple of the paper's size (0.0635 -> 0.0157 deg)"
say "ess_fig11a_typeB.png (unit $U, six beta, a3/a1 = -0.24)"
"$SUNMC" curve $B --unit $U $paper --set validation.alpha_step_deg=0.05 --set validation.alpha_offset_deg=0 \
  --set "validation.beta_deg=-25,-15,-5,5,15,25" --out $data/ess_fig11a $q >/dev/null
gnuplot -e "run='$data/ess_fig11a'; title=\"$f11\"; out='$out/ess_fig11a_typeB.png'" scripts/curve.gp
# Over 124 deg the 0.5-deg ripple fills the band solid: 6 deg of it show it as lines.
say "ess_fig11a_typeB_zoom.png (alpha 0 to 6 deg)"
gnuplot -e "run='$data/ess_fig11a'; xmin=0; xmax=6; out='$out/ess_fig11a_typeB_zoom.png'; \
  title=\"ESS paper Fig. 11(a) zoomed on alpha 0 to 6 deg: the 0.5-deg fine-code ripple of each beta line\\nbefore: the ripple and the structural error; after: what eq. 9's single term leaves (a3/a1 = -0.24, docs/papers.md)\"" scripts/curve.gp
say "ess_fig11b_typeB.png (unit $U, two beta, a3/a1 = -0.24)"
"$SUNMC" curve $B --unit $U $paper --set validation.alpha_step_deg=0.05 --set validation.alpha_offset_deg=0 \
  --set "validation.beta_deg=-25,25" --out $data/ess_fig11b $q >/dev/null
gnuplot -e "run='$data/ess_fig11b'; xmin=40; xmax=50; title=\"ESS paper Fig. 11(b): type-B unit $U, two representative beta, alpha 40 to 50 deg (the ripple as lines)\\nsunmc: given a3/a1 = -0.24 for a unit of the paper's size (docs/papers.md)\"; \
  out='$out/ess_fig11b_typeB.png'" scripts/curve.gp

# Table 2: the campaign's alpha step (common random numbers).
for t in A B; do
  cfg=configs/ess_type_$(echo $t | tr AB ab).ini
  say "ess_table2_step_$t.png (campaign step sweep, $UNITS units)"
  "$SUNMC" sweep $cfg --vary campaign.alpha_step_deg=1,0.8,0.7,0.5,0.3,0.25,0.2 --units $UNITS \
    --out $data/ess_table2_$t $q >/dev/null
  gnuplot -e "run='$data/ess_table2_$t'; out='$out/ess_table2_step_$t.png'; \
    note=\"ESS paper Table 2 (black: the paper, validated on its calibration grid); sunmc validated off the grid:\\ncrosses = steps that alias the 0.5-deg fine-code term, worse between the campaign points (docs/ess.md)\"" scripts/sweep.gp
done

# Budget, yield and improvement histogram of type A.
say "ess_budget_A.png (error budget)"
"$SUNMC" budget $A --units $UNITS --set report.budget_units=50 --set report.budget_steps=3 \
  --out $data/ess_budget_A $q >/dev/null
gnuplot -e "run='$data/ess_budget_A'; out='$out/ess_budget_A.png'" scripts/budget.gp
say "ess_yield_A.png, ess_hist_A.png ($((UNITS * 2)) units)"
"$SUNMC" run $A --units $((UNITS * 2)) --out $data/ess_run_A $q >/dev/null
gnuplot -e "run='$data/ess_run_A'; out='$out/ess_yield_A.png'" scripts/yield.gp
gnuplot -e "run='$data/ess_run_A'; out='$out/ess_hist_A.png'" scripts/hist.gp

# DSS maps (Figs. 2-5) over the sun angles (alpha, beta), every 2 deg: the
# error each source alone adds to the nominal design (error_source).
D=configs/dss.ini
grid="--set validation.b_step_deg=2 --set validation.b_offset_deg=0"
say "dss_fig2_dh.png (dh = 0.2 px)"
if [ -f $D ] && "$SUNMC" curve $D --only dh_px=0.2 $grid --out $data/dss_fig2_dh $q >/dev/null 2>&1; then
  gnuplot -e "run='$data/dss_fig2_dh'; cut=1; out='$out/dss_fig2_dh.png'; \
    title=\"DSS paper Fig. 2: error caused by dh = 0.2 pixel alone (alpha error depends on alpha only)\\nit rises to about 42 arcsec near 47 deg and falls beyond: the line cuts show the shape\"" scripts/map.gp
  # Fig. 3 both ways (design.principal_point): physical = the pinhole
  # displaced, sunmc's default; paper_eq6 = the paper's eq. 5-6 literally.
  # Fig. 4 with campaign.mount = aligned, the paper's eq. 6.
  for s in dx_px=0.1:fig3_dx:3 dy_px=0.1:fig3_dy:3 dx_px=0.1:fig3_dx_paper:3 dy_px=0.1:fig3_dy_paper:3 \
           c1_arcsec=10:fig4_c1:4 c2_arcsec=10:fig4_c2:4 c3_arcsec=10:fig4_c3:4; do
    kv=${s%%:*}; rest=${s#*:}; name=dss_${rest%%:*}; fig=${rest##*:}
    say "$name.png ($kv)"
    note=; extra=
    case $name in
      *dx_paper) extra="--set design.principal_point=paper_eq6 --set campaign.mount=aligned"
        note="\\npaper_eq6 (the paper's eq. 5-6 literally: S_b0 = (dx, dy, -h) rotated with the table): nil at the centre, alpha and beta both err" ;;
      *dy_paper) extra="--set design.principal_point=paper_eq6 --set campaign.mount=aligned"
        note="\\npaper_eq6 (the paper's eq. 5-6 literally: S_b0 = (dx, dy, -h) rotated with the table): beta only, nil at the centre" ;;
      *fig3_dx) note="\\nphysical (sunmc's default: the pinhole displaced): dx moves alpha (beta under 0.5 arcsec), largest at the centre" ;;
      *fig3_dy) note="\\nphysical (sunmc's default: the pinhole displaced): dy moves beta (alpha under 0.5 arcsec), largest at the centre" ;;
      *fig4_*) extra="--set campaign.mount=aligned"
        note="\\ncampaign.mount = aligned (the paper's eq. 6: the sun normal to the detector at table zero): nil at the centre" ;;
    esac
    "$SUNMC" curve $D --only $kv $extra $grid --out $data/$name $q >/dev/null
    gnuplot -e "run='$data/$name'; out='$out/$name.png'; title=\"DSS paper Fig. $fig: error caused by $kv alone$note\"" scripts/map.gp
  done
  # Fig. 5, refraction: the on-board formula ignores the cover glass, so the
  # nominal unit's error before calibration is the refraction error itself
  # (S-curve off so that nothing else is in it).
  say "dss_fig5_refraction.png (cover glass)"
  "$SUNMC" curve $D --only glass_index=0 $grid --set noise.s_curve=off --set design.onboard_refraction=ignored --out $data/dss_fig5_refraction $q >/dev/null
  gnuplot -e "run='$data/dss_fig5_refraction'; what='before'; cut=1; out='$out/dss_fig5_refraction.png'; title='DSS paper Fig. 5: refraction error of the nominal design (0.4 mm glass, n = 1.52; on-board formula ignores it)'" scripts/map.gp
  # One Monte Carlo unit before and after its own calibration.
  say "dss_unit3_after.png (one unit after calibration)"
  "$SUNMC" curve $D --unit 3 $grid --out $data/dss_unit3 $q >/dev/null
  gnuplot -e "run='$data/dss_unit3'; what='after'; out='$out/dss_unit3_after.png'; \
    title=\"DSS unit 3 after its own calibration, noiseless validation readings (each panel's range in its title)\\nthe moire is the pixel S-curve (period one pixel, not modelled by the calibration) sampled on the 2-deg grid: a real residual, aliased by the grid\"" scripts/map.gp
else
  echo "figures.sh: the dss family draws no curves yet: DSS Figs. 2-5 skipped" >&2
fi
echo "figures: done: $(ls "$out"/*.png | wc -l) figures in $out" >&2
ls "$out"/*.png
