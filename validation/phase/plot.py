"""Plots for validation/phase (run by run.sh with Debian's /usr/bin/python3 + matplotlib).

Reads results/phase_sh.csv, results/analytic.csv and results/render_compare.csv and writes
  fit_error_vs_order.png      relative L2 error and min/peak of the fit vs order, per phase function
  sampling_vs_order.png       chi² p-value against the analytic pdf and variance ratio vs order
  error_vs_ns.png             relative L2 error vs ns/sample (SH) with the analytic samplers marked
  render_rmse_vs_time.png     render RMSE vs wall time (analytic, SH pdf, SH as phase)
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results")


def rows(name):
    with open(os.path.join(out, name)) as f:
        return list(csv.DictReader(f))


sh = rows("phase_sh.csv")
phases = list(dict.fromkeys(r["phase"] for r in sh))
colors = dict(zip(phases, plt.cm.tab10.colors))
styles = {"none": "--", "hann": "-"}


def series(phase, window, key):
    pts = [(int(r["order"]), float(r[key])) for r in sh
           if r["phase"] == phase and r["window"] == window]
    return [p[0] for p in pts], [p[1] for p in pts]


# Fit error vs order
fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
for ph in phases:
    for win in ("none", "hann"):
        x, y = series(ph, win, "rel_l2_error")
        axes[0].loglog(x, [max(v, 1e-16) for v in y], styles[win], color=colors[ph], marker="o",
                       ms=3, label=f"{ph} ({win})" if win == "hann" else None)
        x, y = series(ph, win, "max_error")
        _, peak = series(ph, win, "peak_value")
        axes[1].loglog(x, [max(v / p, 1e-16) for v, p in zip(y, peak)], styles[win],
                       color=colors[ph], marker="o", ms=3)
axes[0].set_ylabel("relative L2 error ‖p − p̃‖/‖p‖")
axes[1].set_ylabel("max |p − p̃| / max p")
for ax in axes:
    ax.set_xlabel("order n (bands)")
    ax.grid(alpha=0.3, which="both")
axes[0].legend(fontsize=7, title="solid: Hann, dashed: none", title_fontsize=7)
fig.suptitle("Zonal SH fit of phase functions: error vs order")
fig.tight_layout()
fig.savefig(os.path.join(out, "fit_error_vs_order.png"), dpi=110)

# Sampling fidelity and variance vs order
fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
for ph in phases:
    for win in ("none", "hann"):
        x, y = series(ph, win, "chi2_analytic_p")
        axes[0].loglog(x, [max(v, 1e-300) for v in y], styles[win], color=colors[ph],
                       marker="o", ms=3, label=f"{ph}" if win == "hann" else None)
        x, y = series(ph, win, "var_ratio_sh_over_analytic")
        axes[1].loglog(x, y, styles[win], color=colors[ph], marker="o", ms=3)
n_tests = len(sh)
axes[0].set_ylabel("χ² p-value, SH samples vs analytic pdf (0 drawn at 1e-300)")
axes[0].axhline(1 - 0.99 ** (1 / n_tests), color="k", lw=0.5)  # Šidák threshold of the family
axes[1].set_ylabel("Var[SH pdf estimator] / Var[analytic]")
axes[1].axhline(1, color="k", lw=0.5)
for ax in axes:
    ax.set_xlabel("order n (bands)")
    ax.grid(alpha=0.3, which="both")
axes[0].legend(fontsize=7, title="solid: Hann, dashed: none", title_fontsize=7)
fig.suptitle("SH-sampled directions: fidelity to the analytic pdf, and estimator variance")
fig.tight_layout()
fig.savefig(os.path.join(out, "sampling_vs_order.png"), dpi=110)

# Error vs ns/sample
an = {r["phase"]: r for r in rows("analytic.csv")}
fig, ax = plt.subplots(figsize=(7, 5))
for ph in phases:
    x, y = series(ph, "hann", "ns_sh")
    _, e = series(ph, "hann", "rel_l2_error")
    ax.loglog(y, [max(v, 1e-16) for v in e], "-", color=colors[ph], marker="o", ms=3, label=ph)
    ax.axvline(float(an[ph]["ns_per_sample"]), color=colors[ph], lw=0.8, ls=":")
ax.set_xlabel("ns per sample (SH sampler incl. frame, pdf and p; dotted: analytic sampler)")
ax.set_ylabel("relative L2 error of the fit (Hann)")
ax.grid(alpha=0.3, which="both")
ax.legend(fontsize=7)
ax.set_title("Fit error vs sampling cost (orders 2…64)")
fig.tight_layout()
fig.savefig(os.path.join(out, "error_vs_ns.png"), dpi=110)

# Render RMSE vs time
rc_path = os.path.join(out, "render_compare.csv")
if os.path.exists(rc_path):
    rc = rows("render_compare.csv")
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    orders = sorted({int(r["order"]) for r in rc if r["method"] != "analytic"})
    oc = dict(zip(orders, ["tab:orange", "tab:green", "tab:red", "tab:purple"]))
    for method, ls, marker in [("analytic", "-", "s"), ("sh_pdf", "-", "o"),
                               ("sh_as_phase", "--", "^")]:
        for order in ([0] if method == "analytic" else orders):
            pts = sorted((float(r["wall_time_s"]), float(r["rmse"]), int(r["spp"]))
                         for r in rc if r["method"] == method and int(r["order"]) == order)
            if not pts:
                continue
            color = "k" if method == "analytic" else oc[order]
            label = "analytic HG" if method == "analytic" else f"{method} n={order}"
            axes[0].loglog([p[0] for p in pts], [p[1] for p in pts], ls, marker=marker,
                           color=color, label=label)
            spp = [p[2] for p in pts]
            axes[1].loglog(spp, [p[1] for p in pts], ls, marker=marker, color=color, label=label)
    axes[0].set_xlabel("wall time (s, 2 threads)")
    axes[1].set_xlabel("samples per pixel")
    for ax in axes:
        ax.set_ylabel("RMSE vs analytic reference")
        ax.grid(alpha=0.3, which="both")
    axes[1].legend(fontsize=7)
    fig.suptitle("Default cloud (HG g=0.8): SH-sampled phase vs analytic "
                 "(dashed: SH as phase — a different phase function, RMSE floors at its bias)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "render_rmse_vs_time.png"), dpi=110)
print("plots written to", out)


# Markdown tables for README.md (results/tables.md)
def fmt(v, digits=3):
    v = float(v)
    if v == 0:
        return "0"
    if abs(v) >= 1e4 or abs(v) < 1e-3:
        return f"{v:.{digits - 1}e}"
    return f"{v:.{digits}g}"


def matrix(key, window, orders, f=fmt):
    lines = ["| phase | " + " | ".join(f"n={o}" for o in orders) + " |",
             "|---|" + "---|" * len(orders)]
    for ph in phases:
        vals = {int(r["order"]): r[key] for r in sh if r["phase"] == ph and r["window"] == window}
        lines.append(f"| {ph} | " + " | ".join(f(vals[o]) for o in orders) + " |")
    return "\n".join(lines)


orders_all = sorted({int(r["order"]) for r in sh})
sel = [2, 4, 8, 16, 32, 64]
md = []
for win in ("none", "hann"):
    md.append(f"### Relative L2 error of the fit, window {win}\n\n" +
              matrix("rel_l2_error", win, orders_all))
    md.append(f"### min p̃ / max p, window {win}\n\n" + matrix("min_over_peak", win, sel))
    md.append(f"### Clamped fraction of z-bins, window {win}\n\n" +
              matrix("clamped_fraction", win, sel))
    md.append(f"### χ² p-value of SH samples against the SH pdf, window {win}\n\n" +
              matrix("chi2_sh_p", win, sel))
    md.append(f"### χ² p-value of SH samples against the analytic pdf, window {win}\n\n" +
              matrix("chi2_analytic_p", win, orders_all))
    md.append(f"### Var[SH-pdf estimator] / Var[analytic], window {win}\n\n" +
              matrix("var_ratio_sh_over_analytic", win, orders_all))
    md.append(f"### max p/pdf (Exact use), window {win}\n\n" + matrix("max_weight", win, sel))
    md.append(f"### Relative bias of I under SH-as-phase, window {win}\n\n" +
              matrix("recon_rel_bias", win, sel))

# lowest order whose samples pass χ² against the analytic pdf (and every higher order too)
lines = ["| phase | lowest passing order, none | lowest passing order, hann |", "|---|---|---|"]
for ph in phases:
    cells = []
    for win in ("none", "hann"):
        rs = sorted(((int(r["order"]), r["chi2_analytic_passed"] == "1") for r in sh
                     if r["phase"] == ph and r["window"] == win))
        lowest = "> 64"
        for i, (o, _) in enumerate(rs):
            if all(p for _, p in rs[i:]):
                lowest = str(o)
                break
        cells.append(lowest)
    lines.append(f"| {ph} | " + " | ".join(cells) + " |")
md.append("### Lowest order from which SH samples pass χ² against the analytic pdf "
          "(2e5 samples, Šidák α = 0.01)\n\n" + "\n".join(lines))

# timing
lines = ["| phase | analytic sample (ns) | SH sample, median over configs (ns) | ratio | "
         "zonal warp alone (ns) | build n=16 (ms) | build n=64 (ms) |", "|---|---|---|---|---|---|---|"]
for ph in phases:
    rs = [r for r in sh if r["phase"] == ph]
    med = lambda k: sorted(float(r[k]) for r in rs)[len(rs) // 2]  # noqa: E731
    b = {(r["window"], int(r["order"])): float(r["build_ms"]) for r in rs}
    lines.append(f"| {ph} | {med('ns_analytic'):.1f} | {med('ns_sh'):.1f} | "
                 f"{med('ns_sh') / med('ns_analytic'):.2f} | {med('ns_sh_local'):.1f} | "
                 f"{b[('hann', 16)]:.1f} | {b[('hann', 64)]:.1f} |")
md.append("### Cost per sample (single core, best of 5 passes over 2^20 samples)\n\n" +
          "\n".join(lines))

if os.path.exists(rc_path):
    lines = ["| method | order | spp | RMSE | relative RMSE | mean/ref − 1 | wall time (s) |",
             "|---|---|---|---|---|---|---|"]
    for r in rc:
        lines.append(f"| {r['method']} | {r['order'] if r['method'] != 'analytic' else '–'} | "
                     f"{r['spp']} | {float(r['rmse']):.4f} | {float(r['relative_rmse']):.4f} | "
                     f"{float(r['mean_rel_diff']):+.4f} | {float(r['wall_time_s']):.2f} |")
    md.append("### Render comparison\n\n" + "\n".join(lines))

with open(os.path.join(out, "tables.md"), "w") as f:
    f.write("\n\n".join(md) + "\n")
