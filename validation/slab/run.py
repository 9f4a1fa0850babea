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


# The light paths: phase sampling alone (what render.nee "auto" does under these skies), and
# next-event estimation towards the sky with each light sampler and heuristic; the cases take
# them in turn.
STRATEGIES = [
    ("phase", {}),
    ("nee-environment-balance", {"nee": True}),
    ("nee-wavelet-power", {"nee": True, "light_sampling": "wavelet", "mis": "power"}),
    ("nee-product-balance", {"nee": True, "light_sampling": "product"}),
]


def scene(tau, albedo, g, mu, above_only, seed, strategy):
    """A box 2·10⁴ wide and 1 thick (σ_t = τ), seen from above along cos θ = mu by an
    orthographic camera whose footprint stays far from its sides, under a sky of radiance 1."""
    theta = math.acos(mu)
    render = {"spp": SPP, "seed": seed, "max_depth": 1 << 20, "sampler": "independent"}
    render.update(strategy)
    return {
        "camera": {"type": "orthographic", "extent": 0.5, "resolution": [16, 16],
                   "position": [0, -10 * math.sin(theta), 1 + 10 * math.cos(theta)],
                   "target": [0, 0, 1], "up": [0, 1, 0] if mu == 1 else [0, 0, 1]},
        "render": render,
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
    # (The scenes are grey: the mean of one channel, the relative error of the luminance's.)
    mean, relative = stats["image"]["mean"][1], stats.get("image_mean_relative_error")
    return mean, mean * relative if relative is not None else 0.0


def main():
    os.makedirs(WORK, exist_ok=True)
    cases = [(tau, albedo, g, mu, above)
             for g in (0.0, 0.5, 0.9, -0.5) for tau in (0.1, 1.0, 10.0) for albedo in (0.5, 0.9, 0.99)
             for mu in (1.0, 0.5) for above in (True, False)]
    bound = NormalDist().inv_cdf(1 - (1 - (1 - 0.01) ** (1 / len(cases))) / 2)
    rows, zs = [], []
    for seed, (tau, albedo, g, mu, above) in enumerate(cases, start=1):
        refs = slab(tau, albedo, g, views=(mu,))
        ref = refs[0][0] if above else refs[1][0]
        # (In blocks of the four views and skies, so that each strategy meets all of them.)
        label, strategy = STRATEGIES[((seed - 1) // 4) % len(STRATEGIES)]
        name = f"t{tau:g}_a{albedo:g}_g{g:g}_mu{mu:g}_{'above' if above else 'both'}_{label}"
        mean, err = render(scene(tau, albedo, g, mu, above, seed, strategy), name)
        z = (mean - ref) / err if err > 0 else (0.0 if abs(mean - ref) < 1e-12 else math.inf)
        zs.append(z)
        rows.append(f"| {tau:g} | {albedo:g} | {g:g} | {mu:g} | {'above' if above else 'both'} "
                    f"| {label} | {ref:.6f} | {mean:.6f} ± {err:.6f} | {z:+.2f} |")
        print(rows[-1], flush=True)
    worst = max(zs, key=abs)
    summary = (f"{len(zs)} cases at {SPP} spp: mean z {sum(zs) / len(zs):+.3f}, mean z² "
               f"{sum(z * z for z in zs) / len(zs):.3f}, largest |z| {abs(worst):.2f} "
               f"(Šidák bound at α = 0.01: {bound:.2f})")
    with open(os.path.join(RESULTS, "table.md"), "w") as f:
        f.write("| τ | albedo | g | μ | sky | light paths | adding-doubling | shvol ± standard error "
                "| z |\n|---|---|---|---|---|---|---|---|---|\n" + "\n".join(rows) + "\n\n" +
                summary + "\n")
    print(summary)
    for row, z in zip(rows, zs):
        if abs(z) > bound:
            print("beyond the bound:", row)
    return 0 if abs(worst) <= bound else 1


if __name__ == "__main__":
    sys.exit(main())
