"""Tables of the Cycles comparison (run.sh writes results/<scene>.jsonl; this prints
results.md). Time per spp is the slope from 16 to 256 spp, so each renderer's fixed cost
(loading, Cycles' scene synchronisation) is left out; RMSE·√spp is taken at 256 spp; the time to
an RMSE ε is (RMSE·√spp / ε)² × time per spp."""
import json
import math
import os
import sys

EPSILON = 0.003
out = sys.argv[1]
SCENES = {
    "cloud": "the cloud of issue 11: media/cloud.vdb ×60, albedo 0.9, HG g = 0.6, constant sky 1, 128²",
    "dense_cloud": "the same cloud ×180, albedo 0.98, HG g = 0.8 (long paths), constant sky 1, 128²",
    "plume": "media/plume.json: the sparse plume ×80, albedo 0.9, HG g = 0.6, constant sky 1, 160×240",
    "thick_forward": "the same cloud ×300, albedo 0.95, HG g = 0.9 (thick, strongly forward), constant sky 1, 128²",
    "thin_backward": "the same cloud ×20, albedo 0.99, HG g = −0.3 (thin, backward), constant sky 1, 128²",
    "sunlit": "the same cloud ×60, albedo 0.98, HG g = 0.8 under media/sunsky.exr ×0.05 (sun and sky, next-event estimation), 128²",
}


def load(scene):
    rows = [json.loads(l) for l in open(os.path.join(out, scene + ".jsonl")) if l.strip()]
    return {(r["renderer"], r["spp"]): r for r in rows}


print("# Results: shvol vs Blender 3.4 Cycles (written by run.sh; see README.md)\n")
summary = []
for scene, what in SCENES.items():
    if not os.path.exists(os.path.join(out, scene + ".jsonl")):
        continue
    r = load(scene)
    print("## %s\n\n%s.\n" % (scene, what))
    print("| renderer | ms per spp | RMSE at 16 / 64 / 256 spp | RMSE·√spp (256) | time to RMSE %g |"
          % EPSILON)
    print("|---|---:|---|---:|---:|")
    timeTo = {}
    for name in ("shvol", "cycles"):
        t = 1e3 * (r[(name, 256)]["seconds"] - r[(name, 16)]["seconds"]) / 240
        rmse = [r[(name, s)]["compare"]["rmse"] for s in (16, 64, 256)]
        k = rmse[2] * math.sqrt(256)
        timeTo[name] = (k / EPSILON) ** 2 * t / 1e3
        print("| %s | %.2f | %s | %.4f | %.1f s |" % (
            "shvol" if name == "shvol" else "Cycles 3.4", t, " / ".join("%.4f" % x for x in rmse),
            k, timeTo[name]))
    ratio = timeTo["cycles"] / timeTo["shvol"]
    summary.append((scene, ratio))
    print("\nshvol is **%.2f×** faster than Cycles to equal error.\n" % ratio)
    c = [v for (n, _), v in r.items() if n == "cycles-converged"][0]
    m = c["compare"]
    print("Match check: Cycles at %d spp against the shvol reference: mean %.5f vs %.5f, "
          "difference %+.5f ± %.5f (standard error), RMSE %.4f; difference image `results/%s.difference.png`."
          % (c["spp"], m["image_mean"], m["reference_mean"], m["mean_difference"],
             m["mean_difference_se"], m["rmse"], scene))
    f = {n: v["compare"]["image_mean"] for (n, _), v in r.items() if n.endswith("-furnace")}
    print("White furnace (albedo 1, a constant white sky, 1024 bounces, 256 spp): image mean shvol %.5f, Cycles %.5f.\n"
          % (f["shvol-furnace"], f["cycles-furnace"]))
print("## Summary\n")
print("| scene | shvol speed-up over Cycles 3.4 at equal RMSE |")
print("|---|---:|")
for scene, ratio in summary:
    print("| %s | %.2f× |" % (scene, ratio))
