"""A small fixed-step co-simulation master on fmpy's ``FMU2Slave`` (Gauss-Seidel or Jacobi).

Why not only fmpy's own mechanisms
----------------------------------
``fmpy.ssp.simulate_ssp`` (fmpy 0.3.x) is a *Jacobi* master: every component steps with the input
values exchanged at the end of the previous step, and the exchanged values start at 0.0 (not at the
components' initial outputs). The contact FMU is a direct feedthrough (forces = law(creepages), no
state), so under Jacobi the wheelset integrates step k with the forces of the creepages of step k-1:
one communication step of pure delay inside the stiffest loop of the model. The creep forces act
as very strong damping (time constants m V / (2 f22), I_z V / (2 f11 b0²), I_y V / (2 f11 r0²),
well below a millisecond at low speed), and a delayed explicit damper is stable only for
h < τ (Gauss-Seidel: h < 2τ) and oscillates for h > τ/4 (Gauss-Seidel: monotone up to h = τ).
fmpy's container FMU exchanges values the same way (all components step, then connections are
copied). Neither lets us order the contact FMUs *before* the wheelset within a step.

This master does exactly that (``scheme="gauss-seidel"``, the default): in each step the
components are stepped in the given order, each reading its inputs from the outputs its sources
have *now*. With the order (contact L, contact R, wheelset) the contacts evaluate the law for the
wheelset's current creepages (F_k = law(x_k)), and the wheelset integrates [t_k, t_k + h] with
these forces held: the classical explicit (zero-order-hold) coupling, no delay. There is no
algebraic loop: the wheelset's outputs depend on its states only (its model description declares
no direct feedthrough). ``scheme="jacobi"`` reproduces simulate_ssp's ordering (tested against it
in ``tests/test_wheelsets.py``), and ``ssp.py`` writes the same systems as SSP files for
``fmpy.ssp.simulate_ssp``.

Connections are given by variable name (``"comp.var"``). A connection whose *destination* does not
exist (a scene-specific contact FMU without that input, e.g. ``eta`` in the ``traction`` scene) is
dropped, and its source is then checked at every exchange to be exactly 0 (a non-zero value would
be an effect the scene leaves out: ``RuntimeError``). A missing *source* leaves the destination at
its start value.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Mapping

import numpy as np

from wheel_rail_fmu.host import FmuInstance


def _split(path: str) -> tuple[str, str]:
    comp, sep, var = path.partition(".")
    if not sep:
        raise ValueError(f"{path!r}: expected 'component.variable'")
    return comp, var


class Component(FmuInstance):
    """One FMU instance of the co-simulation (:class:`wheel_rail_fmu.host.FmuInstance`:
    instantiated and initialised with its start values) with the value references it exchanges
    at every step."""

    def __init__(self, name: str, filename: str | Path, start_values: Mapping | None = None,
                 start_time: float = 0.0, stop_time: float | None = None) -> None:
        try:
            super().__init__(filename, name, start_values, start_time=start_time,
                             stop_time=stop_time)
        except Exception as e:
            log = getattr(self, "messages", None)
            raise RuntimeError(f"{name}: instantiating {filename} failed: {e}; log: "
                               f"{self.log_text() if log else '(none)'}") from None
        self.in_vrs: list[int] = []    # inputs set each step (order of in_sources)
        self.out_vrs: list[int] = []   # Real outputs read each step
        self.out_names: list[str] = []
        self.values: dict[str, float] = {}

    def has(self, var: str) -> bool:
        return var in self.vars

    def read_outputs(self) -> None:
        if self.out_vrs:
            vals = self.fmu.getReal(self.out_vrs)
            self.values = dict(zip(self.out_names, vals))


@dataclass
class Result:
    """Recorded trajectories: ``data[name]`` arrays (``"time"`` and ``"comp.var"``) plus timing."""

    data: dict[str, np.ndarray]
    wall_time: float                 #: wall time of the stepping loop, s
    cpu_time: float                  #: process CPU time of the stepping loop, s
    steps: int                       #: communication steps done
    component_time: dict[str, float] = field(default_factory=dict)  #: CPU time per component, s
    aborted: bool = False            #: stopped early by ``abort_above``

    def __getitem__(self, key: str) -> np.ndarray:
        return self.data[key]


class CoSimulation:
    """Fixed-step master; see the module docstring.

    Parameters
    ----------
    components : mapping name -> FMU file, in stepping order (Gauss-Seidel)
    connections : iterable of ("src.var", "dst.var")
    start_values : mapping name -> {variable: value} (parameters, initial inputs)
    inputs : mapping "comp.var" -> f(t), external inputs sampled at each step's start
    scheme : "gauss-seidel" (default) or "jacobi"
    initial_exchange : exchange the components' initial outputs before the first step (default);
        False reproduces simulate_ssp, whose connectors start at 0.0
    """

    def __init__(self, components: Mapping[str, str | Path],
                 connections: Iterable[tuple[str, str]],
                 start_values: Mapping[str, Mapping] | None = None,
                 inputs: Mapping[str, Callable[[float], float]] | None = None,
                 scheme: str = "gauss-seidel", initial_exchange: bool = True,
                 start_time: float = 0.0, stop_time: float | None = None) -> None:
        if scheme not in ("gauss-seidel", "jacobi"):
            raise ValueError(f"scheme={scheme!r} is unknown: allowed 'gauss-seidel', 'jacobi'")
        self.scheme = scheme
        self.initial_exchange = initial_exchange
        self.start_time = start_time
        start_values = start_values or {}
        unknown = set(start_values) - set(components)
        if unknown:
            raise KeyError(f"start values for unknown component(s) {sorted(unknown)}")
        self.components: dict[str, Component] = {}
        try:
            for name, fn in components.items():
                self.components[name] = Component(name, fn, start_values.get(name), start_time,
                                                  stop_time)
        except Exception:
            self.free()
            raise
        self.connections: list[tuple[str, str, str, str]] = []
        self.must_be_zero: list[tuple[str, str, str]] = []   # (src comp, src var, why)
        for src, dst in connections:
            sc, sv = _split(src)
            dc, dv = _split(dst)
            for c in (sc, dc):
                if c not in self.components:
                    raise KeyError(f"connection {src} -> {dst}: unknown component {c!r}")
            if not self.components[sc].has(sv):
                continue  # missing source: the destination keeps its start value
            if not self.components[dc].has(dv):
                self.must_be_zero.append((sc, sv, f"{dst} does not exist"))
                continue
            self.connections.append((sc, sv, dc, dv))
        self.inputs = []
        for path, f in (inputs or {}).items():
            c, v = _split(path)
            self.inputs.append((self.components[c], self.components[c].vr(v), f))
        # Per destination component: its input vrs and their sources.
        self._sources: dict[str, list[tuple[str, str]]] = {n: [] for n in self.components}
        for sc, sv, dc, dv in self.connections:
            comp = self.components[dc]
            comp.in_vrs.append(comp.vr(dv))
            self._sources[dc].append((sc, sv))
        self._out_needed: dict[str, set[str]] = {n: set() for n in self.components}
        for sc, sv, _, _ in self.connections:
            self._out_needed[sc].add(sv)
        for sc, sv, _ in self.must_be_zero:
            self._out_needed[sc].add(sv)

    # ------------------------------------------------------------------------------------------
    def _prepare_outputs(self, record: list[str]) -> None:
        need = {n: set(s) for n, s in self._out_needed.items()}
        for path in record:
            c, v = _split(path)
            if c not in self.components or not self.components[c].has(v):
                raise KeyError(f"cannot record {path!r}: no such variable")
            need[c].add(v)
        for n, comp in self.components.items():
            names = sorted(v for v in need[n] if comp.vars[v].type == "Real")
            comp.out_names = names
            comp.out_vrs = [comp.vr(v) for v in names]
            comp.read_outputs()
            if not self.initial_exchange:
                comp.values = {k: 0.0 for k in names}

    def _check_dropped(self, t: float) -> None:
        for sc, sv, why in self.must_be_zero:
            value = self.components[sc].values[sv]
            if value != 0.0:
                raise RuntimeError(f"t={t:g}: {sc}.{sv} = {value!r} is non-zero but {why} "
                                   "(the contact FMU's scene omits an effect this model needs)")

    def _set_inputs(self, comp: Component, t: float, values_of) -> None:
        srcs = self._sources[comp.name]
        if srcs:
            comp.fmu.setReal(comp.in_vrs, [values_of(sc)[sv] for sc, sv in srcs])

    def run(self, stop_time: float, step: float, record: Iterable[str] = (),
            record_every: int = 1, abort_above: Mapping[str, float] | None = None) -> Result:
        """Run from the start time to ``stop_time`` with communication step ``step``; record the
        given ``"comp.var"`` (Real) every ``record_every`` steps (and at t0). ``abort_above``:
        {"comp.var": limit}: stop (``Result.aborted``) once a recorded |value| exceeds its limit
        (to watch a numerically unstable run without overflowing)."""
        record = list(record)
        limits = [(i, float(lim)) for i, p in enumerate(record)
                  for q, lim in (abort_above or {}).items() if q == p]
        if abort_above and len(limits) != len(abort_above):
            raise KeyError("abort_above names a variable that is not recorded")
        self._prepare_outputs(record)
        n_steps = int(round((stop_time - self.start_time) / step))
        if n_steps < 1 or not math.isclose(self.start_time + n_steps * step, stop_time,
                                           rel_tol=1e-9, abs_tol=1e-12):
            raise ValueError(f"stop_time - start_time = {stop_time - self.start_time!r} is not a "
                             f"positive multiple of step={step!r}")
        rec_paths = [_split(p) for p in record]
        rows = []

        def snapshot(t):
            rows.append([t] + [self.components[c].values[v] for c, v in rec_paths])

        snapshot(self.start_time)
        order = list(self.components.values())
        busy = {c.name: 0.0 for c in order}
        perf = time.thread_time   # CPU time of this thread: the FMUs run in it, others don't count
        t_wall, t_cpu = time.perf_counter(), time.process_time()
        aborted = False
        t = self.start_time
        for k in range(n_steps):
            t = self.start_time + k * step
            for comp, vr, f in self.inputs:
                comp.fmu.setReal([vr], [float(f(t))])
            self._check_dropped(t)
            if self.scheme == "gauss-seidel":
                for comp in order:
                    t0 = perf()
                    self._set_inputs(comp, t, lambda n: self.components[n].values)
                    comp.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
                    comp.read_outputs()
                    busy[comp.name] += perf() - t0
            else:
                frozen = {c.name: c.values for c in order}
                for comp in order:
                    t0 = perf()
                    self._set_inputs(comp, t, frozen.__getitem__)
                    comp.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
                    busy[comp.name] += perf() - t0
                for comp in order:
                    t0 = perf()
                    comp.read_outputs()
                    busy[comp.name] += perf() - t0
            if (k + 1) % record_every == 0 or k + 1 == n_steps:
                snapshot(self.start_time + (k + 1) * step)
            if limits:
                vals = [self.components[c].values[v] for c, v in rec_paths]
                if any(not abs(vals[i]) <= lim for i, lim in limits):
                    if (k + 1) % record_every:
                        snapshot(self.start_time + (k + 1) * step)
                    aborted = True
                    n_steps = k + 1
                    break
        wall, cpu = time.perf_counter() - t_wall, time.process_time() - t_cpu
        arr = np.array(rows, dtype=float)
        data = {"time": arr[:, 0]}
        for i, p in enumerate(record):
            data[p] = arr[:, i + 1]
        return Result(data, wall, cpu, n_steps, busy, aborted)

    def free(self) -> None:
        for comp in self.components.values():
            comp.free()
        self.components = {}

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.free()
