"""The converged reference: the exact solver on a sequence of fine grids, extrapolated to h → 0.

Per case the exact solver (:mod:`contact_core.exact`, ``normal="numerical"``, default tolerance,
one grid each: ``extrapolate=False``) runs on square element counts ``m × m`` for every ``m`` of
``grids`` (short form 40, 48, 64, 80; full form 40, 48, 64, 80, 96). Its discretisation error is
first order in the element size, q(m) ≈ q∞ + C/m, overlaid with an irregular part of about
0.05–0.2 % of μN where the stick/slip boundary crosses elements (spin cases mostly). Grids of
32 and below are not yet in that range (slopes about half: docs/notes/benchmark.md), so the
grids start at 40. Per case and per quantity q ∈ {Fx, Fy, Mz}:

* **reference** q∞: least-squares fit of q(m) = q∞ + C/m over the grids (Richardson
  extrapolation with p = 1; a least-squares fit over a wide range of m rather than the two-grid
  formula, which amplifies the irregular part: 4 q₆₄ - 3 q₄₈ multiplies it by 5); the force is
  the vector (Fx∞, Fy∞), so that its direction is a reference too (an error of a method's
  direction at the right magnitude shows);
* **uncertainty** u: 95 % confidence half-width of q∞, Student t times its standard error, with
  the scatter about the fit pooled over the cases of the same a/b and kind (a case's own scatter
  if larger): with four grids a single case has two degrees of freedom only; the force's
  u_F = √(u_Fx² + u_Fy²) from its components' (on the safe side for the vector);
* **two-grid check** d: |q(finest) - q∞| (the force's: of the vector), how far the finest grid
  alone is from the reference;
* **converged** if every grid's exact solve converged, u_F <= ``tol_force`` (default 0.5 % of
  μN) and u_M <= ``tol_moment`` (default 0.5 % of μN·c, c = √(ab)). Cases that fail are listed
  and excluded from the statistics, never silently used.

Work is split into (case, grid) tasks submitted to any ``concurrent.futures.Executor``-like object
(``submit`` returning futures usable with ``concurrent.futures.as_completed``): by default a Dask
``distributed`` LocalCluster of ``jobs`` processes, or an existing Dask cluster (``scheduler``)
for sweeps that outgrow one machine (:mod:`contact_tools.sweep`). Progress is shown with tqdm.

The grid solutions may be kept in a folder (``cache``; the command line's default is
``build/bench_reference``) as a numpy file (no pickle), named by a digest of the cases, the grids
and the source of the exact solver, of what it uses, of the solve task (:func:`_solve_exact`)
and of the file's reader and writer: a rerun with the same cases and solver reuses them, any
change of either computes them anew.
"""
from __future__ import annotations

import hashlib
import inspect
import json
import math
import os
import time
import warnings
from concurrent.futures import Executor, Future, as_completed
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import numpy as np
from scipy import stats

import contact_core
from contact_core import api

from .. import sweep
from .cases import Case

#: Reference grids (m × m elements) per form of the benchmark.
REFERENCE_GRIDS: dict[str, tuple[int, ...]] = {
    "short": (40, 48, 64, 80),
    "full": (40, 48, 64, 80, 96),
    "smoke": (16, 20, 24, 32),
}
TOL_FORCE = 0.005     # of μN
TOL_MOMENT = 0.005    # of μN·c


@dataclass(frozen=True)
class Reference:
    """The reference of one case. ``Fx``, ``Fy`` in N, ``Mz`` in N·m (Kalker's sign convention);
    ``u_*`` and ``d_*`` (see the module docstring) normalised by μN (force) and μN·c (moment)."""

    case_id: int
    Fx: float
    Fy: float
    Mz: float
    u_F: float
    u_M: float
    d_F: float
    d_M: float
    grids: tuple[int, ...]
    F_grid: tuple[float, ...]        # |F| per grid, N
    Mz_grid: tuple[float, ...]       # Mz per grid, N·m
    solver_converged: bool
    converged: bool
    reason: str                      # why not converged ("" if converged)
    seconds: float                   # CPU time of all grids of this case

    @property
    def F(self) -> float:
        """|F| = √(Fx² + Fy²) in N."""
        return math.hypot(self.Fx, self.Fy)


