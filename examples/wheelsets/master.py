"""A small fixed-step co-simulation master on fmpy's ``FMU2Slave`` (Gauss-Seidel, Jacobi or
linearly implicit).

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

Linearly implicit coupling (``scheme="linearly-implicit"``)
----------------------------------------------------------
The explicit schemes hold F_k = f(u_k) over the step: the stiff creep damping then limits h to
about 2τ (Gauss-Seidel). The linearly implicit scheme holds forces corrected to first order for
the change of the creepages over the step, as the semi-implicit co-simulation of Schweizer & Lu
(B. Schweizer, D. Lu, "Semi-implicit co-simulation approach for solver coupling", Archive of
Applied Mechanics 84 (2014) 1739-1769: a predictor step, the subsystems' partial derivatives of
their coupling variables with respect to the coupling forces from extra subsystem integrations
with perturbed forces, and corrected forces from a linear system) and the coupling with the
components' Jacobians of Kübler & Schiehlen (R. Kübler, W. Schiehlen, "Two methods of simulator
coupling", Mathematical and Computer Modelling of Dynamical Systems 6 (2000) 93-113), whose
convergence and stability rest on the contractivity analysis of Arnold & Günther (M. Arnold,
M. Günther, "Preconditioned dynamic iteration for coupled differential-algebraic systems", BIT
41 (2001) 1-25).

Components are of two kinds, told apart by their model descriptions: *algebraic* ones, whose
connected outputs depend directly on their inputs (the contacts: F = f(u), ``ModelStructure``
dependencies on inputs), which must provide ``fmi2GetDirectionalDerivative``; and *dynamic*
ones, without direct feedthrough (the wheelset: u_{k+1} follows from its state and the forces it
received over the step), which must be able to get and set their FMU state. u are the dynamic
components' outputs read by algebraic ones, F the algebraic components' outputs read by dynamic
ones. Per communication step [t_k, t_k + h]:

1. the algebraic components step at u_k: F_k = f(u_k); their Jacobian J = ∂F/∂u at u_k from
   ``fmi2GetDirectionalDerivative`` (one call per input that moves, seed 1: a column);
2. predictor: each dynamic component saves its state (``fmi2GetFMUstate``) and steps with F_k:
   u^p = u_{k+1}(F_k) (the explicit Gauss-Seidel step);
3. sensitivity S = ∂u_{k+1}/∂F (end values of the forces), by one-sided differences: per force,
   the state set back (``fmi2SetFMUstate``) and a step with that force raised by
   δ = 1e-4 max(|F|, nominal) (Schweizer & Lu's extra integrations). S is kept from step to
   step while it stays valid (below);
4. the implicit condition F* = F_k + J (u_{k+1}(F*) - u_k), with u_{k+1}(F*) = u^p + S (F* - F_k),
   is the linear system

       (I - J S) ΔF = J (u^p - u_k),      F* = F_k + ΔF;

5. corrector: the state set back, a step with F*: held (``hold="constant"``), or ramped linearly
   from F_k at t_k to F* at t_k + h (``hold="linear"``, the first-order hold of the coupling
   variables, M. Busch, "Continuous approximation techniques for co-simulation methods: analysis
   of numerical stability and local error", ZAMM 96 (2016) 1061-1081);
6. validity of S: the corrected step's u_{k+1} against the prediction u^p + S ΔF; if the defect of
   the implicit condition, J (u_{k+1} - u^p - S ΔF), exceeds :attr:`CoSimulation.sensitivity_rtol`
   times ΔF (largest components; and 1e-12 of F_k, the rounding floor) — a dynamic component
   that is not affine in its forces, e.g. a flange contact starting within the step — S is
   computed again from the saved state and steps 4-5 repeated (once per step).

For a linear contact law the held force is that of the step's end, f(u_{k+1}) (constant hold: the
forces' part of the implicit Euler method, whose damping of a creep mode, 1/(1 + h/τ) per step,
needs no step limit), or the trapezoid between f(u_k) and f(u_{k+1}) (linear hold: second order,
damping (1 - h/2τ)/(1 + h/2τ), a stiff mode alternating in sign as it decays). The explicit
stability limit is gone; the step is then limited by accuracy: at a few steps per period of the
slowest motion (hunting) only the linear hold keeps its frequency and growth rate close, which
``examples/run_implicit_coupling.py`` measures.

What it asks per communication step: of each algebraic component one ``fmi2DoStep`` and one
``fmi2GetDirectionalDerivative`` per input that moves; of each dynamic component two
``fmi2DoStep`` (predictor, corrector), one ``fmi2GetFMUstate``, one ``fmi2SetFMUstate`` and one
``fmi2FreeFMUstate``, plus, when S is (re)computed, one ``fmi2SetFMUstate`` and ``fmi2DoStep``
per force it receives; and one solve of a linear system of the size of F. Linear hold: each force
input ``F`` of a dynamic component has a companion input ``F_rate``, which the master sets to the
ramp's slope (FMI 2.0's ``fmi2SetRealInputDerivatives``, sec. 4.2.1, would carry it; the FMI
wrapper of this project's FMUs does not route that call). Dynamic-to-dynamic connections are
exchanged with the values at t_k (Jacobi), algebraic-to-algebraic ones are refused.

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


#: Coupling schemes of :class:`CoSimulation` (module docstring).
SCHEMES = ("gauss-seidel", "jacobi", "linearly-implicit")
#: How the linearly implicit scheme applies the corrected forces over a step.
HOLDS = ("constant", "linear")


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
    scheme : "gauss-seidel" (default), "jacobi" or "linearly-implicit"
    initial_exchange : exchange the components' initial outputs before the first step (default);
        False reproduces simulate_ssp, whose connectors start at 0.0
    hold : linearly implicit scheme: the corrected forces "constant" over the step (default) or
        "linear" (ramped from F_k to F*; needs the dynamic components' ``<force>_rate`` inputs)
    """

    #: Linearly implicit scheme: S is computed again when the defect of the implicit condition
    #: exceeds this fraction of the correction ΔF (module docstring, step 6).
    sensitivity_rtol = 1e-2
    #: Relative perturbation of a force for the differences of S (module docstring, step 3).
    sensitivity_step = 1e-4

    def __init__(self, components: Mapping[str, str | Path],
                 connections: Iterable[tuple[str, str]],
                 start_values: Mapping[str, Mapping] | None = None,
                 inputs: Mapping[str, Callable[[float], float]] | None = None,
                 scheme: str = "gauss-seidel", initial_exchange: bool = True,
                 start_time: float = 0.0, stop_time: float | None = None,
                 hold: str = "constant") -> None:
        if scheme not in SCHEMES:
            raise ValueError(f"scheme={scheme!r} is unknown: allowed "
                             + ", ".join(map(repr, SCHEMES)))
        if hold not in HOLDS or (hold != "constant" and scheme != "linearly-implicit"):
            raise ValueError(f"hold={hold!r} is out of range: allowed 'constant', and 'linear' "
                             "with scheme='linearly-implicit'")
        self.scheme = scheme
        self.hold = hold
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
        self._implicit = None
        if scheme == "linearly-implicit":
            try:
                self._implicit = _LinearlyImplicit(self)
            except Exception:
                self.free()
                raise

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
            if self._implicit is not None:
                self._implicit.step(t, step, busy, perf)
            elif self.scheme == "gauss-seidel":
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


