#!/usr/bin/env bash
# Reproduces validation/product/results/ in one command:
#   validation/product/run.sh          (BUILD_DIR defaults to build/)
# 1. builds shvol with one job if needed (configuring build/ with clang++ and Ninja first);
# 2. runs experiment.py (sunlit cloud, 2 densities x 5 phase functions x 7 strategies, sweeps;
#    about 6 minutes on 2 cores, 378 s in the run README.md reports (7 Dec): do not run anything else
#    meanwhile, the timings are the result);
# 3. installs python3-matplotlib / python3-numpy with apt-get if missing and plots with Debian's
#    /usr/bin/python3.
# Environment: BUILD_DIR, SKIP_RENDER=1 (replot only), REF_SPP, SPP, RES, THREADS, QUICK.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BUILD_DIR="${BUILD_DIR:-build}"
OUT="validation/product/results"
PY=/usr/bin/python3
cd "$ROOT"
t0=$(date +%s)
source validation/configure.sh validate_product
ninja -C "$BUILD_DIR" -j1 shvol validate_product
mkdir -p "$OUT"
if [ "${SKIP_RENDER:-0}" != 1 ]; then
    "$PY" validation/product/experiment.py "$BUILD_DIR" "$OUT" | tee "$OUT/experiment.log"
fi
source validation/plot_deps.sh
"$PY" validation/product/plot.py "$OUT"
echo "run.sh: $(( $(date +%s) - t0 )) s"