def _solve_exact(kwargs: dict[str, float], m: int) -> tuple[float, float, float, bool, float]:
    """One exact solve on an m × m grid (runs in a worker process)."""
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # non-convergence is returned in ``converged``
        r = api.solve("exact", **kwargs, mx=m, my=m, extrapolate=False)
    return r.Fx, r.Fy, r.Mz, bool(r.converged), time.perf_counter() - t0


class _Inline(Executor):
    """An executor that runs each task when submitted (jobs=1; no processes)."""

    def submit(self, fn, /, *args, **kwargs):
        f: Future = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except BaseException as e:  # noqa: BLE001 - handed to the caller through the future
            f.set_exception(e)
        return f


def fit_extrapolation(m: Sequence[int], q: Sequence[float]) -> tuple[float, float, float]:
    """(q∞, residual sum of squares, v00) of the least-squares fit q(m) = q∞ + C/m;
    ``v00`` = [(XᵀX)⁻¹]₀₀, so that the standard error of q∞ is √(s² v00)."""
    x = 1.0 / np.asarray(m, dtype=float)
    y = np.asarray(q, dtype=float)
    X = np.column_stack([np.ones(len(x)), x])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    res = y - X @ coef
    return float(coef[0]), float(res @ res), float(np.linalg.inv(X.T @ X)[0, 0])


def _build(cases: Sequence[Case], grids: tuple[int, ...], sols: Sequence[dict[int, tuple]],
           tol_force: float, tol_moment: float) -> list[Reference]:
    dof1 = len(grids) - 2
    # per case and quantity (Fx, Fy over μN, Mz over μN·c): the fit (q∞, rss, v00)
    fits = []
    for c, sol in zip(cases, sols):
        scale = (c.mu * c.N, c.mu * c.N, c.mu * c.N * c.c)
        fits.append([fit_extrapolation(grids, [sol[m][k] / scale[k] for m in grids])
                     for k in range(3)])
    # scatter pooled per (a/b, kind) and quantity
    pool: dict[tuple, list[float]] = {}
    for c, fit in zip(cases, fits):
        acc = pool.setdefault((c.a_over_b, c.kind), [0.0, 0.0, 0.0, 0])
        for k in range(3):
            acc[k] += fit[k][1]
        acc[3] += dof1
    out = []
    for c, sol, fit in zip(cases, sols, fits):
        *rss, dof = pool[(c.a_over_b, c.kind)]
        t = float(stats.t.ppf(0.975, dof)) if dof > 0 else math.nan
        u = [t * math.sqrt(max(rss[k] / dof, fit[k][1] / dof1) * fit[k][2]) if dof > 0
             else math.nan for k in range(3)]
        (fx, _, _), (fy, _, _), (mz, _, _) = fit
        finest = sol[grids[-1]]
        fs, ms = c.mu * c.N, c.mu * c.N * c.c
        uF, uM = math.hypot(u[0], u[1]), u[2]
        dF = math.hypot(finest[0] / fs - fx, finest[1] / fs - fy)
        dM = abs(finest[2] / ms - mz)
        solver_ok = all(sol[m][3] for m in grids)
        reasons = []
        if not solver_ok:
            bad = [m for m in grids if not sol[m][3]]
            reasons.append(f"exact solver not converged on grid(s) {bad}")
        if not uF <= tol_force:   # also catches NaN
            reasons.append(f"F uncertainty {100 * uF:.2f} % of μN > {100 * tol_force:.2g} %")
        if not uM <= tol_moment:
            reasons.append(f"Mz uncertainty {100 * uM:.2f} % of μN·c > {100 * tol_moment:.2g} %")
        out.append(Reference(c.id, fx * fs, fy * fs, mz * ms, uF, uM, dF, dM, tuple(grids),
                             tuple(math.hypot(sol[m][0], sol[m][1]) for m in grids),
                             tuple(sol[m][2] for m in grids), solver_ok, not reasons,
                             "; ".join(reasons), sum(sol[m][4] for m in grids)))
    return out


