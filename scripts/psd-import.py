#!/usr/bin/python3
"""psd-import.py - convert the public four-channel sun-sensor data sets to
sunmc's lab CSV (alpha_deg,beta_deg,i1,i2,i3,i4; one row per reading,
repeated readings as repeated rows).

  scripts/psd-import.py aeroztark SRC --out FILE.csv [--digital]
      SRC: a folder of beta_<deg>.mat files (MATLAB v5, aeroztark/
      FSSCalibration "test data") or one such file.  Each holds data_a
      (810 x 4 channel volts; data_d: 12-bit counts with --digital): 81
      alpha values, -40..40 deg in 1 deg steps, 10 readings each; beta from
      the file name.  Channels I1..I4 in the file's order (corner layout:
      x = (I2 + I3 - I1 - I4)/sum, y = (I2 + I4 - I1 - I3)/sum).
  scripts/psd-import.py kenscl SRC --out FILE.csv
      SRC: one CSV (Datetime,Stage Angle,xL,xR,yL,yR,X,Y) of
      kenscl/Sun-Sensor-Calibration, or a folder of them.  A file whose name
      ends in _X.txt is a sweep of alpha (beta = 0), _Y.txt one of beta
      (alpha = 0).  i1..i4 = yL, yR, xL, xR (pairs: design.lateral = duo):
      in these files the _X sweep moves the yL, yR pair's balance and the
      _Y sweep the xL, xR pair's, so x = (i2 - i1)/(i1 + i2) follows alpha.
  scripts/psd-import.py 14og SRC --out FILE.csv
      SRC: merged_data.yaml of 14Og/SunSensorCalibration (elevation,
      azimuth in deg, normalised spot x, y).  The sun vector (sin el cos az,
      sin el sin az, cos el) gives alpha = atan(ux/uz), beta = atan(uy/uz)
      (campaign.table_order = projected); the set has no channel signals,
      so i1..i4 = (1 -+ x)(1 -+ y)/4 in the corner layout, whose ratios are
      x and y exactly.

A folder's files are written in sorted order, each after a comment line
"# source: NAME" (sunmc skips comment lines), so a split by file can be
made from the CSV alone.  Exit 2 with FILE: message for input it cannot
read; nothing is written then.
"""
import math
import os
import re
import sys


class ImportError_(Exception):
    pass


