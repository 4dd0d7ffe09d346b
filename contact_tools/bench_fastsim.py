"""Benchmark FASTSIM through ``contact_core.solve``: µs per call for several grids next to "linear",
and what spin costs next to a plain FASTSIM kernel.

Run: ``python -m contact_tools.bench_fastsim``. Prints, for each grid, the minimum and median
time per call over repeated batches (the machine is shared: the minimum is the best estimate of
the cost, the median shows the noise), and the ratio to linear theory timed in the same run.
Then FASTSIM with creepage and spin against a plain kernel, at 20×20 and 10×10, through
``contact_core.solve`` and through a method's ``step``, in interleaved rounds (the minimum of
each over the rounds): the default with creepage and spin (the slip law's anisotropic
projection) against the default on the same state without spin (pure creepage: the radial
projection) and against the flexibility "weighted" on the same state (the radial projection,
with the same spin and nearly the same slip zone); on two states and on the benchmark's states
with spin and creepage (``contact_tools.bench``, kind "combined", mean per call; plain: the
same states without spin). The target: spin / plain at most 1.5. ``--spin``: this comparison
alone.
Finally it measures the first-call cost in a fresh subprocess (numba import + loading the kernel
from numba's on-disk cache, which this run has just warmed).
"""
from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable

import contact_core as cc
from contact_tools.bench.cases import make_cases

CASE = dict(xi=1e-3, eta=5e-4, phi=0.5, N=100e3, mu=0.3, a=6e-3, b=4e-3, G=80e9, nu=0.28)
GRIDS = ((10, 10), (20, 20), (40, 40), (80, 80))
REPEATS = 15
#: spin against a plain kernel: the grids, and the states with creepage and spin (CASE slips on
#: about a quarter of the contact, the second on nearly all of it)
SPIN_GRIDS = ((20, 20), (10, 10))
SPIN_STATES = {"CASE": CASE, "phi=2": CASE | dict(phi=2.0)}
SPIN_ROUNDS = 15
SPIN_CALLS = 1500


def per_call_us(method: str, calls: int, **options) -> tuple[float, float]:
    """(min, median) µs per ``cc.solve`` call over REPEATS batches of ``calls`` calls."""
    solve = cc.solve
    solve(method, **CASE, **options)  # warm-up (compile / load the kernel)
    times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        for _ in range(calls):
            solve(method, **CASE, **options)
        times.append((time.perf_counter() - t0) / calls * 1e6)
    return min(times), statistics.median(times)


FIRST_CALL = """
import time
t0 = time.perf_counter()
import contact_core as cc
t1 = time.perf_counter()
cc.solve("fastsim", xi=1e-3, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=6e-3, b=4e-3, G=8e10, nu=0.28)
t2 = time.perf_counter()
print(f"{(t1 - t0) * 1e3:.0f} {(t2 - t1) * 1e3:.0f}")
"""


def first_call_ms() -> tuple[float, float]:
    """(import contact_core, first fastsim call) in ms, in a fresh interpreter, warm numba cache."""
    out = subprocess.run([sys.executable, "-c", FIRST_CALL], check=True, capture_output=True,
                         text=True, cwd=Path(__file__).resolve().parent.parent).stdout.split()
    return float(out[0]), float(out[1])


def _batch_us(call: Callable[..., Any], args: list[dict], calls: int) -> float:
    """µs per call of ``call(**kw)`` over ``calls`` calls cycling through ``args``."""
    n = len(args)
    t0 = time.perf_counter()
    for k in range(calls):
        call(**args[k % n])
    return (time.perf_counter() - t0) / calls * 1e6


