# curve.gp - error curves from `sunmc curve --out RUN` (ESS): error vs the
# fast table angle (alpha), one colour per series (beta).
#   what='both'   (default) before (top panel) and after (bottom panel)
#                 compensation on one y scale, each line's RMS in the legend
#   what='before' | 'after' | 'source' one kind only; 'source' is the error the
#                 unit's deviations add to the nominal design (paper's "error
#                 caused by ...")
#   run2='DIR'    overlay a second curve run (e.g. the -2 um mirror of +2 um)
#   xmin=..., xmax=...  zoom on part of the alpha range (e.g. 0 and 10)
#   label='...', label2='...'  legend prefixes of run and run2; title='...'
#   gnuplot -e "run='runs/u17'" scripts/curve.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/curve.tsv'
if (!exists("svg")) svg = 0
if (!exists("what")) what = 'both'
if (!exists("out")) out = run.'/curve'.(what eq 'both' ? '' : '_'.what).(svg ? '.svg' : '.png')
hgt = what eq 'both' ? 900 : 600
if (svg) { set terminal svg size 1000,hgt dynamic font 'Sans,12' } else { set terminal pngcairo size 1000,hgt font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
pre(s, p) = strlen(s) >= strlen(p) && s[1:strlen(p)] eq p
colp(p) = sum [i=1:words(hdr)] (pre(word(hdr, i), p) ? i : 0)
cb = colp('error_before_'); ca = colp('error_after_'); cs = colp('error_source_')
yname = word(hdr, cb)
lastus = 0
do for [i=1:strlen(yname)] { if (yname[i:i] eq '_') { lastus = i } }
eunit = yname[lastus+1:]
series = system(sprintf("awk -F'\\t' 'NR>1 && NF && !s[$2]++ {printf \"%%s \", $2}' '%s'", file))
n = words(series)
if (!exists("label")) label = ''
if (!exists("label2")) label2 = ''
# distinct colours, none pale (yellow and light blue are hard to tell apart on white)
array pal[8] = ['#0072b2', '#d55e00', '#009e73', '#cc79a7', '#000000', '#e69f00', '#56b4e9', '#8c564b']
do for [i=1:8] { set linetype i lc rgb pal[i] }
set linetype cycle 8
cfg1 = system(sprintf("head -1 '%s/config.ini'", run))[3:]
only = strstrt(cfg1, '--only') > 0
whatline = what eq 'source' ? 'the error the deviation adds to the nominal design (error_source: what the paper calls the error caused by it)' : what eq 'before' ? 'error before calibration' : what eq 'after' ? 'error after the own calibration of the unit' : ''
if (!exists("title")) title = cfg1.(strlen(whatline) > 0 ? "\n".whatline : '')
set title title
set xlabel word(hdr, 1).' (table angle)'
set ylabel sprintf('error [%s]', eunit)
set grid
set key outside right top
set xzeroaxis
set autoscale xfix
if (exists("xmin") && exists("xmax")) { set xrange [xmin:xmax] }
blk(i) = i - 1
if (what eq 'both') {
  # two stacked panels on one y scale: before on top, after below, the RMS
  # of each beta line in its legend (the after curve is no longer buried)
  stats file skip 1 using cb nooutput
  ym = abs(STATS_min) > abs(STATS_max) ? abs(STATS_min) : abs(STATS_max)
  stats file skip 1 using ca nooutput
  ym = abs(STATS_min) > ym ? abs(STATS_min) : abs(STATS_max) > ym ? abs(STATS_max) : ym
  set yrange [-1.05 * ym:1.05 * ym]
  array rb[n]
  array ra[n]
  do for [i=1:n] {
    stats file skip 1 every :::blk(i)::blk(i) using (column(cb)**2) nooutput
    rb[i] = sqrt(STATS_mean)
    stats file skip 1 every :::blk(i)::blk(i) using (column(ca)**2) nooutput
    ra[i] = sqrt(STATS_mean)
  }
  stats file skip 1 using (column(cb)**2) nooutput
  rball = sqrt(STATS_mean)
  stats file skip 1 using (column(ca)**2) nooutput
  raall = sqrt(STATS_mean)
  set multiplot layout 2, 1 title title
  set lmargin at screen 0.11
  set rmargin at screen 0.70
  set title sprintf('before compensation: RMS %.3g %s over all lines', rball, eunit)
  unset xlabel
  plot for [i=1:n] file skip 1 every :::blk(i)::blk(i) using 1:cb with lines lw 1 lc i title sprintf('%s%s = %s: RMS %.3g', label, word(hdr, 2), word(series, i), rb[i])
  # an --only unit is calibrated on unit 0's campaign noise: what is left
  # after is that noise through the fit, not the deviation
  set title sprintf('after compensation: RMS %.3g %s over all lines (%.1f times smaller)%s', raall, eunit, rball / raall, only ? "\nwhat is left is unit 0's campaign noise through the fit (--only keeps the config's noise)" : '')
  set xlabel word(hdr, 1).' (table angle)'
  plot for [i=1:n] file skip 1 every :::blk(i)::blk(i) using 1:ca with lines lw 1.5 lc i title sprintf('%s%s = %s: RMS %.3g', label, word(hdr, 2), word(series, i), ra[i])
  unset multiplot
} else {
  c = what eq 'before' ? cb : what eq 'after' ? ca : cs
  if (exists("run2")) {
    file2 = run2.'/curve.tsv'
    plot for [i=1:n] file skip 1 every :::blk(i)::blk(i) using 1:c with linespoints pt 7 ps 0.4 lw 2 lc i title sprintf('%s%s = %s', label, word(hdr, 2), word(series, i)), \
         for [i=1:n] file2 skip 1 every :::blk(i)::blk(i) using 1:c with linespoints pt 6 ps 0.4 lw 2 dt 2 lc i+1 title sprintf('%s%s = %s', label2, word(hdr, 2), word(series, i))
  } else {
    plot for [i=1:n] file skip 1 every :::blk(i)::blk(i) using 1:c with linespoints pt 7 ps 0.4 lw 2 lc i title sprintf('%s%s = %s', label, word(hdr, 2), word(series, i))
  }
}
