#!/usr/bin/env python3
"""Load a sunmc run directory in Python: summary.tsv and units.tsv.

Usage: python3 docs/examples/load_run.py RUN_DIR
Prints, for every angle and band of summary.tsv, the mean RMS after calibration
with its interval, and the same mean recomputed from units.tsv's per-unit
column (they agree: units.tsv is what the summary is made of).
Uses pandas when it is installed, the standard library's csv module otherwise;
both read the files as they are (tab-separated, one header line, '-' or 'nan'
for a number the tool could not form).
"""
import sys

run = sys.argv[1] if len(sys.argv) > 1 else "runs/a"

try:
    import pandas as pd

    summary = pd.read_csv(f"{run}/summary.tsv", sep="\t", na_values=["-"])
    units = pd.read_csv(f"{run}/units.tsv", sep="\t", na_values=["-"])
    rows = summary.to_dict("records")
    unit_rows = units.to_dict("records")
except ImportError:
    import csv

    def read(path):
        with open(path, newline="") as f:
            return list(csv.DictReader(f, delimiter="\t"))

    rows = read(f"{run}/summary.tsv")
    unit_rows = read(f"{run}/units.tsv")


def number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


for r in rows:
    band = str(r["band"]).replace(":", "_")
    col = f"rms_after_{r['angle']}_{band}_{r['rms_unit']}"
    vals = [number(u.get(col)) for u in unit_rows]
    vals = [v for v in vals if v == v]  # units with a fit (nan otherwise)
    mean = sum(vals) / len(vals) if vals else float("nan")
    print(f"{r['angle']}\t{r['band']}\t{number(r['rms_after_mean']):.6g}\t"
          f"[{number(r['rms_after_mean_ci_lo']):.6g}, {number(r['rms_after_mean_ci_hi']):.6g}]\t"
          f"{r['rms_unit']}\tfrom units.tsv: {mean:.6g}")
