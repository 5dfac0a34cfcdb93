#!/usr/bin/python3
"""psd-import.py - convert the public four-channel sun-sensor data sets to
sunmc's lab CSV (alpha_deg,beta_deg,i1,i2,i3,i4; one row per reading,
repeated readings as repeated rows).

  scripts/psd-import.py aeroztark SRC --out FILE.csv [--digital]
      SRC: a folder of beta_<deg>.mat files (MATLAB v5, aeroztark/
      FSSCalibration "test data") or one such file.  Each holds data_a
      (810 x 4 channel volts; data_d: 12-bit counts 0..4095 with --digital):
      81 alpha values, -40..40 deg in 1 deg steps, 10 readings each; beta
      from the file name (-2, 7.5; within (-90, 90), one file per beta).
      Channels I1..I4 in the file's order (corner layout:
      x = (I2 + I3 - I1 - I4)/sum, y = (I2 + I4 - I1 - I3)/sum).
  scripts/psd-import.py kenscl SRC --out FILE.csv
      SRC: one CSV (Datetime,Stage Angle,xL,xR,yL,yR,X,Y) of
      kenscl/Sun-Sensor-Calibration, or a folder of them.  A file whose name
      ends in _X.txt is a sweep of alpha (beta = 0), _Y.txt one of beta
      (alpha = 0); the stage angle within (-90, 90).  i1..i4 = yL, yR, xL,
      xR (pairs: design.lateral = duo): in these files the _X sweep moves
      the yL, yR pair's balance and the _Y sweep the xL, xR pair's, so
      x = (i2 - i1)/(i1 + i2) follows alpha.
  scripts/psd-import.py 14og SRC --out FILE.csv
      SRC: merged_data.yaml of 14Og/SunSensorCalibration (elevation,
      azimuth in deg, normalised spot x, y).  The sun vector (sin el cos az,
      sin el sin az, cos el) gives alpha = atan(ux/uz), beta = atan(uy/uz)
      (campaign.table_order = projected); the set has no channel signals,
      so i1..i4 = (1 -+ x)(1 -+ y)/4 in the corner layout, whose ratios are
      x and y exactly.  Elevation within [0, 90) (a sun at or beyond the
      horizon has no alpha, beta), azimuth within [-360, 360], x and y
      within [-1, 1].

A folder's files are written in sorted order, each after a comment line
"# source: NAME" (sunmc skips comment lines), so a split by file can be
made from the CSV alone.

Refused, with "psd-import.py: FILE[:LINE]: message" and exit 2, nothing
written: a value that is not a finite decimal number (nan, inf, 1e999,
complex, a cell array), an empty or mis-shaped array, a row whose cell
count differs from the header's, a file whose rows do not fit the set's
grid, an angle out of its range, two files of one beta, an --out that is a
folder, lies in a missing folder or is one of the inputs (same path or
same file).  FILE.csv is written through a temporary file beside it and
renamed, so it is whole or untouched; the temporary file is removed on
any failure.
"""
import math
import os
import re
import sys
import tempfile
import warnings

PROG = "psd-import.py"
USAGE = "usage: psd-import.py aeroztark|kenscl|14og SRC --out FILE.csv [--digital] (--help)\n"

# aeroztark: 81 alphas, -40..40 deg in 1 deg steps, 10 readings each.
AZ_ALPHAS = 81
AZ_ALPHA_FIRST_DEG = -40.0
AZ_READINGS = 10
AZ_ROWS = AZ_ALPHAS * AZ_READINGS
AZ_CHANNELS = 4
AZ_COUNTS_MAX = 4095  # data_d: 12-bit counts
# A table angle at or beyond +-90 deg puts the sun at or behind the horizon.
TABLE_LIMIT_DEG = 90.0
ELEVATION_LIMIT_DEG = 90.0
AZIMUTH_LIMIT_DEG = 360.0
SPOT_LIMIT = 1.0  # normalised spot coordinates
KEN_COLUMNS = ["Stage Angle", "xL", "xR", "yL", "yR"]

NUMBER = re.compile(r"^[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?$")
BETA_NAME = re.compile(r"^beta_(-?[0-9]+(?:\.[0-9]+)?)\.mat$")

# The file being read or written, for the message of an unexpected error.
current = ["(arguments)"]


