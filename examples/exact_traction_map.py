"""Stick/slip map and traction arrows of the exact theory for combined creepage and spin.

Wheel r0 = 0.46 m, conical tread, rail crown 0.3 m, N = 100 kN, steel, μ = 0.3;
ξ = 0.6 ‰, η = -0.4 ‰, φ·√(ab) = 0.5 ‰, 40×40 grid. Writes out/exact_traction_map.png.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

import contact_core as cc  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "out"
E, NU, N, MU = 210e9, 0.28, 100e3, 0.3


def main() -> int:
    p = cc.hertz_from_radii(N, 0.46, math.inf, 0.3, E, NU)
    c = math.sqrt(p.a * p.b)
    xi, eta, phi = 6e-4, -4e-4, 5e-4 / c
    r = cc.solve("exact", xi=xi, eta=eta, phi=phi, N=N, mu=MU, a=p.a, b=p.b,
                 G=cc.shear_modulus(E, NU), nu=NU, mx=40, my=40, fields=True)
    f = r.fields
    X, Y = np.meshgrid(f.x * 1e3, f.y * 1e3)
    fig, ax = plt.subplots(figsize=(7, 7 * p.b / p.a * 0.8 + 1.5))
    cmap = ListedColormap(["white", "#9ecae1", "#fc9272"])
    dx, dy = (f.x[1] - f.x[0]) * 1e3, (f.y[1] - f.y[0]) * 1e3
    ax.pcolormesh(np.r_[f.x * 1e3 - dx / 2, f.x[-1] * 1e3 + dx / 2],
                  np.r_[f.y * 1e3 - dy / 2, f.y[-1] * 1e3 + dy / 2], f.status, cmap=cmap,
                  vmin=-0.5, vmax=2.5, shading="flat")
    t = np.linspace(0, 2 * math.pi, 200)
    ax.plot(p.a * 1e3 * np.cos(t), p.b * 1e3 * np.sin(t), "k-", lw=0.8)
    sel = f.status != cc.exact.EXTERIOR
    ax.quiver(X[sel], Y[sel], f.px[sel], f.py[sel], angles="xy", pivot="tail", width=0.003)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm), rolling direction →  (material flows in -x)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"exact 40×40: ξ={xi * 1e3:.1f}‰, η={eta * 1e3:.1f}‰, φc={phi * c * 1e3:.1f}‰\n"
                 f"Fx/μN={r.Fx / (MU * N):.3f}, Fy/μN={r.Fy / (MU * N):.3f}, "
                 f"Mz={r.Mz:.1f} N·m; blue stick, red slip ({100 * r.slip_fraction:.0f} %)")
    fig.tight_layout()
    OUT.mkdir(exist_ok=True)
    fig.savefig(OUT / "exact_traction_map.png", dpi=120)
    print(f"converged={r.converged} in {r.iterations} sweeps; wrote {OUT / 'exact_traction_map.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
