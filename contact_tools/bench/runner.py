"""The benchmark pipeline: cases → reference → timings and results → statistics → table and plot."""
from __future__ import annotations

import datetime
import math
import os
import platform
import shutil
import time
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from . import report
from .cases import Case, describe, load_spec, make_cases
from .reference import (REFERENCE_GRIDS, TOL_FORCE, TOL_MOMENT, Reference, compute_references,
                        convergence_by_ratio)
from .settings import Setting, check_unique, default_settings
from .timing import time_fmu, time_inprocess

NAME = "accuracy_vs_time"
REPEATS = {"short": 3, "full": 5, "smoke": 2}


@dataclass
class BenchResult:
    cases: list[Case]
    refs: list[Reference]
    settings: list[Setting]
    stats: list[report.SettingStats]
    results: dict[str, np.ndarray]
    t_in: dict[str, np.ndarray]
    t_fmu: dict[str, np.ndarray] | None
    convergence: list[dict[str, Any]]
    markdown: str
    paths: dict[str, Path] = field(default_factory=dict)
    runtime: float = 0.0


def _machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} logical CPUs, Python {platform.python_version()}, "
            f"numpy {np.__version__}, {platform.system()}")


def run(form: str = "short", *, cases: Sequence[Case] | None = None,
        settings: Sequence[Setting] | None = None, extra_settings: Sequence[Setting] = (),
        ref_grids: Sequence[int] | None = None, jobs: int = 1, executor: Executor | None = None,
        scheduler: str | None = None, fmu: bool = True, repeats: int | None = None,
        out: str | Path | None = "out", docs: str | Path | None = None,
        build_dir: str | Path = "build/bench_fmu", tol_force: float = TOL_FORCE,
        tol_moment: float = TOL_MOMENT, progress: bool = True,
        log: Callable[[str], Any] = print, cli: str = "",
        reference_cache: str | Path | None = None, falling: bool | None = None) -> BenchResult:
    """Run the benchmark and write ``out/accuracy_vs_time.{md,png}`` (and copies in ``docs``).

    ``cases``/``settings`` default to the ``form``'s (``short``, ``full``, ``smoke``);
    ``extra_settings`` are appended (e.g. a perturbed copy of a method, see :class:`Setting`).
    ``jobs``/``scheduler``/``executor``: parallelism of the reference sweep (see
    :func:`~contact_tools.bench.reference.compute_references`), ``reference_cache`` the folder
    where its grid solutions are kept between runs (None: not kept). ``out=None``: write nothing.
    ``falling``: append the falling-friction section (:mod:`contact_tools.bench_falling`; None:
    except in the smoke form).
    """
    t_start = time.perf_counter()
    spec = load_spec()
    cases = list(make_cases(form, spec) if cases is None else cases)
    settings = list(default_settings(form) if settings is None else settings) + list(extra_settings)
    check_unique(settings)
    grids = tuple(ref_grids or REFERENCE_GRIDS[form])
    repeats = repeats or REPEATS.get(form, 3)
    log(f"case set '{form}': {describe(cases)}")
    log(f"settings: {len(settings)} ({', '.join(s.label for s in settings)})")

    t0 = time.perf_counter()
    refs = compute_references(cases, grids, executor=executor, jobs=jobs, scheduler=scheduler,
                              tol_force=tol_force, tol_moment=tol_moment, progress=progress,
                              cache=reference_cache)
    conv = convergence_by_ratio(cases, refs)
    log(f"reference: exact on grids {', '.join(f'{m}x{m}' for m in grids)}, "
        f"{time.perf_counter() - t0:.0f} s wall with jobs={jobs if executor is None else 'executor'}")
    log("reference convergence per a/b (% of muN for F, of muN*c for Mz; u = 95 % half-width "
        "of the extrapolation, d = |finest grid - reference|):")
    for r in conv:
        log(f"  a/b={r['a_over_b']:<4g} {r['converged']:>3}/{r['n']:<3} converged  "
            f"u_F med/max {r['uF_median']:.3f}/{r['uF_max']:.3f}  "
            f"u_M {r['uM_median']:.3f}/{r['uM_max']:.3f}  "
            f"d_F {r['dF_median']:.3f}/{r['dF_max']:.3f}  d_M {r['dM_median']:.3f}/{r['dM_max']:.3f}")
    bad = [(c, r) for c, r in zip(cases, refs) if not r.converged]
    if bad:
        log(f"  {len(bad)} case(s) with a non-converged reference, excluded from the statistics:")
        for c, r in bad:
            log(f"    case {c.id} (a/b={c.a_over_b:g}, {c.kind}, tau={c.tau:.3g}): {r.reason}")

    t0 = time.perf_counter()
    t_in, results = time_inprocess(settings, cases, repeats=repeats, progress=progress)
    log(f"in-process timing: {time.perf_counter() - t0:.0f} s")
    t_fmu = None
    agreement = None
    if fmu:
        t0 = time.perf_counter()
        t_fmu, outputs = time_fmu(settings, cases, build_dir, repeats=repeats, progress=progress)
        agreement = {}
        for lab, o in outputs.items():
            d = [math.hypot(o[j, 0] - results[lab][j, 0], o[j, 1] - results[lab][j, 1])
                 / (c.mu * c.N) for j, c in enumerate(cases)]
            agreement[lab] = float(np.max(d))
        log(f"FMU timing: {time.perf_counter() - t0:.0f} s; largest FMU - in-process force "
            f"difference {100 * max(agreement.values()):.2g} % of muN")

    stats = report.statistics(settings, cases, refs, results, t_in, t_fmu)
    runtime = time.perf_counter() - t_start
    meta = {"form": form, "date": datetime.date.today().isoformat(), "machine": _machine(),
            "runtime": runtime, "cases_desc": describe(cases), "seed": spec["seed"],
            "tol_force": tol_force, "tol_moment": tol_moment, "repeats": repeats, "fmu": fmu,
            "regimes": spec["regimes"], "cli": cli,
            "not_converged": {s.label: int((results[s.label][:, 3] == 0).sum())
                              for s in settings}}
    md = report.markdown(stats=stats, cases=cases, refs=refs, conv=conv, meta=meta,
                         fmu_agreement=agreement, png_name=f"{NAME}.png",
                         by_kind=report.kind_table(settings, cases, refs, results))
    if falling is None:
        falling = form != "smoke"
    if falling:
        from ..bench_falling import section
        t0 = time.perf_counter()
        md += "\n" + section()
        log(f"falling friction section: {time.perf_counter() - t0:.0f} s")
    res = BenchResult(cases, refs, settings, stats, results, t_in, t_fmu, conv, md,
                      runtime=runtime)
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        res.paths["md"] = out / f"{NAME}.md"
        res.paths["png"] = out / f"{NAME}.png"
        res.paths["md"].write_text(md, encoding="utf-8")
        report.plot(stats, settings, res.paths["png"],
                    title=f"{len(cases)} cases ({form}), reference: exact extrapolated from "
                          f"{grids[0]}..{grids[-1]}² grids; filled: in-process, hollow: FMU step")
        if docs is not None:
            docs = Path(docs)
            docs.mkdir(parents=True, exist_ok=True)
            for k in ("md", "png"):
                shutil.copyfile(res.paths[k], docs / res.paths[k].name)
                res.paths[f"docs_{k}"] = docs / res.paths[k].name
    log("\n" + report.summary_table(stats))
    log(f"Pareto-optimal: {', '.join(report.pareto(stats))}")
    log(f"total {runtime:.0f} s" + (f"; wrote {', '.join(str(p) for p in res.paths.values())}"
                                    if res.paths else ""))
    return res
