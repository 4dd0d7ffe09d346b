"""Building the table: independent exact solves on Dask, resumable, reproducible.

``python -m contact_tools.table build [--axes full|small] [--grid M] [--fine-grid M2]
[--fine-below A] [--fine-above A] [--wide-above A] [--tol T] [--tol-sliding T]
[--ghost-below 0|1]
[--scheduler ADDRESS] [--workers N] [--work DIR] [--reuse DIR ...] [--out DIR]``

One task per ray: a node (a/b, ν, θ, ψ) of the table and all its magnitudes s, solved in order
of increasing s, each exact solve warm-started from the previous one (neighbouring nodes are then
a few sweeps each). The exact solver runs at ``M × M`` with ``extrapolate=True`` (grid-
extrapolated, :mod:`contact_core.exact`), at ``M2 × M2`` for the nodes outside ``FINE_INSIDE``,
at ``2M × M`` above ``--wide-above`` (``WIDE_ABOVE``).
On the pure-spin poles (θ = 0, π) ψ has no meaning: one ray is solved and copied.
``--ghost-below 1`` adds a row of nodes one step of ln(a/b) below the table's range, read only
by the interpolation of the first interval (``grid.Axes``); the rows inside are the same rays as
without it (reused).

Tasks run on a Dask ``distributed`` cluster: a ``LocalCluster`` of ``--workers`` processes
(default: every core) or the existing cluster at ``--scheduler``. Every finished ray is saved at
once to the work folder (``--work``, default ``build/table_work/<digest of the configuration>``)
as a numpy file, so an interrupted build resumes where it stopped; a progress bar counts rays.
``--reuse`` takes the finished rays of other builds' work folders, or of finished tables (e.g.
``contact_core/data``: a build in a fresh clone, where no work folder is left, starts from the
shipped table), whose node and exact setting are the same as one of this build's, e.g. when an
axis is refined from n to 2n - 1 nodes or one row is solved again on another grid; like a
resumed build, it assumes those rays were solved by the same exact-solver code.
When every ray is there the table is assembled and written to ``--out`` (default
``contact_core/data``) with its metadata (:mod:`contact_core.table.data`): the command, the
configuration, its digest, the build's wall time and the SHA-256 of the values. Nothing in the
build is random: the same configuration gives the same table.

Wall time across sessions: every run that solves or reuses rays appends its start time to
``sessions.jsonl`` in the work folder, and every ray file's modification time is when it was
saved. A session lasted from its start to the last ray saved before the next session's start (a
run stopped from outside leaves no end of its own); the table's metadata gives each session's
time and rays and their sum, ``wall_seconds`` (rays saved before the first recorded session, by
older code, are counted as ``rays_untimed``).
"""
from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import sys
import time
import warnings
from dataclasses import replace
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from contact_core.api import make_solver
from contact_core.coefficients import creep_coefficients
from contact_core.exact import Exact
from contact_core.table import data
from contact_core.table.grid import (Axes, creepages_from_reduced, node_magnitude,
                                     node_reduced_creepage)

from ..sweep import executor

