# map.gp - 2-D error maps from `sunmc curve --out RUN` (DSS: error of each
# measured angle over the sun angles (alpha, beta)), one panel per angle (the
# 'total' columns are left out), pm3d colour map.
#   what='source' (default) | 'before' | 'after'
#   cut=1         add a row of line cuts under the maps: an alpha error along
#                 the beta grid line nearest 0 against alpha, a beta error
#                 along the alpha line nearest 0 against beta (the shape a
#                 colour map hides); any grid, offset or not
#   scale='shared' one symmetric colour scale for every panel (they compare
#                 side by side); default: each panel its own symmetric scale,
#                 so a small error next to a large one is not one flat colour
# Each panel's title names the angle, what is drawn and its range; a panel
# that is identically zero says so.
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
# the product (config.ini's sensor.product), then the command that drew the
# curve (config.ini's first line), not the command alone (issue 41)
prod = system(sprintf("awk '/^product = / {sub(/^product = /, \"\"); sub(/  #.*$/, \"\"); p = $0} END {print p}' '%s/config.ini' 2>/dev/null", run))
if (!exists("title")) title = (strlen(prod) > 0 ? prod.': ' : '').system(sprintf("head -1 '%s/config.ini'", run))[3:]
if (!exists("scale")) scale = 'panel'
# readable panel names: error_source_alpha_arcsec -> alpha error, source alone [arcsec]
whatname(w) = w eq 'source' ? 'the source alone' : (w eq 'before' ? 'before calibration' : 'after calibration')
unitof(s) = s[strstrt(s, '_arcsec') ? strstrt(s, '_arcsec') + 1 : strlen(s) + 1:]
angof(s) = s[strlen(p) + 1:strlen(s) - strlen(unitof(s)) - 1]
nice(s) = sprintf('%s error, %s [%s]', angof(s), whatname(what), unitof(s))
# the largest |error| of any panel (the shared scale, and the cuts' y range)
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
set xlabel 'alpha [deg]'
set ylabel 'beta [deg]'
set cblabel 'arcsec'
set multiplot layout 1 + cut, npanel title title
do for [i=1:words(hdr)] {
  if (ok(i)) {
    stats file skip 1 using i nooutput
    zero = abs(STATS_min) < 1e-9 * m && abs(STATS_max) < 1e-9 * m
    mi = abs(STATS_min) > abs(STATS_max) ? abs(STATS_min) : abs(STATS_max)
    mi = (scale eq 'shared' || mi <= 0) ? m : mi
    set cbrange [-mi:mi]
    set title nice(word(hdr, i)).(zero ? ': identically zero' : sprintf(': %.4g to %.4g', STATS_min, STATS_max))
    set size ratio -1
    splot file skip 1 using 1:2:i with pm3d notitle
  }
}
if (cut) {
  set size noratio
  set grid
  set xzeroaxis
  set yrange [-m:m]
  # the grid line nearest 0 of column k (0 itself when the grid has it)
  near0(k) = system(sprintf("awk -F'\\t' 'NR>1 && NF {a = $%d < 0 ? -$%d : $%d; if (n++ == 0 || a < b) {b = a; v = $%d}} END {print v}' '%s'", k, k, k, k, file))
  do for [i=1:words(hdr)] {
    if (ok(i)) {
      isb = strstrt(word(hdr, i), '_beta_') > 0
      k = isb ? 1 : 2
      v0 = near0(k)
      set title sprintf('line cut at %s = %s deg: %s error [%s]', isb ? 'alpha' : 'beta', v0, angof(word(hdr, i)), unitof(word(hdr, i)))
      set xlabel isb ? 'beta [deg]' : 'alpha [deg]'
      set ylabel 'arcsec'
      plot sprintf("< awk -F'\\t' 'NR>1 && NF && $%d == %s' '%s'", k, v0, file) using (column(isb ? 2 : 1)):i with linespoints pt 7 ps 0.5 lw 2 lc rgb '#b2182b' notitle
    }
  }
}
unset multiplot
