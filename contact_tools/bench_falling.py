"""Falling friction: every method under the effect against the exact theory with the same law,
and what it costs, measured in one run.

    python -m contact_tools.bench_falling [--out FILE]     # the report: docs/reports/falling_friction.md

States: two Hertzian contacts (the driven wheelset's, a 0.46 m wheel on a 0.3 m rail crown at
50 kN, and the Eurosprinter's of CONTACT's tractcurv example, a/b = 0.5 at 106.7 kN), μ_stat =
0.3, the default law (``contact_core.FrictionLaw()``), rolling speeds 5, 20 and 40 m/s, pure ξ
from 1e-4 to 0.1 (12, logarithmic: the linear range, the adhesion peak, the falling branch) and
six states with η and spin. Reference: ``exact`` with the local law (each element at its own
slip velocity) on its default grid (52×52, extrapolated). Errors: |F - F_ref| with F = (Fx,
Fy), in % of μ_stat N (p95 / max over the pure-ξ states and over all); the same methods with
Coulomb friction against ``exact`` with Coulomb friction, for what the effect adds to each
method's error. Cost: µs per call of a solver built once (``make_solver(...).step``) over the
states at V = 20 m/s, falling and Coulomb friction timed in alternating rounds, best of 9.
"""
from __future__ import annotations

import math
import os
import time
from functools import cache

import numpy as np

import contact_core as cc

from .report_command import report_command

COULOMB = ("longitudinal", "lateral", "spin", "saturation")
FALLING = COULOMB + ("falling_friction",)
MU = 0.3
SPEEDS = (5.0, 20.0, 40.0)
#: (label, method, options); "local"/"creep": how the setting takes the law
SETTINGS = (("Polach (creep velocity)", "polach", {}),
            ("Johnson-Vermeulen (creep velocity)", "johnson_vermeulen", {}),
            ("table (creep velocity)", "table", {}),
            ("FASTSIM 20x20, local law", "fastsim", {}),
            ("FASTSIM 20x20, creep velocity", "fastsim", {"falling": "creep"}),
            ("exact 24x24 one grid, local law", "exact",
             {"mx": 24, "my": 24, "extrapolate": False}),
            ("exact 24x24 one grid, creep velocity", "exact",
             {"mx": 24, "my": 24, "extrapolate": False, "falling": "creep"}))


@cache
def contacts() -> tuple[dict, ...]:
    E, nu = 210e9, 0.28
    wheel = cc.hertz_from_radii(50e3, 0.46, math.inf, 0.3, E, nu)
    return (dict(N=50e3, mu=MU, a=wheel.a, b=wheel.b, G=cc.shear_modulus(E, nu), nu=nu),
            dict(N=106.7e3, mu=MU, a=6.304e-3, b=12.61e-3, G=82e9, nu=0.28))


def states() -> list[tuple[float, float, float]]:
    pure = [(float(x), 0.0, 0.0) for x in np.logspace(-4, -1, 12)]
    return pure + [(2e-3, 1e-3, 0.0), (5e-3, -4e-3, 0.0), (3e-2, 1e-2, 0.0),
                   (1e-3, 0.0, 0.5), (3e-3, -2e-3, 1.0), (2e-2, 5e-3, -2.0)]


def solve_all(method, options, effects, V=None):
    out = []
    for case in contacts():
        solver = cc.make_solver(method, effects, **options)
        for speed in (SPEEDS if V is None else (V,)):
            for xi, eta, phi in states():
                args = (xi, eta, phi, case["N"], case["mu"], case["a"], case["b"], case["G"],
                        case["nu"])
                r = solver.step(*args, None, speed) if effects == FALLING else solver.step(*args)
                out.append((r.Fx, r.Fy, case["mu"] * case["N"]))
    return np.array(out)


def solve_coulomb(method, options):
    """:func:`solve_all` with Coulomb friction, in its order (contact, speed, state): Coulomb's
    law has no speed, so each contact is solved once and its results repeated for every speed."""
    res = solve_all(method, options, COULOMB, V=0.0)
    return np.tile(res.reshape(len(contacts()), 1, -1, 3), (1, len(SPEEDS), 1, 1)).reshape(-1, 3)


def errors(res, ref):
    return 100 * np.hypot(res[:, 0] - ref[:, 0], res[:, 1] - ref[:, 1]) / ref[:, 2]


