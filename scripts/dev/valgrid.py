#!/usr/bin/env python3
"""valgrid.py - what the validation grid's density buys (issue 27).

A unit's RMS after calibration is estimated from its validation readings;
their noise makes that estimate scatter around the unit's true RMS, and the
scatter adds to the spread of the RMS over units, which sets the width of
the population intervals (mean RMS after, its 95th percentile).  For each
alpha step this runs the same units (common random numbers: the same
seed) and prints, per report band:

  n_read     validation readings in the band
  sd_units   standard deviation of the RMS after over the units
  sd_noise   the scatter of one unit's RMS from its readings' noise,
             sqrt(mean over units of (4 s^2 v + 2 v^2) / (4 r^2 n)), with
             r the RMS after, s its systematic part (the same readings
             without noise) and v = r^2 - s^2 the noise's share: the
             variance of a mean of n squared errors (s + e)^2, e ~ N(0, v)
  adds_%     how much that widens a population interval:
             100 (sd_units / sqrt(sd_units^2 - sd_noise^2) - 1)
  vs_ref     root mean square over units of (RMS - the finest grid's RMS)
  ci_mean    width of the mean RMS after's 95 % interval (summary.tsv)
  ci_p95     width of the 95th percentile's 95 % interval

Usage: scripts/dev/valgrid.py [--sunmc build/sunmc] [--units 1000]
       [--config configs/ess_type_a.ini] [--key validation.alpha_step_deg]
       STEP [STEP ...]      (the first STEP is the reference: the finest)
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile


def run(sunmc, config, units, key, step, out):
    subprocess.run([sunmc, "run", config, "--units", str(units), "--threads", "2", "--quiet",
                    "--out", out, "--set", f"{key}={step}"], check=True,
                   stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "units.tsv")) as f:
        units_rows = list(csv.DictReader(f, delimiter="\t"))
    with open(os.path.join(out, "summary.tsv")) as f:
        summary = list(csv.DictReader(f, delimiter="\t"))
    return units_rows, summary


def band_columns(row):
    return [k[len("rms_after_"):] for k in row if k.startswith("rms_after_")
            and not k.startswith("rms_after_sys_")
            and not k.startswith("rms_after_mf_")]


def readings_in_band(config, sunmc, key, step, band):
    """Validation readings whose |alpha| lies in the band (lo, hi]."""
    out = subprocess.run([sunmc, "config", config, "--set", f"{key}={step}"], check=True,
                         capture_output=True, text=True).stdout
    vals = {}
    section = ""
    for line in out.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("["):
            section = line.strip("[]")
        elif "=" in line:
            k, v = (s.strip() for s in line.split("=", 1))
            vals[f"{section}.{k}"] = v
    lo_a = float(vals["validation.alpha_min_deg"])
    hi_a = float(vals["validation.alpha_max_deg"])
    st = float(vals["validation.alpha_step_deg"])
    off = float(vals["validation.alpha_offset_deg"])
    nb = len(vals["validation.beta_deg"].split(","))
    lo, hi = band
    n, a = 0, lo_a + off
    while a <= hi_a + 1e-9:
        x = abs(a)
        n += (x <= hi + 1e-9) if lo == 0 else (lo + 1e-9 < x <= hi + 1e-9)
        a += st
    return n * nb


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sunmc", default="build/sunmc")
    ap.add_argument("--units", type=int, default=1000)
    ap.add_argument("--config", default="configs/ess_type_a.ini")
    ap.add_argument("--key", default="validation.alpha_step_deg")
    ap.add_argument("steps", nargs="+")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    ref = None
    print("step\tband\tn_read\tsd_units\tsd_noise\tadds_%\tvs_ref\tci_mean\tci_p95")
    for step in a.steps:
        rows, summ = run(a.sunmc, a.config, a.units, a.key, step, os.path.join(tmp, step))
        ok = [r for r in rows if r["fit_status"] == "ok"]
        for b in band_columns(ok[0]):
            lo, hi = (float(x) for x in b.split("_")[1:3])
            n = readings_in_band(a.config, a.sunmc, a.key, step, (lo, hi))
            r = [float(u["rms_after_" + b]) for u in ok]
            s = [float(u["rms_after_sys_" + b]) for u in ok]
            m = sum(r) / len(r)
            sd = math.sqrt(sum((x - m) ** 2 for x in r) / (len(r) - 1))
            var_noise = 0.0
            for ri, si in zip(r, s):
                v = max(ri * ri - si * si, 0.0)
                var_noise += (4 * si * si * v + 2 * v * v) / (4 * ri * ri * n)
            sdn = math.sqrt(var_noise / len(r))
            adds = 100 * (sd / math.sqrt(max(sd * sd - sdn * sdn, 1e-300)) - 1)
            if ref is None or b not in ref:
                ref = ref or {}
                ref[b] = {u["unit"]: float(u["rms_after_" + b]) for u in ok}
            d = [float(u["rms_after_" + b]) - ref[b][u["unit"]] for u in ok if u["unit"] in ref[b]]
            vs = math.sqrt(sum(x * x for x in d) / len(d))
            sm = next(x for x in summ if x["band"] == f"{b.split('_')[1]}:{b.split('_')[2]}")
            ci_m = float(sm["rms_after_mean_ci_hi"]) - float(sm["rms_after_mean_ci_lo"])
            ci_p = float(sm["rms_after_p95_ci_hi"]) - float(sm["rms_after_p95_ci_lo"])
            print(f"{step}\t{lo:g}:{hi:g}\t{n}\t{sd:.3g}\t{sdn:.3g}\t{adds:.2f}\t{vs:.3g}"
                  f"\t{ci_m:.3g}\t{ci_p:.3g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
