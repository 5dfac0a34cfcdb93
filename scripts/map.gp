# map.gp - 2-D error maps from `sunmc curve --out RUN` (DSS: error of each
# measured angle over the sun angles (alpha, beta)), one panel per angle (the
# 'total' columns are left out), pm3d colour map.
#   what='source' (default) | 'before' | 'after'
#   cut=1         add a row of line cuts under the maps: an alpha error along
#                 beta = 0 against alpha, a beta error along alpha = 0 against
#                 beta (the shape a colour map hides)
# All panels share one symmetric colour scale (side by side they compare);
# a panel that is identically zero says so in its title.
#   gnuplot -e "run='runs/dh'" scripts/map.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/curve.tsv'
if (!exists("svg")) svg = 0
if (!exists("what")) what = 'source'
if (!exists("out")) out = run.'/map_'.what.(svg ? '.svg' : '.png')
hdr = system(sprintf("head -1 '%s'", file))
pre(s, p) = strlen(s) >= strlen(p) && s[1:strlen(p)] eq p
p = 'error_'.what.'_'
istotal(s) = strstrt(s, '_total_') > 0
ok(i) = pre(word(hdr, i), p) && !istotal(word(hdr, i))
npanel = sum [i=1:words(hdr)] (ok(i) ? 1 : 0)
if (!exists("cut")) cut = 0
hgt = cut ? 860 : 520
if (svg) { set terminal svg size 560*npanel,hgt dynamic font 'Sans,12' } else { set terminal pngcairo size 560*npanel,hgt font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"
if (!exists("title")) title = system(sprintf("head -1 '%s/config.ini'", run))[3:]
# one colour scale for every panel: the largest |error| of any of them
m = 0
do for [i=1:words(hdr)] {
  if (ok(i)) {
    stats file skip 1 using i nooutput
    m = abs(STATS_min) > m ? abs(STATS_min) : m
    m = abs(STATS_max) > m ? abs(STATS_max) : m
  }
}
m = m > 0 ? m : 1
set view map
set pm3d map corners2color c1
# a diverging palette in 20 steps: the steps act as contours, so a rise and
# fall shows as bands that come back instead of one saturated colour
set palette defined (-1 '#000033', -0.75 '#1f4fa8', -0.5 '#4f9ad6', -0.25 '#b7d7ee', 0 '#f7f7f7', 0.25 '#fcc5a5', 0.5 '#ec7a53', 0.75 '#c0262d', 1 '#330000')
set palette maxcolors 20
set cbrange [-m:m]
set xlabel word(hdr, 1)
set ylabel word(hdr, 2)
set multiplot layout 1 + cut, npanel title title
do for [i=1:words(hdr)] {
  if (ok(i)) {
    stats file skip 1 using i nooutput
    zero = abs(STATS_min) < 1e-9 * m && abs(STATS_max) < 1e-9 * m
    set title word(hdr, i).(zero ? ': identically zero' : sprintf(': %.4g to %.4g', STATS_min, STATS_max))
    set size ratio -1
    splot file skip 1 using 1:2:i with pm3d notitle
  }
}
if (cut) {
  set size noratio
  set grid
  set xzeroaxis
  set yrange [-m:m]
  do for [i=1:words(hdr)] {
    if (ok(i)) {
      isb = strstrt(word(hdr, i), '_beta_') > 0
      set title sprintf('line cut: %s along %s = 0', word(hdr, i), isb ? word(hdr, 1) : word(hdr, 2))
      set xlabel isb ? word(hdr, 2) : word(hdr, 1)
      set ylabel word(hdr, i)
      k = isb ? 1 : 2
      plot sprintf("< awk -F'\\t' 'NR>1 && NF && $%d == 0' '%s'", k, file) using (column(isb ? 2 : 1)):i with linespoints pt 7 ps 0.5 lw 2 lc rgb '#b2182b' notitle
    }
  }
}
unset multiplot
