# calib.gp - a lab calibration from `sunmc calibrate --out RUN`: what the fit
# left, reading by reading (residuals.tsv, rows of weight 0 left out), and
# for the ESS the accuracy the fit predicts across the field (field.tsv).
#   ESS: top, the fit's residual (model - reading) against alpha, one colour
#        per beta line; bottom, the propagated 1-sigma error against alpha
#   DSS, PSD: the alpha and beta errors after calibration against alpha and beta
#   gnuplot -e "run='runs/cal'" scripts/calib.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/residuals.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/calib.svg' : '/calib.png')
hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
ess = col('residual_arcsec') > 0
if (svg) { set terminal svg size 1000,800 dynamic font 'Sans,12' } else { set terminal pngcairo size 1000,800 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"
cw = col('weight')
used(cond) = sprintf("< awk -F'\\t' 'NR>1 && $%d > 0 %s' '%s'", cw, cond, file)
pv(k) = system(sprintf("awk '/^%s = / {sub(/^%s = /, \"\"); sub(/  #.*$/, \"\"); v = $0} END {print v}' '%s/params.ini' 2>/dev/null", k, k, run))
data = pv('data_file')
nrow = int(system(sprintf("awk -F'\\t' 'NR>1 && $%d > 0' '%s' | wc -l", cw, file)))
set grid
set xzeroaxis
if (ess) {
  cr = col('residual_arcsec'); ca = col('alpha_deg'); cb = col('beta_deg')
  lines = system(sprintf("awk -F'\\t' 'NR>1 && $%d > 0 && !s[$%d]++ {printf \"%%s \", $%d}' '%s'", cw, cb, cb, file))
  stats used('') using cr nooutput
  rms = sqrt(STATS_sumsq / STATS_records)
  hasfield = system(sprintf("test -f '%s/field.tsv' && echo 1 || echo 0", run)) eq '1'
  set multiplot layout 1 + hasfield, 1 title sprintf("ESS calibration of %s (%d readings): what the fit left and what it predicts", data, nrow)
  # both panels the same width, the legends right of them in the margin
  set lmargin at screen 0.09
  set rmargin at screen 0.80
  set title sprintf('fit residual (model - reading): RMS %.3g arcsec', rms)
  set xlabel 'alpha [deg] (table, inner frame)'
  set ylabel 'residual [arcsec]'
  set key outside right top
  plot for [i=1:words(lines)] used(sprintf("&& $%d == %s", cb, word(lines, i))) using ca:cr with points pt 7 ps 0.4 lc i title sprintf('beta = %s deg', word(lines, i))
  if (hasfield) {
    ffile = run.'/field.tsv'
    set title "predicted 1-sigma error of the compensated angle\n(the fit covariance propagated; it ripples with the 0.5-deg fine-code term)"
    set ylabel 'sigma [arcsec]'
    set yrange [0:*]
    plot ffile skip 1 using 1:2 with lines lw 0.5 lc rgb '#1f77b4' title 'predicted sigma'
  }
  unset multiplot
} else {
  cea = col('alpha_error_arcsec'); ceb = col('beta_error_arcsec')
  ca = col('alpha_deg'); cb = col('beta_deg')
  # the two-axis families (DSS, PSD) share this layout: the title names which
  fam = pv('sensor')
  famname = fam eq 'psd' ? 'PSD' : fam eq 'dss' ? 'DSS' : fam
  set multiplot layout 1, 2 title sprintf("%s calibration of %s (%d points): error after calibration at each campaign point", famname, data, nrow)
  stats used('') using cea nooutput
  set title sprintf('alpha error: RMS %.3g arcsec', sqrt(STATS_sumsq / STATS_records))
  set xlabel 'alpha [deg]'
  set ylabel 'error [arcsec]'
  plot used('') using ca:cea with points pt 7 ps 0.5 lc rgb '#1f77b4' notitle
  stats used('') using ceb nooutput
  set title sprintf('beta error: RMS %.3g arcsec', sqrt(STATS_sumsq / STATS_records))
  set xlabel 'beta [deg]'
  plot used('') using cb:ceb with points pt 7 ps 0.5 lc rgb '#d62728' notitle
  unset multiplot
}
