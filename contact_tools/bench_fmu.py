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
import time
from pathlib import Path

import numpy as np
from fmpy import read_model_description

import contact_core as cc
from wheel_rail_fmu.build import build
from wheel_rail_fmu.host import FmuInstance

#: The trivial FMU's pythonfmu slave script.
TRIVIAL = Path(__file__).resolve().parent / "trivial_fmu" / "trivial_contact.py"

#: Small grids for the discretised methods (per-option overrides, applied if the method has them).
SMALL_OPTIONS = {"nx": 10, "ny": 10, "mx": 10, "my": 10, "extrapolate": False}


def build_trivial(out: Path) -> Path:
    from pythonfmu import FmuBuilder
    return Path(FmuBuilder.build_FMU(TRIVIAL, dest=out))


class Session(FmuInstance):
    """One initialised instance (the start values it has) with its inputs and Real outputs."""

    def __init__(self, path: Path, start: dict | None = None) -> None:
        names = {v.name for v in read_model_description(str(path)).modelVariables}
        super().__init__(path, "bench", {k: v for k, v in (start or {}).items() if k in names},
                         logging_on=False)
        self.inputs = [n for n, v in self.vars.items() if v.causality == "input"]
        self.outputs = [n for n, v in self.vars.items()
                        if v.causality == "output" and v.type == "Real"]

    def run(self, steps: int) -> float:
        """µs per setReal + doStep + getReal over ``steps`` steps."""
        fmu = self.fmu
        vin = [self.vr(n) for n in self.inputs]
        vout = [self.vr(n) for n in self.outputs]
        # (V: the rolling speed of falling friction; A, B: the default curvatures, a, b their
        # patch under 100 kN, for the scenes with varying_geometry)
        base = {"xi": 1e-3, "eta": -5e-4, "phi": 0.2, "N": 1e5, "mu": 0.3, "V": 20.0,
                "A": 0.5 / 0.46, "B": 0.5 / 0.3, "a": 7e-3, "b": 5.4e-3}
        rng = np.random.default_rng(0)
        scale = 1.0 + 0.1 * rng.random(steps)
        rows = [[base[n] * s for n in self.inputs] for s in scale]
        set_real, do_step, get_real = fmu.setReal, fmu.doStep, fmu.getReal
        t, dt = 0.0, 1e-3
        t0 = time.perf_counter()
        for row in rows:
            set_real(vin, row)
            do_step(t, dt)
            get_real(vout)
            t += dt
        return (time.perf_counter() - t0) / steps * 1e6



def measure(cases: dict[str, tuple[Path, dict | None]], steps: int, repeat: int,
            slow_steps: int) -> dict[str, float]:
    """µs per step of each case (label -> (fmu, start values)): all instances are live at once
    and measured round-robin, best of ``repeat`` rounds, so slow drifts of the machine's load hit
    every case alike. Cases slower than 1 ms per step run ``slow_steps`` steps."""
    sessions = {k: Session(path, start) for k, (path, start) in cases.items()}
    try:
        n = {}
        for k, s in sessions.items():
            quick = s.run(20)  # warm-up (imports, caches, JIT)
            n[k] = steps if quick < 1000 else slow_steps
        times = {k: float("inf") for k in sessions}
        for _ in range(repeat):
            for k, s in sessions.items():
                times[k] = min(times[k], s.run(n[k]))
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