class Refusal(Exception):
    """Input the importer cannot stand behind; the text names the file."""


def number(text, where, what):
    """The finite decimal number in text, else a Refusal naming where."""
    s = text.strip()
    if not NUMBER.match(s):
        raise Refusal("%s: %s is not a number: '%s'" % (where, what, s))
    v = float(s)
    if not math.isfinite(v):
        raise Refusal("%s: %s is out of range: '%s'" % (where, what, s))
    return v


def within(v, lo, hi, where, what, hi_open=False):
    if v < lo or v > hi or (hi_open and v == hi):
        raise Refusal("%s: %s %g is outside [%g, %g%s" % (where, what, v, lo, hi,
                                                       ")" if hi_open else "]"))
    return v


def table_angle(v, where, what):
    if not abs(v) < TABLE_LIMIT_DEG:
        raise Refusal("%s: %s %g deg is outside (-%g, %g)" % (where, what, v, TABLE_LIMIT_DEG,
                                                           TABLE_LIMIT_DEG))
    return v


def read_bytes(path):
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        raise Refusal("%s: cannot read (%s)" % (path, e.strerror or e))


# ---- aeroztark -----------------------------------------------------------------

def aeroztark_beta(path):
    m = BETA_NAME.match(os.path.basename(path))
    if not m:
        raise Refusal("%s: the file name must be beta_<deg>.mat, <deg> a number as -2 or 7.5"
                      % path)
    return table_angle(float(m.group(1)), path, "beta")


def aeroztark_array(path, digital):
    try:
        import numpy as np
        import scipy.io
    except ImportError:
        raise Refusal("%s: reading .mat needs python3-scipy (scripts/install-deps.sh)" % path)
    read_bytes(path)  # a missing or unreadable file says so plainly
    try:
        mat = scipy.io.loadmat(path)
    except Exception as e:  # scipy raises several kinds
        raise Refusal("%s: not a MATLAB v5 file (%s)" % (path, str(e).splitlines()[0] if str(e)
                                                           else type(e).__name__))
    key = "data_d" if digital else "data_a"
    if key not in mat:
        raise Refusal("%s: no variable %s" % (path, key))
    d = mat[key]
    if not isinstance(d, np.ndarray) or d.dtype.kind not in "fiu":
        kind = getattr(getattr(d, "dtype", None), "kind", "")
        what = {"c": "complex numbers", "O": "a cell array", "V": "a struct", "b": "logicals",
                "U": "text"}.get(kind, "no real numbers (%s)" % type(d).__name__)
        raise Refusal("%s: %s holds %s, want real numbers" % (path, key, what))
    shape = " x ".join(str(n) for n in d.shape)
    if d.size == 0:
        raise Refusal("%s: %s is empty (%s)" % (path, key, shape))
    if d.shape != (AZ_ROWS, AZ_CHANNELS):
        raise Refusal("%s: %s is %s, want %d x %d (%d alphas x %d readings, 4 channels)"
                      % (path, key, shape, AZ_ROWS, AZ_CHANNELS, AZ_ALPHAS, AZ_READINGS))
    bad = ~np.isfinite(d)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise Refusal("%s: %s row %d channel %d is %s, not a finite number"
                      % (path, key, r + 1, c + 1, d[r, c]))
    if digital:
        bad = (d < 0) | (d > AZ_COUNTS_MAX) | (d != np.floor(d))
        if bad.any():
            r, c = np.argwhere(bad)[0]
            raise Refusal("%s: %s row %d channel %d is %s, not a 12-bit count 0..%d"
                          % (path, key, r + 1, c + 1, d[r, c], AZ_COUNTS_MAX))
    return d


