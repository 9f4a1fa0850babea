"""Render comparison for validation/phase (run by run.sh with /usr/bin/python3).

The default cloud (media/default.json, HG g = 0.8) at reduced resolution: a reference with the
analytic HG sampler at high spp, then analytic HG vs SH pdf (evaluate "exact": the phase function
is HG, the SH fit only supplies directions and their pdf; unbiased) vs SH as phase (evaluate "sh":
the clamped, normalised SH reconstruction *is* the phase function; a different phase function, so
a different image) at orders 4, 8, 16, 32, each at several equal spp. Writes
results/render_compare.csv with the RMSE against the reference (shvol diff) and the wall time.

Usage: render_compare.py [BUILD_DIR] [OUT_DIR]
Environment: REF_SPP (default 4096), SPPS (default "16,64,256"), RES (default "160,106").
"""
import csv
import json
import os
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
OUT = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "validation/phase/results")
SHVOL = os.path.join(BUILD, "shvol")
SCENE = os.path.join(ROOT, "media/default.json")
REF_SPP = int(os.environ.get("REF_SPP", "4096"))
SPPS = [int(s) for s in os.environ.get("SPPS", "16,64,256").split(",")]
RES = os.environ.get("RES", "160,106")
ORDERS = [4, 8, 16, 32]
THREADS = 2
G = 0.8
WORK = os.path.join(OUT, "render_tmp")  # EXRs are not committed (see .gitignore in results/)


def render(name, phase, spp, seed):
    out = os.path.join(WORK, f"{name}_spp{spp}.exr")
    cmd = [SHVOL, "render", SCENE, "-o", out, "--spp", str(spp), "--seed", str(seed),
           "--threads", str(THREADS), "--quiet", "--set", f"camera.resolution=[{RES}]",
           "--set", "media.0.phase=" + json.dumps(phase)]
    t0 = time.monotonic()
    subprocess.run(cmd, check=True)
    elapsed = time.monotonic() - t0
    with open(out[:-4] + ".stats.json") as f:
        stats = json.load(f)
    return out, stats, elapsed


def diff(img, ref):
    r = subprocess.run([SHVOL, "diff", img, ref, "--json"], check=True, capture_output=True,
                       text=True)
    return json.loads(r.stdout)


def main():
    os.makedirs(WORK, exist_ok=True)
    ref_phase = {"type": "hg", "g": G}
    print(f"reference: analytic HG g={G}, {REF_SPP} spp at {RES} on {THREADS} threads ...",
          flush=True)
    ref, ref_stats, ref_time = render("reference", ref_phase, REF_SPP, 1000)
    print(f"  {ref_stats['wall_time_s']:.1f} s, {ref_stats['paths_per_second']:.3g} paths/s",
          flush=True)

    configs = [("analytic", "analytic", 0, ref_phase)]
    for order in ORDERS:
        for evaluate, label in [("exact", "sh_pdf"), ("sh", "sh_as_phase")]:
            configs.append((f"{label}_n{order}", label, order,
                            {"type": "hg", "g": G, "sampling": "sh", "order": order,
                             "window": "hann", "evaluate": evaluate}))

    rows = []
    for spp in SPPS:
        for name, method, order, phase in configs:
            img, stats, elapsed = render(name, phase, spp, 1)
            d = diff(img, ref)
            row = {
                "method": method, "order": order, "spp": spp,
                "rmse": d["rmse"], "relative_rmse": d["relative_rmse"],
                "mean": d["mean"], "reference_mean": d["reference_mean"],
                "mean_rel_diff": d["mean"] / d["reference_mean"] - 1,
                "wall_time_s": stats["wall_time_s"], "process_time_s": elapsed,
                "paths_per_second": stats["paths_per_second"],
                "mean_path_length": stats["mean_path_length"],
                "phase_samples": stats["phase_samples"],
                "non_finite_samples": stats["non_finite_samples"],
            }
            rows.append(row)
            print(f"  spp {spp:4d} {name:16s} rmse {d['rmse']:.4f} rel {d['relative_rmse']:.4f} "
                  f"mean {row['mean_rel_diff']:+.4f}  {stats['wall_time_s']:.2f} s", flush=True)

    with open(os.path.join(OUT, "render_compare.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(OUT, "render_reference.json"), "w") as f:
        json.dump({"spp": REF_SPP, "resolution": RES, "seed": 1000, "threads": THREADS,
                   "wall_time_s": ref_stats["wall_time_s"],
                   "paths_per_second": ref_stats["paths_per_second"],
                   "mean_path_length": ref_stats["mean_path_length"]}, f, indent=2)


if __name__ == "__main__":
    main()
