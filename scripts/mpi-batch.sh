#!/usr/bin/env bash
# mpi-batch.sh - one sunmc run across the ranks of an MPI job (README,
# "Running on a cluster"); needs the MPI build (make MPI=1).
#
#   sbatch scripts/mpi-batch.sh CONFIG OUT [RUN OPTIONS...]
#
# Ranks: $SLURM_NTASKS (else 2), started by $MPIEXEC (else mpiexec, which
# reads the Slurm allocation); threads per rank: $SLURM_CPUS_PER_TASK
# (else 1).  Rank 0 writes OUT with --resume: a requeued job continues
# from the blocks it had checkpointed.  The sunmc binary: $SUNMC, else
# build/sunmc beside this script.  Without Slurm it runs as it is, e.g.
#   SLURM_NTASKS=2 scripts/mpi-batch.sh configs/dss.ini runs/d --units 300
#
#SBATCH --job-name=sunmc-mpi
#SBATCH --nodes=2
#SBATCH --ntasks-per-node=1
#SBATCH --cpus-per-task=16
#SBATCH --time=04:00:00
#SBATCH --requeue
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
SUNMC=${SUNMC:-$here/../build/sunmc}
MPIEXEC=${MPIEXEC:-mpiexec}

if [ $# -lt 2 ]; then
  sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
config=$1 out=$2
shift 2
if ! "$SUNMC" --version | grep -q 'built with MPI'; then
  echo "mpi-batch.sh: $SUNMC is not an MPI build (make MPI=1)" >&2
  exit 2
fi
ranks=${SLURM_NTASKS:-2}
threads=${SLURM_CPUS_PER_TASK:-1}
export OMP_NUM_THREADS=$threads
# shellcheck disable=SC2086
exec $MPIEXEC -n "$ranks" "$SUNMC" run "$config" --threads "$threads" --quiet "$@" \
  --out "$out" --resume
