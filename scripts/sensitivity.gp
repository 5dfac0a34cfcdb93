# sensitivity.gp - Sobol indices from `sunmc sensitivity --out RUN`: for each
# random input (sensitivity.tsv's order: by total index after calibration),
# the first-order index S1 (solid) and the total index ST (light) with their
# bootstrap intervals as error bars; before calibration on top, after below.
# S1 is the share of the unit-to-unit variance of the RMS the input explains
# alone, ST with its interactions.
#   gnuplot -e "run='runs/sens'" scripts/sensitivity.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/sensitivity.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/sensitivity.svg' : '/sensitivity.png')
maxlen = int(system(sprintf("awk -F'\\t' 'NR>1 && length($2)>m {m=length($2)} END {print m+0}' '%s'", file)))
if (svg) { set terminal svg size 1000,900 dynamic font 'Sans,12' } else { set terminal pngcairo size 1000,900 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
field(c, row) = system(sprintf("awk -F'\\t' 'NR==%d {print $%d}' '%s'", row, c, file))
sel(w) = sprintf("< awk -F'\\t' 'NR>1 && $1==\"%s\"' '%s'", w, file)
csrc = col('source'); c1 = col('S1'); c1l = col('S1_ci_lo'); c1h = col('S1_ci_hi')
ct = col('ST'); ctl = col('ST_ci_lo'); cth = col('ST_ci_hi')
level = real(field(col('confidence'), 2))
w = 0.2
set multiplot layout 2,1 title sprintf("Sobol indices of the unit RMS (%s, |%s| %s deg), %s units; bars: %g%% bootstrap intervals", field(col('angle'), 2), field(col('angle'), 2), field(col('band'), 2), field(col('units'), 2), 100 * level)
set style fill solid 0.85 border -1
set boxwidth 0.38
set grid ytics
set key top right box opaque
set yrange [-0.05:1.05]
set xrange [-0.6:*]
set xtics rotate by 90 right nomirror
set bmargin maxlen * 0.44 + 2
do for [when in "before after"] {
  set ylabel sprintf('index, RMS %s calibration', when)
  plot sel(when) using ($0 - w):(column(c1)) with boxes lc rgb '#1f77b4' title 'S1 (first order)', \
       sel(when) using ($0 + w):(column(ct)) with boxes lc rgb '#9ecae1' title 'ST (total)', \
       sel(when) using ($0 - w):(column(c1l)):(0):(column(c1h) - column(c1l)) with vectors heads size 0.06,90 lc rgb 'black' lw 1.5 notitle, \
       sel(when) using ($0 + w):(column(ctl)):(0):(column(cth) - column(ctl)) with vectors heads size 0.06,90 lc rgb 'black' lw 1.5 notitle, \
       sel(when) using 0:(NaN):xtic(strcol(csrc)) notitle
}
unset multiplot
