# budget.gp - the tolerance budget from `sunmc budget --out RUN`: for each
# source, in rank order, the share of the mean-square error that goes away
# without it, after and before calibration.
#   gnuplot -e "run='runs/budget'" scripts/budget.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/budget.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/budget.svg' : '/budget.png')
if (svg) { set terminal svg size 1000,600 dynamic font 'Sans,12' } else { set terminal pngcairo size 1000,600 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
field(c, row) = system(sprintf("awk -F'\\t' 'NR==%d {print $%d}' '%s'", row, c, file))
ranked = sprintf("< awk -F'\\t' 'NR>1 && $1>0' '%s'", file)
csrc = col('source'); ctol = col('tolerance'); cu = col('unit')
set title sprintf("tolerance budget: %s in band %s deg, %s units per run", field(col('angle'), 2), field(col('band'), 2), field(col('units'), 2))
set ylabel 'share of the mean-square error removed without the source [%]'
set xlabel 'error source (today''s tolerance), in rank order'
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set xtics rotate by -35 left
set grid ytics
set key top right
set yrange [*:*]
plot ranked using (100*column(col('share_removed_after'))):xtic(sprintf('%s (%s %s)', strcol(csrc), strcol(ctol), strcol(cu))) title 'after calibration' lc rgb '#1f77b4', \
     ranked using (100*column(col('share_removed_before'))) title 'before calibration' lc rgb '#ff7f0e'
