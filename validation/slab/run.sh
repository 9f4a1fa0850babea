#!/usr/bin/env bash
# Reproduces validation/slab/results/table.md in one command (about 90 s on 2 cores):
#   validation/slab/run.sh          (BUILD_DIR defaults to build/; SPP to 2048)
# Builds shvol with one job if needed, installs python3-numpy and python3-matplotlib
# (validation/plot_deps.sh) if /usr/bin/python3 cannot import them, and exits 1 if a slab disagrees.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD_DIR="${BUILD_DIR:-build}"
PY=/usr/bin/python3
cd "$ROOT"
source validation/configure.sh shvol
ninja -C "$BUILD_DIR" -j1 shvol
source validation/plot_deps.sh  # (numpy, with matplotlib)
SHVOL="$(cd "$BUILD_DIR" && pwd)/shvol" "$PY" validation/slab/run.py
