#!/usr/bin/env bash
# shvol against Blender 3.4 Cycles at equal error (issue 11; README.md here). For each scene of
# scenes/: a shvol reference (REF_SPP, its own seed), shvol and Cycles at 16, 64 and 256 spp on
# 2 threads (time per spp from the 16 → 256 spp difference, so that loading and Cycles' scene
# synchronisation are left out; RMSE against the reference), Cycles converged (CYCLES_SPP) against
# the reference with a difference image, and a white furnace (albedo 1, a constant white sky,
# 1024 bounces) in both.
# Writes results/*.jsonl, results/*.png and results.md. Run it on an idle machine (about 15
# minutes on two cores). Needs Debian's blender package (installed here if missing) and a built
# build/shvol.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
shvol=${SHVOL:-$root/build/shvol}
REF_SPP=${REF_SPP:-16384}
CYCLES_SPP=${CYCLES_SPP:-1024}
SCENES=${SCENES:-"cloud dense_cloud plume"}
if ! command -v blender > /dev/null; then
  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends blender
fi
[ -x "$shvol" ] || { echo "run.sh: $shvol not found; build shvol first" >&2; exit 1; }
out=$here/results
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
blender_run() { blender -b --factory-startup --python "$@" 2> /dev/null; }

# A JSON record of one render: renderer, scene, spp, seconds, and the comparison with `ref`.
record() {  # renderer scene spp seconds image reference
  local m
  m=$(blender_run "$here/compare.py" -- "$5" "$6" "$tmp/diff.png" | sed -n 's/^COMPARE //p')
  echo "{\"renderer\": \"$1\", \"scene\": \"$2\", \"spp\": $3, \"seconds\": $4, \"compare\": $m}"
}

for scene in $SCENES; do
  s=$here/scenes/$scene.json
  log=$out/$scene.jsonl
  : > "$log"
  # The resolved scene (defaults filled in) for Blender, with the directory its files are in.
  $shvol render "$s" --spp 1 --quiet -o "$tmp/resolved.exr"
  /usr/bin/python3 -c "
import json, sys
d = json.load(open('$tmp/resolved.stats.json'))['scene_resolved']
d['scene_dir'] = '$here/scenes'
json.dump(d, open('$tmp/$scene.json', 'w'))"
  furnace=$tmp/$scene.furnace.json
  /usr/bin/python3 -c "
import json
d = json.load(open('$tmp/$scene.json'))
for m in d['media']: m['albedo'] = 1.0
d['environment'] = {'type': 'constant', 'radiance': 1.0}
d['render']['max_depth'] = 1024
json.dump(d, open('$furnace', 'w'))"

  ref=$out/$scene.reference.exr
  if [ ! -f "$ref" ]; then
    echo "$scene: shvol reference, $REF_SPP spp"
    $shvol render "$s" --spp "$REF_SPP" --seed 1000000 --quiet -o "$ref"
  fi
  for spp in 16 64 256; do
    echo "$scene: $spp spp"
    $shvol render "$s" --spp $spp --threads 2 --quiet -o "$tmp/shvol.exr"
    t=$(/usr/bin/python3 -c "import json; print(json.load(open('$tmp/shvol.stats.json'))['wall_time_s'])")
    record shvol "$scene" $spp "$t" "$tmp/shvol.exr" "$ref" >> "$log"
    t=$(blender_run "$here/cycles_render.py" -- "$tmp/$scene.json" "$tmp/cycles.exr" $spp 1 2 |
        sed -n 's/^CYCLES_TIME //p')
    record cycles "$scene" $spp "$t" "$tmp/cycles.exr" "$ref" >> "$log"
  done
  echo "$scene: Cycles converged, $CYCLES_SPP spp"
  conv=$out/$scene.cycles.exr
  t=$(blender_run "$here/cycles_render.py" -- "$tmp/$scene.json" "$conv" "$CYCLES_SPP" 7 2 |
      sed -n 's/^CYCLES_TIME //p')
  m=$(blender_run "$here/compare.py" -- "$conv" "$ref" "$out/$scene.difference.png" |
      sed -n 's/^COMPARE //p')
  echo "{\"renderer\": \"cycles-converged\", \"scene\": \"$scene\", \"spp\": $CYCLES_SPP, \"seconds\": $t, \"compare\": $m}" >> "$log"
  echo "$scene: white furnace"
  $shvol render "$s" --spp 256 --quiet -o "$tmp/f_shvol.exr" \
    --set "render.max_depth=1024" --set 'environment={"type": "constant", "radiance": 1}' $(for i in $(/usr/bin/python3 -c "import json; print(' '.join(str(i) for i in range(len(json.load(open('$s'))['media']))))"); do echo "--set media[$i].albedo=1"; done)
  blender_run "$here/cycles_render.py" -- "$furnace" "$tmp/f_cycles.exr" 256 1 2 > /dev/null
  for r in shvol cycles; do
    m=$(blender_run "$here/compare.py" -- "$tmp/f_$r.exr" "$tmp/f_shvol.exr" "$tmp/diff.png" |
        sed -n 's/^COMPARE //p')
    echo "{\"renderer\": \"$r-furnace\", \"scene\": \"$scene\", \"spp\": 256, \"seconds\": 0, \"compare\": $m}" >> "$log"
  done
done
/usr/bin/python3 "$here/analyze.py" "$out" > "$here/results.md"
echo "wrote $here/results.md"
