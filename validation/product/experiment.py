"""What product sampling buys: light-sampling strategies on a sunlit cloud (run by run.sh).

For the default cloud (media/sunlit_cloud.json: density_scale 60, optically thick) and a thin one
(density_scale 6), each with HG g in {0, 0.5, 0.8, 0.95} and the tabulated Mie-like phase
function, under a Preetham clear sky with a 0.53 degree sun behind the cloud:
  * a converged reference (MIS(environment, phase), REF_SPP spp, seed 1000);
  * every strategy at SPP spp with two seeds: MSE against the reference (mean of the two), the
    variance of one image (RMSE(seed 1, seed 2)^2 / 2: independent, unbiased estimates), the
    render time (stats wall_time_s: the sampling loop on THREADS threads, without loading) and
    the efficiency 1 / (MSE x time);
  * every strategy again at equal time: spp chosen so that its time matches MIS(environment,
    phase) at SPP spp, one seed, MSE and efficiency;
  * sweeps on the thin cloud at g = 0.8 and 0.95 of MIS(product, phase): wavelet compression K,
    product order and product depth.
Writes results/strategies.csv, results/sweeps.csv, PNG previews of some images (shvol tonemap)
and results/run.json (settings, machine). EXRs stay in results/tmp/ (not committed).

Usage: experiment.py [BUILD_DIR] [OUT_DIR]
Environment: REF_SPP (default 2048), SPP (default 64), RES (default "120,80"), THREADS (2),
QUICK=1 (one phase function per scene, for a smoke test), PHASES (comma-separated names, e.g.
"hg0.8,hg0.95"), SKY (an EXR replacing the scene's sky; its environment.scale is set to 1),
SWEEPS=0 (skip the sweeps).
"""
import csv
import json
import os
import platform
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
OUT = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "validation/product/results")
SHVOL = os.path.join(BUILD, "shvol")
SCENE = os.path.join(ROOT, "media/sunlit_cloud.json")
REF_SPP = int(os.environ.get("REF_SPP", "2048"))
SPP = int(os.environ.get("SPP", "64"))
RES = os.environ.get("RES", "120,80")
THREADS = int(os.environ.get("THREADS", "2"))
QUICK = os.environ.get("QUICK", "0") == "1"
TMP = os.path.join(OUT, "tmp")

CLOUDS = [("dense", 60), ("thin", 6)]
PHASES = [("hg0", {"type": "hg", "g": 0.0}), ("hg0.5", {"type": "hg", "g": 0.5}),
          ("hg0.8", {"type": "hg", "g": 0.8}), ("hg0.95", {"type": "hg", "g": 0.95}),
          ("mie", {"type": "tabulated", "file": "phase/mie_like.csv"})]
if QUICK:
    PHASES = [PHASES[2]]
if os.environ.get("PHASES"):
    PHASES = [p for p in PHASES if p[0] in os.environ["PHASES"].split(",")]
SKY = os.environ.get("SKY")
SWEEPS = os.environ.get("SWEEPS", "1") != "0"
STRATEGIES = [
    ("phase", {"render.nee": False}),
    ("environment", {"render.light_sampling": "environment", "render.mis": "none"}),
    ("wavelet", {"render.light_sampling": "wavelet", "render.mis": "none"}),
    ("product", {"render.light_sampling": "product", "render.mis": "none"}),
    ("mis_environment", {"render.light_sampling": "environment", "render.mis": "balance"}),
    ("mis_wavelet", {"render.light_sampling": "wavelet", "render.mis": "balance"}),
    ("mis_product", {"render.light_sampling": "product", "render.mis": "balance"}),
]
BASELINE = "mis_environment"
NON_PRODUCT = ["phase", "environment", "wavelet", "mis_environment", "mis_wavelet"]
PREVIEWS = {("dense", "hg0.8"), ("thin", "hg0.95")}


def sets(overrides):
    out = []
    for k, v in overrides.items():
        out += ["--set", f"{k}={json.dumps(v)}"]
    return out


def render(name, overrides, spp, seed):
    out = os.path.join(TMP, f"{name}_spp{spp}_s{seed}.exr")
    cmd = [SHVOL, "render", SCENE, "-o", out, "--spp", str(spp), "--seed", str(seed),
           "--threads", str(THREADS), "--quiet", "--set", f"camera.resolution=[{RES}]"]
    subprocess.run(cmd + sets(overrides), check=True)
    with open(out[:-4] + ".stats.json") as f:
        return out, json.load(f)


def diff(img, ref):
    r = subprocess.run([SHVOL, "diff", img, ref, "--json"], check=True, capture_output=True,
                       text=True)
    return json.loads(r.stdout)


def preview(exr, png):
    subprocess.run([SHVOL, "tonemap", exr, "-o", png], check=True)


