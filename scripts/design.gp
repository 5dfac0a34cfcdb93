# design.gp - `sunmc design --out RUN`: the yield of every candidate campaign
# against its turntable hours, with its confidence interval, the Pareto front
# (no cheaper candidate has a higher yield) as a line, the target as a
# horizontal line, aliased candidates as crosses, the input campaign and the
# chosen one (best.ini) marked.
#   gnuplot -e "run='runs/design'" scripts/design.gp    [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/design.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/design.svg' : '/design.png')
if (svg) { set terminal svg size 900,600 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,600 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
ch = col('hours'); cy = col('yield'); cl = col('yield_ci_lo'); cu = col('yield_ci_hi')
cv = col('verdict'); cp = col('pareto'); cb = col('best'); ci = col('input')
rows(cond) = sprintf("< awk -F'\\t' 'NR>1 && (%s)' '%s'", cond, file)
# the product and the yield target from the run's config.ini
cfgv(k) = system(sprintf("awk '/^%s = / {sub(/^%s = /, \"\"); sub(/  #.*$/, \"\"); v = $0} END {print v}' '%s/config.ini' 2>/dev/null", k, k, run))
prod = cfgv('product')
target = cfgv('yield_target')
target = strlen(target) > 0 ? real(target) : 0.95
# the spec's verdict the yield counts (report.spec_*)
cov = cfgv('min_coverage')
rule = sprintf("yield under the spec: %s <= %s\" in %s bands, %s", cfgv('spec_statistic'), cfgv('spec_arcsec'), cfgv('spec_bands'), (cov eq '1' || cov eq '') ? 'every point read' : cov.' of the points read')
set title sprintf("%s: campaign design, the yield of each candidate campaign against its turntable time\n%s\n(error bars: confidence interval; dashed: the yield target %g %%)", strlen(prod) > 0 ? prod : run, rule, 100 * target)
set xlabel 'turntable time [h]'
set ylabel 'yield under the spec (every band it names, every point read)'
set grid
set key below horizontal maxcols 3
set yrange [*:1.01]
# the chosen campaign, when design chose one (too few units: none, all undecided)
nbest = int(system(sprintf("awk -F'\\t' 'NR>1 && $%d==1' '%s' | wc -l", cb, file)))
BEST = nbest > 0 ? sprintf(", rows(\"$%d==1\") using ch:cy:cl:cu with yerrorbars pt 9 ps 2 lc rgb 'red' title 'chosen (best.ini)'", cb) : ""
set arrow from graph 0, first target to graph 1, first target nohead lw 2 dt 2 lc rgb '#d62728'
plot rows(sprintf("$%d!=\"aliased\" && $%d==0 && $%d==0", cv, cp, ci)) using ch:cy:cl:cu with yerrorbars pt 7 ps 0.6 lc rgb '#9090c0' title 'candidate', \
     rows(sprintf("$%d==1", cp)) using ch:cy with linespoints lw 2 pt 7 lc rgb '#1060c0' title 'Pareto front', \
     rows(sprintf("$%d==\"aliased\"", cv)) using ch:cy with points pt 2 ps 1.2 lc rgb 'grey' title 'aliased step (never chosen)', \
     rows(sprintf("$%d==1", ci)) using ch:cy:cl:cu with yerrorbars pt 5 ps 1.5 lc rgb 'black' title 'input campaign' @BEST