#: Axes of the shipped table and of a quick build (tests of the pipeline, trials).
AXES = {"full": Axes(ghost_below=1), "small": Axes(n_ab=4, n_theta=7, n_psi=4, n_s=8)}
#: The exact solver of the build: M × M elements, extrapolated (module docstring), and the finer
#: grid of the nodes with a/b outside ``FINE_INSIDE``, the low end of the axis, where the square
#: grid's elements are most elongated and 48×48 is biased in Mz (64×64, whose half grid of 32 is
#: short of the first-order range, is worse there). The upper bound is None (``--fine-above``):
#: the large a/b take the wide grid below instead, at a fraction of the cost. Why these grids,
#: and what each row took the held-out errors from and to: docs/notes/table_build.md.
DEFAULT_GRID, DEFAULT_FINE_GRID, FINE_INSIDE = 48, 80, (0.6, None)
#: ``--wide-above A``: inside ``FINE_INSIDE`` and above a/b = A the nodes are solved on 2M × M
#: elements: along the rolling direction, where the contact is long, the square grid's elements
#: are a/b times as long as wide, and its two-grid extrapolation scatters there (the spin band of
#: ``check``). Default 4: the shipped table's design, the rows a/b = 5.6 and 10 on 96×48 (other
#: shapes tried, and the cost: docs/notes/table_build.md).
WIDE_ABOVE: float | None = 4.0
# The ghost row of a/b (``--ghost-below``, ``grid.Axes``) is solved like the rows next to it
# (80×80 below ``FINE_INSIDE``), although its weight in the first interval's cubic is at most
# 0.064: 48×48 there is biased in Mz. ``--tol``: the exact solver's tolerance at the nodes
# (``config``); rays of different tolerances are not reused for one another. A looser tolerance
# than the exact method's default (1e-5) changes the nodes by a small fraction of the table's
# 1 % target at about half the build time (the trials: docs/notes/table_build.md).
#: ``--tol-sliding``: the tolerance once the ray's previous node slides on at least this fraction
#: of the contact area. Full sliding is where a loose tolerance stops early (the slip direction
#: converges slowly) and where its nodes cost least (docs/notes/table_build.md).
SLIDING = 0.9
#: ``--tol`` and ``--tol-sliding`` by default: the shipped table's (the comments above).
DEFAULT_TOL, DEFAULT_TOL_SLIDING = 5e-4, 1e-4
#: The exact solver's ``spin_shift`` of a table whose configuration does not name one: 1/4, the
#: solver's fixed sampling before it became an option (default now 1/6, CONTACT's). Every table so
#: far was built with it. The nodes are extrapolated solves, where the shift's first-order term
#: cancels (docs/notes/exact_solver.md).
SPIN_SHIFT = 0.25
# The canonical problem every node is solved in (similarity: any values would do): c = √(ab),
# G, μ, and N = G c² so that G c²/(μN) = 1 and the reduced creepages are C·(ξ, η, c φ).
_C, _G, _MU = 1e-2, 8e10, 1.0


def solve_ray(a_over_b: float, nu: float, theta: float, psi: float, s_nodes: list[float],
              options: dict[str, Any], spin_weight: float) -> np.ndarray:
    """The node values (n_s, 4) of one ray (runs in a worker; see
    :mod:`contact_core.table.data`); ``options``: the exact solver's (:func:`node_options`;
    ``tol_sliding``: its tolerance at the nodes after one whose slip fraction is at least
    ``SLIDING``), ``spin_weight``: w(a/b) of the axes (:mod:`contact_core.table.grid`)."""
    b = _C / math.sqrt(a_over_b)
    a = a_over_b * b
    N = _G * _C * _C / _MU
    c11, c22, c23, _ = creep_coefficients(a_over_b, nu)
    options = dict(options)
    tol_sliding = options.pop("tol_sliding", None)
    solver = make_solver("exact", **options)
    sliding = solver if tol_sliding is None else make_solver("exact", **{**options,
                                                                        "tol": tol_sliding})
    out = np.empty((len(s_nodes), data.N_VALUES))
    prev = None
    for k, s in enumerate(s_nodes):
        u = node_reduced_creepage(theta, psi, s, spin_weight)
        xi, eta, phi = creepages_from_reduced(u, c11, c22, c23, _C, 1.0)
        step = sliding.step if prev is not None and prev.slip_fraction >= SLIDING else solver.step
        with warnings.catch_warnings():
            warnings.simplefilter("error")          # a non-converged solve fails the build
            r = step(xi, eta, phi, N, _MU, a, b, _G, nu, warm_start=prev)
        prev = r
        r_node = node_magnitude(s)
        sk = s if 0.0 < s < 1.0 else r_node / (1.0 + r_node)
        out[k] = (r.Fx / (_MU * N) / sk, r.Fy / (_MU * N) / sk, r.Mz / (_MU * N * _C) / sk,
                  r.slip_fraction)
    return out


