#!/usr/bin/python3
"""fuzz-import.py - fuzz scripts/psd-import.py and scripts/psd-score.py
(`make fuzz` runs it after the libFuzzer harnesses; `make fuzz-import`
alone).

  scripts/dev/fuzz-import.py [--seconds N] [--work DIR] [--seed S]

Mutates small well-formed seed inputs of the three formats (a beta_1.mat
of 810 x 4, a kenscl _X.txt, a 14og YAML) and a compensated CSV for the
scorer, for N seconds (default 60): numbers swapped for nasty ones (nan,
inf, 1e999, 95, ...), cells and lines dropped or doubled, bytes flipped,
arrays of other shapes and types, odd file names, --out onto the input or
a folder.  Each run must exit 0 or 2 with no traceback and no "unexpected"
error (the wrapper's "FILE: unexpected TYPE: ..." for a check the importer lacks); on exit 2 nothing is written; no
temporary file is left; the inputs are unchanged; an exit 0 writes only
finite rows with |alpha|, |beta| < 90.  A failing case is kept in
DIR/crash-K/ (DIR default build/fuzz/import) with the command; exit 1.
"""
import hashlib
import math
import os
import re
import random
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
IMPORT = os.path.join(ROOT, "scripts", "psd-import.py")
SCORE = os.path.join(ROOT, "scripts", "psd-score.py")
NASTY = ["nan", "-nan", "NaN", "inf", "-inf", "Infinity", "1e999", "-1e999", "1e400", "1e-400",
         "95", "90", "-90", "89.999999", "180", "-0.5", "0", "-0", "1_0", "0x10", "", " ", "x",
         ".nan", ".inf", "-.inf", "true", "null", "~", "[1,", "{a: 1}", "1e308", "-1e308",
         "99999999999999999999999999999999999999", "1.5", "4095", "4096", "-1", "\xff"]
BETA_NAMES = ["beta_1.mat", "beta_-1.mat", "beta_1.5.mat", "beta_1.2.3.mat", "beta_..mat",
              "beta_90.mat", "beta_-89.5.mat", "beta_x.mat", "beta_.mat", "beta_01.mat"]
KEN_SEED = ("# Sensor: ADPD2140, Rotationstage: ELL18M\n"
            "Datetime,Stage Angle,xL,xR,yL,yR,X,Y\n"
            "01.12.2021 18:29:29,-59.992,650.634,648.529,392.150,718.597,-46.576,0.256\n"
            "01.12.2021 18:29:30,-59.904,653.198,650.604,393.188,720.397,-46.566,0.315\n"
            "01.12.2021 18:29:31,10.5,653.198,650.604,393.188,720.397,-46.566,0.315\n")
OG_SEED = ("- elevation: 0.0\n  azimuth: 45.0\n  x: -0.0511\n  y: 0.0320\n"
           "- elevation: 3.993\n  azimuth: 90.0\n  x: -0.0659\n  y: 0.0228\n"
           "- elevation: 45\n  azimuth: 300.5\n  x: 0.1\n  y: -0.2\n")
SCORE_SEED = ("# compensated\nalpha_deg,beta_deg,i1,i2,i3,i4,compensated_alpha_deg,"
              "compensated_beta_deg,truth_alpha_deg,truth_beta_deg\n"
              "1,2,0.1,0.2,0.3,0.4,1.0001,2.0002,1,2\n"
              "1,2,0.1,0.2,0.3,0.4,nan,nan,1,2\n"
              "-3,4,0.1,0.2,0.3,0.4,-3.001,4,-3,4\n")


def tokens(text):
    """Spans of the numbers and words in text."""
    spans, i = [], 0
    while i < len(text):
        if text[i] in ",:\n -" and not text[i].isalnum():
            i += 1
            continue
        j = i
        while j < len(text) and text[j] not in ",:\n ":
            j += 1
        spans.append((i, j))
        i = j
    return spans


