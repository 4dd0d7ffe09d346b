"""Main job, part 1: creep-force table and curves of every registered method for a default case.

Default wheel/rail case: rolling radius 0.46 m, conical tread, rail crown 0.3 m, N = 100 kN,
steel (E = 210 GPa, ν = 0.28), μ = 0.3. Writes out/creep_curves.png and prints a table.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import contact_core as cc  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "out"
E, NU, N, MU = 210e9, 0.28, 100e3, 0.3


def default_case() -> dict:
    p = cc.hertz_from_radii(N, 0.46, math.inf, 0.3, E, NU)
    return dict(N=N, mu=MU, a=p.a, b=p.b, G=cc.shear_modulus(E, NU), nu=NU)


def main() -> int:
    case = default_case()
    c = math.sqrt(case["a"] * case["b"])
    print(f"Default case: a = {case['a'] * 1e3:.3f} mm, b = {case['b'] * 1e3:.3f} mm, "
          f"a/b = {case['a'] / case['b']:.3f}, N = {N / 1e3:.0f} kN, mu = {MU}, nu = {NU}")
    print(f"{'method':<18} {'xi':>8} {'eta':>8} {'phi c':>8} {'Fx/muN':>9} {'Fy/muN':>9} "
          f"{'Mz/(muN c)':>11} {'slip':>6}")
    states = [(1e-4, 0.0, 0.0), (1e-3, 0.0, 0.0), (0.0, 1e-3, 0.0), (0.0, 0.0, 1e-3 / c),
              (1e-3, 5e-4, 0.2e-3 / c), (5e-3, 0.0, 0.0)]
    for m in cc.methods():
        for xi, eta, phi in states:
            r = cc.solve(m, xi=xi, eta=eta, phi=phi, **case)
            print(f"{m:<18} {xi:8.1e} {eta:8.1e} {phi * c:8.1e} {r.Fx / (MU * N):9.4f} "
                  f"{r.Fy / (MU * N):9.4f} {r.Mz / (MU * N * c):11.5f} {r.slip_fraction:6.2f}")

    creep = np.linspace(0.0, 5e-3, 101)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    panels = [("xi", "longitudinal creepage ξ", "Fx"), ("eta", "lateral creepage η", "Fy"),
              ("phi", "spin φ·c", "Fy")]
    for ax, (name, label, out) in zip(axes, panels):
        for m in cc.methods():
            f = []
            for v in creep:
                inp = dict(xi=0.0, eta=0.0, phi=0.0) | {name: v / c if name == "phi" else v}
                f.append(getattr(cc.solve(m, **inp, **case), out) / (MU * N))
            ax.plot(creep, f, label=m)
        ax.set_xlabel(label)
        ax.set_ylabel(f"{out}/(μN)")
        ax.set_ylim(-1.6, 0.2)
        ax.grid(True, alpha=0.3)
    axes[0].legend()
    fig.suptitle(f"Creep-force curves, a/b = {case['a'] / case['b']:.2f}, N = {N / 1e3:.0f} kN, μ = {MU}")
    fig.tight_layout()
    OUT.mkdir(exist_ok=True)
    fig.savefig(OUT / "creep_curves.png", dpi=120)
    print(f"wrote {OUT / 'creep_curves.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
