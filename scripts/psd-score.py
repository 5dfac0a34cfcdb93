#!/usr/bin/python3
"""psd-score.py - score `sunmc compensate` output of the four-channel
sensor against its truth columns.

  scripts/psd-score.py COMPENSATED.csv [--mean]

COMPENSATED.csv: the output of `sunmc compensate` on a lab CSV with the
table angles (alpha_deg, beta_deg), so that it holds compensated_alpha_deg,
compensated_beta_deg, truth_alpha_deg, truth_beta_deg.  Prints the RMS of
the total angular error (the angle between the compensated and the true
sun vectors) and per axis, in arcsec, over single readings, and with
--mean over the means of the readings at each table position (repeated
rows averaged first, as FSScalibration does).  Rows that could not be
compensated (nan) are counted and left out.
"""
import math
import sys


def vec(a_deg, b_deg):
    tx, ty = math.tan(math.radians(a_deg)), math.tan(math.radians(b_deg))
    n = math.sqrt(1 + tx * tx + ty * ty)
    return (tx / n, ty / n, 1 / n)


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    mean = "--mean" in argv
    rows, names = [], None
    with open(argv[1]) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            cells = line.strip().split(",")
            if names is None:
                names = cells
                try:
                    ix = [names.index(c) for c in ("alpha_deg", "beta_deg", "compensated_alpha_deg",
                                                   "compensated_beta_deg", "truth_alpha_deg",
                                                   "truth_beta_deg")]
                except ValueError as e:
                    sys.stderr.write("psd-score: %s: %s\n" % (argv[1], e))
                    return 2
                continue
            rows.append([float(cells[i]) for i in ix])
    failed = sum(1 for r in rows if any(math.isnan(v) for v in r))
    rows = [r for r in rows if not any(math.isnan(v) for v in r)]
    if mean:
        groups = {}
        for r in rows:
            groups.setdefault((r[0], r[1]), []).append(r)
        rows = [[sum(c) / len(g) for c in zip(*g)] for g in groups.values()]
    s2 = sa = sb = 0.0
    for r in rows:
        u, v = vec(r[2], r[3]), vec(r[4], r[5])
        c = sum(x * y for x, y in zip(u, v))
        cross = math.sqrt(max(0.0, 1 - c * c))
        e = math.degrees(math.atan2(cross, c)) * 3600
        s2 += e * e
        sa += ((r[2] - r[4]) * 3600) ** 2
        sb += ((r[3] - r[5]) * 3600) ** 2
    n = len(rows)
    if n == 0:
        sys.stderr.write("psd-score: no row could be scored\n")
        return 2
    print("%s: %d %s, %d failed; RMS total %.1f arcsec, alpha %.1f, beta %.1f"
          % (argv[1], n, "points (means)" if mean else "readings", failed, math.sqrt(s2 / n),
             math.sqrt(sa / n), math.sqrt(sb / n)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