def measure(label, overrides, ref, spp, seeds):
    """MSE (mean over seeds), variance of one image (from the first two seeds), time."""
    imgs, mse, times, stats = [], [], [], None
    for seed in seeds:
        img, stats = render(label, overrides, spp, seed)
        imgs.append(img)
        mse.append(diff(img, ref)["rmse"] ** 2)
        times.append(stats["wall_time_s"])
    var = diff(imgs[0], imgs[1])["rmse"] ** 2 / 2 if len(imgs) > 1 else float("nan")
    t = sum(times) / len(times)
    m = sum(mse) / len(mse)
    return {"mse": m, "variance": var, "time_s": t, "efficiency": 1 / (m * t),
            "ns_per_path": 1e9 * t * THREADS / stats["paths"],
            "light_samples": stats["light_samples"], "product_samples": stats["product_samples"],
            "mean_path_length": stats["mean_path_length"],
            "non_finite": stats["non_finite_samples"], "image": imgs[0]}


def main():
    os.makedirs(TMP, exist_ok=True)
    rows, sweeps = [], []
    for cloud, scale in CLOUDS:
        for pname, phase in PHASES:
            base = {"media.0.density_scale": scale, "media.0.phase": phase}
            if SKY:
                base.update({"environment.file": os.path.abspath(SKY), "environment.scale": 1})
            tag = f"{cloud}_{pname}"
            print(f"{tag}: reference ({REF_SPP} spp) ...", flush=True)
            ref, ref_stats = render(f"{tag}_ref", {**base, **dict(STRATEGIES)[BASELINE]},
                                    REF_SPP, 1000)
            if (cloud, pname) in PREVIEWS:
                preview(ref, os.path.join(OUT, f"{tag}_reference.png"))
            results = {}
            for name, ov in STRATEGIES:
                results[name] = measure(f"{tag}_{name}", {**base, **ov}, ref, SPP, [1, 2])
            budget = results[BASELINE]["time_s"]
            for name, ov in STRATEGIES:
                r = results[name]
                spp_eq = max(1, round(SPP * budget / r["time_s"]))
                eq = measure(f"{tag}_{name}_eqtime", {**base, **ov}, ref, spp_eq, [3])
                if (cloud, pname) in PREVIEWS and name in ("environment", BASELINE,
                                                           "mis_product"):
                    preview(eq["image"], os.path.join(OUT, f"{tag}_{name}_equal_time.png"))
                row = {"cloud": cloud, "phase": pname, "strategy": name, "spp": SPP,
                       "mse": r["mse"], "variance": r["variance"], "time_s": r["time_s"],
                       "ns_per_path": r["ns_per_path"], "efficiency": r["efficiency"],
                       "eq_time_spp": spp_eq, "eq_time_s": eq["time_s"], "eq_time_mse": eq["mse"],
                       "eq_time_efficiency": eq["efficiency"],
                       "ref_noise_mse": results[BASELINE]["variance"] * SPP / REF_SPP,
                       "mean_path_length": r["mean_path_length"],
                       "non_finite": r["non_finite"] + eq["non_finite"]}
                rows.append(row)
                print(f"  {name:16s} mse {r['mse']:.3e} var {r['variance']:.3e} "
                      f"t {r['time_s']:.2f}s eff {r['efficiency']:.3g} | equal time "
                      f"{spp_eq} spp mse {eq['mse']:.3e}", flush=True)
            if SWEEPS and cloud == "thin" and pname in ("hg0.8", "hg0.95"):
                mp = {**base, **dict(STRATEGIES)["mis_product"]}
                for key, values in [("environment.wavelet_coefficients",
                                     [0, 100, 1000, 10000, 100000]),
                                    ("render.product_order", [2, 4, 8, 16, 32]),
                                    ("render.product_depth", [3, 4, 5, 6, 7, 8, 9])]:
                    for v in values:
                        r = measure(f"{tag}_sweep_{key}_{v}", {**mp, key: v}, ref, SPP, [1, 2])
                        with open(r["image"][:-4] + ".stats.json") as f:
                            ls = json.load(f)["light_sampling"]
                        sweeps.append({"cloud": cloud, "phase": pname, "key": key, "value": v,
                                       "mse": r["mse"], "variance": r["variance"],
                                       "time_s": r["time_s"], "efficiency": r["efficiency"],
                                       "sky_memory_bytes": ls["sky_memory_bytes"],
                                       "wavelet_relative_l2_error":
                                           ls["wavelet_relative_l2_error"],
                                       "product_depth": ls["product_depth"]})
                        print(f"  sweep {key}={v}: mse {r['mse']:.3e} t {r['time_s']:.2f}s "
                              f"eff {r['efficiency']:.3g}", flush=True)
    for fname, data in [("strategies.csv", rows), ("sweeps.csv", sweeps)]:
        if data:
            with open(os.path.join(OUT, fname), "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=list(data[0].keys()))
                w.writeheader()
                w.writerows(data)
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    with open(os.path.join(OUT, "run.json"), "w") as f:
        json.dump({"ref_spp": REF_SPP, "spp": SPP, "resolution": RES, "threads": THREADS,
                   "baseline": BASELINE, "cpu": cpu, "machine": platform.machine()}, f, indent=2)


if __name__ == "__main__":
    main()
