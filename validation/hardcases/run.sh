#!/usr/bin/env bash
# Reproduces validation/hardcases/results/table.md in one command:
#   validation/hardcases/run.sh          (BUILD_DIR defaults to build/)
# Builds validate_hardcases with one job if needed and runs every case at 128 spp (a few
# seconds on 2 cores). ctest runs the same cases at 16 spp (`validate_hardcases --check --quick`).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD_DIR="${BUILD_DIR:-build}"
OUT="validation/hardcases/results"
cd "$ROOT"
source validation/configure.sh validate_hardcases
ninja -C "$BUILD_DIR" -j1 validate_hardcases
mkdir -p "$OUT"
"$BUILD_DIR/validate_hardcases" --check --out "$OUT/table.md"
