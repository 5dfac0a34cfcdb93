#!/usr/bin/env python3
"""Load a `sunmc run --format hdf5 --out DIR` file: python3 docs/examples/load_h5.py DIR

load(path) returns (units, summary, attrs): units and summary map each
column name of units.tsv / summary.tsv to a numpy array (int64, float64, or
str for text columns), attrs the run's identity (config = config.ini's text,
family, product, seed, units, first, end)."""
import sys

import h5py


def _column(d):
    a = d[()]
    if a.dtype.kind == "S":  # fixed-length strings: bytes -> str
        a = a.astype(str)
    return a


def load(path):
    with h5py.File(path, "r") as f:
        units = {k: _column(f["units"][k]) for k in f["units"]}
        summary = {k: _column(f["summary"][k]) for k in f["summary"]}
        attrs = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
    return units, summary, attrs


if __name__ == "__main__":
    units, summary, attrs = load(sys.argv[1] + "/results.h5")
    print(f"{attrs['product']} ({attrs['family']}), seed {attrs['seed']}, "
          f"units {attrs['first']}:{attrs['end']}: {len(units['unit'])} units")
    for band, mean, lo, hi in zip(summary["band"], summary["rms_after_mean"],
                                  summary["rms_after_mean_ci_lo"], summary["rms_after_mean_ci_hi"]):
        print(f"band {band}: mean after-calibration RMS {mean:g} [{lo:g}, {hi:g}]")