def _direct_feedthrough(comp: Component, outputs: Iterable[str]) -> bool:
    """Whether any of ``outputs`` of ``comp`` depends directly on an input (its model
    description's ModelStructure; no dependencies attribute: on every input)."""
    by_name = {u.variable.name: u for u in comp.md.outputs}
    for name in outputs:
        unknown = by_name.get(name)
        if unknown is None or unknown.dependencies is None:
            return True
        if any(d.causality == "input" for d in unknown.dependencies):
            return True
    return False


class _LinearlyImplicit:
    """The linearly implicit coupling of :class:`CoSimulation` (module docstring): the
    components' roles, the coupling variables u and F, and one communication step."""

    def __init__(self, sim: CoSimulation) -> None:
        self.sim = sim
        comps = sim.components
        feeding = {n: {sv for sc, sv, _, _ in sim.connections if sc == n} for n in comps}
        algebraic = {n for n, c in comps.items() if _direct_feedthrough(c, feeding[n])}
        self.algebraic = [c for n, c in comps.items() if n in algebraic]
        self.dynamic = [c for n, c in comps.items() if n not in algebraic]
        self.u: list[tuple[str, str]] = []          # (dynamic comp, output)
        u_index: dict[tuple[str, str], int] = {}
        #: algebraic comp -> [(input vr, u index)]
        self.knowns: dict[str, list[tuple[int, int]]] = {c.name: [] for c in self.algebraic}
        self.f: list[tuple[str, str, str, str]] = []  # (algebraic comp, output, dynamic, input)
        for sc, sv, dc, dv in sim.connections:
            if sc in algebraic and dc in algebraic:
                raise ValueError(f"linearly implicit scheme: {sc}.{sv} -> {dc}.{dv} connects two "
                                 "components with direct feedthrough (not supported)")
            if dc in algebraic:
                i = u_index.setdefault((sc, sv), len(self.u))
                if i == len(self.u):
                    self.u.append((sc, sv))
                self.knowns[dc].append((comps[dc].vr(dv), i))
            elif sc in algebraic:
                self.f.append((sc, sv, dc, dv))
        for c in self.algebraic:
            if not c.md.coSimulation.providesDirectionalDerivative:
                raise ValueError(f"linearly implicit scheme: {c.name} has direct feedthrough but "
                                 "does not provide directional derivatives")
        #: algebraic comp -> (vrs of its outputs in F, their F indices), one per F entry
        self.rows: dict[str, tuple[list[int], np.ndarray]] = {}
        for c in self.algebraic:
            idx = [j for j, (sc, _, _, _) in enumerate(self.f) if sc == c.name]
            self.rows[c.name] = ([c.vr(self.f[j][1]) for j in idx], np.array(idx, dtype=int))
        self.forces = {}    # dynamic comp -> (F indices, their vrs, rate vrs, nominal values)
        self.sources = {}   # dynamic comp -> (u indices it outputs, their names)
        for d in self.dynamic:
            idx = [j for j, (_, _, dc, _) in enumerate(self.f) if dc == d.name]
            if idx and not d.md.coSimulation.canGetAndSetFMUstate:
                raise ValueError(f"linearly implicit scheme: {d.name} cannot get and set its FMU "
                                 "state (canGetAndSetFMUstate)")
            rates = []
            if sim.hold == "linear":
                for j in idx:
                    rate = f"{self.f[j][3]}_rate"
                    if not d.has(rate):
                        raise ValueError(f"hold='linear': {d.name} has no input {rate!r} for the "
                                         f"slope of {self.f[j][3]}")
                    rates.append(d.vr(rate))
            nominal = [float(d.variable(self.f[j][3]).nominal or 1.0) for j in idx]
            self.forces[d.name] = (idx, [d.vr(self.f[j][3]) for j in idx], rates, nominal)
            ui = [i for i, (c, _) in enumerate(self.u) if c == d.name]
            self.sources[d.name] = (ui, [self.u[i][1] for i in ui])
        self.S: np.ndarray | None = None
        self.step_size: float | None = None

    # -- pieces of a step --------------------------------------------------------------------------
    def _u_of(self, d: Component, out: np.ndarray) -> None:
        ui, names = self.sources[d.name]
        out[ui] = [d.values[n] for n in names]

    def _step_dynamic(self, d: Component, state, t: float, h: float, F0: np.ndarray,
                      F_end: np.ndarray, values_of) -> None:
        """Set ``d`` back to ``state`` (if given) and step it with forces going from F0 to F_end
        (held at F_end, or ramped with ``hold="linear"``)."""
        if state is not None:
            d.fmu.setFMUstate(state)
        self.sim._set_inputs(d, t, values_of)
        idx, vrs, rates, _ = self.forces[d.name]
        if idx:
            if rates:
                d.fmu.setReal(vrs, list(F0[idx]))
                d.fmu.setReal(rates, list((F_end[idx] - F0[idx]) / h))
            else:
                d.fmu.setReal(vrs, list(F_end[idx]))
        d.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        d.read_outputs()

    def _sensitivity(self, states, t, h, F0, u_pred, values_of) -> np.ndarray:
        """S = ∂u_{k+1}/∂F by one-sided differences from the saved states (step 3)."""
        S = np.zeros((len(self.u), len(self.f)))
        u = np.empty(len(self.u))
        for d in self.dynamic:
            idx, _, _, nominal = self.forces[d.name]
            ui, _ = self.sources[d.name]
            for j, nom in zip(idx, nominal):
                delta = self.sim.sensitivity_step * max(abs(F0[j]), nom)
                F_end = F0.copy()
                F_end[j] += delta
                self._step_dynamic(d, states[d.name], t, h, F0, F_end, values_of)
                self._u_of(d, u)
                S[ui, j] = (u[ui] - u_pred[ui]) / delta
        self.step_size = h
        return S

    def _jacobian(self, moving: np.ndarray) -> np.ndarray:
        """J = ∂F/∂u at the algebraic components' present inputs, the columns that move."""
        J = np.zeros((len(self.f), len(self.u)))
        for a in self.algebraic:
            unknowns, rows = self.rows[a.name]
            for vr, i in self.knowns[a.name]:
                if moving[i] and unknowns:
                    J[rows, i] += a.fmu.getDirectionalDerivative(unknowns, [vr], [1.0])
        return J

    # -- one communication step ------------------------------------------------------------------
    def step(self, t: float, h: float, busy: dict[str, float], perf) -> None:
        comps = self.sim.components
        for a in self.algebraic:
            t0 = perf()
            self.sim._set_inputs(a, t, lambda n: comps[n].values)
            a.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            a.read_outputs()
            busy[a.name] += perf() - t0
        frozen = {d.name: d.values for d in self.dynamic}

        def values_of(name):   # dynamic sources at t_k, algebraic ones now (F_k)
            return frozen[name] if name in frozen else comps[name].values

        u0 = np.empty(len(self.u))
        for d in self.dynamic:
            self._u_of(d, u0)
        F0 = np.array([comps[a].values[v] for a, v, _, _ in self.f])
        states = {}
        try:
            u_pred = np.empty(len(self.u))
            for d in self.dynamic:                                   # predictor
                t0 = perf()
                if self.forces[d.name][0]:       # the ones with forces: corrected below
                    states[d.name] = d.fmu.getFMUstate()
                self._step_dynamic(d, None, t, h, F0, F0, values_of)
                self._u_of(d, u_pred)
                busy[d.name] += perf() - t0
            fresh = self.S is None or self.step_size != h
            if fresh:
                self.S = self._sensitivity(states, t, h, F0, u_pred, values_of)
            u_new = u_pred.copy()        # a dynamic component without forces: its predictor
            while True:
                S = self.S
                moving = np.any(S != 0.0, axis=1) | (u_pred != u0)
                J = self._jacobian(moving)
                try:
                    dF = np.linalg.solve(np.eye(len(self.f)) - J @ S, J @ (u_pred - u0))
                except np.linalg.LinAlgError:
                    raise RuntimeError(f"t={t:g}: the linearly implicit system I - J S is "
                                       "singular") from None
                for d in self.dynamic:                               # corrector
                    if d.name not in states:
                        continue
                    t0 = perf()
                    self._step_dynamic(d, states[d.name], t, h, F0, F0 + dF, values_of)
                    self._u_of(d, u_new)
                    busy[d.name] += perf() - t0
                defect = np.abs(J @ (u_new - u_pred - S @ dF)).max(initial=0.0)
                tol = self.sim.sensitivity_rtol * np.abs(dF).max(initial=0.0)
                if fresh or defect <= tol + 1e-12 * (np.abs(F0).max(initial=0.0) + 1.0):
                    break
                self.S = self._sensitivity(states, t, h, F0, u_pred, values_of)
                fresh = True
        finally:
            for d in self.dynamic:
                if d.name in states:
                    d.fmu.freeFMUstate(states[d.name])
