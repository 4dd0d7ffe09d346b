"""Benchmark of the exact solver: ms per solve, cold and warm-started (not a test).

Eurosprinter case of CONTACT's tractcurv example (a = 6.304 mm, b = 12.61 mm, N = 106.7 kN,
G = 82 GPa, ν = 0.28, μ = 0.33). Case types: longitudinal ξ = 1.2 ‰; lateral η = 1 ‰;
spin φ = 0.2 /m (φ·√(ab) = 1.8 ‰); combined ξ = 1 ‰, η = 0.5 ‰, φ = 0.1 /m.
"Cold" = no warm start, normal solution cached (it depends only on the grid and a/b, the
situation of a co-simulation); "+normal" also solves the normal problem (influence tables of the
grid cached); "new a/b" also recomputes the influence tables and the folded normal operator
(they depend on dy/dx, i.e. on a/b); "warm" = warm start
from the solution at 0.1 % (a co-simulation step) or 1 % smaller creepages. Each timing is
the minimum over repeats (the machine is shared). Numba compile/cache-load time reported
separately.
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

import contact_core as cc
from contact_core.exact import influence as exact_influence
from contact_core.exact import normal as exact_normal
from contact_core.exact import solver as exact_solver

A, B, N, G, NU, MU = 6.304e-3, 12.61e-3, 106.7e3, 82e9, 0.28, 0.33
CASES = {"longitudinal": (1.2e-3, 0.0, 0.0), "lateral": (0.0, 1e-3, 0.0),
         "spin": (0.0, 0.0, 0.2e3 * 1e-3), "combined": (1e-3, 5e-4, 0.1)}


def _best(fn, repeat: int) -> tuple[float, object]:
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best * 1e3, out


def main() -> int:
    t = time.perf_counter()
    cc.solve("exact", xi=1e-3, eta=1e-4, phi=0.1, N=N, mu=MU, a=A, b=B, G=G, nu=NU, mx=8, my=8)
    print(f"first call (numba compile or cache load, influence tables): "
          f"{(time.perf_counter() - t) * 1e3:.0f} ms")
    rows = []
    for mx, my in ((20, 20), (32, 32), (48, 44)):
        solver = cc.make_solver("exact", mx=mx, my=my)
        repeat = 15 if mx <= 32 else 7
        for name, (xi, eta, phi) in CASES.items():
            args = (xi, eta, phi, N, MU, A, B, G, NU)
            solver.step(*args)                       # influence tables, normal solution cached
            ms_cold, r = _best(lambda: solver.step(*args), repeat)

            def cold_normal():
                exact_normal.clear_cache()
                exact_solver._GRIDS.clear()
                return solver.step(*args)
            ms_cn, _ = _best(cold_normal, max(3, repeat // 3))

            def cold_all():
                # a new a/b: also the influence tables and the folded normal operator
                exact_influence.element_integrals.cache_clear()
                exact_influence.tangential_tables.cache_clear()
                exact_normal.folded_operator.cache_clear()
                solver._tables.clear()
                return cold_normal()
            ms_all, _ = _best(cold_all, max(3, repeat // 3))
            warm = []
            for step in (1e-3, 1e-2):
                prev = solver.step(xi * (1 - step), eta * (1 - step), phi * (1 - step), N, MU,
                                   A, B, G, NU)
                ms_w, rw = _best(lambda: solver.step(*args, warm_start=prev), repeat)
                warm.append((ms_w, rw.iterations))
            rows.append((f"{mx}x{my}", name, ms_cold, ms_cn, ms_all, r.iterations, warm,
                         r.Fx / (MU * N), r.Fy / (MU * N)))
    print("warm: started from the solution at creepages 0.1 % / 1 % smaller (same load)")
    print(f"{'grid':7s} {'case':13s} {'cold ms':>8s} {'+normal':>8s} {'new a/b':>8s} {'sweeps':>6s} "
          f"{'warm0.1%':>9s} {'x':>5s} {'sw':>3s} {'warm1%':>8s} {'x':>5s} {'sw':>3s}"
          "  Fx/μN    Fy/μN")
    for g, name, c, cn, ca, it, warm, fx, fy in rows:
        (w1, i1), (w2, i2) = warm
        print(f"{g:7s} {name:13s} {c:8.2f} {cn:8.2f} {ca:8.2f} {it:6d} {w1:9.2f} {c / w1:5.1f} {i1:3d}"
              f" {w2:8.2f} {c / w2:5.1f} {i2:3d}  {fx:+.4f} {fy:+.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