def aeroztark_file(path, digital):
    beta = aeroztark_beta(path)
    d = aeroztark_array(path, digital)
    return [(AZ_ALPHA_FIRST_DEG + i // AZ_READINGS, beta) + tuple(float(v) for v in d[i])
            for i in range(AZ_ROWS)]


def aeroztark_set(paths, digital):
    blocks, seen = [], {}
    for p in paths:
        current[0] = p
        beta = aeroztark_beta(p)
        if beta in seen:
            raise Refusal("%s: beta %g deg is also %s: one file per beta" % (p, beta, seen[beta]))
        seen[beta] = os.path.basename(p)
        blocks.append((os.path.basename(p), aeroztark_file(p, digital)))
    return blocks


# ---- kenscl --------------------------------------------------------------------

def kenscl_file(path):
    name = os.path.basename(path)
    if name.endswith("_X.txt"):
        axis = 0
    elif name.endswith("_Y.txt"):
        axis = 1
    else:
        raise Refusal("%s: the file name must end in _X.txt or _Y.txt" % path)
    text = read_bytes(path).decode("utf-8", errors="replace")
    rows, header, col = [], None, None
    for ln, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.split(",")]
        where = "%s:%d" % (path, ln)
        if header is None:
            header = cells
            if any(header.count(w) != 1 for w in KEN_COLUMNS):
                raise Refusal("%s: header lacks %s (each once)" % (where, KEN_COLUMNS))
            col = [header.index(w) for w in KEN_COLUMNS]
            continue
        if len(cells) != len(header):
            raise Refusal("%s: %d cells, the header has %d" % (where, len(cells), len(header)))
        v = [number(cells[c], where, w) for c, w in zip(col, KEN_COLUMNS)]
        table_angle(v[0], where, "Stage Angle")
        a = v[0] if axis == 0 else 0.0
        b = v[0] if axis == 1 else 0.0
        rows.append((a, b, v[3], v[4], v[1], v[2]))
    if not rows:
        raise Refusal("%s: no data rows" % path)
    return rows


# ---- 14og ----------------------------------------------------------------------

def parse_simple_yaml(path, text):
    """The list-of-maps YAML of 14Og (- key: number), when PyYAML is absent."""
    items = []
    for ln, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        if s.startswith("- "):
            items.append({})
            s = s[2:]
        if ":" not in s or not items:
            raise Refusal("%s:%d: not a list of key: value maps" % (path, ln))
        k, v = s.split(":", 1)
        items[-1][k.strip()] = v.strip()
    return items


def og14_items(path):
    data = read_bytes(path)
    try:
        import yaml
    except ImportError:
        return parse_simple_yaml(path, data.decode("utf-8", errors="replace"))
    try:
        return yaml.safe_load(data)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = "%s:%d" % (path, mark.line + 1) if mark else path
        raise Refusal("%s: not YAML (%s)" % (where, getattr(e, "problem", None) or
                                             str(e).splitlines()[0]))


def yaml_number(v, where, what):
    if isinstance(v, str):
        return number(v, where, what)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise Refusal("%s: %s is not a number: %r" % (where, what, v))
    try:
        f = float(v)
    except OverflowError:
        f = math.inf
    if not math.isfinite(f):
        raise Refusal("%s: %s is out of range: %r" % (where, what, v))
    return f


def og14_point(path, k, it):
    where = "%s: point %d" % (path, k)
    if not isinstance(it, dict) or any(w not in it for w in ("elevation", "azimuth", "x", "y")):
        raise Refusal("%s lacks elevation, azimuth, x or y" % where)
    el = yaml_number(it["elevation"], where, "elevation")
    az = yaml_number(it["azimuth"], where, "azimuth")
    x, y = yaml_number(it["x"], where, "x"), yaml_number(it["y"], where, "y")
    within(el, 0.0, ELEVATION_LIMIT_DEG, where, "elevation", hi_open=True)
    within(az, -AZIMUTH_LIMIT_DEG, AZIMUTH_LIMIT_DEG, where, "azimuth")
    within(x, -SPOT_LIMIT, SPOT_LIMIT, where, "x")
    within(y, -SPOT_LIMIT, SPOT_LIMIT, where, "y")
    el, az = math.radians(el), math.radians(az)
    u = (math.sin(el) * math.cos(az), math.sin(el) * math.sin(az), math.cos(el))
    a, b = math.degrees(math.atan2(u[0], u[2])), math.degrees(math.atan2(u[1], u[2]))
    ch = [(1 + sx * x) * (1 + sy * y) / 4 for sx, sy in ((-1, -1), (1, 1), (1, -1), (-1, 1))]
    return (a, b) + tuple(ch)


def og14_file(path):
    items = og14_items(path)
    if not isinstance(items, list) or not items:
        raise Refusal("%s: not a list of points" % path)
    return [og14_point(path, k + 1, it) for k, it in enumerate(items)]