def rays(axes: Axes) -> list[tuple[int, int, int, int]]:
    """Index (a/b, ν, θ, ψ) of every ray to solve (ψ = 0 only at the poles θ = 0, π)."""
    out = []
    for ia in range(axes.shape[0]):
        for inu in range(axes.n_nu):
            for it in range(axes.n_theta):
                pole = it in (0, axes.n_theta - 1)
                for ip in range(1 if pole else axes.n_psi):
                    out.append((ia, inu, it, ip))
    return out


def config(axes: Axes, grid: int, fine_grid: int | None = None,
           coarse: tuple[float, float | None] = FINE_INSIDE,
           wide_above: float | None = None, tol: float | None = None,
           tol_sliding: float | None = None) -> dict[str, Any]:
    """The build's configuration (recorded in the table): ``coarse``, the a/b range of the
    ``grid`` nodes, outside it ``fine_grid`` (``FINE_INSIDE``); inside it above ``wide_above``
    2·grid × grid (``WIDE_ABOVE``; None: none); ``tol``: the exact solver's tolerance (None: its
    default, recorded as absent, as in the tables built before the option; the comment above
    ``SLIDING``), ``tol_sliding``: the tolerance after a node whose slip fraction reached
    ``SLIDING`` (None: ``tol`` everywhere, recorded as absent)."""
    fine = grid if fine_grid is None else fine_grid
    wide = {} if wide_above is None else {"wide_above": wide_above, "wide_mx": 2 * grid,
                                           "wide_my": grid}
    tolerance = {} if tol is None else {"tol": tol}
    if tol_sliding is not None:
        tolerance.update(tol_sliding=tol_sliding, sliding_from=SLIDING)
    return {"axes": axes.to_record(),
            "exact": {"mx": grid, "my": grid, "extrapolate": True,
                      "coarse_a_over_b": list(coarse), "fine_mx": fine, "fine_my": fine, **wide,
                      **tolerance},
            "canonical": {"c": _C, "G": _G, "mu": _MU}, "format_version": data.FORMAT_VERSION}


def node_options(exact: dict[str, Any], a_over_b: float) -> dict[str, Any]:
    """The exact solver's options of the nodes at ``a_over_b`` (``exact``: the table's
    ``config["exact"]``), the ghost row's too (the comment above ``_C``)."""
    lo, hi = exact["coarse_a_over_b"]
    kind = ("fine_" if a_over_b < lo or (hi is not None and a_over_b > hi)
            else "wide_" if a_over_b > exact.get("wide_above", math.inf) else "")
    out = {"mx": exact[kind + "mx"], "my": exact[kind + "my"], "extrapolate": exact["extrapolate"],
           "spin_shift": exact.get("spin_shift", SPIN_SHIFT)}
    if "tol" in exact:
        out["tol"] = exact["tol"]
    if "tol_sliding" in exact:
        if exact["sliding_from"] != SLIDING:
            raise ValueError(f"sliding_from={exact['sliding_from']!r}: this code switches the "
                             f"tolerance at a slip fraction of {SLIDING}")
        out["tol_sliding"] = exact["tol_sliding"]
    return out


def digest(cfg: dict[str, Any]) -> str:
    return hashlib.sha256(json.dumps(cfg, sort_keys=True).encode()).hexdigest()[:16]