def spin_vs_plain(rounds: int = SPIN_ROUNDS) -> list[tuple[str, str, str, float, float, float]]:
    """(grid, states, interface, spin µs, plain µs, weighted µs) per call, each the minimum over
    ``rounds`` interleaved rounds (module docstring)."""
    combined = [c.solve_kwargs() for c in make_cases("full") if c.kind == "combined"]
    sets = {name: [state] for name, state in SPIN_STATES.items()}
    sets["bench combined"] = combined
    variants = {"spin": ({}, False), "plain": ({}, True),
                "weighted": ({"flexibility": "weighted"}, False)}
    cells = {}
    for nx, ny in SPIN_GRIDS:
        for set_name, states in sets.items():
            for variant, (options, no_spin) in variants.items():
                args = [st | dict(phi=0.0) if no_spin else st for st in states]
                method = cc.METHODS["fastsim"](nx=nx, ny=ny, **options)
                solve_args = [kw | dict(nx=nx, ny=ny, **options) for kw in args]
                cells[(f"{nx}x{ny}", set_name, "solve", variant)] = (
                    lambda **kw: cc.solve("fastsim", **kw), solve_args)
                cells[(f"{nx}x{ny}", set_name, "step", variant)] = (method.step, args)
    best = {key: math.inf for key in cells}
    for _ in range(rounds):
        for key, (call, args) in cells.items():
            _batch_us(call, args, len(args))           # warm (compile, caches)
            best[key] = min(best[key], _batch_us(call, args, max(SPIN_CALLS, len(args))))
    rows = []
    for nx, ny in SPIN_GRIDS:
        for set_name in sets:
            for interface in ("solve", "step"):
                key = (f"{nx}x{ny}", set_name, interface)
                rows.append((*key, *(best[key + (v,)] for v in variants)))
    return rows


def grids() -> None:
    """FASTSIM's grids next to linear theory (module docstring)."""
    lin_min, lin_med = per_call_us("linear", 20000)
    print(f"{'method':<10} {'grid':>7} {'min µs':>8} {'median µs':>10} {'min/linear':>11}")
    print(f"{'linear':<10} {'-':>7} {lin_min:8.2f} {lin_med:10.2f} {1.0:11.1f}")
    for nx, ny in GRIDS:
        calls = max(200, 400000 // (nx * ny))
        t_min, t_med = per_call_us("fastsim", calls, nx=nx, ny=ny)
        print(f"{'fastsim':<10} {f'{nx}x{ny}':>7} {t_min:8.2f} {t_med:10.2f} "
              f"{t_min / lin_min:11.1f}")
    t_min, t_med = per_call_us("fastsim", 1000, nx=20, ny=20, scheme="kalker")
    print(f"{'fs kalker':<10} {'20x20':>7} {t_min:8.2f} {t_med:10.2f} {t_min / lin_min:11.1f}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--spin", action="store_true", help="only the spin vs plain comparison")
    p.add_argument("--rounds", type=int, default=SPIN_ROUNDS,
                   help=f"interleaved rounds of that comparison (default {SPIN_ROUNDS})")
    a = p.parse_args()
    if not a.spin:
        grids()
        print()
    print(f"spin vs plain kernel, min of {a.rounds} interleaved rounds (µs per call; "
          "plain: the same state without spin; weighted: the same state, radial projection)")
    print(f"{'grid':>6} {'states':<15} {'call':<5} {'spin':>7} {'plain':>7} {'ratio':>6} "
          f"{'weighted':>9} {'ratio':>6}")
    for grid, set_name, interface, spin, plain, weighted in spin_vs_plain(a.rounds):
        print(f"{grid:>6} {set_name:<15} {interface:<5} {spin:7.2f} {plain:7.2f} "
              f"{spin / plain:6.2f} {weighted:9.2f} {spin / weighted:6.2f}")
    if not a.spin:
        runs = [first_call_ms() for _ in range(3)]
        imp = min(r[0] for r in runs)
        first = min(r[1] for r in runs)
        print(f"fresh process, warm numba cache: import contact_core {imp:.0f} ms, "
              f"first fastsim call {first:.0f} ms (min of 3)")


if __name__ == "__main__":
    main()
