#!/usr/bin/env bash
# plots.sh RUN [svg] - draw every figure a run directory holds, next to its data:
#   summary.tsv + units.tsv (sunmc run)  -> yield.png, hist.png, convergence.png
#   sweep.tsv   (sunmc sweep)            -> sweep.png
#   budget.tsv  (sunmc budget)           -> budget.png
#   sensitivity.tsv (sunmc sensitivity)  -> sensitivity.png
#   curve.tsv   (sunmc curve)            -> curve.png + curve_source.png (one measured
#                                           angle: ESS) or map_{before,after,source}.png
#   residuals.tsv (sunmc calibrate, ESS or DSS) -> calib.png (residuals; ESS: field.tsv's
#                                           predicted sigma too)
# Pass "svg" as the second argument for SVG instead of PNG.
set -eu
run=${1:?usage: plots.sh RUN_DIR [svg]}
svg=0
[ "${2:-}" = svg ] && svg=1
dir=$(cd "$(dirname "$0")" && pwd)
[ -d "$run" ] || { echo "plots.sh: $run is not a directory" >&2; exit 2; }
gp() { gnuplot -e "run='$run'; svg=$svg" "$@"; }
drew=0
if [ -f "$run/units.tsv" ] && [ -f "$run/summary.tsv" ]; then
  gp "$dir/yield.gp"; gp "$dir/hist.gp"; gp "$dir/convergence.gp"; drew=1
fi
if [ -f "$run/sweep.tsv" ]; then gp "$dir/sweep.gp"; drew=1; fi
if [ -f "$run/budget.tsv" ]; then gp "$dir/budget.gp"; drew=1; fi
if [ -f "$run/design.tsv" ]; then gp "$dir/design.gp"; drew=1; fi
if [ -f "$run/sensitivity.tsv" ]; then gp "$dir/sensitivity.gp"; drew=1; fi
if [ -f "$run/curve.tsv" ]; then
  n=$(head -1 "$run/curve.tsv" | tr '\t' '\n' | grep -c '^error_before_')
  if [ "$n" -eq 1 ]; then
    gp "$dir/curve.gp"; gp -e "what='source'" "$dir/curve.gp"
  else
    for w in before after source; do gp -e "what='$w'" "$dir/map.gp"; done
  fi
  drew=1
fi
if [ -f "$run/residuals.tsv" ]; then
  if head -1 "$run/residuals.tsv" | tr '\t' '\n' | grep -qx 'residual_arcsec\|alpha_error_arcsec'; then
    gp "$dir/calib.gp"; drew=1
  else
    echo "plots.sh: $run/residuals.tsv: no figure for this family's calibration" >&2
  fi
fi
[ "$drew" -eq 1 ] || { echo "plots.sh: nothing to draw in $run" >&2; exit 2; }
ls "$run"/*.png "$run"/*.svg 2>/dev/null || true
