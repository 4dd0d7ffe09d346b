"""What a contact geometry that changes at every step costs (the effect ``varying_geometry``).

    python -m contact_tools.bench_geometry [--calls N] [--steps N] [--repeat R] [--out DIR]
                                           [--skip-exact] [--skip-fmu]

A contact point moving over curved profiles: the relative curvatures A, B, the load, the
creepages and the spin change slowly along a trajectory (:func:`trajectory`), so every call has a
new a/b. Measured in one run, each case the least over chunks of 250 calls or steps of R
interleaved rounds (the machine's load drifts hit every case alike; the ratios are the result,
the µs depend on the machine):

1. in process, µs per ``contact_core.solve`` call, for linear, Johnson–Vermeulen, FASTSIM
   (10×10) and the table: the fixed geometry (the default effects; the Hertz patch of the default
   curvatures under the varying load, whose a/b repeats), the new geometry at every call with the
   effect ``varying_geometry`` (the methods' per-call path), and the new geometry without it
   (Kalker's coefficients cached per a/b: a miss at every call; ``--calls`` above the cache's
   4096 entries, so that no round finds the previous one's); then the evaluators the FMU wraps,
   ``WheelRailEvaluator.evaluate`` (fixed geometry) against ``VaryingGeometryEvaluator.evaluate``
   (Hertz's patch of A, B solved at every call);
2. the exact method along the trajectory: Gauss–Seidel sweeps per step warm-started from the
   previous step's result (a/b changes at every step) against cold starts;
3. through fmpy's ``FMU2Slave``, µs per ``setReal + doStep + getReal``: the ``vehicle`` scene's
   FMU (inputs A, B) with its geometry changing at every step, for its default method (the
   table) and linear, Johnson–Vermeulen, FASTSIM 10×10, against a trivial pythonfmu FMU with
   the same interface (``trivial_fmu/trivial_geometry.py``), and the ``full`` scene's FMU
   (fixed geometry) with the same method for comparison.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import contact_core as cc
from wheel_rail_fmu.build import build

from .fmu_timing import CHUNK, TimedInstance, interleaved_best

#: The trivial FMU's pythonfmu slave script (the vehicle scene's interface).
TRIVIAL = Path(__file__).resolve().parent / "trivial_fmu" / "trivial_geometry.py"
METHODS = ("linear", "johnson_vermeulen", "fastsim", "table")
#: FASTSIM on 10×10 (as ``bench_fmu``); the others have no grid.
OPTIONS = {"fastsim": {"nx": 10, "ny": 10}}
E, NU = 210e9, 0.28
G = cc.shear_modulus(E, NU)
#: The curvatures of the default radii (contact_core.variables: R_wheel 0.46 m, rail crown 0.3 m).
A0, B0 = 0.5 / 0.46, 0.5 / 0.3
VARYING = cc.Effects(varying_geometry=True)


def trajectory(n: int) -> dict[str, list[float]]:
    """``n`` steps of a contact moving over curved profiles (module docstring), Python floats."""
    k = np.arange(n)
    cols = {"xi": 1e-3 * (1 + 0.2 * np.sin(k * 0.013)), "eta": -5e-4 * (1 + 0.2 * np.cos(k * 7e-3)),
            "phi": 0.2 * (1 + 0.2 * np.sin(k * 5e-3)), "N": 1e5 * (1 + 0.1 * np.sin(k * 0.011)),
            "mu": 0.3 + 0.02 * np.sin(k * 3e-3), "A": A0 * (1 + 0.3 * np.sin(k * 2e-3)),
            "B": B0 * (1 + 0.3 * np.cos(k * 1.7e-3))}
    return {name: [float(v) for v in col] for name, col in cols.items()}


def _solve_rows(tr: dict[str, list[float]], fixed: bool) -> list[tuple]:
    """(ξ, η, φ, N, μ, a, b) per step: the patch of the trajectory's curvatures, or with
    ``fixed`` of the default ones."""
    geometry = cc.hertz_geometry(A0, B0, E, NU)
    rows = []
    for i in range(len(tr["N"])):
        N = tr["N"][i]
        p = geometry.patch(N) if fixed else cc.hertz(N, tr["A"][i], tr["B"][i], E, NU)
        rows.append((tr["xi"][i], tr["eta"][i], tr["phi"][i], N, tr["mu"][i], p.a, p.b))
    return rows


def _time_solve(method: str, effects, rows: list[tuple]) -> float:
    solve, options = cc.solve, OPTIONS.get(method, {})
    best = math.inf
    for i in range(0, len(rows), CHUNK):
        chunk = rows[i:i + CHUNK]
        t0 = time.perf_counter()
        for xi, eta, phi, N, mu, a, b in chunk:
            solve(method, xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=a, b=b, G=G, nu=NU,
                  effects=effects, **options)
        best = min(best, (time.perf_counter() - t0) / len(chunk))
    return best * 1e6


def _time_evaluate(evaluate, args: list[tuple]) -> float:
    best = math.inf
    for i in range(0, len(args), CHUNK):
        chunk = args[i:i + CHUNK]
        t0 = time.perf_counter()
        for a in chunk:
            evaluate(*a)
        best = min(best, (time.perf_counter() - t0) / len(chunk))
    return best * 1e6


def per_call(calls: int, repeat: int) -> dict[str, float]:
    """Section 1 of the module docstring: µs per call by case label."""
    tr = trajectory(calls)
    fixed, new = _solve_rows(tr, True), _solve_rows(tr, False)
    cases = {}
    for m in METHODS:
        cases[f"{m}/fixed"] = lambda m=m: _time_solve(m, None, fixed)
        cases[f"{m}/new"] = lambda m=m: _time_solve(m, VARYING, new)
        cases[f"{m}/new, no effect"] = lambda m=m: _time_solve(m, None, new)
        ev_fixed = cc.WheelRailEvaluator(cc.WheelRailConfig(method=m, E=E, nu=NU,
                                                            options=OPTIONS.get(m, {})))
        ev_new = cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(
            method=m, E=E, nu=NU, options=OPTIONS.get(m, {})))
        args = [(r[0], r[1], r[2], r[3], r[4]) for r in fixed]
        args_new = [(r[0], r[1], r[2], r[3], r[4], tr["A"][i], tr["B"][i])
                    for i, r in enumerate(new)]
        cases[f"{m}/evaluate fixed"] = lambda f=ev_fixed.evaluate, x=args: _time_evaluate(f, x)
        cases[f"{m}/evaluate new"] = lambda f=ev_new.evaluate, x=args_new: _time_evaluate(f, x)
    return interleaved_best(cases, repeat)


def exact_warm_start(steps: int) -> dict[str, float]:
    """Section 2: sweeps and seconds along ``steps`` steps of the trajectory (every 20th of
    it, so that a/b changes by about 1 % per step), warm from the previous step and cold."""
    tr = trajectory(20 * steps)
    rows = _solve_rows({k: v[::20] for k, v in tr.items()}, False)
    out = {"warm sweeps": 0.0, "cold sweeps": 0.0, "warm s": 0.0, "cold s": 0.0}
    warm = None
    for i, (xi, eta, phi, N, mu, a, b) in enumerate(rows):
        kw = dict(xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=a, b=b, G=G, nu=NU)
        t0 = time.perf_counter()
        cold = cc.solve("exact", **kw)
        t1 = time.perf_counter()
        warm = cc.solve("exact", **kw, warm_start=warm)
        t2 = time.perf_counter()
        if i:                                   # the first step has nothing to start from
            out["cold sweeps"] += cold.iterations
            out["warm sweeps"] += warm.iterations
            out["cold s"] += t1 - t0
            out["warm s"] += t2 - t1
        out["max |F warm - F cold| / muN"] = max(out.get("max |F warm - F cold| / muN", 0.0),
                                                  math.hypot(warm.Fx - cold.Fx, warm.Fy - cold.Fy)
                                                  / (mu * N))
    return out


def per_step(steps: int, repeat: int, out: Path) -> dict[str, float]:
    """Section 3: µs per FMU step by case label."""
    from pythonfmu import FmuBuilder
    tr = trajectory(steps)
    trivial = Path(FmuBuilder.build_FMU(TRIVIAL, dest=out / "trivial"))
    vehicle = build("vehicle", out=out / "vehicle")
    full = build("full", out=out / "full")
    sessions = {"trivial": TimedInstance(trivial, None, tr)}
    for m in METHODS:
        start = {"method": m, **OPTIONS.get(m, {})}
        sessions[f"vehicle/{m}"] = TimedInstance(vehicle, start, tr)
        sessions[f"full/{m}"] = TimedInstance(full, start, tr)
    try:
        return interleaved_best({k: s.run for k, s in sessions.items()}, repeat)
    finally:
        for s in sessions.values():
            s.free()


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--calls", type=int, default=5000, help="calls per round (in process)")
    p.add_argument("--steps", type=int, default=5000, help="FMU steps per round")
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--exact-steps", type=int, default=30)
    p.add_argument("--skip-exact", action="store_true")
    p.add_argument("--skip-fmu", action="store_true")
    p.add_argument("--out", default=None, help="where to build the FMUs (default: a temp dir)")
    a = p.parse_args(argv)

    t = per_call(a.calls, a.repeat)
    print(f"1. in process, µs per call, least over chunks of {CHUNK} of {a.repeat} interleaved "
          f"rounds of {a.calls} calls (a new a/b at every call)\n")
    print(f"{'method':<20}{'fixed':>9}{'new':>9}{'new/fixed':>11}{'no effect':>11}"
          f"{'evaluate':>10}{'new':>9}{'new/fixed':>11}")
    for m in METHODS:
        f, n, o = t[f"{m}/fixed"], t[f"{m}/new"], t[f"{m}/new, no effect"]
        ef, en = t[f"{m}/evaluate fixed"], t[f"{m}/evaluate new"]
        print(f"{m:<20}{f:>9.2f}{n:>9.2f}{n / f:>11.3f}{o:>11.2f}{ef:>10.2f}{en:>9.2f}"
              f"{en / ef:>11.3f}")
    print("(solve: fixed = default effects, the default curvatures' patch; new = effect "
          "varying_geometry; no effect = new a/b, default effects. evaluate: WheelRailEvaluator "
          "against VaryingGeometryEvaluator with A, B)\n")

    if not a.skip_exact:
        w = exact_warm_start(a.exact_steps)
        print(f"2. exact (default options) along {a.exact_steps} steps, a/b new at every step: "
              f"sweeps warm {w['warm sweeps']:.0f} ({w['warm s']:.2f} s) against cold "
              f"{w['cold sweeps']:.0f} ({w['cold s']:.2f} s); largest |F warm - F cold| "
              f"{w['max |F warm - F cold| / muN']:.1e} muN\n")

    if not a.skip_fmu:
        with tempfile.TemporaryDirectory(prefix="bench_geometry_") as tmp:
            s = per_step(a.steps, a.repeat, Path(a.out or tmp))
        tt = s["trivial"]
        print(f"3. FMU, µs per setReal + doStep + getReal through fmpy, least over chunks of "
              f"{CHUNK} of {a.repeat} interleaved rounds of {a.steps} steps\n")
        print(f"{'FMU':<44}{'µs/step':>9}{'x trivial':>11}")
        print(f"{'trivial pythonfmu FMU, inputs A, B':<44}{tt:>9.2f}{1.0:>11.2f}")
        for m in METHODS:
            grid = " 10x10" if m in OPTIONS else ""
            for scene, what in (("vehicle", "new A, B every step"), ("full", "fixed geometry")):
                label = f"{scene}, {m}{grid} ({what})"
                v = s[f"{scene}/{m}"]
                print(f"{label:<44}{v:>9.2f}{v / tt:>11.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