def mutate_text(rng, text):
    for _ in range(rng.choice((1, 1, 2, 3))):
        lines = text.split("\n")
        op = rng.randrange(9)
        if op <= 2 and tokens(text):
            a, b = rng.choice(tokens(text))
            text = text[:a] + rng.choice(NASTY) + text[b:]
        elif op == 3 and len(lines) > 1:
            del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
        elif op == 4:
            k = rng.randrange(len(lines))
            lines.insert(k, lines[k])
            text = "\n".join(lines)
        elif op == 5 and "," in text:
            k = rng.choice([i for i, c in enumerate(text) if c == ","])
            text = text[:k] + text[k + 1:]
        elif op == 6:
            k = rng.randrange(len(text) + 1)
            text = text[:k] + rng.choice([",", ":", "\n", "- ", "#", "\t", "\x00"]) + text[k:]
        elif op == 7:
            text = text[:rng.randrange(len(text) + 1)]
        else:
            k = rng.randrange(max(1, len(text)))
            text = text[:k] + chr(rng.randrange(1, 256)) + text[k + 1:]
    return text


def mat_case(rng, path):
    """A .mat of the seed grid, its data_a mutated in shape, type or value."""
    import numpy as np
    import scipy.io
    rows = rng.choice([810] * 6 + [0, 1, 10, 400, 800, 809, 811, 820])
    cols = rng.choice([4] * 6 + [0, 1, 3, 5])
    g = np.array([[1 + j / 100 + k / 10 + r / 1000 for k in range(cols)]
                  for j in range(rows // 10 + 1) for r in range(10)])[:rows]
    op = rng.randrange(8)
    if op == 1 and g.size:
        g = g.astype(float)
        g.flat[rng.randrange(g.size)] = rng.choice([np.nan, np.inf, -np.inf, 1e308, -1e308])
    elif op == 2:
        g = g + 1j * rng.choice([0, 1])
    elif op == 3:
        g = (g * 1000).astype(rng.choice([np.int32, np.uint16, np.int8, np.uint8]))
    elif op == 4:
        c = np.empty((1, 2), dtype=object)
        c[0, 0], c[0, 1] = g, "x"
        g = c
    elif op == 5:
        g = g.T
    with np.errstate(all="ignore"):
        d = np.clip(np.round(np.abs(g.real if g.dtype.kind == "c" else g) * 1000)
                    if g.dtype.kind in "fiuc" else np.zeros((810, 4)), 0, rng.choice([4095, 5000]))
        var = {"data_a": g, "data_d": d.astype(np.uint16) if rng.random() < 0.8 else d}
    if op == 6:
        del var[rng.choice(["data_a", "data_d"])]
    scipy.io.savemat(path, var)
    if op == 7:
        data = bytearray(open(path, "rb").read())
        for _ in range(rng.randrange(1, 8)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        if rng.random() < 0.3:
            data = data[:rng.randrange(len(data))]
        open(path, "wb").write(bytes(data))


def digest(folder):
    h = {}
    for dp, _, fs in os.walk(folder):
        for f in fs:
            p = os.path.join(dp, f)
            h[p] = hashlib.sha256(open(p, "rb").read()).hexdigest()
    return h


def temps(folder):
    return [os.path.join(dp, f) for dp, _, fs in os.walk(folder) for f in fs if f.endswith(".tmp")]


def check_csv(path):
    """An imported CSV: every data row six finite numbers, the angles within (-90, 90)."""
    for line in open(path):
        if line.startswith("#") or line.startswith("alpha_deg"):
            continue
        v = [float(c) for c in line.split(",")]
        if len(v) != 6 or not all(math.isfinite(x) for x in v):
            return "row %r" % line
        if abs(v[0]) >= 90 or abs(v[1]) >= 90:
            return "angle out of range in %r" % line
    return None


def one_case(rng, case):
    """Lay out one mutated input in case/; the command and the folders it reads."""
    src = os.path.join(case, "src")
    os.makedirs(src)
    fmt = rng.choice(["aeroztark", "kenscl", "14og", "score", "kenscl", "14og"])
    if fmt == "aeroztark":
        for _ in range(rng.choice([1, 1, 2])):
            mat_case(rng, os.path.join(src, rng.choice(BETA_NAMES)))
        arg = src if rng.random() < 0.5 else os.path.join(src, sorted(os.listdir(src))[0])
    elif fmt == "kenscl":
        for _ in range(rng.choice([1, 1, 2])):
            name = rng.choice(["a_X.txt", "b_Y.txt", "c_X.txt", "d.txt"])
            with open(os.path.join(src, name), "w", encoding="utf-8", errors="surrogateescape") as f:
                f.write(mutate_text(rng, KEN_SEED) if rng.random() < 0.9 else KEN_SEED)
        arg = src if rng.random() < 0.5 else os.path.join(src, sorted(os.listdir(src))[0])
    else:
        arg = os.path.join(src, "m.yaml" if fmt == "14og" else "comp.csv")
        with open(arg, "w", encoding="utf-8", errors="surrogateescape") as f:
            f.write(mutate_text(rng, OG_SEED if fmt == "14og" else SCORE_SEED))
    if fmt == "score":
        return [SCORE, arg] + (["--mean"] if rng.random() < 0.3 else []), src, None
    out = os.path.join(case, "out.csv")
    r = rng.random()
    if r < 0.05:
        out = arg if os.path.isfile(arg) else os.path.join(arg, sorted(os.listdir(arg))[0])
    elif r < 0.08:
        out = src
    elif r < 0.1:
        out = os.path.join(case, "missing", "out.csv")
    cmd = [IMPORT, fmt, arg, "--out", out]
    if fmt == "aeroztark" and rng.random() < 0.3:
        cmd.append("--digital")
    return cmd, src, out


def main(argv):
    seconds, work, seed = 60.0, os.path.join(ROOT, "build", "fuzz", "import"), None
    args = argv[1:]
    while args:
        if args[0] in ("-h", "--help"):
            sys.stdout.write(__doc__)
            return 0
        if len(args) < 2 or args[0] not in ("--seconds", "--work", "--seed"):
            sys.stderr.write("usage: fuzz-import.py [--seconds N] [--work DIR] [--seed S]\n")
            return 2
        if args[0] == "--seconds":
            seconds = float(args[1])
        elif args[0] == "--work":
            work = args[1]
        else:
            seed = int(args[1])
        args = args[2:]
    seed = seed if seed is not None else int(time.time())
    rng = random.Random(seed)
    os.makedirs(work, exist_ok=True)
    scratch = os.path.join(work, "case")
    t_end, n, found = time.time() + seconds, 0, 0
    counts = {0: 0, 2: 0}
    while time.time() < t_end:
        shutil.rmtree(scratch, ignore_errors=True)
        cmd, src, out = one_case(rng, scratch)
        before = digest(src)
        r = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=60)
        n += 1
        why = None
        if r.returncode not in (0, 2):
            why = "exit %d" % r.returncode
        elif "Traceback" in r.stderr or re.search(r": unexpected [A-Z][A-Za-z_]*: ", r.stderr):
            why = "an error no check foresaw"
        elif temps(scratch):
            why = "temporary file left: %s" % temps(scratch)
        elif digest(src) != before:
            why = "an input changed"
        elif out and r.returncode == 2 and os.path.basename(out) == "out.csv" and os.path.exists(out):
            why = "refused, but %s was written" % out
        elif out and r.returncode == 0:
            why = check_csv(out)
        counts[r.returncode] = counts.get(r.returncode, 0) + 1
        if why:
            found += 1
            keep = os.path.join(work, "crash-%d" % found)
            shutil.rmtree(keep, ignore_errors=True)
            shutil.copytree(scratch, keep)
            with open(os.path.join(keep, "command.txt"), "w") as f:
                f.write("%s\n%s\nexit %d\n%s%s" % (why, " ".join(cmd), r.returncode, r.stdout,
                                                  r.stderr))
            sys.stderr.write("fuzz-import: %s: %s (kept in %s)\n%s" % (why, " ".join(cmd), keep,
                                                                       r.stderr))
    shutil.rmtree(scratch, ignore_errors=True)
    print("fuzz-import: seed %d, %d runs (%d imported or scored, %d refused), %d failing"
          % (seed, n, counts.get(0, 0), counts.get(2, 0), found))
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