# ---- files ---------------------------------------------------------------------

def sources(src, pattern):
    if os.path.isdir(src):
        names = sorted(n for n in os.listdir(src) if re.search(pattern, n))
        if not names:
            raise Refusal("%s: no file matches %s" % (src, pattern))
        return [os.path.join(src, n) for n in names]
    if not os.path.exists(src):
        raise Refusal("%s: no such file or folder" % src)
    return [src]


def same_file(a, b):
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        sa, sb = os.stat(a), os.stat(b)
    except OSError:
        return False
    return (sa.st_dev, sa.st_ino) == (sb.st_dev, sb.st_ino)


def check_out(out, inputs):
    """Refuse an --out that is a folder, in a missing folder, or an input."""
    if os.path.isdir(out):
        raise Refusal("%s: is a folder; --out names the CSV file to write" % out)
    parent = os.path.dirname(out) or "."
    if not os.path.isdir(parent):
        raise Refusal("%s: no such folder %s" % (out, parent))
    for p in inputs:
        if same_file(out, p):
            raise Refusal("%s: --out is the input %s; write the CSV elsewhere" % (out, p))


def write_atomic(out, text):
    """text into out through a temporary file beside it, removed on failure."""
    umask = os.umask(0)
    os.umask(umask)
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(out) + ".", suffix=".tmp",
                                   dir=os.path.dirname(out) or ".")
    except OSError as e:
        raise Refusal("%s: cannot write (%s)" % (out, e.strerror or e))
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, out)
    except BaseException as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(e, OSError):
            raise Refusal("%s: cannot write (%s); nothing written" % (out, e.strerror or e))
        raise


def csv_text(fmt, src, blocks):
    lines = ["# sunmc lab data imported by scripts/psd-import.py %s from %s" % (fmt, src),
             "alpha_deg,beta_deg,i1,i2,i3,i4"]
    for name, rows in blocks:
        lines.append("# source: %s" % name)
        lines.extend(",".join("%.10g" % v for v in r) for r in rows)
    return "\n".join(lines) + "\n"


def run(argv):
    if any(a in ("-h", "--help") for a in argv[1:]):
        sys.stdout.write(__doc__)
        return 0
    args = [a for a in argv[1:] if a != "--digital"]
    digital = len(args) != len(argv) - 1
    if len(args) != 4 or args[2] != "--out" or args[0] not in ("aeroztark", "kenscl", "14og"):
        sys.stderr.write(USAGE)
        return 2
    fmt, src, out = args[0], args[1], args[3]
    if digital and fmt != "aeroztark":
        raise Refusal("--digital: only aeroztark has digital counts")
    current[0] = src
    if fmt == "aeroztark":
        paths = sources(src, r"^beta_.*\.mat$")
    elif fmt == "kenscl":
        paths = sources(src, r"_[XY]\.txt$")
    else:
        if os.path.isdir(src):
            raise Refusal("%s: is a folder; 14og reads one file (merged_data.yaml)" % src)
        paths = sources(src, "")
    check_out(out, paths)
    if fmt == "aeroztark":
        blocks = aeroztark_set(paths, digital)
    else:
        blocks = []
        for p in paths:
            current[0] = p
            blocks.append((os.path.basename(p), kenscl_file(p) if fmt == "kenscl" else og14_file(p)))
    current[0] = out
    write_atomic(out, csv_text(fmt, src, blocks))
    print("psd-import: %d rows from %d file(s) into %s" % (sum(len(r) for _, r in blocks),
                                                         len(blocks), out))
    return 0


def main(argv):
    """run(argv); every refusal and any unexpected error: one line, exit 2."""
    warnings.filterwarnings("error", category=RuntimeWarning)
    warnings.filterwarnings("error", category=UserWarning)
    try:
        return run(argv)
    except Refusal as e:
        sys.stderr.write("%s: %s\n" % (PROG, e))
    except Exception as e:  # a bug or an input no check foresaw: still no traceback
        sys.stderr.write("%s: %s: unexpected %s: %s\n" % (PROG, current[0], type(e).__name__,
                                                          str(e).splitlines()[0] if str(e) else ""))
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
