"""Per-step cost of the WheelRailContact FMU through fmpy, next to a trivial pythonfmu FMU.

    python -m contact_tools.bench_fmu [--steps N] [--repeat R] [--out DIR]

One "step" is what a co-simulation master does per communication point:
``setReal(inputs) + doStep + getReal(outputs)`` on fmpy's ``FMU2Slave``. Measured in one run:

1. the trivial FMU (``contact_tools/trivial_fmu/``: same inputs/outputs, copies them) — the
   floor that pythonfmu's C++/Python bridge and fmpy's ctypes calls cost;
2. the full-scene FMU with each registered method (small grids for discretised methods), and
   with Johnson–Vermeulen once more with pythonfmu's generic binary instead of this project's
   FMI wrapper (``wheel_rail_fmu/native``);
3. each shipped scene's FMU with its default method, against the full FMU with the same method.

Times are the best of R repeats of N steps (µs per step). Inputs change every step.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

import contact_core as cc
from wheel_rail_fmu.build import build

from .fmu_timing import TimedInstance

#: The trivial FMU's pythonfmu slave script.
TRIVIAL = Path(__file__).resolve().parent / "trivial_fmu" / "trivial_contact.py"

#: Small grids for the discretised methods (per-option overrides, applied if the method has them).
SMALL_OPTIONS = {"nx": 10, "ny": 10, "mx": 10, "my": 10, "extrapolate": False}


def build_trivial(out: Path) -> Path:
    from pythonfmu import FmuBuilder
    return Path(FmuBuilder.build_FMU(TRIVIAL, dest=out))


#: Each input's value in the steps (V: the rolling speed of falling friction; A, B: the default
#: curvatures, a, b their patch under 100 kN, for the scenes with varying_geometry), scaled by
#: up to 10 % at random per step.
BASE = {"xi": 1e-3, "eta": -5e-4, "phi": 0.2, "N": 1e5, "mu": 0.3, "V": 20.0,
        "A": 0.5 / 0.46, "B": 0.5 / 0.3, "a": 7e-3, "b": 5.4e-3}
#: Steps of the warm-up, which tells the slow cases (over 1 ms per step).
WARM_UP = 20


def measure(cases: dict[str, tuple[Path, dict | None]], steps: int, repeat: int,
            slow_steps: int) -> dict[str, float]:
    """µs per step of each case (label -> (fmu, start values)): all instances are live at once
    and measured round-robin, best of ``repeat`` rounds, so slow drifts of the machine's load hit
    every case alike. Cases slower than 1 ms per step run ``slow_steps`` steps."""
    scale = 1.0 + 0.1 * np.random.default_rng(0).random(max(steps, slow_steps, WARM_UP))
    columns = {n: [v * s for s in scale] for n, v in BASE.items()}
    sessions = {k: TimedInstance(path, start, columns) for k, (path, start) in cases.items()}
    try:
        n = {k: steps if s.run(WARM_UP, None) < 1000 else slow_steps   # imports, caches, JIT
             for k, s in sessions.items()}
        times = {k: float("inf") for k in sessions}
        for _ in range(repeat):
            for k, s in sessions.items():
                times[k] = min(times[k], s.run(n[k], None))
        return times
    finally:
        for s in sessions.values():
            s.free()


def method_start(method: str) -> dict:
    opts = cc.METHODS[method].default_options
    return {"method": method, **{k: v for k, v in SMALL_OPTIONS.items() if k in opts}}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--slow-steps", type=int, default=200,
                   help="steps for methods slower than 1 ms per step")
    p.add_argument("--out", default=None, help="where to build the FMUs (default: a temp dir)")
    a = p.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_fmu_") as tmp:
        out = Path(a.out or tmp)
        fmus = {"trivial": build_trivial(out / "trivial"), "full": build("full", out=out / "full"),
                "generic": build("full", out=out / "generic", wrapper="pythonfmu")}
        cases = {"trivial": (fmus["trivial"], None)}
        for m in cc.methods():
            cases[f"full/{m}"] = (fmus["full"], method_start(m))
        jv = "johnson_vermeulen"
        cases["generic"] = (fmus["generic"], method_start(jv))
        for name in cc.scenes():
            sc = cc.load_scene(name)
            if name != "full":
                fmus[name] = build(name, out=out / name)
                cases[f"{name}/{sc.default_method}"] = (fmus[name], method_start(sc.default_method))
        t = measure(cases, a.steps, a.repeat, a.slow_steps)

        print(f"per step = setReal + doStep + getReal through fmpy FMU2Slave, best of {a.repeat} "
              f"interleaved rounds of {a.steps} steps\n")
        print(f"{'FMU':<36}{'µs/step':>10}{'x trivial':>11}")
        print(f"{'trivial pythonfmu FMU':<36}{t['trivial']:>10.2f}{1.0:>11.2f}")
        for m in cc.methods():
            small = len(method_start(m)) > 1
            label = f"full, {m}" + (" (small grid)" if small else "")
            print(f"{label:<36}{t[f'full/{m}']:>10.2f}{t[f'full/{m}'] / t['trivial']:>11.2f}")
        label = f"full, {jv}, pythonfmu's binary"
        print(f"{label:<36}{t['generic']:>10.2f}{t['generic'] / t['trivial']:>11.2f}")
        print("\nper scene: its FMU with its default method vs the full FMU with the same method")
        print(f"{'scene':<16}{'method':<20}{'µs/step':>10}{'full':>10}{'ratio':>9}")
        for name in cc.scenes():
            m = cc.load_scene(name).default_method
            ts, tf = t[f"{name}/{m}"] if name != "full" else t[f"full/{m}"], t[f"full/{m}"]
            print(f"{name:<16}{m:<20}{ts:>10.2f}{tf:>10.2f}{ts / tf:>9.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