def build(axes: Axes, grid: int, work: Path, out: Path, scheduler: str | None = None,
          workers: int | None = None, progress: bool = True, command: str = "",
          fine_grid: int | None = None,
          coarse: tuple[float, float | None] = FINE_INSIDE, reuse: Sequence[Path] = (),
          wide_above: float | None = None, tol: float | None = None,
          tol_sliding: float | None = None) -> Path:
    """Solve the missing rays on Dask, then assemble and write the table (module docstring);
    ``reuse``: work folders of other builds (:func:`reuse_rays`)."""
    from concurrent.futures import as_completed

    from tqdm.auto import tqdm

    cfg = config(axes, grid, fine_grid, coarse, wide_above, tol, tol_sliding)
    work.mkdir(parents=True, exist_ok=True)
    (work / "config.json").write_text(json.dumps(cfg, indent=1) + "\n", encoding="utf-8")
    ab, nu, th, ps, s = axes.a_over_b(), axes.nu(), axes.theta(), axes.psi(), axes.s()
    start = time.time()
    reused = sum(reuse_rays(folder, axes, cfg, work) for folder in reuse)
    all_rays = rays(axes)
    todo = [r for r in all_rays if not _ray_file(work, r).is_file()]
    if todo or reused:
        with (work / SESSIONS).open("a", encoding="utf-8") as f:
            f.write(json.dumps({"start": start, "rays_reused": reused,
                                "rays_missing": len(todo)}) + "\n")
    if todo:
        with executor(scheduler, workers) as ex:
            futures = {ex.submit(solve_ray, float(ab[r[0]]), float(nu[r[1]]), float(th[r[2]]),
                                 float(ps[r[3]]), [float(v) for v in s],
                                 node_options(cfg["exact"], float(ab[r[0]])),
                                 axes.spin_weight(float(ab[r[0]]))): r for r in todo}
            with tqdm(total=len(all_rays), initial=len(all_rays) - len(todo),
                      desc="table (exact rays)", unit="ray", disable=not progress) as bar:
                for fut in as_completed(futures):
                    _save_ray(_ray_file(work, futures[fut]), fut.result())
                    bar.update()
    values = np.empty(axes.shape + (data.N_VALUES,))
    for ia, inu, it, ip in all_rays:
        v = np.load(_ray_file(work, (ia, inu, it, ip)), allow_pickle=False)
        if it in (0, axes.n_theta - 1):
            values[ia, inu, it, :] = v
        else:
            values[ia, inu, it, ip] = v
    meta = {"command": command, "config": cfg, "config_digest": digest(cfg),
            "rays": len(all_rays), **wall_time(work, all_rays),
            "built": time.strftime("%Y-%m-%d")}
    return data.write(values, axes, meta, out)


def wall_time(work: Path, all_rays: Sequence[tuple[int, int, int, int]]) -> dict[str, Any]:
    """The build's wall time over its sessions (module docstring): ``wall_seconds``, ``sessions``
    (start in UTC, seconds, rays solved and reused) and ``rays_untimed``; a session that saved
    no ray counts 0 s."""
    path = work / SESSIONS
    records = sorted((json.loads(line) for line in
                      path.read_text(encoding="utf-8").splitlines() if line.strip()),
                     key=lambda x: x["start"]) if path.is_file() else []
    saved = np.sort([_ray_file(work, r).stat().st_mtime for r in all_rays])
    sessions = []
    for i, rec in enumerate(records):
        stop = records[i + 1]["start"] if i + 1 < len(records) else math.inf
        mine = saved[(saved >= rec["start"]) & (saved < stop)]
        end = float(mine[-1]) if mine.size else rec["start"]
        sessions.append({"start": time.strftime("%Y-%m-%d %H:%M:%S UTC",
                                                time.gmtime(rec["start"])),
                         "seconds": round(end - rec["start"], 1),
                         "rays_solved": int(mine.size) - rec["rays_reused"],
                         "rays_reused": rec["rays_reused"]})
    untimed = int(np.count_nonzero(saved < records[0]["start"])) if records else int(saved.size)
    return {"wall_seconds": round(sum(x["seconds"] for x in sessions), 1),
            "sessions": sessions, "rays_untimed": untimed}


