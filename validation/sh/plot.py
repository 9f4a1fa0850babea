"""Plots for validation/sh (run by run.sh with /usr/bin/python3)."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "validation/sh/results"


def rows(name):
    with open(f"{out}/{name}") as f:
        return list(csv.DictReader(f))


# Gautron Figure 4
r = rows("fig4_energy.csv")
fig, ax = plt.subplots(figsize=(6, 4))
for lobe, style in [("cos5_normal", "-"), ("cos20_normal", "--"), ("cos5_tilt45", ":")]:
    for basis, color in [("SH", "tab:blue"), ("HSH", "tab:red")]:
        pts = [(int(x["coefficients"]), float(x["energy_fraction"])) for x in r
               if x["lobe"] == lobe and x["basis"] == basis]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], style, color=color, marker="o", ms=3,
                label=f"{basis} {lobe}")
ax.set_xlabel("number of coefficients n²")
ax.set_ylabel("energy fraction (Gautron eq. 15)")
ax.set_xlim(0, 100)
ax.set_ylim(0, 1.02)
ax.grid(alpha=0.3)
ax.legend(fontsize=7)
ax.set_title("Phong lobes: SH vs HSH (cf. Gautron et al. 2004, Fig. 4)")
fig.tight_layout()
fig.savefig(f"{out}/fig4_energy.png", dpi=120)

# Rotation error
r = rows("rotation_error.csv")
fig, ax = plt.subplots(figsize=(6, 4))
l = [int(x["l"]) for x in r]
for key, lab in [("ir_max_abs_RRt_minus_I", "Ivanic–Ruedenberg |RRᵀ−I|"),
                 ("ir_max_abs_RaRb_minus_Rab", "Ivanic–Ruedenberg |R(a)R(b)−R(ab)|"),
                 ("eig_max_abs_RRt_minus_I", "Euler/eigen |RRᵀ−I|"),
                 ("eig_max_abs_RaRb_minus_Rab", "Euler/eigen |R(a)R(b)−R(ab)|")]:
    ax.semilogy(l[1:], [max(float(x[key]), 1e-17) for x in r][1:], label=lab)
ax.set_xlabel("band l")
ax.set_ylabel("max abs error")
ax.grid(alpha=0.3)
ax.legend(fontsize=7)
ax.set_title("SH rotation matrices: error vs band")
fig.tight_layout()
fig.savefig(f"{out}/rotation_error.png", dpi=120)

# Legendre accuracy
r = rows("legendre_accuracy.csv")
fig, ax = plt.subplots(figsize=(6, 4))
l = [int(x["l"]) for x in r]
ax.loglog(l, [max(float(x["max_abs_err_over_envelope"]), 1e-18) for x in r], "o-",
          label="max |N − ref| / √((2l+1)/4π)")
ax.loglog(l, [max(float(x["max_rel_err_near_pole"]), 1e-18) for x in r], "s-",
          label="max rel. error, |z| ≥ 1−1e-9")
ax.loglog(l, [float(x["eps_l_1.5"]) for x in r], "k--", label="ε·l^1.5")
ax.set_xlabel("l")
ax.set_ylabel("error")
ax.grid(alpha=0.3)
ax.legend(fontsize=7)
ax.set_title("Normalised Legendre functions vs 50-digit boost::math")
fig.tight_layout()
fig.savefig(f"{out}/legendre_accuracy.png", dpi=120)

# Integral accuracy
r = rows("integral_accuracy.csv")
fig, axs = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
names = list(dict.fromkeys(x["interval"] for x in r))
for ax, key, title in [(axs[0], "max_err_switch", "library (narrow-interval switch)"),
                       (axs[1], "max_err_recurrence_only", "recurrence only")]:
    for nm in names:
        pts = [(int(x["n"]), max(float(x[key]), 1e-18)) for x in r if x["interval"] == nm]
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=nm)
    ax.set_title(title)
    ax.set_xlabel("order n")
    ax.grid(alpha=0.3)
axs[0].set_ylabel("max |J − ref| / (env · min(1, Δz))")
axs[1].legend(fontsize=7)
fig.tight_layout()
fig.savefig(f"{out}/integral_accuracy.png", dpi=120)
print("plots written to", out)
