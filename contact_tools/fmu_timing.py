"""Timing of the per-step benchmarks (``bench_fmu``, ``bench_geometry``, ``bench_multi``): an FMU
instance stepped through rows of inputs, timed in chunks, and cases measured in interleaved
rounds (the machine's load drifts hit every case alike).
"""
from __future__ import annotations

import math
import time
from ctypes import c_double, c_uint
from pathlib import Path
from typing import Callable, Mapping, Sequence

import numpy as np
from fmpy.fmi2 import fmi2True
from wheel_rail_fmu.host import FmuInstance

#: Steps timed together: a case's time is the least over its chunks and rounds (another
#: process taking the core for a while spoils a chunk, not the case).
CHUNK = 250


def interleaved_best(cases: Mapping[str, Callable[[], float]], repeat: int) -> dict[str, float]:
    """Best µs of each case (label -> callable returning µs): one warm-up call each
    (compilation, caches, table rows), then ``repeat`` rounds over all cases."""
    best = {k: math.inf for k in cases}
    for f in cases.values():
        f()
    for _ in range(repeat):
        for k, f in cases.items():
            best[k] = min(best[k], f())
    return best


class TimedInstance(FmuInstance):
    """One initialised instance (logging off) with the rows of inputs it is stepped through.

    ``start``: start values, those of variables the FMU lacks left out (a scene's FMU has only
    some of the options). ``columns``: values per step by input name; the FMU's inputs that have
    a column are set at every step, and every Real output is read.
    """

    def __init__(self, path: Path, start: Mapping | None,
                 columns: Mapping[str, Sequence[float]]) -> None:
        super().__init__(path, "bench", initialize=False, logging_on=False)
        self.init({k: v for k, v in (start or {}).items() if k in self.vars})
        names = [n for n in columns if n in self.vars and self.vars[n].causality == "input"]
        self.vin = [self.vr(n) for n in names]
        self.vout = [v.valueReference for v in self.vars.values()
                     if v.causality == "output" and v.type == "Real"]
        self.rows = [list(row) for row in zip(*(columns[n] for n in names))]

    def run(self, steps: int | None = None, chunk: int | None = CHUNK) -> float:
        """µs per ``setReal + doStep + getReal`` (fmpy's ``FMU2Slave``, Python lists) over the
        first ``steps`` rows (None: all), the least over chunks of ``chunk`` steps (None: the
        mean over all)."""
        rows = self.rows[:steps]
        chunk = chunk or len(rows)
        set_real, do_step, get_real = self.fmu.setReal, self.fmu.doStep, self.fmu.getReal
        vin, vout = self.vin, self.vout
        t, dt = self.t, 1e-3
        best = math.inf
        for i in range(0, len(rows), chunk):
            part = rows[i:i + chunk]
            t0 = time.perf_counter()
            for row in part:
                set_real(vin, row)
                do_step(t, dt)
                get_real(vout)
                t += dt
            best = min(best, (time.perf_counter() - t0) / len(part))
        self.t = t
        return best * 1e6

    def run_arrays(self) -> float:
        """µs per ``fmi2SetReal + fmi2DoStep + fmi2GetReal`` with arrays made once (each step's
        inputs copied into them, what a C host does), the least over chunks of the rows."""
        fmu = self.fmu
        set_real, do_step, get_real = fmu.fmi2SetReal, fmu.fmi2DoStep, fmu.fmi2GetReal
        component = fmu.component
        n_in, n_out = len(self.vin), len(self.vout)
        vin = (c_uint * n_in)(*self.vin)
        vout = (c_uint * n_out)(*self.vout)
        values = (c_double * n_in)()
        outputs = (c_double * n_out)()
        into = np.frombuffer(values)
        rows = np.array(self.rows)
        t, dt = self.t, 1e-3
        best = math.inf
        for i in range(0, len(rows), CHUNK):
            part = rows[i:i + CHUNK]
            t0 = time.perf_counter()
            for row in part:
                into[:] = row
                set_real(component, vin, n_in, values)
                do_step(component, t, dt, fmi2True)
                get_real(component, vout, n_out, outputs)
                t += dt
            best = min(best, (time.perf_counter() - t0) / len(part))
        self.t = t
        return best * 1e6
