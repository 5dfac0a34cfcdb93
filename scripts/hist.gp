# hist.gp - histogram of the units' times of accuracy improvement (RMS before
# / RMS after calibration) in the widest band of the last measured angle, from
# `sunmc run --out RUN` (units.tsv), mean marked.
#   gnuplot -e "run='runs/a'" scripts/hist.gp   [-e "out='x.png'"] [-e "svg=1"] [-e "binwidth=0.1"]
if (!exists("run")) run = '.'
file = run.'/units.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/hist.svg' : '/hist.png')
if (svg) { set terminal svg size 900,600 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,600 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
# after-calibration columns, not their noise-free (rms_after_sys_) part
isafter(s) = strlen(s) > 10 && s[1:10] eq 'rms_after_' && !(strlen(s) > 14 && s[1:14] eq 'rms_after_sys_')
cafter = sum [i=1:words(hdr)] ((isafter(word(hdr, i)) && (i == words(hdr))) ? i : 0)
aname = word(hdr, cafter)
bname = 'rms_before_'.aname[11:]
cbefore = col(bname)
if (!exists("binwidth")) binwidth = 0.1
bin(x) = binwidth * (floor(x / binwidth) + 0.5)
stats file skip 1 using (column(cbefore) / column(cafter)) nooutput
set title sprintf('times of accuracy improvement, %s / %s (%d units)', bname, aname, STATS_records)
set xlabel 'RMS before / RMS after calibration [times]'
set ylabel 'units'
set style fill solid 0.6 border -1
set boxwidth binwidth
set grid ytics
set arrow from STATS_mean, graph 0 to STATS_mean, graph 1 nohead lw 2 lc rgb 'red' dt 3
set label sprintf('mean %.2f', STATS_mean) at STATS_mean, graph 0.95 left offset 0.5,0 tc rgb 'red'
plot file skip 1 using (bin(column(cbefore) / column(cafter))):(1.0) smooth frequency with boxes lc rgb '#1f77b4' notitle
