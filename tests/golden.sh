#!/usr/bin/env bash
# golden.sh SUNMC OUTDIR - run a fixed set of commands (both families, small
# unit counts, fixed seeds) and collect every file they write under OUTDIR.
# tests/golden/ holds the recorded outputs; `make golden` re-records them and
# test_golden compares a fresh run byte for byte.  Run from the repository
# root (config.ini records the config's path as its origin).
set -eu
S=$1
O=$2
rm -rf "$O"
mkdir -p "$O"
q=--quiet
"$S" run configs/ess_type_a.ini --units 12 --seed 3 --threads 2 $q --out "$O/run_ess_a" >/dev/null
"$S" run configs/ess_type_b.ini --units 8 --seed 5 $q --out "$O/run_ess_b" >/dev/null
"$S" run configs/dss.ini --units 8 --seed 2 --threads 2 $q --out "$O/run_dss" >/dev/null
"$S" run configs/dss.ini --units 6 --seed 2 $q --set calibration.model=polynomial \
    --set calibration.poly_order=4 --out "$O/run_dss_poly" >/dev/null
"$S" sweep configs/ess_type_a.ini --units 6 --seed 4 $q --vary campaign.alpha_step_deg=0.2,0.3 \
    --out "$O/sweep_ess" >/dev/null
"$S" sweep configs/dss.ini --units 4 --seed 4 $q --vary tolerance.dh_px=0,2 --out "$O/sweep_dss" >/dev/null
"$S" budget configs/ess_type_a.ini --units 10 --seed 4 $q --set report.budget_units=10 \
    --set report.budget_steps=2 --out "$O/budget_ess" >/dev/null
"$S" budget configs/dss.ini --units 10 --seed 4 $q --set report.budget_units=10 \
    --set report.budget_steps=1 --out "$O/budget_dss" >/dev/null
"$S" sensitivity configs/ess_type_a.ini --units 10 --seed 4 $q --set validation.alpha_step_deg=2.3 \
    --out "$O/sens_ess" >/dev/null
"$S" sensitivity configs/dss.ini --units 10 --seed 4 $q --set validation.b_step_deg=10 \
    --out "$O/sens_dss" >/dev/null
"$S" curve configs/ess_type_a.ini --unit 3 --seed 1 $q --out "$O/curve_ess" >/dev/null
"$S" curve configs/ess_type_a.ini --only dH_um=2 $q --out "$O/curve_ess_dh" >/dev/null
"$S" curve configs/dss.ini --unit 2 --seed 1 $q --set validation.b_step_deg=10 --out "$O/curve_dss" >/dev/null
for fam in ess_type_a dss; do
  "$S" simulate configs/$fam.ini --unit 3 --seed 1 --out "$O/sim_$fam" > "$O/sim_$fam.stdout"
done
roll=$(sed -n 's/.*calibration.roll_measured_arcsec=\([-0-9.e+]*\).*/\1/p' "$O/sim_ess_type_a.stdout" | head -1)
"$S" calibrate --sensor ess --config configs/ess_type_a.ini ${roll:+--set calibration.roll_measured_arcsec=$roll} \
    "$O/sim_ess_type_a/campaign.csv" --out "$O/cal_ess" > "$O/cal_ess.stdout"
"$S" calibrate --sensor dss --config configs/dss.ini "$O/sim_dss/campaign.csv" --out "$O/cal_dss" > "$O/cal_dss.stdout"
"$S" compensate "$O/cal_ess/params.ini" "$O/sim_ess_type_a/validation.csv" > "$O/comp_ess.csv"
"$S" compensate "$O/cal_dss/params.ini" "$O/sim_dss/validation.csv" > "$O/comp_dss.csv"
# units.bin holds every double's last bit, which the vector math may round
# differently on another instruction set (README, Speed); units.tsv holds the
# same results as text and is compared.  test_shards checks units.bin.
find "$O" -name units.bin -delete
# Paths of this run's directory, the version and the machine's kernel path and
# build (manifest.ini kernel_isa, build) are not part of the result, nor the
# checksums of units.bin (units_fnv1a64), which hash those last bits.
find "$O" -type f | while read -r f; do
  sed -i -e "s#$O#OUT#g" -e '/^# sunmc [0-9]/d' -e '/^version *=/d' -e '/^sunmc_version *=/d' \
      -e '/^kernel_isa *=/d' -e '/^build *=/d' -e '/^units_fnv1a64 *=/d' "$f"
done
