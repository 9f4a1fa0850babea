#!/usr/bin/python3
"""Tables and plots of the radiance-cache experiment (run.sh): equal-RMSE time of the HSH radiance
cache against path tracing, and error against time over accuracy a, HSH order n and rays per
record N.

Path tracing's error falls as RMSE = c / sqrt(t) (its runs here confirm it); c is taken as the
geometric mean of RMSE * sqrt(t) over the path-traced runs with at least 16 spp. A cached render's
time is its whole cost: the BRDF tables, filling the records and the render (stats.json), and
path tracing would reach the same RMSE in c^2 / RMSE^2 seconds; the ratio of the two is the
speed-up at equal error.
"""
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))


def rows(folder):
    path = os.path.join(HERE, folder, "results.jsonl")
    out = []
    for line in open(path):
        r = json.loads(line)
        st = json.load(open(os.path.join(HERE, folder, r["run"] + ".stats.json")))
        rc = st.get("radiance_cache", {})
        r["fill_s"] = rc.get("fill_s", 0.0)
        r["table_s"] = rc.get("brdf_table_s", 0.0)
        r["records"] = rc.get("records", 0)
        r["memory_mib"] = rc.get("memory_bytes", 0) / 2**20
        r["lookup_s"] = rc.get("lookup_s", 0.0)
        r["answered"] = rc.get("lookups_answered", 0) / max(1, rc.get("lookups", 0))
        r["total_s"] = r["wall_time_s"] + r["fill_s"] + r["table_s"]
        out.append(r)
    return out


def analyze(scene, lines, fig_name):
    pt = rows(scene + "_pt")
    cache = [r for folder in sorted(os.listdir(HERE))
             if folder == scene + "_cache" or folder.startswith(scene + "_cache_")
             for r in rows(folder)]
    fit = [r for r in pt if r["spp"] >= 16]
    c = math.exp(sum(math.log(r["rmse"] * math.sqrt(r["total_s"])) for r in fit) / len(fit))
    # Path tracing's time to an RMSE: interpolated in log–log between the two path-traced
    # renders whose RMSEs bracket it, beyond them by RMSE = c/√t from the nearest render. (A
    # single c fitted over all spp is pulled up by the low-spp renders, whose RMSE·√t is
    # larger, and would overstate the time path tracing needs at the cache's error.)
    curve = sorted((r["rmse"], r["total_s"]) for r in pt)

    def pt_time(rmse):
        if rmse <= curve[0][0]:
            e, t = curve[0]
            return t * (e / rmse) ** 2
        if rmse >= curve[-1][0]:
            e, t = curve[-1]
            return t * (e / rmse) ** 2
        for (e0, t0), (e1, t1) in zip(curve, curve[1:]):
            if e0 <= rmse <= e1:
                f = math.log(rmse / e0) / math.log(e1 / e0)
                return math.exp(math.log(t0) + f * math.log(t1 / t0))

    lines.append("### %s\n" % scene)
    lines.append("Path tracing (RMSE·√t = %.4f s^½ as a geometric mean over spp ≥ 16; a cached "
                 "render's \"PT time at equal RMSE\" is interpolated in log–log between the "
                 "path-traced renders that bracket its RMSE):\n" % c)
    lines.append("| spp | time s | RMSE | RMSE·√t |")
    lines.append("|---|---|---|---|")
    for r in pt:
        lines.append("| %d | %.2f | %.5f | %.4f |" % (r["spp"], r["total_s"], r["rmse"],
                                                   r["rmse"] * math.sqrt(r["total_s"])))
    lines.append("\nRadiance cache (spp: samples per pixel for the direct light and the pixel "
                 "footprint; time = tables + fill + render):\n")
    lines.append("| a | n | N | light samples | spp | records | MiB | tables s | fill s | render s | lookups s | "
                 "answered | RMSE | bias | PT time at equal RMSE s | speed-up |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    best = None
    for r in sorted(cache, key=lambda r: (r["render.radiance_cache.accuracy"],
                                          r.get("render.radiance_cache.hsh_order", 6),
                                          r["render.radiance_cache.rays_per_record"],
                                          r.get("render.radiance_cache.light_samples", 1),
                                          r["spp"])):
        t_pt = pt_time(r["rmse"])
        speed = t_pt / r["total_s"]
        r["speedup"] = speed
        if best is None or speed > best["speedup"]:
            best = r
        lines.append("| %.2f | %d | %d | %d | %d | %d | %.1f | %.2f | %.2f | %.2f | %.2f | %.3f | "
                     "%.5f | %+.5f | %.1f | %.2f× |" % (
                         r["render.radiance_cache.accuracy"],
                         r.get("render.radiance_cache.hsh_order", 6),
                         r["render.radiance_cache.rays_per_record"],
                         r.get("render.radiance_cache.light_samples", 1), r["spp"], r["records"],
                         r["memory_mib"], r["table_s"], r["fill_s"], r["wall_time_s"],
                         r["lookup_s"], r["answered"], r["rmse"], r["bias"], t_pt, speed))
    lines.append("\nBest: a = %.2f, n = %d, N = %d, %d spp: %.2f× path tracing at equal RMSE "
                 "(%.5f).\n" % (best["render.radiance_cache.accuracy"],
                                 best.get("render.radiance_cache.hsh_order", 6),
                                 best["render.radiance_cache.rays_per_record"], best["spp"],
                                 best["speedup"], best["rmse"]))

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ts = [min(r["total_s"] for r in pt) / 2, max(r["total_s"] for r in pt) * 2]
    ax.loglog(ts, [c / math.sqrt(t) for t in ts], "k:", label="RMSE = c/√t (geometric mean c)")
    ax.loglog([r["total_s"] for r in pt], [r["rmse"] for r in pt], "ko-",
              label="path tracing (the speed-ups interpolate this)")
    for a in sorted({r["render.radiance_cache.accuracy"] for r in cache}):
        sel = [r for r in cache if r["render.radiance_cache.accuracy"] == a]
        ax.loglog([r["total_s"] for r in sel], [r["rmse"] for r in sel], "o", label="cache a = %g" % a)
    ax.set_xlabel("time (tables + fill + render), s")
    ax.set_ylabel("RMSE against the reference")
    ax.set_title(scene + ", 128²")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, fig_name), dpi=110)
    return best


def main():
    lines = ["# Radiance cache results (written by analyze.py)\n"]
    for scene in ["cornell", "cornell_fog"]:
        if os.path.exists(os.path.join(HERE, scene + "_cache", "results.jsonl")):
            analyze(scene, lines, scene + "_error_vs_time.png")
    open(os.path.join(HERE, "results.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
