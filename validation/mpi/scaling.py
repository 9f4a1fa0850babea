"""Measures how shvol render and shvol batch scale over MPI ranks and batch jobs on this machine
and fits the model in README.md; writes scaling.json and scaling.png here.

Every configuration runs `repeats` times; the median wall time counts (process start to exit), and
the median of the rendering times its stats files report (`wall_time_s`, the render loop alone).
"""
import json, os, shutil, statistics, subprocess, sys, tempfile, time

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SHVOL = os.path.join(ROOT, "build", "shvol")
MPIRUN = ["mpirun", "--oversubscribe", "-np"]
if os.geteuid() == 0:
    MPIRUN = ["mpirun", "--oversubscribe", "--allow-run-as-root", "-np"]
SCENE = os.path.join(ROOT, "media", "default.json")
SPP = 32
REPEATS = 3


def timed(cmd, work):
    """Median wall time of `cmd` and the median rendering time of its runs (`work`/out.stats.json;
    None when the command writes no stats)."""
    times, renders = [], []
    for _ in range(REPEATS):
        shutil.rmtree(work, ignore_errors=True)
        os.makedirs(work)
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, cwd=work, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - t0)
        stats = os.path.join(work, "out.stats.json")
        if os.path.exists(stats):
            renders.append(json.load(open(stats))["wall_time_s"])
    return statistics.median(times), (statistics.median(renders) if renders else None)


def main():
    tmp = tempfile.mkdtemp(prefix="shvol_scaling_")
    render = [SHVOL, "render", SCENE, "--spp", str(SPP), "--quiet", "-o", "out.exr"]
    res = {"spp": SPP, "scene": "media/default.json", "repeats": REPEATS, "render": {}, "batch": {}}
    configs = {
        "1 process, 1 thread": render + ["--threads", "1"],
        "1 process, 2 threads": render + ["--threads", "2"],
        "mpirun -np 1, 1 thread": MPIRUN + ["1"] + render + ["--threads", "1"],
        "mpirun -np 2, 1 thread each": MPIRUN + ["2"] + render + ["--threads", "1"],
    }
    for name, cmd in configs.items():
        t, rt = timed(cmd, os.path.join(tmp, "r"))
        res["render"][name] = {"wall_s": t, "render_s": rt}
        print(f"render  {name:32s} {t:7.2f} s (rendering {rt:.2f} s)", flush=True)

    # A sweep of small renders: 16 runs of 150x100 pixels at 4 to 32 spp.
    sweep = os.path.join(tmp, "sweep.json")
    json.dump({"scene": SCENE, "set": ["camera.resolution=[150,100]"],
               "axes": {"spp": [4, 8, 16, 32]}, "repeats": 4}, open(sweep, "w"))
    batch = [SHVOL, "batch", sweep, "--quiet", "--output", "b"]
    bconfigs = {
        "1 job, 2 threads": batch + ["--jobs", "1", "--threads", "2"],
        "2 jobs, 1 thread each": batch + ["--jobs", "2", "--threads", "1"],
        "mpirun -np 2, 1 thread each": MPIRUN + ["2"] + batch + ["--threads", "1"],
        "1 job, 1 thread": batch + ["--jobs", "1", "--threads", "1"],
    }
    for name, cmd in bconfigs.items():
        t, _ = timed(cmd, os.path.join(tmp, "b"))
        res["batch"][name] = {"wall_s": t}
        print(f"batch   {name:32s} {t:7.2f} s", flush=True)
    shutil.rmtree(tmp)

    # The model (README.md): T(N) = T_serial + T_parallel / N + T_reduce * ceil(log2 N), all three
    # from the MPI runs themselves: the serial part is -np 1's wall time less its own rendering.
    r = res["render"]
    t1 = r["mpirun -np 1, 1 thread"]["wall_s"]
    t2 = r["mpirun -np 2, 1 thread each"]["wall_s"]
    tpar = r["mpirun -np 1, 1 thread"]["render_s"]
    tser = t1 - tpar
    tred = max(0.0, t2 - tser - tpar / 2)
    res["model"] = {"serial_s": tser, "parallel_s": tpar, "reduce_s": tred}
    json.dump(res, open(os.path.join(HERE, "scaling.json"), "w"), indent=2)

    ns = [1, 2, 4, 8, 16, 32, 64]
    model = [t1 / (tser + tpar / n + tred * max(0, (n - 1).bit_length())) for n in ns]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(ns, ns, ":", color="grey", label="ideal")
    ax.plot(ns, model, "--", label="model (serial part and reduce measured here)")
    ax.plot([1, 2], [1, t1 / t2], "o", label="measured, mpirun render")
    b = res["batch"]
    ax.plot([2], [b["1 job, 1 thread"]["wall_s"] / b["mpirun -np 2, 1 thread each"]["wall_s"]],
            "s", label="measured, mpirun batch (16 small runs)")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log", base=2)
    ax.set_xlabel("ranks (1 thread each)")
    ax.set_ylabel("speed-up over 1 rank")
    ax.set_title(f"shvol render, media/default.json, {SPP} spp")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "scaling.png"), dpi=110)
    print(json.dumps(res["model"]))


if __name__ == "__main__":
    sys.exit(main())
