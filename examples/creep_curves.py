"""Main job, part 1: creep-force table and curves of every registered method for a default case.

Default wheel/rail case: rolling radius 0.46 m, conical tread, rail crown 0.3 m, N = 100 kN,
steel (E = 210 GPa, ν = 0.28), μ = 0.3. Prints a table of every registered method, plots the
longitudinal, lateral and spin creep-force curves of every method against the exact theory
(out/creep_curves.png) and prints each method's largest deviation from the exact curve (in μN).
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
CURVE_OPTIONS = {"exact": {"mx": 32, "my": 32}}


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

    # Curves: longitudinal (η = φ = 0), lateral (ξ = φ = 0) and spin (ξ = η = 0) of every method;
    # the exact solver on a 32×32 grid, warm-started along each curve.
    creep = np.linspace(0.0, 4e-3, 41)
    spin = np.linspace(0.0, 12e-3, 41) / c         # φ c up to 12e-3 (past the force peak)
    panels = [("longitudinal: ξ", creep, lambda v: (v, 0.0, 0.0), "Fx"),
              ("lateral: η", creep, lambda v: (0.0, v, 0.0), "Fy"),
              ("spin: φ·√(ab)", spin, lambda v: (0.0, 0.0, v), "Fy")]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for ax, (title, xs, creepages, comp) in zip(axes, panels):
        curves = {}
        for m in cc.methods():
            solver = cc.make_solver(m, **CURVE_OPTIONS.get(m, {}))
            r = None
            ys = []
            for v in xs:
                r = solver.step(*creepages(v), case["N"], case["mu"], case["a"], case["b"],
                                case["G"], case["nu"], warm_start=r)
                ys.append(-getattr(r, comp) / (MU * N))
            curves[m] = np.array(ys)
            xplot = xs * (c if "spin" in title else 1.0) * 1e3
            ax.plot(xplot, curves[m], "-" if m == "exact" else "--",
                    lw=2.5 if m == "exact" else 1.2, label=m)
        ax.set_ylim(0, 1.6)
        ax.set_xlabel(title + " (‰)")
        ax.set_ylabel(f"-{comp}/(μN)")
        ax.grid(alpha=0.3)
        ax.legend()
        for m, ys in curves.items():
            if m != "exact":
                print(f"{title:18s} {m:18s} max |dev| from exact = "
                      f"{np.abs(ys - curves['exact']).max():.3f} μN")
    fig.suptitle(f"Creep forces of every method (exact 32×32), wheel 0.46 m, rail crown 0.3 m, "
                 f"a/b = {case['a'] / case['b']:.2f}, N = {N / 1e3:.0f} kN, μ = {MU}")
    fig.tight_layout()
    OUT.mkdir(exist_ok=True)
    fig.savefig(OUT / "creep_curves.png", dpi=120)
    print(f"wrote {OUT / 'creep_curves.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
