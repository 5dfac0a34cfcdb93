# budget.gp - the error budget from `sunmc budget --out RUN`: the share of the
# mean-square error of each row of budget.tsv -- the floor (nominal design,
# no noise) as its own grey bar, every source in rank order, the interaction
# last -- after (blue) and before (orange) calibration, each with its
# confidence interval as an error bar.  Floor + sources + interaction = 100 %.
# A hatched bar (and ~ after its name) is inside the Monte Carlo noise: its
# after-calibration interval includes 0.  The after_part rows (the after
# mean square by kind: reading noise, estimation, model form) are not bars:
# the subtitle states them.  The legend sits above the plot, off the bars.
#   gnuplot -e "run='runs/budget'" scripts/budget.gp   [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/budget.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/budget.svg' : '/budget.png')
# the longest label sets the bottom margin: vertical labels are never clipped
maxlen = int(system(sprintf("awk -F'\\t' 'NR>1 && $2 != \"after_part\" {n=length($3)+length($5)+length($4)+6; if (n>m) m=n} END {print m+0}' '%s'", file)))
if (svg) { set terminal svg size 1100,720 dynamic font 'Sans,12' } else { set terminal pngcairo size 1100,720 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
# the bars: every row but the after-calibration parts
data = sprintf("< awk -F'\t' 'NR==1 {for (i = 1; i <= NF; i++) if ($i == \"kind\") k = i} $k != \"after_part\"' '%s'", file)
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
field(c, row) = system(sprintf("awk -F'\\t' 'NR==%d {print $%d}' '%s'", row, c, file))
ckind = col('kind'); csrc = col('source'); ctol = col('tolerance'); cu = col('unit')
csa = col('share_after'); csal = col('share_after_ci_lo'); csah = col('share_after_ci_hi')
csb = col('share_before'); csbl = col('share_before_ci_lo'); csbh = col('share_before_ci_hi')
csig = col('significant_after')
level = real(field(col('confidence'), 2))
label(k, s, t, u, sig) = (k eq 'floor' ? 'FLOOR (design, no noise)' : k eq 'interaction' ? 'INTERACTION' : sprintf('%s (%s %s)', s, t, u)).(sig eq 'no' ? ' ~' : '')
issig(s) = s eq 'yes'
isfloor(k) = k eq 'floor'

# the product (config.ini's sensor.product) and its units, for the title
prod = system(sprintf("awk '/^product = / {sub(/^product = /, \"\"); sub(/  #.*$/, \"\"); p = $0} END {print p}' '%s/config.ini' 2>/dev/null", run))
prod = strlen(prod) > 0 ? prod : run
# the parts after calibration (budget.tsv's after_part rows), in words
part(name) = system(sprintf("awk -F'\t' '$%d == \"%s\" {printf \"%%.1f%%%%\", 100 * $%d}' '%s'", csrc, name, csa, file))
parts = strlen(part('MODEL_FORM')) > 0 ? sprintf("after calibration: %s reading noise, %s estimation, %s model form", part('NOISE_OF_READING'), part('ESTIMATION'), part('MODEL_FORM')) : ''
# the spec's verdict (report.spec_*, config.ini)
cfgv(k) = system(sprintf("awk -F'=' '$1 ~ /^%s *$/ {split($2, v, \"#\"); gsub(/^ +| +$/, \"\", v[1]); print v[1]}' '%s/config.ini' 2>/dev/null", k, run))
cov = cfgv('min_coverage')
rule = sprintf("spec: %s <= %s\" in %s bands, %s; the limits keep a yield of %s", cfgv('spec_statistic'), cfgv('spec_arcsec'), cfgv('spec_bands'), (cov eq '1' || cov eq '') ? 'every point read' : cov.' of the points read', cfgv('yield_target'))
line1 = sprintf("%s: error budget, %s error in band %s deg, %s units per run", prod, field(col('angle'), 2), field(col('band'), 2), field(col('units'), 2))
line2 = sprintf("bars: %g%% intervals; floor + sources + interaction = 100%%", 100 * level)
set title line1."\n".line2.(strlen(parts) > 0 ? "\n".parts : "")."\n".rule
set ylabel 'share of the mean-square error [%]'
set xtics rotate by 90 right nomirror
set bmargin maxlen * 0.44 + 2
set grid ytics
set key tmargin center horizontal box opaque
set tmargin 8
set xrange [-0.6:*]
set boxwidth 0.38
set style fill solid 0.85 border -1
w = 0.2
plot data skip 1 using ($0 - w):(isfloor(strcol(ckind)) || !issig(strcol(csig)) ? NaN : 100*column(csa)) with boxes lc rgb '#1f77b4' title 'after calibration', \
     data skip 1 using ($0 + w):(isfloor(strcol(ckind)) || !issig(strcol(csig)) ? NaN : 100*column(csb)) with boxes lc rgb '#ff7f0e' title 'before calibration', \
     data skip 1 using ($0 - w):(isfloor(strcol(ckind)) ? 100*column(csa) : NaN) with boxes lc rgb '#555555' title 'floor after', \
     data skip 1 using ($0 + w):(isfloor(strcol(ckind)) ? 100*column(csb) : NaN) with boxes lc rgb '#aaaaaa' title 'floor before', \
     data skip 1 using ($0 - w):(!isfloor(strcol(ckind)) && !issig(strcol(csig)) ? 100*column(csa) : NaN) with boxes fs pattern 4 border lc rgb '#1f77b4' title 'inside the noise (~)', \
     data skip 1 using ($0 + w):(!isfloor(strcol(ckind)) && !issig(strcol(csig)) ? 100*column(csb) : NaN) with boxes fs pattern 5 border lc rgb '#ff7f0e' notitle, \
     data skip 1 using ($0 - w):(100*column(csal)):(0):(100*(column(csah) - column(csal))) with vectors heads size 0.06,90 lc rgb 'black' lw 1.5 notitle, \
     data skip 1 using ($0 + w):(100*column(csbl)):(0):(100*(column(csbh) - column(csbl))) with vectors heads size 0.06,90 lc rgb 'black' lw 1.5 notitle, \
     data skip 1 using 0:(NaN):xtic(label(strcol(ckind), strcol(csrc), strcol(ctol), strcol(cu), strcol(csig))) notitle
