# convergence.gp - how the Monte Carlo converges, from `sunmc run --out RUN`:
# the running mean of the after-calibration RMS (top; the widest band of the
# last measured angle, the last of equally wide ones, as hist.gp and budget
# take it, or band='0:30') and the running yield under the spec (bottom:
# units.tsv's pass, the verdict over every band the spec names, as Table 1's
# YIELD) against the number of units, in unit order, each with its
# confidence band at summary.tsv's level.  The mean's band is mean +- z sd / sqrt(n)
# (normal quantile z: Table 1's Student t is the same to 1 % past 30
# units), the yield's Wilson's score interval over all units so far (a failed
# fit fails, as in summary.tsv).  The dashed line is the final estimate: the
# band should shrink as 1/sqrt(n) around it.
#   gnuplot -e "run='runs/a'" scripts/convergence.gp  [-e "band='0:30'"] [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/units.tsv'
sfile = run.'/summary.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/convergence.svg' : '/convergence.png')
if (svg) { set terminal svg size 900,700 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,700 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

shdr = system(sprintf("head -1 '%s'", sfile))
scol(n) = sum [i=1:words(shdr)] (word(shdr, i) eq n ? i : 0)
sfield(c) = system(sprintf("awk -F'\\t' 'NR==2 {print $%d}' '%s'", c, sfile))
unit = sfield(scol('rms_unit'))
spec = real(sfield(scol('spec_arcsec'))) / (unit eq 'deg' ? 3600.0 : 1.0)
level = real(sfield(scol('confidence')))
z = invnorm(0.5 + 0.5 * level)
angle = system(sprintf("awk -F'\\t' 'NR>1 {a=$%d} END {print a}' '%s'", scol('angle'), sfile))
if (!exists("band")) band = system(sprintf("awk -F'\\t' 'NR>1 && $%d==\"%s\" && $%d-$%d>=w {w=$%d-$%d; b=$%d} END {print b}' '%s'", scol('angle'), angle, scol('band_hi_deg'), scol('band_lo_deg'), scol('band_hi_deg'), scol('band_lo_deg'), scol('band'), sfile))
lo = band[1:strstrt(band, ':')-1]; hi = band[strstrt(band, ':')+1:]
name = sprintf('rms_after_%s_%s_%s_%s', angle, lo, hi, unit)
hdr = system(sprintf("head -1 '%s'", file))
c = sum [i=1:words(hdr)] (word(hdr, i) eq name ? i : 0)
cs = sum [i=1:words(hdr)] (word(hdr, i) eq 'fit_status' ? i : 0)
# the spec's verdict of each unit (units.tsv's pass: every band the spec names)
cp = sum [i=1:words(hdr)] (word(hdr, i) eq 'pass' ? i : 0)
if (c == 0) { print sprintf("convergence.gp: no column %s in %s", name, file); exit status 2 }
# n, mean, lo, hi, yield, ylo, yhi after each unit
running = sprintf("< awk -F'\\t' -v z=%.10g -v spec=%.10g 'NR>1 {n++; ok=($%d==\"ok\" && $%d!=\"nan\"); if (ok) {k++; d=$%d-m; m+=d/k; s2+=d*($%d-m); } p+=($%d==1); sd=(k>1)?sqrt(s2/(k-1)):0; h=(k>1)?z*sd/sqrt(k):0; y=p/n; zz=z*z; den=1+zz/n; ctr=(y+zz/(2*n))/den; w=z*sqrt(y*(1-y)/n+zz/(4*n*n))/den; print n, (k?m:\"nan\"), (k>1?m-h:\"nan\"), (k>1?m+h:\"nan\"), y, ctr-w, ctr+w}' '%s'", z, spec, cs, c, c, c, cp, file)
final_mean = real(system(sprintf("awk -F'\\t' 'NR>1 && $%d==\"ok\" && $%d!=\"nan\" {k++; s+=$%d} END {print s/k}' '%s'", cs, c, c, file)))
final_yield = real(system(sprintf("awk -F'\\t' 'NR>1 {n++; p+=($%d==1)} END {print p/n}' '%s'", cp, file)))
set datafile separator whitespace
# the product (config.ini's sensor.product) and its units, for the title
prod = system(sprintf("awk '/^product = / {sub(/^product = /, \"\"); sub(/  #.*$/, \"\"); p = $0} END {print p}' '%s/config.ini' 2>/dev/null", run))
prod = strlen(prod) > 0 ? prod : run
# what a band bins: the ESS its angle's magnitude, the DSS and PSD the field angle
bandvar = sfield(scol('family')) eq 'ess' ? '|'.angle.'|' : 'field angle'
# the spec's rule (summary.tsv: report.spec_*)
cov = sfield(scol('min_coverage'))
rule = sprintf("%s <= %g %s in %s bands, %s", sfield(scol('spec_statistic')), spec, unit, sfield(scol('spec_bands')), cov eq '1' ? 'every point read' : cov.' of the points read')
set multiplot layout 2,1 title sprintf("%s: mean RMS after calibration and yield as the units accrue\n%s error, band %s %s deg; %g%% confidence bands", prod, angle, bandvar, band, 100 * level)
set grid
set key top right box opaque
set xlabel 'units'
set ylabel sprintf('running mean RMS after [%s]', unit)
plot running using 1:3:4 with filledcurves lc rgb '#a6c8e6' title sprintf('%g%% interval', 100 * level), \
     running using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'running mean', \
     final_mean with lines dt 2 lc rgb 'black' title sprintf('final %.4g %s', final_mean, unit)
set ylabel 'running yield under the spec'
set title sprintf('yield under the spec: %s (every unit, its verdict)', rule)
set yrange [*:1.01]
# the running yield ends at the final yield: the legend on the other side,
# so it never covers the line and its interval where they settle (issue 41)
if (final_yield >= 0.5) { set key bottom right box opaque } else { set key top right box opaque }
plot running using 1:6:7 with filledcurves lc rgb '#f6c89f' title sprintf('%g%% Wilson interval', 100 * level), \
     running using 1:5 with lines lw 2 lc rgb '#d95f02' title 'running yield', \
     final_yield with lines dt 2 lc rgb 'black' title sprintf('final %.1f%%', 100 * final_yield)
unset multiplot
