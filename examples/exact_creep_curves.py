"""Creep-force curves of the exact theory against the cheaper laws, for one wheel/rail case.

Wheel r0 = 0.46 m, conical tread, rail crown 0.3 m, N = 100 kN, steel (E = 210 GPa, ν = 0.28),
μ = 0.3. Longitudinal (η = φ = 0), lateral (ξ = φ = 0) and spin (ξ = η = 0) curves of every
registered method (exact on a 32×32 grid). Writes out/exact_creep_curves.png and prints the
largest deviation of each method from the exact curve (in μN).
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
OPTIONS = {"exact": {"mx": 32, "my": 32}}


def main() -> int:
    p = cc.hertz_from_radii(N, 0.46, math.inf, 0.3, E, NU)
    case = dict(N=N, mu=MU, a=p.a, b=p.b, G=cc.shear_modulus(E, NU), nu=NU)
    c = math.sqrt(p.a * p.b)
    creep = np.linspace(0.0, 4e-3, 41)
    spin = np.linspace(0.0, 12e-3, 41) / c         # φ c up to 12e-3 (past the peak)
    panels = [("longitudinal: ξ", creep, lambda v: dict(xi=v, eta=0.0, phi=0.0), "Fx"),
              ("lateral: η", creep, lambda v: dict(xi=0.0, eta=v, phi=0.0), "Fy"),
              ("spin: φ·√(ab)", spin, lambda v: dict(xi=0.0, eta=0.0, phi=v), "Fy")]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    print(f"a = {p.a * 1e3:.2f} mm, b = {p.b * 1e3:.2f} mm, a/b = {p.a / p.b:.3f}")
    for ax, (title, xs, args, comp) in zip(axes, panels):
        curves = {}
        for m in cc.methods():
            solver = cc.make_solver(m, **OPTIONS.get(m, {}))
            prev = None
            ys = []
            for v in xs:
                kw = args(v)
                r = solver.step(kw["xi"], kw["eta"], kw["phi"], case["N"], case["mu"], case["a"],
                                case["b"], case["G"], case["nu"],
                                **({"warm_start": prev} if m == "exact" else {}))
                prev = r
                ys.append(-getattr(r, comp) / (MU * N))
            curves[m] = np.array(ys)
            xplot = xs * (c if "spin" in title else 1.0) * 1e3
            ax.plot(xplot, curves[m], "-" if m == "exact" else "--", lw=2.5 if m == "exact" else 1.2,
                    label=m)
        ax.set_ylim(0, 1.6)
        ax.set_xlabel(title + " (‰)")
        ax.set_ylabel(f"-{comp}/(μN)")
        ax.grid(alpha=0.3)
        ax.legend()
        for m, ys in curves.items():
            if m != "exact":
                print(f"{title:18s} {m:18s} max |dev| from exact = "
                      f"{np.abs(ys - curves['exact']).max():.3f} μN")
    fig.suptitle("Creep forces: exact (32×32) vs cheaper methods; wheel 0.46 m, rail crown 0.3 m, "
                 "100 kN, μ = 0.3")
    fig.tight_layout()
    OUT.mkdir(exist_ok=True)
    fig.savefig(OUT / "exact_creep_curves.png", dpi=120)
    print(f"wrote {OUT / 'exact_creep_curves.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
