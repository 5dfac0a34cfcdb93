# sweep.gp - a design trade from `sunmc sweep --out RUN`: mean RMS error after
# (solid) and before (dashed) calibration vs the first varied key, one line
# per band (one axis) or per value of the second key in the widest band (two
# axes), each point with its confidence interval (sweep.tsv's _ci_lo and
# _ci_hi columns) as an error bar; the spec as a horizontal line.  A key
# varied over alternatives (e.g. campaign.beta_deg=-20,0,20|-30,0,30) is
# drawn at evenly spaced x with its `label` as tick.  Points whose campaign
# aliased (column `aliased`) are drawn as crosses and not joined to their
# neighbours: the curve is broken there.  A sweep of campaign.alpha_step_deg
# of ESS type A or B also shows the ESS paper's Table 2 (squares: after,
# diamonds: before calibration).
#   gnuplot -e "run='runs/step'" scripts/sweep.gp    [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/sweep.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/sweep.svg' : '/sweep.png')
if (svg) { set terminal svg size 900,680 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,680 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
field(c, row) = system(sprintf("awk -F'\\t' 'NR==%d {print $%d}' '%s'", row, c, file))
uniq(c) = system(sprintf("awk -F'\\t' 'NR>1 && !s[$%d]++ {printf \"%%s \", $%d}' '%s'", c, c, file))
nlead = col('product') - 1   # the varied keys, label, aliased
ca = col('angle'); cb = col('band')
cbef = col('rms_before_mean'); caft = col('rms_after_mean')
cbl = col('rms_before_mean_ci_lo'); cbh = col('rms_before_mean_ci_hi')
cal = col('rms_after_mean_ci_lo'); cah = col('rms_after_mean_ci_hi')
level = real(field(col('confidence'), 2))
unit = field(col('rms_unit'), 2)
spec = real(field(col('spec_arcsec'), 2)) / (unit eq 'deg' ? 3600.0 : 1.0)
angles = uniq(ca)
angle = word(angles, words(angles))
bands = uniq(cb)
wide = word(bands, words(bands))
# What a band bins: the ESS its own angle's magnitude, the DSS and PSD the field angle.
bandvar = field(col('family'), 2) eq 'ess' ? '|'.angle.'|' : 'field angle'
cali = col('aliased'); clab = col('label')
# Every selected row is prefixed with its point number (column 1, so every
# sweep.tsv column moves up by one); an aliased row becomes a blank line in
# the curves (breaking them) and is the only kind of row in the crosses.
# aliased = 2 keeps every row (the error before calibration has no campaign).
pick(cond, aliased) = sprintf("< awk -F'\\t' 'NR>1 && %s {n++; if ($%d==%d || %d==2) print n-1 \"\\t\" $0; else if (!%d) print \"\"}' '%s'", cond, cali, aliased, aliased, aliased, file)
selb(b) = pick(sprintf("$%d==\"%s\" && $%d==\"%s\"", ca, angle, cb, b), 2)
selb2(v) = pick(sprintf("$%d==\"%s\" && $%d==\"%s\" && $2==\"%s\"", ca, angle, cb, wide, v), 2)
sel(b) = pick(sprintf("$%d==\"%s\" && $%d==\"%s\"", ca, angle, cb, b), 0)
sela(b) = pick(sprintf("$%d==\"%s\" && $%d==\"%s\"", ca, angle, cb, b), 1)
sel2(v) = pick(sprintf("$%d==\"%s\" && $%d==\"%s\" && $2==\"%s\"", ca, angle, cb, wide, v), 0)
sela2(v) = pick(sprintf("$%d==\"%s\" && $%d==\"%s\" && $2==\"%s\"", ca, angle, cb, wide, v), 1)
# A number axis is drawn against its values, alternatives against their labels.
xnum = int(system(sprintf("awk -F'\\t' 'NR>1 && $1 !~ /^[-+]?[0-9.]+([eE][-+]?[0-9]+)?$/ {n++} END {print n+0}' '%s'", file))) == 0
ua(c, l, h) = xnum ? sprintf("2:%d:%d:%d", c+1, l+1, h+1) : sprintf("1:%d:%d:%d:xtic(%d)", c+1, l+1, h+1, clab+1)
UA = ua(caft, cal, cah); UB = ua(cbef, cbl, cbh)
n_alias = int(system(sprintf("awk -F'\\t' 'NR>1 && $%d==1' '%s' | wc -l", cali, file)))

set title sprintf("%s: sweep of %s (error bars: %g%% confidence)", field(col('product'), 2), word(hdr, 1), 100 * level).(exists("note") ? "\n".note : "")
# the varied key with its unit: campaign.alpha_step_deg -> campaign.alpha_step [deg]
kunit(k) = system(sprintf("echo '%s' | sed -nE 's/.*_(deg|arcsec|um|mm|px|pct|h|s|ppm_k|c)$/\\1/p'", k))
xunit = kunit(word(hdr, 1))
set xlabel strlen(xunit) > 0 ? sprintf('%s [%s]', word(hdr, 1)[1:strlen(word(hdr, 1)) - strlen(xunit) - 1], xunit) : word(hdr, 1)
set ylabel sprintf('mean RMS error of %s [%s]', angle, unit)
set grid
set key outside below horizontal maxcols 3 width -4   # below: the plot and its title keep the full width
# One linear axis hides the after-calibration curves (and the spec) on the
# floor when the before curves are over 10 times higher: then a log axis.
yext(c, f) = real(system(sprintf("awk -F'\\t' 'NR>1 && $%d==\"%s\" && $%d > 0 {v=$%d; if (!n++ || %s) m=v} END {print m+0}' '%s'", ca, angle, c, c, f, file)))
ylo = yext(caft, 'v < m'); yhi = yext(cbef, 'v > m')
ylo = (spec > 0 && spec < ylo) ? spec : ylo
yhi = (spec > yhi) ? spec : yhi
logy = ylo > 0 && yhi / ylo > 10
if (logy) {
  set logscale y
  set yrange [ylo / 1.6 : yhi * 1.6]
  set ylabel sprintf('mean RMS error of %s [%s], log scale', angle, unit)
  # labels at 1, 2, 5 of every decade: a decade or two of range has them
  # all inside, not only the powers of ten (issue 41)
  set ytics format '%g'
  do for [e = floor(log10(ylo / 1.6)) : ceil(log10(yhi * 1.6))] {
    set ytics add (sprintf('%g', 10.0**e) 10.0**e, sprintf('%g', 2 * 10.0**e) 2 * 10.0**e, sprintf('%g', 5 * 10.0**e) 5 * 10.0**e)
  }
} else {
  set yrange [0:*]
}
if (!xnum) { set xtics rotate by -30; set offsets 0.5, 0.5, 0, 0 } else { set offsets graph 0.04, graph 0.04, 0, 0 }  # no marker half-clipped at the ends
# The ESS paper's Table 2 (one unit of each type, |alpha| <= 62 deg): drawn
# over a sweep of campaign.alpha_step_deg of product "ESS type A" or "B",
# against the widest band (macro @T2).
$T2 << EOD
A	1	0.0399	0.0141
A	0.25	0.0296	0.0102
B	1	0.020	0.007
B	0.25	0.0191	0.0056
EOD
prod = field(col('product'), 2)
ptype = prod eq 'ESS type A' ? 'A' : prod eq 'ESS type B' ? 'B' : ''
T2 = (nlead == 3 && word(hdr, 1) eq 'campaign.alpha_step_deg' && ptype ne '') ? \
     sprintf("$T2 using (strcol(1) eq '%s' ? $2 : NaN):4 with points pt 4 ps 2.5 lw 2 lc rgb 'black' title 'ESS paper Table 2, after (one type %s unit)', $T2 using (strcol(1) eq '%s' ? $2 : NaN):3 with points pt 12 ps 2.5 lw 2 lc rgb 'black' title 'ESS paper Table 2, before',", ptype, ptype, ptype) : ""
# The aliased points' crosses, only when there are some (macros @AL1, @AL2).
AL1 = n_alias > 0 ? "for [i=1:words(bands)] sela(word(bands, i)) using @UA with yerrorbars pt 2 ps 2 lw 2 lc i notitle, NaN with points pt 2 ps 2 lw 2 lc rgb 'black' title 'aliased (not joined)'," : ""
AL2 = n_alias > 0 ? "for [i=1:words(vals)] sela2(word(vals, i)) using @UA with yerrorbars pt 2 ps 2 lw 2 lc i notitle, NaN with points pt 2 ps 2 lw 2 lc rgb 'black' title 'aliased (not joined)'," : ""
# Points whose campaign scan stops short of the validation (extrapolation_deg
# > 0: the compensation extrapolates there) ringed in grey (macro @EX).
cex = col('extrapolation_deg')
n_ex = cex > 0 ? int(system(sprintf("awk -F'\\t' 'NR>1 && $%d > 0' '%s' | wc -l", cex, file))) : 0
exsel = pick(sprintf("$%d==\"%s\" && $%d==\"%s\" && $%d > 0", ca, angle, cb, wide, cex), 2)
EX = n_ex > 0 ? sprintf("exsel using %s with points pt 6 ps 3.5 lw 1.5 lc rgb '#888888' title 'scan short: extrapolates',", xnum ? "2:".(caft+1) : "1:".(caft+1)) : ""
if (nlead == 3) {
  plot for [i=1:words(bands)] sel(word(bands, i)) using @UA with yerrorlines lw 2 pt 7 lc i title 'after, '.bandvar.' '.word(bands, i).' deg', \
       for [i=1:words(bands)] selb(word(bands, i)) using @UB with yerrorlines dt 2 pt 6 lc i title 'before, '.bandvar.' '.word(bands, i).' deg', \
       @AL1 @EX @T2 \
       spec with lines lw 2 lc rgb 'red' dt 3 title sprintf('spec %g %s', spec, unit)
} else {
  vals = uniq(2)
  plot for [i=1:words(vals)] sel2(word(vals, i)) using @UA with yerrorlines lw 2 pt 7 lc i title sprintf('after, %s = %s', word(hdr, 2), word(vals, i)), \
       for [i=1:words(vals)] selb2(word(vals, i)) using @UB with yerrorlines dt 2 pt 6 lc i title sprintf('before, %s = %s', word(hdr, 2), word(vals, i)), \
       @AL2 @EX \
       spec with lines lw 2 lc rgb 'red' dt 3 title sprintf('spec %g %s (%s %s deg)', spec, unit, bandvar, wide)
}
