#!/usr/bin/env bash
# slurm-array.sh - one sunmc run as a Slurm job array of shards plus a merge
# job (README, "Running on a cluster").
#
#   scripts/slurm-array.sh submit CONFIG OUT N [RUN OPTIONS...]
#       submits the array (tasks 0..N-1, each `run --shard K/N`) and a merge
#       job that starts when every task has ended well; prints both job ids.
#   scripts/slurm-array.sh shard CONFIG OUT N [RUN OPTIONS...]
#       the body of array task K = $SLURM_ARRAY_TASK_ID: writes OUT.shards/K
#       with --resume, so a requeued or restarted task continues its blocks.
#   scripts/slurm-array.sh merge CONFIG OUT N
#       the merge job: `sunmc merge OUT OUT.shards/0 .. OUT.shards/N-1`.
#
# Threads per task: $SLURM_CPUS_PER_TASK (else run.threads).  The sunmc
# binary: $SUNMC, else build/sunmc beside this script.  Resources: the
# #SBATCH lines below, or sbatch options in $SBATCH_OPTIONS at submit.
# Without Slurm the bodies run as they are, e.g. a whole run on this
# machine:  for k in 0 1 2; do SLURM_ARRAY_TASK_ID=$k scripts/slurm-array.sh \
#           shard configs/dss.ini runs/d 3 --units 300; done
#           scripts/slurm-array.sh merge configs/dss.ini runs/d 3
#
#SBATCH --job-name=sunmc-shard
#SBATCH --cpus-per-task=8
#SBATCH --time=04:00:00
#SBATCH --requeue
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
SUNMC=${SUNMC:-$here/../build/sunmc}
SBATCH=${SBATCH:-sbatch}

usage() {
  sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

[ $# -ge 4 ] || usage
mode=$1 config=$2 out=$3 n=$4
shift 4
case $n in '' | *[!0-9]* | 0) echo "slurm-array.sh: N must be a whole number >= 1: $n" >&2; exit 2 ;; esac

threads=()
if [ -n "${SLURM_CPUS_PER_TASK:-}" ]; then
  threads=(--threads "$SLURM_CPUS_PER_TASK")
fi

case $mode in
submit)
  # shellcheck disable=SC2086
  array=$($SBATCH --parsable ${SBATCH_OPTIONS:-} --array=0-$((n - 1)) \
    "${BASH_SOURCE[0]}" shard "$config" "$out" "$n" "$@")
  array=${array%%;*}
  # shellcheck disable=SC2086
  merge=$($SBATCH --parsable ${SBATCH_OPTIONS:-} --job-name=sunmc-merge --cpus-per-task=1 \
    --dependency=afterok:"$array" "${BASH_SOURCE[0]}" merge "$config" "$out" "$n")
  echo "shards: job array $array (tasks 0-$((n - 1))); merge: job ${merge%%;*} -> $out"
  ;;
shard)
  k=${SLURM_ARRAY_TASK_ID:?shard runs as a Slurm array task: SLURM_ARRAY_TASK_ID is not set}
  mkdir -p "$out.shards"
  exec "$SUNMC" run "$config" --shard "$k/$n" "${threads[@]}" --quiet "$@" \
    --out "$out.shards/$k" --resume
  ;;
merge)
  dirs=()
  for ((k = 0; k < n; k++)); do dirs+=("$out.shards/$k"); done
  exec "$SUNMC" merge "$out" "${dirs[@]}"
  ;;
*) usage ;;
esac
