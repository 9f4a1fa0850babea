#!/usr/bin/env bash
# The radiance-cache experiment (README.md here): path tracing against the HSH radiance cache on
# the Cornell box with its Phong-22 back wall and on its fog variant, at 128², against rendered
# references; each sweep of media/sweeps/cache/ writes its ledger and runs into a folder here, and
# analyze.py turns them into tables and plots. Run it on an idle machine (about 10 minutes on two
# cores).
# validate_cache (hsh_vs_sh.cpp: HSH against SH on hemispherical fields) writes hsh_vs_sh.txt.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR="${BUILD_DIR:-build}"
source validation/configure.sh validate_cache
ninja -C "$BUILD_DIR" -j1 shvol validate_cache >/dev/null
shvol="$(cd "$BUILD_DIR" && pwd)/shvol"
"$BUILD_DIR/validate_cache" > validation/cache/hsh_vs_sh.txt.tmp  # (a failed run leaves the old one)
mv validation/cache/hsh_vs_sh.txt.tmp validation/cache/hsh_vs_sh.txt
cd validation/cache
for s in cornell_pt cornell_cache cornell_cache_light cornell_cache_rays cornell_fog_pt \
         cornell_fog_cache; do
  # A fresh run of the sweep: the runs of the last one go (batch refuses to mix versions); the
  # cached reference stays, and batch re-renders it if its fingerprint no longer matches.
  rm -f "$s"/results.jsonl "$s"/results.csv "$s"/r[0-9]*.exr "$s"/r[0-9]*.stats.json
  $shvol batch ../../media/sweeps/cache/$s.json --output $s --quiet
done
/usr/bin/python3 analyze.py
