"""Draws docs/latlong_mapping.png: which column of a lat-long image faces which world direction
under the two conventions of environment.mapping (see include/shvol/lights/latlong.h).

Usage: /usr/bin/python3 docs/latlong_mapping.py [OUT.png]
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__),
                                                          "latlong_mapping.png")
AXES = [(0.0, "+x"), (math.pi / 2, "+y"), (math.pi, "−x"), (1.5 * math.pi, "−y")]


def u_of(mapping, phi):
    """u = x/W of image φ (lights/latlong.h: φ = π − 2πu for blender, 2πu for shvol)."""
    u = (math.pi - phi) / (2 * math.pi) if mapping == "blender" else phi / (2 * math.pi)
    return u - math.floor(u)


fig, axs = plt.subplots(2, 1, figsize=(8, 6.2))
for ax, mapping, title in [(axs[0], "blender", '"blender" (default): image φ = π − 2πu'),
                           (axs[1], "shvol", '"shvol": image φ = 2πu (mirror image)')]:
    ax.set_xlim(0, 1)
    ax.set_ylim(1, 0)  # row 0 at the top
    ax.add_patch(plt.Rectangle((0, 0), 1, 0.5, color="#cfe3ff"))
    ax.add_patch(plt.Rectangle((0, 0.5), 1, 0.5, color="#d9cbb5"))
    for phi, name in AXES:
        u = u_of(mapping, phi)
        ax.axvline(u, color="k", lw=1)
        ax.text(u, 0.47, name, ha="center", va="bottom", fontsize=13, weight="bold",
                bbox=dict(facecolor="white", edgecolor="none", pad=1.5))
    ax.text(0.01, 0.04, "row 0: +z (zenith)", va="top", fontsize=9)
    ax.text(0.01, 0.97, "last row: −z (nadir)", va="bottom", fontsize=9)
    ax.text(0.99, 0.52, "horizon (θ = 90°)", ha="right", va="top", fontsize=9)
    ax.axhline(0.5, color="gray", lw=0.8, ls="--")
    ax.set_xticks([0, 0.25, 0.5, 0.75, 1])
    ax.set_xticklabels(["u = 0", "¼", "½", "¾", "1"])
    ax.set_yticks([])
    ax.set_title(title, fontsize=11)
    arrow = "φ decreases →" if mapping == "blender" else "φ increases →"
    ax.text(0.5, 0.8, arrow + "  (world φ = image φ + rotation; φ from +x towards +y)",
            ha="center", fontsize=9)
fig.suptitle("Which lat-long column faces which direction (z up; columns at u = x/W)",
             fontsize=12)
fig.tight_layout()
fig.savefig(OUT, dpi=90)
print("wrote", OUT)