def _ray_keys(cfg: dict[str, Any], axes: Axes) -> dict[tuple, tuple[int, int, int, int]]:
    """Every ray by what its values depend on: its node, the magnitudes s, the spin weight and the
    exact solver's options (the solver is deterministic; the canonical problem is in ``cfg``)."""
    ab, nu, th, ps = axes.a_over_b(), axes.nu(), axes.theta(), axes.psi()
    common = (tuple(axes.s().tolist()), json.dumps(cfg["canonical"], sort_keys=True),
              cfg["format_version"])
    keys = {}
    for r in rays(axes):
        a = float(ab[r[0]])
        keys[(a, float(nu[r[1]]), float(th[r[2]]), float(ps[r[3]]), axes.spin_weight(a),
              tuple(sorted(node_options(cfg["exact"], a).items()))) + common] = r
    return keys


def reuse_rays(source: Path, axes: Axes, cfg: dict[str, Any], work: Path) -> int:
    """Copy into ``work`` the finished rays of ``source`` that solved one of this build's rays
    (same :func:`_ray_keys` key, node values equal to the bit); returns how many were copied.
    ``source``: another build's work folder, or a finished table's folder (``data.NAME`` .json
    and .npz, checked as :func:`contact_core.table.data.load` checks them), e.g. the package's
    data folder, so that a build in a fresh clone starts from the shipped table. A table holds
    its rays in single precision (``data.DTYPE``): a table written from them has the source's
    values to the bit."""
    if (source / f"{data.NAME}.json").is_file():
        table = data.load(str(source))
        src_cfg = table.meta["config"]

        def ray(r: tuple[int, int, int, int]) -> np.ndarray | None:
            return table.values[r].astype(np.float64)
    else:
        src_cfg = json.loads((source / "config.json").read_text(encoding="utf-8"))

        def ray(r: tuple[int, int, int, int]) -> np.ndarray | None:
            path = _ray_file(source, r)
            return np.load(path, allow_pickle=False) if path.is_file() else None
    wanted = _ray_keys(cfg, axes)
    work.mkdir(parents=True, exist_ok=True)
    copied = 0
    for key, r in _ray_keys(src_cfg, Axes(**src_cfg["axes"])).items():
        target = wanted.get(key)
        if target is None or _ray_file(work, target).is_file():
            continue
        values = ray(r)
        if values is not None:
            _save_ray(_ray_file(work, target), values)
            copied += 1
    return copied


#: Start times of the build's sessions, one JSON object per line (module docstring).
SESSIONS = "sessions.jsonl"


def _ray_file(work: Path, r: tuple[int, int, int, int]) -> Path:
    return work / ("ray_%d_%d_%d_%d.npy" % r)


def _save_ray(path: Path, values: np.ndarray) -> None:
    """Written under another name, then renamed: a build stopped mid-write leaves no partial ray
    that a resumed build would take as finished."""
    tmp = path.with_name(path.stem + ".part.npy")
    np.save(tmp, values, allow_pickle=False)
    os.replace(tmp, path)


def _number(text: str) -> float:
    """``text`` as a float, NaN if it is not a number (every range check below refuses NaN)."""
    try:
        return float(text)
    except ValueError:
        return math.nan


def _bound_or_none(text: str) -> float | None:
    if text.lower() == "none":
        return None
    value = _number(text)
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"{text!r} is invalid: allowed a/b > 0 or 'none'")
    return value


def _tolerance(text: str) -> float:
    value = _number(text)
    if not 1e-12 <= value <= 1e-2:
        raise argparse.ArgumentTypeError(f"{text!r} is invalid: allowed 1e-12 <= tol <= 1e-2")
    return value


