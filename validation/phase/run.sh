#!/usr/bin/env bash
# Reproduces validation/phase/results/ (CSV tables + PNG plots) in one command:
#   validation/phase/run.sh            (BUILD_DIR defaults to build/)
# 1. configures build/ if needed (clang++, Ninja, Release) and builds validate_phase and shvol with
#    one job (the machine is shared);
# 2. runs validate_phase (fit quality, chi², estimator variance, ns/sample; ~5 min, one core);
# 3. runs render_compare.py (default cloud at 160×106: reference + 27 renders; ~4-5 min, 2 cores);
# 4. installs python3-matplotlib / python3-numpy with apt-get if they are missing, and plots with
#    Debian's /usr/bin/python3 (not a pyenv python that may be first on PATH).
# Environment: BUILD_DIR, SKIP_RENDER=1 (keep the existing render_compare.csv), REF_SPP, SPPS, RES
# (passed to render_compare.py).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD_DIR="${BUILD_DIR:-build}"
OUT="validation/phase/results"
PY=/usr/bin/python3
cd "$ROOT"
t0=$(date +%s)

source validation/configure.sh validate_phase
ninja -C "$BUILD_DIR" -j1 validate_phase
if ! ninja -C "$BUILD_DIR" -j1 shvol; then
    # The tree is shared: another engineer's half-finished edit of src/app can break this target.
    if [ -x "$BUILD_DIR/shvol" ]; then
        echo "run.sh: WARNING: building shvol failed; using the existing $BUILD_DIR/shvol" >&2
    else
        exit 1
    fi
fi

mkdir -p "$OUT"
"$BUILD_DIR/validate_phase" "$OUT" | tee "$OUT/validate_phase.log"

if [ "${SKIP_RENDER:-0}" != 1 ]; then
    "$PY" validation/phase/render_compare.py "$BUILD_DIR" "$OUT" | tee "$OUT/render_compare.log"
fi

source validation/plot_deps.sh
"$PY" validation/phase/plot.py "$OUT"
echo "run.sh: $(( $(date +%s) - t0 )) s"
