"""Benchmark FASTSIM through ``contact_core.solve``: µs per call for several grids next to "linear".

Run: ``python -m contact_tools.bench_fastsim``. Prints, for each grid, the minimum and median
time per call over repeated batches (the machine is shared: the minimum is the best estimate of
the cost, the median shows the noise), and the ratio to linear theory timed in the same run.
Finally it measures the first-call cost in a fresh subprocess (numba import + loading the kernel
from numba's on-disk cache, which this run has just warmed).
"""
from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

import contact_core as cc

CASE = dict(xi=1e-3, eta=5e-4, phi=0.5, N=100e3, mu=0.3, a=6e-3, b=4e-3, G=80e9, nu=0.28)
GRIDS = ((10, 10), (20, 20), (40, 40), (80, 80))
REPEATS = 15


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


def main() -> None:
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
    runs = [first_call_ms() for _ in range(3)]
    imp = min(r[0] for r in runs)
    first = min(r[1] for r in runs)
    print(f"fresh process, warm numba cache: import contact_core {imp:.0f} ms, "
          f"first fastsim call {first:.0f} ms (min of 3)")


if __name__ == "__main__":
    main()
