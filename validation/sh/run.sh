#!/usr/bin/env bash
# Reproduces validation/sh/results/ (tables + plots) in one command:
#   validation/sh/run.sh            (BUILD_DIR defaults to build/)
# Builds validate_sh with CMake + Ninja if needed (one job), runs it, then plots with Debian's
# /usr/bin/python3 + matplotlib.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD_DIR="${BUILD_DIR:-build}"
cd "$ROOT"
source validation/configure.sh validate_sh  # (clang++, as setup.sh configures build/)
ninja -C "$BUILD_DIR" -j1 validate_sh
mkdir -p validation/sh/results
"$BUILD_DIR/validate_sh" validation/sh/results | tee validation/sh/results/summary.txt
PY=/usr/bin/python3
source validation/plot_deps.sh
"$PY" validation/sh/plot.py validation/sh/results