def costs_us(method, options, coulomb_options, rounds=9):
    """(falling, Coulomb) µs per call: the two solvers timed in alternating rounds over the
    states at V = 20 m/s, best round of each."""
    case = contacts()[0]
    calls = [(xi, eta, phi, case["N"], case["mu"], case["a"], case["b"], case["G"], case["nu"])
             for xi, eta, phi in states()]
    falling = cc.make_solver(method, FALLING, **options)
    coulomb = cc.make_solver(method, COULOMB, **coulomb_options)
    reps = 1 if method == "exact" else 100
    best = [math.inf, math.inf]
    for _ in range(rounds):
        for k, run in enumerate((lambda args: falling.step(*args, None, 20.0),
                                 lambda args: coulomb.step(*args))):
            t = time.perf_counter()
            for _ in range(reps):
                for args in calls:
                    run(args)
            best[k] = min(best[k], (time.perf_counter() - t) / (reps * len(calls)) * 1e6)
    return best[0], best[1]


def section(heading: str = "##") -> str:
    """The report (markdown) under a ``heading`` of the given level: the standalone report
    (``main``) and the falling-friction section of the accuracy-vs-time report
    (:mod:`contact_tools.bench`)."""
    t0 = time.perf_counter()
    ref_fall = solve_all("exact", {}, FALLING)
    ref_coul = solve_coulomb("exact", {})
    pure = np.array([eta == 0.0 and phi == 0.0 for xi, eta, phi in states()]
                    * (len(contacts()) * len(SPEEDS)))
    lines = [f"{heading} Falling friction: every method against the exact theory with the same "
             "local law", "",
             f"{len(ref_fall)} states, {int(pure.sum())} of them pure ξ "
             "(`python -m contact_tools.bench_falling --out docs/reports/falling_friction.md`). "
             "States: the driven wheelset's contact (0.46 m wheel, 0.3 m rail crown, 50 kN) and "
             "the Eurosprinter's (CONTACT's tractcurv, a/b = 0.5, 106.7 kN), μ_stat = 0.3, the "
             "default law (`FrictionLaw()`: Polach's exponential law, A = 0.38, B = 0.7 s/m), "
             "V = 5, 20, 40 m/s, pure ξ 1e-4..0.1 and six states with η and spin. Reference: "
             "`exact` with the local law (every element at its own slip velocity) on its "
             "default grid (52×52 extrapolated). Errors |F - F_ref| in % of μ_stat N; "
             "\"Coulomb\": the same settings with Coulomb friction against `exact` with Coulomb "
             "friction. \"creep velocity\": one coefficient μ(V s_C) for the whole contact, "
             "then the Coulomb solve (the table keeps its speed this way); \"local law\": each "
             "element's bound at its own slip velocity. Cost at V = 20 m/s, falling and "
             "Coulomb friction timed in alternating rounds.", "",
             "| setting | falling, pure ξ: p95 / max | falling, all: p95 / max | Coulomb, all: "
             "p95 / max | µs/call falling | µs/call Coulomb | ratio |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for label, method, options in SETTINGS:
        e_f = errors(solve_all(method, options, FALLING), ref_fall)
        coul_opts = {k: v for k, v in options.items() if k != "falling"}
        e_c = errors(solve_coulomb(method, coul_opts), ref_coul)
        t_f, t_c = costs_us(method, options, coul_opts)
        fmt = lambda e: f"{np.percentile(e, 95):.2f} / {e.max():.2f}"  # noqa: E731
        ms = method == "exact"
        unit, suffix = (1e3, " ms") if ms else (1.0, "")
        lines.append(f"| {label} | {fmt(e_f[pure])} | {fmt(e_f)} | {fmt(e_c)} | "
                     f"{t_f / unit:.1f}{suffix} | {t_c / unit:.1f}{suffix} | {t_f / t_c:.2f} |")
    lines += ["", f"(one run of {time.perf_counter() - t0:.0f} s on {time.strftime('%Y-%m-%d')}, "
              f"{os.cpu_count()} logical CPUs: compare settings within one run)", ""]
    return "\n".join(lines)


def main(argv=None) -> int:
    return report_command(__doc__, lambda: section("#"), argv)


if __name__ == "__main__":
    raise SystemExit(main())
