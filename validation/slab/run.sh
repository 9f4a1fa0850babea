#!/usr/bin/env bash
# Reproduces validation/slab/results/table.md in one command (about 90 s on 2 cores):
#   validation/slab/run.sh          (BUILD_DIR defaults to build/; SPP to 2048)
# Builds shvol with one job if needed, installs Debian's python3-numpy with apt-get if
# /usr/bin/python3 cannot import it, and exits 1 if a slab disagrees.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD_DIR="${BUILD_DIR:-build}"
PY=/usr/bin/python3
cd "$ROOT"
source validation/configure.sh shvol
ninja -C "$BUILD_DIR" -j1 shvol
if ! "$PY" -c 'import numpy' 2>/dev/null; then
    SUDO=""
    [ "$(id -u)" -ne 0 ] && SUDO=sudo
    $SUDO apt-get update
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends python3-numpy
fi
SHVOL="$(cd "$BUILD_DIR" && pwd)/shvol" "$PY" validation/slab/run.py
