"""Memory of the WheelRailContact FMU in a long-running host: RSS growth per operation (fmpy).

    python -m contact_tools.bench_fmu_leaks [--refused N] [--cycles N] [--wrapper W ...] [--json]

For each FMU binary (``native``: this project's wrapper; ``pythonfmu``: pythonfmu's generic
binary), in a fresh process each:

* refused steps: ``N`` steps with a NaN input (each refused with ``fmi2Discard`` and a logged
  message, logging on), after 5000 such steps to warm up;
* instantiate/step/free cycles: ``N`` cycles of instantiate, initialise, one step, free (fmpy
  unloads the library each time), after 100 cycles to warm up; then ``N`` more (the heap has
  settled by then: growth there would be a leak per cycle);
* the same ``N`` cycles again, each taking 20 FMU states (``fmi2GetFMUstate``) that it leaves to
  ``fmi2FreeInstance`` to free (FMI 2.0 sec. 2.1.6), with the size of one state.

Prints the growth of the resident set size (RSS, /proc/self/statm) over the measured part.
The targets: at most 2 MB over 1e5 refused steps and 3 MB over 300 cycles, with or without the
states.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

WARM_REFUSED, WARM_CYCLES = 5000, 100
#: FMU states taken and left unfreed in each cycle of the third measurement.
STATES = 20


def rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def measure(path: str, refused: int, cycles: int) -> dict:
    """RSS growth (MB) in this process; a cycle that fails is reported, not raised."""
    import gc

    from fmpy.fmi1 import FMICallException

    from wheel_rail_fmu.host import FmuInstance

    out: dict = {}
    inst = FmuInstance(path, "refused")
    xi = [inst.vr("xi")]

    def refuse(n):
        for _ in range(n):
            inst.fmu.setReal(xi, [math.nan])
            try:
                inst.fmu.doStep(0.0, 1e-3)
            except FMICallException:
                pass

    refuse(WARM_REFUSED)
    r0 = rss_mb()
    refuse(refused)
    out["refused_mb"] = rss_mb() - r0
    out["refused_messages"] = inst.counts[2] + inst.counts[3]
    inst.free()

    def cycle(n, states=0):
        for k in range(n):
            j = FmuInstance(path, f"cycle{k}")
            j.step(xi=1e-3, N=1e5)
            for _ in range(states):     # left to fmi2FreeInstance
                j.fmu.getFMUstate()
            j.free()

    try:
        cycle(WARM_CYCLES)
        gc.collect()
        r0 = rss_mb()
        cycle(cycles)
        gc.collect()
        out["cycles_mb"] = rss_mb() - r0
        r0 = rss_mb()
        cycle(cycles)
        gc.collect()
        out["cycles_next_mb"] = rss_mb() - r0
        j = FmuInstance(path, "state size")
        out["state_bytes"] = len(j.fmu.serializeFMUstate(j.fmu.getFMUstate()))
        j.free()
        r0 = rss_mb()
        cycle(cycles, STATES)
        gc.collect()
        out["states_mb"] = rss_mb() - r0
    except Exception as e:  # pythonfmu 0.7's binary: fmi2Instantiate fails after a few cycles
        out["cycles_error"] = f"{type(e).__name__}: {e}"
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--refused", type=int, default=100_000)
    p.add_argument("--cycles", type=int, default=300)
    p.add_argument("--wrapper", action="append", choices=("native", "pythonfmu"))
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.add_argument("--child", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.child:
        print(json.dumps(measure(a.child, a.refused, a.cycles)))
        return 0

    from wheel_rail_fmu.build import build
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for wrapper in a.wrapper or ["native", "pythonfmu"]:
            fmu = build("traction", out=tmp, name=f"traction_{wrapper}", wrapper=wrapper)
            done = subprocess.run([sys.executable, "-m", "contact_tools.bench_fmu_leaks",
                                   "--child", str(fmu), "--refused", str(a.refused),
                                   "--cycles", str(a.cycles)],
                                  capture_output=True, text=True)
            lines = done.stdout.strip().splitlines()
            results[wrapper] = (json.loads(lines[-1]) if done.returncode == 0 and lines else
                                {"crashed": f"exit status {done.returncode}: "
                                            f"{done.stderr.strip()[-300:]}"})
    if a.json:
        print(json.dumps(results))
        return 0
    print(f"RSS growth, traction FMU in fmpy ({a.refused} refused steps with logging on; "
          f"{a.cycles} instantiate/step/free cycles)\n")
    print(f"| FMU binary | refused steps | cycles | next cycles | cycles, {STATES} states each "
          "left unfreed |")
    print("|---|---:|---:|---:|---:|")
    for wrapper, r in results.items():
        refused = f"{r['refused_mb']:.2f} MB" if "refused_mb" in r else r.get("crashed", "")
        cycles = (f"{r['cycles_mb']:.2f} MB | {r['cycles_next_mb']:.2f} MB" if "cycles_mb" in r
                  else r.get("cycles_error", r.get("crashed", "")) + " |")
        states = (f"{r['states_mb']:.2f} MB ({r['state_bytes']} bytes per state)"
                  if "states_mb" in r else "")
        print(f"| {wrapper} | {refused} | {cycles} | {states} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
