"""Stick/slip map and traction arrows of FASTSIM for a combined creepage + spin case.

Writes ``out/fastsim_traction_map.png``: the contact ellipse of a wheel on a rail (a = 6 mm along
the rolling direction, b = 4 mm), ξ = 0.1 %, η = 0.05 %, φ = 1 /m, μ = 0.3, N = 100 kN,
parabolic traction bound (Kalker's FASTSIM, ``contact_core.fastsim``), 30 strips × 30 elements.
Left: elements in stick (blue) and slip (red), the leading edge is on the right (x = +a).
Right: traction vectors (rail on wheel) over |p|/(μ p_n).
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402

import contact_core as cc  # noqa: E402

OUT = Path(__file__).resolve().parent.parent / "out" / "fastsim_traction_map.png"
CASE = dict(xi=1e-3, eta=5e-4, phi=1.0, N=100e3, mu=0.3, a=6e-3, b=4e-3,
            G=cc.shear_modulus(210e9, 0.28), nu=0.28)


def main() -> Path:
    r = cc.solve("fastsim", **CASE, nx=30, ny=30, bound="parabolic", fields=True)
    f = r.fields
    x_mm, y_mm = f.x * 1e3, f.y * 1e3
    a_mm, b_mm = CASE["a"] * 1e3, CASE["b"] * 1e3
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 5.2), constrained_layout=True)

    ax1.scatter(x_mm.ravel(), y_mm.ravel(), c=f.slip.ravel().astype(float), s=14, marker="s",
                cmap=ListedColormap(["tab:blue", "tab:red"]), vmin=0, vmax=1)
    ax1.scatter([], [], c="tab:blue", marker="s", label="stick")
    ax1.scatter([], [], c="tab:red", marker="s", label="slip")
    ax1.legend(loc="upper left", fontsize=8)
    ax1.set_title(f"stick/slip (slip fraction {r.slip_fraction:.2f}); rolling: leading edge x = +a")

    ratio = np.hypot(f.px, f.py) / np.where(f.bound > 0, f.bound, 1.0)
    q = ax2.quiver(x_mm, y_mm, f.px, f.py, ratio, cmap="viridis", clim=(0, 1), pivot="tail",
                   scale=None, width=0.003)
    fig.colorbar(q, ax=ax2, label="|p| / (μ p_n)")
    ax2.set_title(f"tractions: Fx = {r.Fx / 1e3:.1f} kN, Fy = {r.Fy / 1e3:.1f} kN, "
                  f"Mz = {r.Mz:.1f} N·m")
    for ax in (ax1, ax2):
        ax.add_patch(Ellipse((0, 0), 2 * a_mm, 2 * b_mm, fill=False, color="k", lw=1))
        ax.set_aspect("equal")
        ax.set_xlim(-1.15 * a_mm, 1.15 * a_mm)
        ax.set_ylim(-1.15 * b_mm, 1.15 * b_mm)
        ax.set_xlabel("x, mm (rolling direction)")
        ax.set_ylabel("y, mm (lateral)")
    fig.suptitle(f"FASTSIM, ξ = {CASE['xi'] * 100:.2f} %, η = {CASE['eta'] * 100:.2f} %, "
                 f"φ = {CASE['phi']:g} 1/m, μ = {CASE['mu']}, N = {CASE['N'] / 1e3:.0f} kN, "
                 "parabolic bound, 30×30")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, dpi=120)
    plt.close(fig)
    print(f"wrote {OUT}")
    return OUT


if __name__ == "__main__":
    main()
