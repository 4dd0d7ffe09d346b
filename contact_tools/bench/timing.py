"""Time per call: in-process through :func:`contact_core.solve`, and per FMU step through fmpy.

Both are measured serially (one process; the reference's parallel sweep is finished by then), in
round-robin order over settings and cases, so slow drifts of the machine's load hit every setting
alike; each (setting, case) is measured ``repeats`` times and the per-case time is the median of
its repeats. Garbage collection is off while timing (as in :mod:`timeit`).

In-process
    One warm-up call per (setting, case) gives the result used for the errors (and fills the
    caches a simulation also has warm: the solver object, influence tables, the exact solver's
    normal solution per a/b, numba's compiled code). A measurement is ``n`` back-to-back calls
    of ``contact_core.solve(method, ..., **options)`` (cold: no ``warm_start``), ``n`` chosen so
    that it lasts about ``target`` seconds (1 for slow methods): per call = total / n.

FMU
    The ``full``-scene FMU (built once by ``wheel_rail_fmu.build.build`` and cached under
    ``build_dir`` by a hash of the sources) is instantiated through fmpy's ``FMU2Slave`` once per
    (setting, a/b), with the ``method`` and option parameters of the setting and the radii of the
    a/b (:meth:`Case.fmu_parameters`; the FMU derives a, b from Hertz at each step's N, the same
    arithmetic as the case). A step is ``setReal(xi, eta, phi, N, mu) + doStep + getReal(Fx, Fy,
    Mz)``, timed one by one; a round steps through the a/b's cases in order. Per a/b every
    setting's instance is open at once and the rounds go round-robin over the settings, each for
    as many rounds as its budget allows: the cheap ones (up to ``max_rounds``) side by side
    throughout, the dear ones (``repeats``) within the first rounds, so that a slow spell of the
    machine hits the settings compared alike (timed one setting after the other, a slow spell
    once made linear theory's steps dearer than FASTSIM's: docs/notes/benchmark.md). The first
    round's outputs are compared with the in-process results. Note: the FMU warm-starts each step
    from the previous one (what a co-simulation does); between unrelated cases that gains little,
    so exact-solver steps cost about an in-process call plus the FMU overhead.
"""
from __future__ import annotations

import gc
import hashlib
import math
import time
import warnings
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from contact_core import api
from .cases import Case
from .settings import Setting


@contextmanager
def _no_gc():
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _caller(setting: Setting, case: Case) -> Callable[[], Any]:
    kw = case.solve_kwargs()
    if setting.call is not None:
        fn = setting.call
        return lambda: fn(**kw)
    method, opts = setting.method, setting.kwargs
    solve = api.solve
    return lambda: solve(method, **kw, **opts)


