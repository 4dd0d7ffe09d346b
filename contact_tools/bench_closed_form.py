"""Benchmark: µs per call of the closed-form laws through ``contact_core.solve`` (one run).

Prints median and minimum over repeated batches, through ``solve`` (the documented entry point)
and through a solver object built once by ``make_solver`` (what the FMU uses per step). The target
is <= 2 µs per in-process call.
"""
from __future__ import annotations

import statistics
import timeit

import contact_core as cc

CASE = dict(xi=1e-3, eta=-4e-4, phi=0.3, N=100e3, mu=0.3, a=6.1e-3, b=4.4e-3, G=82e9, nu=0.28)
SETTINGS = [("linear", {}), ("johnson_vermeulen", {}),
            ("johnson_vermeulen", {"variant": "original"}),
            ("johnson_vermeulen", {"spin": "ignore"})]


def per_call_us(call, number: int = 20000, repeat: int = 15) -> list[float]:
    call()
    return [x / number * 1e6 for x in timeit.repeat(call, number=number, repeat=repeat)]


def main() -> None:
    args = tuple(CASE.values())
    print(f"{'method':<20} {'options':<24} {'path':<18} {'median µs':>10} {'min µs':>8} {'ratio':>6}")
    base = None
    for method, options in SETTINGS:
        solver = cc.make_solver(method, **options)
        for path, call in (("solve()", lambda: cc.solve(method, **CASE, **options)),
                           ("make_solver().step", lambda: solver.step(*args))):
            t = per_call_us(call)
            med = statistics.median(t)
            base = base or med
            print(f"{method:<20} {str(options):<24} {path:<18} {med:10.2f} {min(t):8.2f} {med / base:6.2f}")
    print("ratio: to linear through solve(), measured in this run")


if __name__ == "__main__":
    main()
