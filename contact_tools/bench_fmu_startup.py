"""Start-up of the WheelRailContact FMU in a new process: the first one compiles, the next reuse.

    python -m contact_tools.bench_fmu_startup [--repeat R]

For the exact (24 x 24), FASTSIM and table FMUs (full scene; the table FMU also reads its
table), with an empty cache folder (``CONTACT_CORE_FMU_CACHE``, see ``wheel_rail_fmu.entry``):
the first process, then R more, each a fresh Python process that imports fmpy, instantiates
and initialises the FMU and does one step. Printed: seconds for instantiate + initialise +
first doStep (the target: at most 3 s from the second process on), and for the whole process.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHILD = """
import json, sys, time
t0 = time.perf_counter()
from wheel_rail_fmu.host import FmuInstance
t1 = time.perf_counter()
inst = FmuInstance(sys.argv[1], "startup")
inst.step(xi=1e-3, eta=2e-4, phi=0.1, N=1e5)
t2 = time.perf_counter()
inst.free()
print(json.dumps({"import": t1 - t0, "first_step": t2 - t1}))
"""


def run(fmu: Path, cache: Path) -> dict:
    env = {**os.environ, "CONTACT_CORE_FMU_CACHE": str(cache)}
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", CHILD, str(fmu)], env=env, check=True,
                         capture_output=True, text=True).stdout
    r = json.loads(out.strip().splitlines()[-1])
    r["process"] = time.perf_counter() - t0
    return r


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeat", type=int, default=3, help="processes after the first (default 3)")
    a = p.parse_args(argv)
    from wheel_rail_fmu.build import build

    print("FMU start-up in a new process: instantiate + initialise + first doStep, s "
          "(whole process in brackets)\n")
    print(f"| FMU | first process | next {a.repeat} processes: min / median / max |")
    print("|---|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for method in ("exact", "fastsim", "table"):
            fmu = build("full", method, tmp)
            cache = Path(tmp) / f"cache_{method}"
            first = run(fmu, cache)
            nxt = [run(fmu, cache) for _ in range(a.repeat)]
            s = sorted(r["first_step"] for r in nxt)
            w = sorted(r["process"] for r in nxt)
            print(f"| {method} | {first['first_step']:.2f} ({first['process']:.1f}) | "
                  f"{s[0]:.2f} / {statistics.median(s):.2f} / {s[-1]:.2f} "
                  f"({w[0]:.1f} / {statistics.median(w):.1f} / {w[-1]:.1f}) |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
