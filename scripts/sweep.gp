# sweep.gp - a design trade from `sunmc sweep --out RUN`: mean RMS error after
# (solid) and before (dashed) calibration vs the first varied key, one line
# per band (one axis) or per value of the second key in the widest band (two
# axes), each point with its confidence interval (sweep.tsv's _ci_lo and
# _ci_hi columns) as an error bar; the spec as a horizontal line.
#   gnuplot -e "run='runs/step'" scripts/sweep.gp    [-e "out='x.png'"] [-e "svg=1"]
if (!exists("run")) run = '.'
file = run.'/sweep.tsv'
if (!exists("svg")) svg = 0
if (!exists("out")) out = run.(svg ? '/sweep.svg' : '/sweep.png')
if (svg) { set terminal svg size 900,600 dynamic font 'Sans,12' } else { set terminal pngcairo size 900,600 font 'Sans,11' }
set output out
set termoption noenhanced
set datafile separator "\t"

hdr = system(sprintf("head -1 '%s'", file))
col(n) = sum [i=1:words(hdr)] (word(hdr, i) eq n ? i : 0)
field(c, row) = system(sprintf("awk -F'\\t' 'NR==%d {print $%d}' '%s'", row, c, file))
uniq(c) = system(sprintf("awk -F'\\t' 'NR>1 && !s[$%d]++ {printf \"%%s \", $%d}' '%s'", c, c, file))
nlead = col('product') - 1
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
sel(b) = sprintf("< awk -F'\\t' 'NR>1 && $%d==\"%s\" && $%d==\"%s\"' '%s'", ca, angle, cb, b, file)
sel2(v) = sprintf("< awk -F'\\t' 'NR>1 && $%d==\"%s\" && $%d==\"%s\" && $2==\"%s\"' '%s'", ca, angle, cb, wide, v, file)

set title sprintf("%s: sweep of %s (error bars: %g%% confidence)", field(col('product'), 2), word(hdr, 1), 100 * level)
set xlabel word(hdr, 1).' (unit in the key name)'
set ylabel sprintf('mean RMS error of %s [%s]', angle, unit)
set grid
set key outside right top
set yrange [0:*]
if (nlead == 1) {
  plot for [i=1:words(bands)] sel(word(bands, i)) using 1:caft:cal:cah with yerrorlines lw 2 pt 7 lc i title 'after, |x| '.word(bands, i).' deg', \
       for [i=1:words(bands)] sel(word(bands, i)) using 1:cbef:cbl:cbh with yerrorlines dt 2 pt 6 lc i title 'before, |x| '.word(bands, i).' deg', \
       spec with lines lw 2 lc rgb 'red' dt 3 title sprintf('spec %g %s', spec, unit)
} else {
  vals = uniq(2)
  plot for [i=1:words(vals)] sel2(word(vals, i)) using 1:caft:cal:cah with yerrorlines lw 2 pt 7 lc i title sprintf('after, %s = %s', word(hdr, 2), word(vals, i)), \
       for [i=1:words(vals)] sel2(word(vals, i)) using 1:cbef:cbl:cbh with yerrorlines dt 2 pt 6 lc i title sprintf('before, %s = %s', word(hdr, 2), word(vals, i)), \
       spec with lines lw 2 lc rgb 'red' dt 3 title sprintf('spec %g %s (|x| %s deg)', spec, unit, wide)
}