def grid_solutions(kwargs: Sequence[dict[str, float]], grids: Sequence[int], *,
                   executor: Executor | None = None, jobs: int = 1, scheduler: str | None = None,
                   progress: bool = True, solve_task: Callable[..., tuple] = _solve_exact
                   ) -> list[dict[int, tuple]]:
    """``solve_task(kwargs[i], m)`` for every state and grid m, as ``out[i][m]``.

    ``executor``: any object with ``submit`` whose futures work with
    ``concurrent.futures.as_completed``; if None, Dask (:func:`contact_tools.sweep.executor`: a
    LocalCluster of ``jobs`` processes, or the cluster at ``scheduler``) when ``jobs > 1`` or a
    scheduler is given, else the tasks run inline. Also the held-out check of the table
    (:mod:`contact_tools.table.check`).
    """
    from tqdm.auto import tqdm

    with ExitStack() as stack:
        if executor is None:
            executor = (stack.enter_context(sweep.executor(scheduler, jobs))
                        if jobs > 1 or scheduler is not None else _Inline())
        # Dearest tasks first (finest grids): better load balance at the end of the sweep.
        futures = {executor.submit(solve_task, kwargs[i], m): (i, m)
                   for m in sorted(grids, reverse=True) for i in range(len(kwargs))}
        sols: list[dict[int, tuple]] = [{} for _ in kwargs]
        with tqdm(total=len(futures), desc="reference (exact, fine grids)", unit="solve",
                  disable=not progress, leave=False) as bar:
            for fut in as_completed(futures):
                i, m = futures[fut]
                sols[i][m] = fut.result()
                bar.update()
    return sols


def compute_references(cases: Sequence[Case], grids: Iterable[int] = REFERENCE_GRIDS["short"], *,
                       executor: Executor | None = None, jobs: int = 1,
                       scheduler: str | None = None, tol_force: float = TOL_FORCE,
                       tol_moment: float = TOL_MOMENT, progress: bool = True,
                       solve_task: Callable[..., tuple] = _solve_exact,
                       cache: str | Path | None = None) -> list[Reference]:
    """The reference of every case (same order as ``cases``); see the module docstring.
    ``executor``, ``jobs``, ``scheduler``: where the solves run (:func:`grid_solutions`);
    ``cache``: folder of kept grid solutions (module docstring; the default solve task only)."""
    grids = tuple(sorted(set(int(m) for m in grids)))
    if len(grids) < 3:
        raise ValueError(f"grids={grids}: need at least 3 grids for the extrapolation and its "
                         "uncertainty")
    kwargs = [c.solve_kwargs() for c in cases]
    if cache is not None and solve_task is _solve_exact:
        sols = kept_grid_solutions(kwargs, grids, cache, executor=executor, jobs=jobs,
                                   scheduler=scheduler, progress=progress)
    else:
        sols = grid_solutions(kwargs, grids, executor=executor, jobs=jobs, scheduler=scheduler,
                              progress=progress, solve_task=solve_task)
    return _build(cases, grids, sols, tol_force, tol_moment)


