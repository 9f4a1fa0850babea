"""Renders homogeneous slabs with shvol and compares the radiance leaving their top with the
adding-doubling solution (adding_doubling.py): README.md here. Writes results/table.md (or
$SLAB_RESULTS/table.md) and exits 1 if any z-score is beyond the Šidák bound at α = 0.01.
$SHVOL names the program (default build/shvol), $SPP the samples per pixel (default 2048)."""
import json
import math
import os
import subprocess
import sys

from adding_doubling import slab
from statistics import NormalDist

HERE = os.path.dirname(os.path.abspath(__file__))
SHVOL = os.environ.get("SHVOL", os.path.join(HERE, "..", "..", "build", "shvol"))
RESULTS = os.environ.get("SLAB_RESULTS", os.path.join(HERE, "results"))
WORK = os.path.join(RESULTS, "work")
SPP = int(os.environ.get("SPP", "2048"))


def scene(tau, albedo, g, mu, above_only, seed):
    """A box 2·10⁴ wide and 1 thick (σ_t = τ), seen from above along cos θ = mu by an
    orthographic camera whose footprint stays far from its sides, under a sky of radiance 1."""
    theta = math.acos(mu)
    return {
        "camera": {"type": "orthographic", "extent": 0.5, "resolution": [16, 16],
                   "position": [0, -10 * math.sin(theta), 1 + 10 * math.cos(theta)],
                   "target": [0, 0, 1], "up": [0, 1, 0] if mu == 1 else [0, 0, 1]},
        "render": {"spp": SPP, "seed": seed, "max_depth": 1 << 20, "sampler": "independent"},
        "environment": {"type": "constant", "radiance": 1, "lower_hemisphere_black": above_only},
        "media": [{"type": "homogeneous", "sigma_t": tau, "albedo": albedo,
                   "phase": {"type": "hg", "g": g} if g else {"type": "isotropic"},
                   "shape": {"type": "box", "min": [-1e4, -1e4, 0], "max": [1e4, 1e4, 1]}}],
    }


def render(s, name):
    path = os.path.join(WORK, name)
    with open(path + ".json", "w") as f:
        json.dump(s, f, indent=1)
    subprocess.run([SHVOL, "render", path + ".json", "-o", path + ".exr", "--quiet"], check=True)
    with open(path + ".stats.json") as f:
        stats = json.load(f)
    mean = stats["image"]["mean"][1]
    return mean, mean * stats["image_mean_relative_error"]


def main():
    os.makedirs(WORK, exist_ok=True)
    cases = [(tau, albedo, g, mu, above)
             for g in (0.0, 0.5, 0.9) for tau in (0.1, 1.0, 10.0) for albedo in (0.5, 0.9, 0.99)
             for mu in (1.0, 0.5) for above in (True, False)]
    bound = NormalDist().inv_cdf(1 - (1 - (1 - 0.01) ** (1 / len(cases))) / 2)
    rows, zs = [], []
    for seed, (tau, albedo, g, mu, above) in enumerate(cases, start=1):
        refs = slab(tau, albedo, g, views=(mu,))
        ref = refs[0][0] if above else refs[1][0]
        name = f"t{tau:g}_a{albedo:g}_g{g:g}_mu{mu:g}_{'above' if above else 'both'}"
        mean, err = render(scene(tau, albedo, g, mu, above, seed), name)
        z = (mean - ref) / err
        zs.append(z)
        rows.append(f"| {tau:g} | {albedo:g} | {g:g} | {mu:g} | {'above' if above else 'both'} "
                    f"| {ref:.6f} | {mean:.6f} ± {err:.6f} | {z:+.2f} |")
        print(rows[-1], flush=True)
    worst = max(zs, key=abs)
    summary = (f"{len(zs)} cases at {SPP} spp: mean z {sum(zs) / len(zs):+.3f}, mean z² "
               f"{sum(z * z for z in zs) / len(zs):.3f}, largest |z| {abs(worst):.2f} "
               f"(Šidák bound at α = 0.01: {bound:.2f})")
    with open(os.path.join(RESULTS, "table.md"), "w") as f:
        f.write("| τ | albedo | g | μ | sky | adding-doubling | shvol ± standard error | z |\n"
                "|---|---|---|---|---|---|---|---|\n" + "\n".join(rows) + "\n\n" + summary + "\n")
    print(summary)
    for row, z in zip(rows, zs):
        if abs(z) > bound:
            print("beyond the bound:", row)
    return 0 if abs(worst) <= bound else 1


if __name__ == "__main__":
    sys.exit(main())
