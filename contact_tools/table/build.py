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
#: grid of the nodes with a/b outside ``FINE_INSIDE``, the ends of the axis, where the square
#: grid's elements are most elongated. Measured against 96×96 extrapolated on 12 random nodes per
#: row (|F| / Mz max, % of μN and μN·c): a/b = 0.1: 48×48 0.21 / 0.75, 64×64 0.57 / 1.21 (its
#: half grid, 32, is short of the first-order range), 80×80 0.18 / 0.43; a/b = 0.178: 0.27 / 0.58,
#: 0.32 / 0.51, 0.21 / 0.33. Linear range against Kalker's table (Kalker 1990, Table E.3) at
#: a/b = 10: C22 +1.6 % at 48×48, +0.2 % at 80×80; at a/b = 5.6 +0.9 % at 48×48. (The +0.2 %
#: is a chance of the two-grid extrapolation: at a/b = 10 the values move by up to 1 % from one
#: grid to the next; single grids with square elements, 160×16 to 400×40 fitted in 1/m, converge
#: to C22 +1.2 % and C11 +0.8 % above Kalker's table, at ν = 0.25 and 0.28.) The upper
#: bound is None (``--fine-above``): 80×80 at a/b = 10 costs about 9 s per ray and worker, a row
#: of rays 3.3 h on two; the large a/b take the wide grid below instead.
#: Against the converged references of ``check`` (single states, extrapolated; |F| / Mz max, % of
#: μN and μN·c), at a/b < 0.3, 60 random and 60 hard-region states: 48×48 1.22 / 1.03 and
#: 2.03 / 1.48, 56×56 1.08 / 0.78 and 0.77 / 0.93, 64×64 0.51 / 0.64 and 0.71 / 0.98, 72×72
#: 1.06 / 0.63 and 0.60 / 0.74, 80×80 0.13 / 0.37 and 0.17 / 0.27; grids finer across the
#: contact than along it were no better (40 and 40 states: 48×96 0.71 / 0.68 and 0.61 / 0.27,
#: 40×120 0.36 / 0.48 and 0.42 / 0.42, 64×128 0.52 / 0.44 and 0.41 / 0.33). At a/b 0.28-0.5
#: (80 and 80): 48×48 0.52 / 0.43 and 0.66 / 0.32, 80×80 0.15 / 0.21 and 0.11 / 0.16: the
#: 48×48 rows' own error is a good part of the hard region's largest errors (``check``): the 260
#: rays of the rows a/b = 0.316 and 0.562 that the six worst hard-region states read, solved on
#: 80×80 in a patched copy, took those states from 1.08, 1.03, 1.00, 1.00 % (a/b 0.466, 0.132,
#: 0.716, 0.326) to 0.95, 1.05, 0.96, 0.04 % of μN (the hard region's p95 0.39 -> 0.37 %); the
#: state at a/b = 0.132 is limited by the a/b nodes (README). The whole row a/b = 0.316 on 80×80
#: (``--fine-below 0.4``, 2,650 rays, about 1.9 h on two workers), on ``check``'s states with a/b
#: in 0.178-0.562 (515 random, 478 hard region): |F| p95 0.43 -> 0.24 and 0.47 -> 0.34 %, max
#: 0.92 -> 0.79 and 1.08 -> 1.07 % (the last at a/b = 0.466, which reads the row 0.562). The
#: row a/b = 0.562 on 80×80 too (``--fine-below 0.6``, 2,650 rays, about 2 h): ``check``'s random
#: states at a/b 0.316-0.562 and 0.562-1, |F| p95 0.29 -> 0.20 and 0.26 -> 0.20 %, max 0.77 ->
#: 0.75 and 0.45 -> 0.43 %; the hard region's max 1.07 -> 0.96 % (a/b = 0.716; the state at 0.466
#: 0.95 %), p95 0.33 -> 0.30 %.
DEFAULT_GRID, DEFAULT_FINE_GRID, FINE_INSIDE = 48, 80, (0.6, None)
#: ``--wide-above A``: inside ``FINE_INSIDE`` and above a/b = A the nodes are solved on 2M × M
#: elements: along the rolling direction, where the contact is long, the square grid's elements
#: are a/b times as long as wide. Measured against the converged exact theory (the references of
#: ``check``) on its states with a/b in 7..10 (80 random, 80 hard region, 41 spin band; |F| / Mz
#: max, % of μN and μN·c): 48×48 0.41 / 0.36, 0.75 / 0.29, 0.96 / 1.35; 96×48 0.31 / 0.37,
#: 0.12 / 0.23, 0.46 / 0.57; at a/b 4..7 (80, 80, 82): 48×48 0.39 / 0.41, 0.77 / 0.54,
#: 0.75 / 0.80; 96×48 0.30 / 0.22, 0.29 / 0.20, 0.43 / 0.21 (80×40 and 64×32 were worse than
#: 48×48 on the spin band, 72×48 everywhere). Linear range against Kalker's table at a/b = 10,
#: ν = 0.25: C11 +0.96 -> +0.56 %, C22 +1.60 -> +1.17 %; at a/b = 5.6 +0.54 -> +0.23 %,
#: +0.87 -> +0.47 %. Cost per ray (32 magnitudes, warm-started) at a/b = 5.6 and 10: 48×48
#: 1.4-3.0 s, 96×48 4.5-7.2 s (one process), so the rows a/b = 5.6 and 10 of the shipped axes
#: (5,300 rays) take about 3.7 h on two workers instead of 0.6-0.9 h (measured: 1 h 52 min a row).
#: Default 4: the shipped table's design, both rows on 96×48; on ``check``'s spin band this took
#: the |F| / Mz max from 1.22 / 1.52 (both on 48×48) to 1.25 / 1.29 (a/b = 10 on 96×48) and
#: 0.83 / 0.84.
WIDE_ABOVE: float | None = 4.0
# The ghost row of a/b (``--ghost-below``, ``grid.Axes``) is solved like the rows next to it
# (80×80 below ``FINE_INSIDE``), although its weight in the first interval's cubic is at most
# 0.064: 48×48 there is biased in Mz. Measured with the ghost row a/b = 0.0562 on 48×48 (2,650
# rays in 18 min on two workers) against the table without it, on the states of ``check`` with
# a/b in [0.1, 0.178] (286 random, 240 hard region; % of μN and μN·c): |F| p95 0.35 -> 0.23 and
# 0.58 -> 0.35, max 0.97 -> 0.56 and 1.03 -> 0.71; but Mz worse in 280 of the 286 random states,
# median 0.18 -> 0.25, p95 0.30 -> 0.39, hard-region max 0.81 -> 0.93. On four rays at a/b =
# 0.0562 against 96×96 (extrapolated), Mz is 0.47-1.47 % of μN·c off on 48×48, 0.10-0.37 % on
# 80×80 (Fx and Fy within 0.26 and 0.06 % of μN); on the four states of ``grid.Axes``,
# |F| 0.31, 0.31, 0.14, 0.36 % with the row on 80×80 and 0.32, 0.32, 0.15, 0.37 on 48×48, Mz
# 0.33, 0.35, 0.28, 0.91 against 0.38, 0.39, 0.32, 0.93 % (82 rays: 536 s against 78 s, one
# process). The shipped table has it on 80×80 (``AXES["full"]``; 2,628 rays in 1 h 44 min on two
# workers): on all of ``check``'s states with the row a/b = 0.316 on 80×80 too, random |F| max
# 0.98 -> 0.79 %, hard-region p95 0.34 -> 0.33 %, Mz max 0.89 -> 0.91 % (a/b = 0.11).
# ``--tol``: the exact solver's tolerance at the nodes (``config``). The table shipped before was
# built with the exact method's default, 1e-5, the shipped one with ``DEFAULT_TOL`` and
# ``DEFAULT_TOL_SLIDING`` (below). Measured on 40 random rays of each kind (two workers on
# this 2-core machine, s per ray, default -> 1e-4): 80×80 2.55 -> 1.84, 48×48 0.53 -> 0.34,
# 96×48 2.24 -> 1.40, the forces s·g within 3.7e-5 of μN (Mz of μN·c) of the 1e-5 values and
# the slip fraction within 6.6e-4: a build of the shipped design from scratch takes about 6.0 h
# instead of 9.0 h (the design before the row a/b = 0.316 on 80×80 and the ghost row; with them
# about 8.5 h instead of 12.2 h). Rays of different tolerances are not reused for one another.
# Looser still (6 random rays each, one process beside a running build, time relative to 1e-5
# and the largest force change s·g in % of μN): 48×48 at a/b = 1: 1e-4 0.69 and 0.0014, 3e-4
# 0.56 and 0.0031, 1e-3 0.42 and 0.014; 80×80 at a/b = 0.178: 0.70 and 0.0027, 0.58 and
# 0.0080, 0.45 and 0.059.
# Measured again 2026-11-25 on 6 random rays per row (one process beside a running build; time
# relative to 1e-5, the fine grid's sweeps in the same ratio within 0.03; the largest node change
# s·g in % of μN), for 3e-4, 5e-4, 1e-3: 80×80 at a/b = 0.178 0.59, 0.53, 0.45 and 0.008, 0.014,
# 0.059; at a/b = 0.562 0.58, 0.51, 0.45 and 0.007, 0.016, 0.028; 96×48 at a/b = 10 0.50, 0.45,
# 0.38 and 0.007, 0.019, 0.055; 48×48 at a/b = 1 0.57, 0.51, 0.42 and 0.003, 0.011, 0.014. The
# shipped design from scratch (about 14 h at 1e-5) would take about 7.8 h at 3e-4, 7.0 h at 5e-4
# and 6.0 h at 1e-3.
#: ``--tol-sliding``: the tolerance once the ray's previous node slides on at least this fraction
#: of the contact area. Measured 2026-11-25 on the first 941 rays of a build at ``--tol 5e-4``
#: (the ghost row, 80×80) against the table then shipped (1e-5): the largest node change s·g is
#: 0.006 % of μN in partial slip and 0.058 % at full sliding with a little spin (slip fraction
#: 1, θ near π/2, the nodes the hard region of ``check`` reads), p99 0.038 %; on 868 of those
#: rays solved again with ``--tol-sliding 1e-4`` max 0.011 % (a node just past slip fraction
#: 0.87, still at 5e-4), p99 0.007 %, median 0.002 % (5e-4 alone: 0.058, 0.039, 0.008 %), at
#: no lower speed on this row (44 rays a minute with other work beside it, 48 without). On 4-6
#: rays per row kind (one process beside the build; time relative to 1e-5 and largest change in
#: % of μN; 5e-4, then 5e-4 with 1e-4 from here on, then 1e-3 with 1e-4): 80×80 at a/b =
#: 0.178 0.54 and 0.018, 0.57 and 0.003, 0.52 and 0.006; at a/b = 0.562 0.52 and 0.008, 0.56
#: and 0.006, 0.51 and 0.007; 48×48 at a/b = 1 0.54 and 0.006, 0.57 and 0.006, 0.52 and 0.025;
#: 96×48 at a/b = 10 0.48 and 0.020, 0.52 and 0.015, 0.46 and 0.027. Full sliding is where a
#: loose tolerance stops early (the slip direction converges slowly) and where its nodes cost
#: least.
SLIDING = 0.9
#: ``--tol`` and ``--tol-sliding`` by default: the shipped table's (measured: the comments above).
DEFAULT_TOL, DEFAULT_TOL_SLIDING = 5e-4, 1e-4
#: The exact solver's ``spin_shift`` of a table whose configuration does not name one: 1/4, the
#: solver's fixed sampling before it became an option (default now 1/6, CONTACT's). Every table so
#: far was built with it. The nodes are extrapolated solves, where the shift's first-order term
#: cancels (at 52×52 extrapolated the two give the same |F| p95 and max on the benchmark's 400
#: cases, Mz p95 0.58 against 0.56 % of μN·c: ``exact/solver.py``).
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
    default, recorded as absent, as in the tables built before the option; measured: the comment
    above ``_C``), ``tol_sliding``: the tolerance after a node whose slip fraction reached
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