def kept_grid_solutions(kwargs: Sequence[dict[str, float]], grids: Sequence[int],
                        cache: str | Path, **where: Any) -> list[dict[int, tuple]]:
    """:func:`grid_solutions` of the exact solver, kept in the folder ``cache`` (module
    docstring): read from there when the states, the grids and the solver's source are the ones
    they were computed with, else computed (``where``: ``executor``, ``jobs``, ``scheduler``,
    ``progress`` of :func:`grid_solutions`) and written there. Also the held-out check's
    references (:mod:`contact_tools.table.check`)."""
    grids = tuple(sorted(set(int(m) for m in grids)))
    kwargs = list(kwargs)
    kept = _cache_file(Path(cache), kwargs, grids)
    sols = _load_solutions(kept, len(kwargs), grids)
    if sols is None:
        sols = grid_solutions(kwargs, grids, **where)
        _save_solutions(kept, sols, grids)
    return sols


#: Sources the reference depends on (relative to ``contact_core``): the exact solver and what it
#: uses; of this module only the solve task and the kept file's layout (``_KEPT_CODE``: its
#: other text, e.g. a docstring, does not change a grid solution and does not throw the kept
#: ones away).
_SOURCES = ("exact", "base.py", "hertz.py", "material.py", "coefficients.py", "result.py",
            "api.py")


def _cache_file(folder: Path, kwargs: list[dict[str, float]], grids: tuple[int, ...]) -> Path:
    root = Path(contact_core.__file__).resolve().parent
    code = hashlib.sha256()
    for name in _SOURCES:
        path = root / name
        for f in sorted(path.glob("*.py")) if path.is_dir() else [path]:
            code.update(f.read_bytes())
    for fn in _KEPT_CODE:
        code.update(inspect.getsource(fn).encode())
    key = json.dumps({"grids": grids, "cases": kwargs, "code": code.hexdigest()}, sort_keys=True)
    return folder / f"reference_{hashlib.sha256(key.encode()).hexdigest()[:16]}.npz"


def _load_solutions(path: Path, n: int, grids: tuple[int, ...]) -> list[dict[int, tuple]] | None:
    """The kept (Fx, Fy, Mz, converged, seconds) per case and grid, or None if there are none
    of this shape."""
    if not path.is_file():
        return None
    with np.load(path, allow_pickle=False) as z:
        arr = z["solutions"]
    if arr.shape != (n, len(grids), 5) or not np.isfinite(arr[:, :, 3:]).all():
        return None
    return [{m: (float(row[0]), float(row[1]), float(row[2]), bool(row[3]), float(row[4]))
             for m, row in zip(grids, per_case)} for per_case in arr]


def _save_solutions(path: Path, sols: list[dict[int, tuple]], grids: tuple[int, ...]) -> None:
    arr = np.array([[[float(v) for v in sol[m]] for m in grids] for sol in sols])
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".part.npz")
    np.savez(tmp, solutions=arr)
    os.replace(tmp, path)


_KEPT_CODE = (_solve_exact, _load_solutions, _save_solutions)


def convergence_by_ratio(cases: Sequence[Case], refs: Sequence[Reference]) -> list[dict[str, Any]]:
    """Per a/b: counts, uncertainty and two-grid-check statistics (in % of μN or μN·c), and the
    exact-solver seconds spent."""
    out = []
    for ab in sorted({c.a_over_b for c in cases}):
        idx = [i for i, c in enumerate(cases) if c.a_over_b == ab]
        rs = [refs[i] for i in idx]
        uF = np.array([r.u_F for r in rs]) * 100
        uM = np.array([r.u_M for r in rs]) * 100
        dF = np.array([r.d_F for r in rs]) * 100
        dM = np.array([r.d_M for r in rs]) * 100
        out.append({
            "a_over_b": ab, "n": len(rs), "converged": sum(r.converged for r in rs),
            "uF_median": float(np.median(uF)), "uF_max": float(uF.max()),
            "uM_median": float(np.median(uM)), "uM_max": float(uM.max()),
            "dF_median": float(np.median(dF)), "dF_max": float(dF.max()),
            "dM_median": float(np.median(dM)), "dM_max": float(dM.max()),
            "seconds": float(sum(r.seconds for r in rs)),
        })
    return out
