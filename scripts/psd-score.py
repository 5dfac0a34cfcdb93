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
compensated ("-", or nan) are counted and left out.

Refused, with "psd-score.py: FILE[:LINE]: message" and exit 2: a file that
cannot be read or lacks a column, a row whose cell count differs from the
header's, a value that is neither a finite decimal number nor nan.
"""
import math
import re
import sys

PROG = "psd-score.py"
COLUMNS = ("alpha_deg", "beta_deg", "compensated_alpha_deg", "compensated_beta_deg",
           "truth_alpha_deg", "truth_beta_deg")
NUMBER = re.compile(r"^[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?$")
NAN = ("nan", "-nan", "-")  # "-": sunmc compensate's mark of a reading it could not compensate


class Refusal(Exception):
    """Input the scorer cannot stand behind; the text names the file."""


def vec(a_deg, b_deg):
    tx, ty = math.tan(math.radians(a_deg)), math.tan(math.radians(b_deg))
    n = math.sqrt(1 + tx * tx + ty * ty)
    return (tx / n, ty / n, 1 / n)


def value(cell, where, name):
    """A finite number, or nan (a row compensate could not invert)."""
    s = cell.strip()
    if s.lower() in NAN:
        return math.nan
    v = float(s) if NUMBER.match(s) else math.inf
    if not math.isfinite(v):
        raise Refusal("%s: %s is not a finite number: '%s'" % (where, name, s))
    return v


def read_rows(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
    except OSError as e:
        raise Refusal("%s: cannot read (%s)" % (path, e.strerror or e))
    rows, names, ix = [], None, None
    for ln, line in enumerate(text.splitlines(), 1):
        if line.startswith("#") or not line.strip():
            continue
        cells = line.strip().split(",")
        where = "%s:%d" % (path, ln)
        if names is None:
            names = cells
            missing = [c for c in COLUMNS if c not in names]
            if missing:
                raise Refusal("%s: no column %s" % (where, ", ".join(missing)))
            ix = [names.index(c) for c in COLUMNS]
            continue
        if len(cells) != len(names):
            raise Refusal("%s: %d cells, the header has %d" % (where, len(cells), len(names)))
        rows.append([value(cells[i], where, c) for i, c in zip(ix, COLUMNS)])
    return rows


def run(argv):
    opts = [a for a in argv[1:] if a.startswith("-")]
    files = [a for a in argv[1:] if not a.startswith("-")]
    if len(files) != 1 or any(o != "--mean" for o in opts):
        sys.stderr.write(__doc__)
        return 2
    mean = "--mean" in opts
    path = files[0]
    rows = read_rows(path)
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
        raise Refusal("%s: no row could be scored (%d failed)" % (path, failed))
    print("%s: %d %s, %d failed; RMS total %.1f arcsec, alpha %.1f, beta %.1f"
          % (path, n, "points (means)" if mean else "readings", failed, math.sqrt(s2 / n),
             math.sqrt(sa / n), math.sqrt(sb / n)))
    return 0


def main(argv):
    """run(argv); every refusal and any unexpected error: one line, exit 2."""
    try:
        return run(argv)
    except Refusal as e:
        sys.stderr.write("%s: %s\n" % (PROG, e))
    except Exception as e:  # a bug or an input no check foresaw: still no traceback
        sys.stderr.write("%s: %s: unexpected %s: %s\n" % (PROG, argv[1:], type(e).__name__, e))
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
