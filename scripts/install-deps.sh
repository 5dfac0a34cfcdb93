#!/usr/bin/env bash
# Installs the system packages sunmc needs to build, test and plot.
# Debian/Ubuntu: apt-get as root, through sudo otherwise. Elsewhere: prints the
# list and exits 1, so the caller knows nothing was installed.
set -euo pipefail

# python3-scipy, python3-yaml: scripts/psd-import.py reads the public four-channel
# sun-sensor data (.mat, .yaml); tests/unit/psd/test_psd_lab.c writes a synthetic .mat with scipy.
# libhdf5-dev: run --format hdf5 (src/util/h5out.c); python3-h5py: its test and
# docs/examples/load_h5.py read the file back.
PACKAGES="build-essential pkg-config libgsl-dev libcmocka-dev librandom123-dev gnuplot-nox python3 python3-scipy python3-yaml libhdf5-dev python3-h5py"
# MPI=1 (make MPI=1, make test-mpi): Debian's MPICH as well (README,
# "Running on a cluster", says why MPICH).
if [ "${MPI:-0}" = 1 ]; then
  PACKAGES="$PACKAGES mpich libmpich-dev"
fi
# FUZZ=1 (make fuzz): clang with libFuzzer and its OpenMP runtime as well;
# never for make test, so CI does not pay for them.
if [ "${FUZZ:-0}" = 1 ]; then
  PACKAGES="$PACKAGES clang libclang-rt-dev libomp-dev"
fi

if ! command -v apt-get >/dev/null 2>&1; then
  echo "install-deps: no apt-get on this machine; please install: $PACKAGES" >&2
  exit 1
fi

if [ "$(id -u)" -eq 0 ]; then
  SUDO=""
elif command -v sudo >/dev/null 2>&1; then
  SUDO="sudo"
else
  echo "install-deps: not root and no sudo; please install: $PACKAGES" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $PACKAGES
