# hist.gp - histogram of the units' times of accuracy improvement (RMS before
# / RMS after calibration) in the widest band of the last measured angle (the
# band convergence.gp draws), from
# `sunmc run --out RUN` (units.tsv), mean marked above the bars; bins
# from the data (Freedman-Diaconis) unless binwidth is given.
#   gnuplot -e "run='runs/a'" scripts/hist.gp   [-e "out='x.png'"] [-e "svg=1"] [-e "binwidth=0.1"]
if (!exists("run")) run = '.'
file = run.'/units.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/hist.svg' : '/hist.png')
if (svg) { set terminal svg size 900,600 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,600 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
# the band: the widest of the last measured angle (the last of equally wide
# ones), as convergence.gp takes it, from summary.tsv
sfile = run.'/summary.tsv'
shdr = system(sprintf("head -1 '%s'", sfile))
scol(n) = sum [i=1:words(shdr)] (word(shdr, i) eq n ? i : 0)
angle = system(sprintf("awk -F'\\t' 'NR>1 {a=$%d} END {print a}' '%s'", scol('angle'), sfile))
band = system(sprintf("awk -F'\\t' 'NR>1 && $%d==\"%s\" && $%d-$%d>=w {w=$%d-$%d; b=$%d} END {print b}' '%s'", scol('angle'), angle, scol('band_hi_deg'), scol('band_lo_deg'), scol('band_hi_deg'), scol('band_lo_deg'), scol('band'), sfile))
family = system(sprintf("awk -F'\\t' 'NR==2 {print $%d}' '%s'", scol('family'), sfile))
unit = system(sprintf("awk -F'\\t' 'NR==2 {print $%d}' '%s'", scol('rms_unit'), sfile))
lo = band[1:strstrt(band, ':')-1]; hi = band[strstrt(band, ':')+1:]
aname = sprintf('rms_after_%s_%s_%s_%s', angle, lo, hi, unit)
cafter = col(aname)
if (cafter == 0) { print sprintf("hist.gp: no column %s in %s", aname, file); exit status 2 }
bname = 'rms_before_'.aname[11:]
cbefore = col(bname)
stats file skip 1 using (column(cbefore) / column(cafter)) nooutput
# bins from the data (Freedman-Diaconis: 2 IQR / n^(1/3)), at least 5 and at
# most 60 across the range, unless binwidth is given
if (!exists("binwidth")) {
  iqr = STATS_up_quartile - STATS_lo_quartile
  range = STATS_max - STATS_min
  binwidth = iqr > 0 ? 2 * iqr / STATS_records**(1.0 / 3) : range / sqrt(STATS_records)
  binwidth = binwidth > 0 ? binwidth : 1
  binwidth = range / binwidth > 60 ? range / 60 : range / binwidth < 5 && range > 0 ? range / 5 : binwidth
}
bin(x) = binwidth * (floor(x / binwidth) + 0.5)
# the product (config.ini's sensor.product) and its units, for the title
prod = system(sprintf("awk '/^product = / {sub(/^product = /, \"\"); sub(/  #.*$/, \"\"); p = $0} END {print p}' '%s/config.ini' 2>/dev/null", run))
prod = strlen(prod) > 0 ? prod : run
desc = sprintf("%s error, band %s %s deg (the widest, as convergence.png)", angle, family eq 'ess' ? '|'.angle.'|' : 'field angle', band)
set title sprintf("%s, %d units: times of accuracy improvement\n(RMS before / RMS after calibration), %s", prod, STATS_records, desc)
set xlabel 'RMS before / RMS after calibration [times]'
set ylabel 'units'
set style fill solid 0.6 border -1
set boxwidth binwidth
set grid ytics
set arrow from STATS_mean, graph 0 to STATS_mean, graph 1 nohead lw 2 lc rgb 'red' dt 3 front
# headroom above the tallest bar for the mean's label
set offsets 0, 0, graph 0.12, 0
set yrange [0:*]
mtext = sprintf('mean %.2f (median %.2f), bin %.3g', STATS_mean, STATS_median, binwidth)
if (STATS_mean > (STATS_min + STATS_max) / 2) {
  set label mtext at STATS_mean, graph 0.96 right offset -0.5,0 tc rgb 'red' front boxed
} else {
  set label mtext at STATS_mean, graph 0.96 left offset 0.5,0 tc rgb 'red' front boxed
}
set style textbox opaque noborder
plot file skip 1 using (bin(column(cbefore) / column(cafter))):(1.0) smooth frequency with boxes lc rgb '#1f77b4' notitle
