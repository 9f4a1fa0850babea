#!/usr/bin/env bash
# Russian roulette's threshold θ (render.rr_threshold) with next-event estimation on four scenes
# (README.md here): efficiency 1/(MSE·time) of θ = 1, 0.5 and 0.25 against a converged reference,
# 4 seeds each, on 1 thread. Run it on an otherwise idle machine: the times are CPU-bound wall
# times. About 7 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")"
SHVOL=${SHVOL:-../../build/shvol}
OUT=${OUT:-out}
mkdir -p "$OUT"
# scene, size, spp, reference spp (0: the exact image uniform100.json renders)
cases=("../../media/default.json [96,64] 64 4096"
       "../../media/cornell_fog.json [48,48] 256 16384"
       "../../media/cornell.json [64,64] 128 4096"
       "enclosure.json [32,32] 16 0")
for c in "${cases[@]}"; do
  read -r scene size spp refspp <<< "$c"
  name=$(basename "$scene" .json)
  ref="$OUT/$name.ref.exr"
  if [ "$refspp" = 0 ]; then
    "$SHVOL" render uniform100.json -o "$ref" --quiet
  elif [ ! -f "$ref" ]; then
    "$SHVOL" render "$scene" -o "$ref" --spp "$refspp" --seed 99 --set "camera.resolution=$size" --quiet
  fi
  for seed in 1 2 3 4; do
    for theta in 1 0.5 0.25; do
      img="$OUT/$name.t$theta.s$seed.exr"
      "$SHVOL" render "$scene" -o "$img" --spp "$spp" --threads 1 --seed "$seed" --quiet \
        --set "camera.resolution=$size" --set "render.rr_threshold=$theta" --set render.nee=true
      t=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['wall_time_s'])" \
          "${img%.exr}.stats.json")
      rmse=$("$SHVOL" diff "$img" "$ref" | awk '$1 == "rmse" {print $2}')
      echo "$name $theta $seed $t $rmse"
    done
  done
done | tee "$OUT/runs.txt"
/usr/bin/python3 - "$OUT/runs.txt" <<'PY'
import collections, sys
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    name, theta, seed, t, rmse = line.split()
    runs[name, theta].append((float(t), float(rmse)))
print("| scene | θ = 1 | θ = 0.5 | θ = 0.25 |\n|---|---:|---:|---:|")
for name in dict.fromkeys(n for n, _ in runs):
    eff = {}
    for theta in ("1", "0.5", "0.25"):
        v = runs[name, theta]
        time = sum(t for t, _ in v) / len(v)
        mse = sum(r * r for _, r in v) / len(v)
        eff[theta] = 1 / (time * mse)
    print(f"| {name} | " + " | ".join(f"{eff[t] / eff['1']:.2f}" for t in ("1", "0.5", "0.25")) + " |")
PY