def time_inprocess(settings: Sequence[Setting], cases: Sequence[Case], repeats: int = 3,
                   target: float = 2e-4, progress: bool = True
                   ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Seconds per call and results of every setting on every case.

    Returns ``(times, results)``: ``times[label]`` has shape (cases, repeats); ``results[label]``
    has shape (cases, 4): Fx, Fy, Mz, converged (1.0/0.0; a custom ``call`` without
    ``converged`` counts as converged).
    """
    from tqdm.auto import tqdm

    callers = {s.label: [_caller(s, c) for c in cases] for s in settings}
    results = {s.label: np.zeros((len(cases), 4)) for s in settings}
    times = {s.label: np.zeros((len(cases), repeats)) for s in settings}
    ncalls = {s.label: np.ones(len(cases), dtype=int) for s in settings}
    total = len(settings) * len(cases) * (repeats + 1)
    with tqdm(total=total, desc="time in-process", unit="case", disable=not progress,
              leave=False) as bar, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an exact solve that does not converge is recorded
        for s in settings:
            for j, call in enumerate(callers[s.label]):
                t0 = time.perf_counter()
                r = call()
                dt = time.perf_counter() - t0
                results[s.label][j] = (r.Fx, r.Fy, r.Mz, float(getattr(r, "converged", True)))
                ncalls[s.label][j] = int(min(2000, max(1, math.ceil(target / max(dt, 1e-9)))))
                bar.update()
        with _no_gc():
            for k in range(repeats):
                for s in settings:
                    ns = ncalls[s.label]
                    for j, call in enumerate(callers[s.label]):
                        n = int(ns[j])
                        t0 = time.perf_counter()
                        for _ in range(n):
                            call()
                        times[s.label][j, k] = (time.perf_counter() - t0) / n
                    bar.update(len(cases))
    return times, results


# ---------------------------------------------------------------------------------------------
# FMU
# ---------------------------------------------------------------------------------------------

def _source_hash() -> str:
    import wheel_rail_fmu
    h = hashlib.sha256()
    for d in (Path(api.__file__).parent, Path(wheel_rail_fmu.__file__).parent):
        for f in sorted(f for f in d.rglob("*") if f.is_file() and "__pycache__" not in f.parts
                        and f.suffix not in (".pyc", ".nbi", ".nbc")):
            h.update(f.relative_to(d.parent).as_posix().encode() + b"\0" + f.read_bytes())
    return h.hexdigest()[:16]


def cached_fmu(build_dir: str | Path) -> Path:
    """The full-scene FMU, built once per version of the sources into ``build_dir/<hash>/``."""
    from wheel_rail_fmu.build import build
    out = Path(build_dir) / _source_hash()
    fmu = out / "WheelRailContact.fmu"
    if not fmu.is_file():
        build("full", out=out, name=fmu.stem)
    return fmu


def _steps(inst, rows: list[list[float]], out: np.ndarray | None = None) -> np.ndarray:
    """Seconds of each step (setReal + doStep + getReal) of the FMU instance ``inst``
    (:class:`wheel_rail_fmu.host.FmuInstance`) over ``rows`` of inputs (xi, eta, phi, N, mu)."""
    fmu = inst.fmu
    vin = [inst.vr(n) for n in ("xi", "eta", "phi", "N", "mu")]
    vout = [inst.vr(n) for n in ("Fx", "Fy", "Mz")]
    set_real, do_step, get_real, clock = fmu.setReal, fmu.doStep, fmu.getReal, time.perf_counter
    dt = np.empty(len(rows))
    t, h = inst.t, 1e-3
    for i, row in enumerate(rows):
        t0 = clock()
        set_real(vin, row)
        do_step(t, h)
        y = get_real(vout)
        dt[i] = clock() - t0
        t += h
        if out is not None:
            out[i] = y
    inst.t = t
    return dt


def time_fmu(settings: Sequence[Setting], cases: Sequence[Case], build_dir: str | Path,
             repeats: int = 3, budget: float = 0.05, max_rounds: int = 30,
             progress: bool = True) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Seconds per FMU step and FMU outputs of every FMU-capable setting on every case.

    Returns ``(times, outputs)``: ``times[label]`` has shape (cases, rounds) with at least
    ``repeats`` rounds (more, up to ``max_rounds``, for cheap settings: about ``budget`` seconds
    per (setting, a/b)); ``outputs[label]`` (cases, 3): Fx, Fy, Mz of the first round.
    """
    from tqdm.auto import tqdm

    from wheel_rail_fmu.host import FmuInstance

    path = cached_fmu(build_dir)
    groups: dict[float, list[int]] = {}
    for j, c in enumerate(cases):
        groups.setdefault(c.a_over_b, []).append(j)
    fmu_settings = [s for s in settings if s.fmu]
    per: dict[str, list[list[float]]] = {s.label: [[] for _ in cases] for s in fmu_settings}
    outputs = {s.label: np.full((len(cases), 3), np.nan) for s in fmu_settings}
    with tqdm(total=len(fmu_settings) * len(groups), desc="time FMU", unit="instance",
              disable=not progress, leave=False) as bar, _no_gc():
        for idx in groups.values():
            rows = [[cases[j].xi, cases[j].eta, cases[j].phi, cases[j].N, cases[j].mu]
                    for j in idx]
            with ExitStack() as stack:
                insts, rounds = {}, {}
                for s in fmu_settings:
                    params = {"method": s.method, **s.kwargs, **cases[idx[0]].fmu_parameters()}
                    inst = stack.enter_context(FmuInstance(path, "accuracy_vs_time", params,
                                                           logging_on=False))
                    out = np.empty((len(idx), 3))
                    first = _steps(inst, rows, out)   # warm-up round: outputs, caches
                    outputs[s.label][idx] = out
                    insts[s.label] = inst
                    rounds[s.label] = int(min(max_rounds, max(repeats, math.ceil(
                        budget / max(first.sum(), 1e-9)))))
                for r in range(max(rounds.values(), default=0)):
                    for label, inst in insts.items():
                        if r < rounds[label]:
                            for j, t in zip(idx, _steps(inst, rows)):
                                per[label][j].append(t)
            bar.update(len(fmu_settings))
    times = {}
    for label, rows in per.items():
        n = min(len(r) for r in rows)
        times[label] = np.array([r[:n] for r in rows])
    return times, outputs