def _tolerance_or_none(text: str) -> float | None:
    return None if text.lower() == "none" else _tolerance(text)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    p = argparse.ArgumentParser(
        prog="python -m contact_tools.table",
        description="Build the exact-theory table (method 'table'). Its accuracy on held-out "
        "states: python -m contact_tools.table check --help.")
    sub = p.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("build", help="solve the table's nodes (resumable) and write it")
    b.add_argument("--axes", choices=sorted(AXES), default="full")
    b.add_argument("--grid", type=int, default=DEFAULT_GRID,
                   help=f"exact solver grid, extrapolated (default {DEFAULT_GRID})")
    b.add_argument("--fine-grid", type=int, default=DEFAULT_FINE_GRID,
                   help=f"the grid below --fine-below and above --fine-above (default "
                   f"{DEFAULT_FINE_GRID})")
    b.add_argument("--fine-below", type=_bound_or_none, default=FINE_INSIDE[0],
                   help=f"the fine grid below this a/b (default {FINE_INSIDE[0]}; 'none': "
                   "nowhere below)")
    b.add_argument("--fine-above", type=_bound_or_none, default=FINE_INSIDE[1],
                   help=f"the fine grid above this a/b too (default {FINE_INSIDE[1]}: not at "
                   "large a/b)")
    b.add_argument("--wide-above", type=_bound_or_none, default=WIDE_ABOVE,
                   help=f"2M x M elements above this a/b (default {WIDE_ABOVE}; 'none': square "
                   "grids only)")
    b.add_argument("--tol", type=_tolerance, default=DEFAULT_TOL,
                   help=f"the exact solver's tolerance at the nodes (default {DEFAULT_TOL:g}, the "
                   f"shipped table's; the exact method's own is "
                   f"{Exact.default_options['tol']:g}, see this module)")
    b.add_argument("--tol-sliding", type=_tolerance_or_none, default=DEFAULT_TOL_SLIDING,
                   help=f"the tolerance at the nodes after one whose slip fraction reached "
                   f"{SLIDING} (default {DEFAULT_TOL_SLIDING:g}, the shipped table's; 'none': "
                   "--tol everywhere; see this module)")
    b.add_argument("--ghost-below", type=int, choices=(0, 1), default=None,
                   help="a ghost row of a/b below the table's range, read by the first "
                   "interval's cubic (grid.Axes; default: the axes')")
    b.add_argument("--scheduler", default=None, help="address of a Dask scheduler (default: a "
                   "LocalCluster on this machine)")
    b.add_argument("--workers", type=int, default=None, help="LocalCluster processes")
    b.add_argument("--work", default=None, help="folder of the finished rays (resume)")
    b.add_argument("--reuse", action="append", default=[], metavar="DIR",
                   help="work folder of another build, or folder of a finished table (e.g. "
                   "contact_core/data): its rays at the same nodes and exact setting are taken "
                   "(repeatable)")
    b.add_argument("--out", default=None, help="where to write the table (default: the "
                   "package's data folder)")
    b.add_argument("--no-progress", action="store_true")
    a = p.parse_args(argv)
    axes = AXES[a.axes]
    if a.ghost_below is not None:
        axes = replace(axes, ghost_below=a.ghost_below)
    coarse = (0.0 if a.fine_below is None else a.fine_below, a.fine_above)
    cfg = config(axes, a.grid, a.fine_grid, coarse, a.wide_above, a.tol, a.tol_sliding)
    work = Path(a.work) if a.work else Path("build") / "table_work" / digest(cfg)
    out = Path(a.out) if a.out else data.data_dir()
    # the command that reproduces the table: reused rays are the same values, solved earlier
    kept, skip = [], False
    for x in argv:
        if x == "--reuse":
            skip = True
        elif skip:
            skip = False
        elif not x.startswith("--reuse="):
            kept.append(x)
    path = build(axes, a.grid, work, out, a.scheduler, a.workers, not a.no_progress,
                 command="python -m contact_tools.table " + " ".join(kept), fine_grid=a.fine_grid,
                 coarse=coarse, reuse=[Path(d) for d in a.reuse], wide_above=a.wide_above,
                 tol=a.tol, tol_sliding=a.tol_sliding)
    print(f"wrote {path} (sha256 {data.sha256(path)})")
    return 0