def aeroztark_file(path, digital):
    try:
        import scipy.io
    except ImportError:
        raise ImportError_("reading .mat needs python3-scipy (scripts/install-deps.sh)")
    m = re.search(r"beta_(-?[0-9.]+)\.mat$", os.path.basename(path))
    if not m:
        raise ImportError_("%s: the file name must be beta_<deg>.mat" % path)
    beta = float(m.group(1))
    try:
        mat = scipy.io.loadmat(path)
    except Exception as e:  # scipy raises several kinds
        raise ImportError_("%s: not a MATLAB v5 file (%s)" % (path, e))
    key = "data_d" if digital else "data_a"
    if key not in mat:
        raise ImportError_("%s: no variable %s" % (path, key))
    d = mat[key]
    if d.ndim != 2 or d.shape[1] != 4 or d.shape[0] % 10 != 0:
        raise ImportError_("%s: %s is %s, want (10 n) x 4" % (path, key, d.shape))
    n_alpha = d.shape[0] // 10
    first = -(n_alpha - 1) / 2.0
    rows = []
    for i in range(d.shape[0]):
        rows.append((first + i // 10, beta) + tuple(float(v) for v in d[i]))
    return rows


def kenscl_file(path):
    name = os.path.basename(path)
    if name.endswith("_X.txt"):
        axis = 0
    elif name.endswith("_Y.txt"):
        axis = 1
    else:
        raise ImportError_("%s: the file name must end in _X.txt or _Y.txt" % path)
    rows = []
    with open(path, encoding="utf-8", errors="replace") as f:
        header = None
        for ln, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cells = line.split(",")
            if header is None:
                header = cells
                want = ["Stage Angle", "xL", "xR", "yL", "yR"]
                if any(w not in header for w in want):
                    raise ImportError_("%s:%d: header lacks %s" % (path, ln, want))
                col = [header.index(w) for w in want]
                continue
            try:
                v = [float(cells[c]) for c in col]
            except (ValueError, IndexError):
                raise ImportError_("%s:%d: not a number row" % (path, ln))
            a = v[0] if axis == 0 else 0.0
            b = v[0] if axis == 1 else 0.0
            rows.append((a, b, v[3], v[4], v[1], v[2]))
    if not rows:
        raise ImportError_("%s: no data rows" % path)
    return rows


def parse_simple_yaml(path):
    """The list-of-maps YAML of 14Og (- key: number); PyYAML when present."""
    try:
        import yaml
        with open(path) as f:
            return yaml.safe_load(f)
    except ImportError:
        pass
    items = []
    with open(path) as f:
        for ln, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            if s.startswith("- "):
                items.append({})
                s = s[2:]
            if ":" not in s or not items:
                raise ImportError_("%s:%d: not a list of key: value maps" % (path, ln))
            k, v = s.split(":", 1)
            items[-1][k.strip()] = float(v)
    return items


def og14_file(path):
    try:
        items = parse_simple_yaml(path)
    except ValueError as e:
        raise ImportError_("%s: %s" % (path, e))
    if not isinstance(items, list) or not items:
        raise ImportError_("%s: not a list of points" % path)
    rows = []
    for k, it in enumerate(items):
        try:
            el, az = math.radians(float(it["elevation"])), math.radians(float(it["azimuth"]))
            x, y = float(it["x"]), float(it["y"])
        except (KeyError, TypeError, ValueError):
            raise ImportError_("%s: point %d lacks elevation, azimuth, x or y" % (path, k + 1))
        u = (math.sin(el) * math.cos(az), math.sin(el) * math.sin(az), math.cos(el))
        a, b = math.degrees(math.atan2(u[0], u[2])), math.degrees(math.atan2(u[1], u[2]))
        ch = [(1 + sx * x) * (1 + sy * y) / 4 for sx, sy in ((-1, -1), (1, 1), (1, -1), (-1, 1))]
        rows.append((a, b) + tuple(ch))
    return rows


def sources(src, pattern):
    if os.path.isdir(src):
        names = sorted(n for n in os.listdir(src) if re.search(pattern, n))
        if not names:
            raise ImportError_("%s: no file matches %s" % (src, pattern))
        return [os.path.join(src, n) for n in names]
    if not os.path.exists(src):
        raise ImportError_("%s: no such file or folder" % src)
    return [src]


def main(argv):
    args = [a for a in argv[1:] if a != "--digital"]
    digital = len(args) != len(argv) - 1
    if len(args) != 4 or args[2] != "--out" or args[0] not in ("aeroztark", "kenscl", "14og"):
        sys.stderr.write("usage: psd-import.py aeroztark|kenscl|14og SRC --out FILE.csv "
                         "[--digital]\n")
        return 2
    fmt, src, out = args[0], args[1], args[3]
    try:
        blocks = []
        if fmt == "aeroztark":
            for p in sources(src, r"^beta_-?[0-9.]+\.mat$"):
                blocks.append((os.path.basename(p), aeroztark_file(p, digital)))
        elif fmt == "kenscl":
            for p in sources(src, r"_[XY]\.txt$"):
                blocks.append((os.path.basename(p), kenscl_file(p)))
        else:
            blocks.append((os.path.basename(src), og14_file(src)))
    except ImportError_ as e:
        sys.stderr.write("psd-import: %s\n" % e)
        return 2
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.write("# sunmc lab data imported by scripts/psd-import.py %s from %s\n" % (fmt, src))
        f.write("alpha_deg,beta_deg,i1,i2,i3,i4\n")
        for name, rows in blocks:
            f.write("# source: %s\n" % name)
            for r in rows:
                f.write(",".join("%.10g" % v for v in r) + "\n")
    os.replace(tmp, out)
    print("psd-import: %d rows from %d file(s) into %s" % (sum(len(r) for _, r in blocks),
                                                         len(blocks), out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
