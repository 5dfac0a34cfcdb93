# yield.gp - the yield curve from `sunmc run --out RUN`: cumulative
# distribution of the units' after-calibration RMS in every band of the last
# measured angle (units.tsv), with the spec (summary.tsv) marked.  The
# fraction at the spec line is the yield; summary.tsv's yield and its
# confidence interval (Wilson) are drawn there as error bars (failed fits
# count as not passing in summary.tsv; the curves leave them out).
#   gnuplot -e "run='runs/a'" scripts/yield.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/units.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/yield.svg' : '/yield.png')
if (svg) { set terminal svg size 900,700 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,700 font 'Sans,11' }
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
# after-calibration columns, not their noise-free (rms_after_sys_) or model-form
# (rms_after_mf_) parts
isafter(s) = strlen(s) > 10 && s[1:10] eq 'rms_after_' && !(strlen(s) > 14 && s[1:14] eq 'rms_after_sys_') && !(strlen(s) > 13 && s[1:13] eq 'rms_after_mf_')
nafter = sum [i=1:words(hdr)] (isafter(word(hdr, i)) ? 1 : 0)
firstafter = sum [i=1:words(hdr)] ((isafter(word(hdr, i)) && !isafter(word(hdr, i-1))) ? i : 0)
# the last angle's bands: the last nb after-columns (nb = bands in summary.tsv)
nb = int(system(sprintf("awk -F'\\t' 'NR>1 && !s[$%d]++' '%s' | wc -l", scol('band'), sfile)))
c0 = firstafter + nafter - nb

# the product (config.ini's sensor.product) and its units, for the title: a
# line of their own, so a long product name does not push the rest off the
# canvas (issue 41)
prod = system(sprintf("awk '/^product = / {sub(/^product = /, \"\"); sub(/  #.*$/, \"\"); p = $0} END {print p}' '%s/config.ini' 2>/dev/null", run))
prod = strlen(prod) > 0 ? prod : run
set title sprintf("%s, %d units\nper band, the share of units whose RMS after calibration meets the spec\nunder the spec (%s in every band it names, every point read): %.1f%%", prod, int(system(sprintf("awk 'END {print NR - 1}' '%s'", file))), system(sprintf("awk -F'\\t' 'NR==1 {for (i = 1; i <= NF; i++) if ($i == \"spec_statistic\") c = i} NR==2 {print $c}' '%s'", sfile)), 100 * real(system(sprintf("awk -F'\\t' 'NR==1 {for (i = 1; i <= NF; i++) if ($i == \"spec_yield\") c = i} END {print $c}' '%s'", sfile))))
set xlabel sprintf('RMS error after calibration [%s]', unit)
set ylabel 'fraction of units with RMS <= x'
set yrange [0:1.02]
set offsets 0, graph 0.12, 0, 0  # room right of the spec line for its label and bars
set grid
set key outside below center box
set bmargin 9
set arrow from spec, graph 0 to spec, graph 1 nohead lw 2 lc rgb 'red' dt 3
set label sprintf('spec %g %s%s', spec, unit, unit eq 'deg' ? sprintf(' (%g arcsec)', spec_as) : '') at spec, graph 0.05 right offset -0.5,0 tc rgb 'red'
# summary.tsv rows of the last angle, in band order (the curves' order)
lastangle = system(sprintf("awk -F'\\t' 'NR>1 {a=$%d} END {print a}' '%s'", scol('angle'), sfile))
srow(i) = sprintf("< awk -F'\\t' 'NR>1 && $%d==\"%s\"' '%s' | sed -n %dp", scol('angle'), lastangle, sfile, i)
cy = scol('yield'); cylo = scol('yield_ci_lo'); cyhi = scol('yield_ci_hi')
# the yield target (report.yield_target in the run's config.ini)
target = real(system(sprintf("awk -F'=' '$1 ~ /^yield_target *$/ {split($2, v, \"#\"); print v[1]+0}' '%s/config.ini'", run)))
if (target > 0) {
  set arrow from graph 0, first target to graph 1, first target nohead lw 1.5 lc rgb '#555555' dt 2
}
# named in the legend's title, not on the line: a label there sat where the
# best band's curve crosses the target (the DSS's at 4 arcsec; issue 41)
target_txt = target > 0 ? sprintf('; dashed: yield target %g%%', 100 * target) : ''
# legend in words: the measured angle, the band and the yield with its interval
legend = system(sprintf("awk -F'\\t' 'NR>1 && $%d==\"%s\" {printf \"\\\"%%s error, band %%s-%%s deg: yield %%.1f%%%% [%%.1f, %%.1f]\\\" \", $%d, $%d, $%d, 100*$%d, 100*$%d, 100*$%d}' '%s'", \
  scol('angle'), lastangle, scol('angle'), scol('band_lo_deg'), scol('band_hi_deg'), scol('yield'), scol('yield_ci_lo'), scol('yield_ci_hi'), sfile))
set key title sprintf('yield at the spec: bars are %g%% intervals%s', 100 * real(system(sprintf("awk -F'\\t' 'NR==2 {print $%d}' '%s'", scol('confidence'), sfile))), target_txt)
plot for [c=c0:c0+nb-1] file skip 1 using (column(c)):(1.0) smooth cnormal with steps lw 2 lc (c-c0+1) title word(legend, c-c0+1), \
     for [i=1:nb] srow(i) using (spec):(column(cy)):(column(cylo)):(column(cyhi)) with yerrorbars lc (i) pt 7 ps 0.8 lw 2 notitle
