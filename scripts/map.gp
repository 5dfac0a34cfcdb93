# map.gp - 2-D error maps from `sunmc curve --out RUN` (DSS: error of each
# measured angle over the sun angles (alpha, beta)), one panel per angle (the
# 'total' columns are left out), pm3d colour map.
#   what='source' (default) | 'before' | 'after'
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
if (svg) { set terminal svg size 560*npanel,520 dynamic font 'Sans,12' } else { set terminal pngcairo size 560*npanel,520 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"
if (!exists("title")) title = system(sprintf("head -1 '%s/config.ini'", run))[3:]
set view map
set pm3d map corners2color c1
set palette defined (-1 'blue', 0 'white', 1 'red')
set xlabel word(hdr, 1)
set ylabel word(hdr, 2)
set size ratio -1
set multiplot layout 1, npanel title title
do for [i=1:words(hdr)] {
  if (ok(i)) {
    set title word(hdr, i)
    set cblabel word(hdr, i)
    stats file skip 1 using i nooutput
    m = (abs(STATS_min) > abs(STATS_max) ? abs(STATS_min) : abs(STATS_max))
    m = m > 0 ? m : 1
    set cbrange [-m:m]
    splot file skip 1 using 1:2:i with pm3d notitle
  }
}
unset multiplot
