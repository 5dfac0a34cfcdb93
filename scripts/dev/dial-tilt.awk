# dial-tilt.awk - the ESS paper's sec. 3.2 findings from `sunmc curve`'s
# curve.tsv of one error source at beta = 0 every 0.05 deg over -62..62
# (docs/ess.md, "Which the paper's figures show"), summed as
# tests/oracle/test_ess_paper_findings.c's test_paper_dial_tilt_findings
# does: the largest |error|, its mean at |alpha| < 5 and at |alpha| >= 55,
# the mean |second difference| of the error sampled every 0.5 deg over
# -40..40 at a 0.5-deg and a 1-deg spacing, and how often the 0.5-deg one
# changes sign.  Usage: awk -F'\t' -f scripts/dev/dial-tilt.awk curve.tsv
$2 == 0 && $1 ~ /^-?[0-9.]+$/ {
    e = $3; a = e < 0 ? -e : e
    if (a > mx) mx = a
    if ($1 > -5 && $1 < 5) { lo += a; nlo++ }
    if ($1 >= 55 || $1 <= -55) { hi += a; nhi++ }
    E[sprintf("%.0f", $1 * 20)] = e     # keyed by alpha in 0.05-deg steps
}
END {
    if (nlo == 0 || nhi == 0) { print "dial-tilt.awk: no alpha rows at beta = 0" > "/dev/stderr"; exit 2 }
    for (k = -800; k <= 800; k += 10) {
        if (!((k - 20) in E) || !((k + 20) in E)) { print "dial-tilt.awk: the grid is not every 0.05 deg over -41..41" > "/dev/stderr"; exit 2 }
        sh = E[k - 10] - 2 * E[k] + E[k + 10]
        s1 = E[k - 20] - 2 * E[k] + E[k + 20]
        dh += sh < 0 ? -sh : sh
        d1 += s1 < 0 ? -s1 : s1
        if (n > 0 && sh * p < 0) f++
        p = sh; n++
    }
    printf "max %.5f low %.5f high %.5f second %.5f %.6f flips %d of %d\n", mx, lo / nlo, hi / nhi, dh / n, d1 / n, f, n - 1
}
