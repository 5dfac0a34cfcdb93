# yield.gp - the yield curve from `sunmc run --out RUN`: cumulative
# distribution of the units' after-calibration RMS in every band of the last
# measured angle (units.tsv), with the spec (summary.tsv) marked.  The
# fraction at the spec line is the yield (failed fits count as not passing in
# summary.tsv; here they are left out).
#   gnuplot -e "run='runs/a'" scripts/yield.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/units.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/yield.svg' : '/yield.png')
if (svg) { set terminal svg size 900,600 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,600 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
sfile = run.'/summary.tsv'
shdr = system(sprintf("head -1 '%s'", sfile))
scol(n) = sum [i=1:words(shdr)] (word(shdr, i) eq n ? i : 0)
spec_as = real(system(sprintf("awk -F'\\t' 'NR==2 {print $%d}' '%s'", scol('spec_arcsec'), sfile)))
unit = system(sprintf("awk -F'\\t' 'NR==2 {print $%d}' '%s'", scol('rms_unit'), sfile))
spec = spec_as / (unit eq 'deg' ? 3600.0 : 1.0)
isafter(s) = strlen(s) > 10 && s[1:10] eq 'rms_after_'
nafter = sum [i=1:words(hdr)] (isafter(word(hdr, i)) ? 1 : 0)
firstafter = sum [i=1:words(hdr)] ((isafter(word(hdr, i)) && !isafter(word(hdr, i-1))) ? i : 0)
# the last angle's bands: the last nb after-columns (nb = bands in summary.tsv)
nb = int(system(sprintf("awk -F'\\t' 'NR>1 && !s[$%d]++' '%s' | wc -l", scol('band'), sfile)))
c0 = firstafter + nafter - nb

set title sprintf('yield: cumulative distribution of the after-calibration RMS (%s)', run)
set xlabel sprintf('RMS error after calibration [%s]', unit)
set ylabel 'fraction of units with RMS <= x'
set yrange [0:1.02]
set grid
set key bottom right
set arrow from spec, graph 0 to spec, graph 1 nohead lw 2 lc rgb 'red' dt 3
set label sprintf('spec %g %s', spec, unit) at spec, graph 0.05 left offset 0.5,0 tc rgb 'red'
plot for [c=c0:c0+nb-1] file skip 1 using (column(c)):(1.0) smooth cnormal with steps lw 2 title word(hdr, c)
