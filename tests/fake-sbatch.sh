#!/usr/bin/env bash
# fake-sbatch.sh - a stand-in for Slurm's sbatch that runs the job at once
# on this machine, for test_cluster: --array=A-B runs the script once per
# task with SLURM_ARRAY_TASK_ID set, --cpus-per-task=C sets
# SLURM_CPUS_PER_TASK, other options are ignored; prints a job id like
# `sbatch --parsable`.  Fails when a task fails (as afterok would stop the
# dependent job).
set -euo pipefail
array=""
cpus=""
while [ $# -gt 0 ] && [ "${1#--}" != "$1" ]; do
  case $1 in
  --array=*) array=${1#--array=} ;;
  --cpus-per-task=*) cpus=${1#--cpus-per-task=} ;;
  esac
  shift
done
script=$1
shift
export SLURM_JOB_ID=$$
if [ -n "$cpus" ]; then export SLURM_CPUS_PER_TASK=$cpus; fi
if [ -n "$array" ]; then
  for ((k = ${array%-*}; k <= ${array#*-}; k++)); do
    SLURM_ARRAY_TASK_ID=$k bash "$script" "$@" >&2
  done
else
  bash "$script" "$@" >&2
fi
echo "$SLURM_JOB_ID"
