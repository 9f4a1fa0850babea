#!/usr/bin/env bash
# MPI and --jobs scaling (README.md here): times shvol render and shvol batch over 1 and 2
# processes on this machine, then plots the measured speed-ups with the model of how they extend.
# Run it on an otherwise idle machine: every figure is a wall time.
set -euo pipefail
cd "$(dirname "$0")"
PY=/usr/bin/python3
. ../plot_deps.sh
"$PY" scaling.py "$@"
