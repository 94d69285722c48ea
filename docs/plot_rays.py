#!/usr/bin/env python3
"""Plot a few ray paths around a Kerr black hole and the redshift map of the
same view, with curray's Python package and matplotlib.

    pip install "./python[plot]"    # once (see docs/python.md)
    python3 docs/plot_rays.py [output folder]   # default: docs/

Writes ray_paths.png (the rays of one image row, seen from above the hole
and from the side) and redshift_map.png (nu_obs / nu_em of every pixel).
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import curray  # noqa: E402

A = 0.9  # spin a / M
SCENE = {
    "metric": {"m": 1, "a": A, "q": 0},
    "observer": {"r": 30, "theta": "85 deg", "phi": 0, "hfov": "40 deg"},
    "accretion": {"model": "keplerian", "radius": [12]},  # from the ISCO (2.32 M) out
    "sky_color": [0, 0, 0],
    "horizon_color": [255, 0, 0],
}
W, H = 160, 120
COLOURS = {"disc": "tab:green", "horizon": "black", "sky": "tab:blue", "sphere": "tab:orange"}


def main(out):
    r_plus = 1 + np.sqrt(1 - A * A)
    fig, (top, side) = plt.subplots(1, 2, figsize=(9, 4.2))
    ring = np.linspace(0, 2 * np.pi, 200)
    for ax in (top, side):
        ax.set_aspect("equal")
        ax.set_xlim(-16, 32)
        ax.set_xlabel("x / M")
    top.set_ylim(-16, 16)
    side.set_ylim(-16, 16)
    top.set_ylabel("y / M")
    side.set_ylabel("z / M")
    top.set_title("rays of the middle row, from above")
    side.set_title("rays of the middle column, from the side")
    rho = np.sqrt(r_plus ** 2 + A * A)  # the horizon in the Cartesian (2.2.8) view
    top.fill(rho * np.cos(ring), rho * np.sin(ring), color="black")
    for rr in (2.32, 12):
        top.plot(np.sqrt(rr * rr + A * A) * np.cos(ring), np.sqrt(rr * rr + A * A) * np.sin(ring),
                 color="tab:green", lw=0.8, ls=":")
    side.fill(rho * np.cos(ring), r_plus * np.sin(ring), color="black")
    side.plot([-12, -2.32], [0, 0], [2.32, 12], [0, 0], color="tab:green", lw=2)
    for i in range(4, W, 12):  # a row just above the disc plane
        p = curray.trace(SCENE, pixel=(i, H // 2 - 1), width=W, height=H)
        top.plot(p.x, p.y, color=COLOURS[p.outcome], lw=0.8)
    for j in range(6, H, 9):  # the middle column, top to bottom
        p = curray.trace(SCENE, pixel=(W // 2, j), width=W, height=H)
        side.plot(p.x, p.z, color=COLOURS[p.outcome], lw=0.8)
    top.plot([p.x[0]], [p.y[0]], marker=">", color="red")
    side.plot([p.x[0]], [p.z[0]], marker=">", color="red")
    handles = [plt.Line2D([], [], color=c, label=k) for k, c in COLOURS.items() if k != "sphere"]
    side.legend(handles=handles, loc="upper right", fontsize=8, title="ray ends at",
                title_fontsize=8)
    fig.suptitle("Kerr a = %.1f M, observer at r = 30 M, theta = 85 deg (red marker)" % A)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "ray_paths.png"), dpi=70)

    img = curray.render(SCENE, W * 2, H * 2)
    z = np.ma.masked_where(img["outcome"] != curray.OUTCOMES.index("disc"), img["redshift"])
    fig, ax = plt.subplots(figsize=(5.4, 3.6))
    im = ax.imshow(z, cmap="coolwarm_r", vmin=0.2, vmax=1.8)
    ax.set_title("Keplerian disc: g = nu_obs / nu_em (Kerr a = %.1f M)" % A, fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])
    fig.colorbar(im, ax=ax, shrink=0.8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "redshift_map.png"), dpi=70)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__)))
