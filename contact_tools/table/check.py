"""``python -m contact_tools.table check``: the table against the converged exact theory on a
held-out random set, and its cost against FASTSIM's, measured in one run.

Cases (seeded, never the table's nodes): a/b log-uniform over the table's range, ν uniform over
its range, the direction of the reduced creepage u (:mod:`contact_core.table.grid`) uniform on
the sphere (every sign), |u| log-uniform from 1e-3 (linear range) to 1e2 (full sliding), N and μ
log-uniform. The reference is the benchmark's (:mod:`contact_tools.bench.reference`): the exact
solver on square grids, each on its own (``extrapolate=False``), fitted to q(m) = q∞ + C/m and
taken at m -> ∞; its grid solutions are kept as the benchmark's are (in
``build/table_check_reference``) and computed again when the exact solver changes.
Errors: |F| vector error in % of μN, Mz error in % of μN c. Writes a Markdown report.

A second, smaller set (``--hard``, seed + 1) samples the region where interpolation is hardest and
the uniform set rarely goes: near full sliding (s from 0.85 to 0.999) with the creepage direction
within 9° (``HARD_PSI``) of pure ξ or pure η (ψ near 0 or π/2), any θ. There, with spin, the forces
turn steeply with ψ, more than a cubic on the uniform ψ nodes follows.

A third set (``--spin``, seed + 2) samples the band where the lateral force of a large spin
peaks: a/b from 1 to 10, the direction within 30° of pure spin, s from 0.3 to 0.65. There, at
large a/b, the slip fraction jumps within a small step of s at a place that moves with the grid,
and the two-grid extrapolation of the exact solver (m with m/2) can straddle the jump, while the
reference fit over four single grids stays smooth (the figures: docs/notes/table_build.md).
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

import contact_core as cc
from contact_core.coefficients import creep_coefficients
from contact_core.table import data
from contact_core.table.grid import creepages_from_reduced, node_reduced_creepage

from ..bench.reference import fit_extrapolation, grid_solutions, kept_grid_solutions
from .build import AXES

GRIDS = (40, 48, 64, 80)
#: Width of the hard region in ψ next to 0 and π/2 (module docstring): one node spacing of the
#: 11-node ψ axis the region was drawn for; fixed, so the cases (and their kept references) do
#: not change with the axes.
HARD_PSI = math.pi / 20
_C, _G = 6e-3, 8e10
#: Folder of the references' grid solutions (:func:`references`).
KEPT = "build/table_check_reference"
#: A second draw of the three sets (the arguments of :func:`held_out_sets`): fewer states, seeds
#: apart from the default's; choices made on the first draw are checked on it
#: (``contact_tools/fastsim_vs_contact.py``).
SECOND_DRAW = {"n": 600, "seed": 20261201, "hard": 600, "spin": 300}


def _shape(rng: np.random.Generator, axes) -> tuple[float, float]:
    """a/b log-uniform and ν uniform over the table's ranges."""
    ab = math.exp(rng.uniform(math.log(axes.ab_lo), math.log(axes.ab_hi)))
    return ab, rng.uniform(axes.nu_lo, axes.nu_hi)


def _state(rng: np.random.Generator, ab: float, nu: float, u: np.ndarray) -> dict[str, float]:
    """The contact state of reduced creepage ``u`` (:mod:`contact_core.table.grid`) at a/b and
    ν, N and μ log-uniform."""
    N = 10.0 ** rng.uniform(4.0, 5.3)
    mu = 10.0 ** rng.uniform(-1.0, -0.3)
    b = _C / math.sqrt(ab)
    c11, c22, c23, _ = creep_coefficients(ab, nu)
    xi, eta, phi = creepages_from_reduced(u, c11, c22, c23, _C, _G * _C * _C / (mu * N))
    return {"xi": xi, "eta": eta, "phi": phi, "N": N, "mu": mu, "a": ab * b, "b": b, "G": _G,
            "nu": nu}


def random_cases(n: int, seed: int, axes) -> list[dict[str, float]]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        ab, nu = _shape(rng, axes)
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        out.append(_state(rng, ab, nu, 10.0 ** rng.uniform(-3.0, 2.0) * d))
    return out


def _state_at(rng: np.random.Generator, axes, ab: float, nu: float, theta: float, psi: float,
              s: float) -> dict[str, float]:
    """The state at table coordinates (θ, ψ, s) (θ the angle of v to the spin axis), with random
    signs of ξ and η."""
    u = node_reduced_creepage(theta, psi, s, axes.spin_weight(ab))
    u[:2] *= rng.choice([-1.0, 1.0], size=2)
    return _state(rng, ab, nu, u)


def hard_cases(n: int, seed: int, axes) -> list[dict[str, float]]:
    """The hard region (module docstring): table coordinates (θ, ψ, s) sampled directly, ψ
    within ``HARD_PSI`` of 0 or π/2, s in [0.85, 0.999], random signs of ξ and η."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        ab, nu = _shape(rng, axes)
        theta = rng.uniform(0.0, math.pi)
        psi = (rng.uniform(0.0, HARD_PSI) if rng.integers(2) == 0
               else rng.uniform(0.5 * math.pi - HARD_PSI, 0.5 * math.pi))
        out.append(_state_at(rng, axes, ab, nu, theta, psi, rng.uniform(0.85, 0.999)))
    return out


def spin_cases(n: int, seed: int, axes) -> list[dict[str, float]]:
    """The band of the spin force's peak (module docstring): a/b log-uniform from 1 to the
    table's end, the angle of v to the spin axis within 30° of 0 or π, ψ uniform, s in
    [0.3, 0.65], random signs of ξ and η."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        ab = math.exp(rng.uniform(0.0, math.log(axes.ab_hi)))
        nu = rng.uniform(axes.nu_lo, axes.nu_hi)
        theta = rng.uniform(0.0, math.pi / 6)
        if rng.integers(2):
            theta = math.pi - theta
        psi = rng.uniform(0.0, 0.5 * math.pi)
        out.append(_state_at(rng, axes, ab, nu, theta, psi, rng.uniform(0.3, 0.65)))
    return out


def references(cases, scheduler=None, workers=None, progress=True,
               folder: str | Path | None = None) -> tuple[np.ndarray, float]:
    """(Fx, Fy, Mz) extrapolated to zero element size per case (module docstring), and the
    seconds of exact solves they took; the grid solutions are kept in ``folder`` if given
    (:func:`contact_tools.bench.reference.kept_grid_solutions`: computed again when the exact
    solver changes)."""
    where = {"jobs": workers or os.cpu_count() or 1, "scheduler": scheduler,
             "progress": progress}
    sols = (kept_grid_solutions(cases, GRIDS, folder, **where) if folder is not None
            else grid_solutions(cases, GRIDS, **where))
    out = np.empty((len(cases), 3))
    for i, s in enumerate(sols):
        for j in range(3):
            out[i, j] = fit_extrapolation(GRIDS, [s[m][j] for m in GRIDS])[0]
    return out, sum(s[m][4] for s in sols for m in GRIDS)


def held_out_sets(n: int = 2000, seed: int = 20261123, hard: int = 2000,
                  spin: int = 300) -> list[tuple[str, str, list[dict[str, float]], int]]:
    """The held-out sets (module docstring) as (name, title, cases, seed): ``n`` random cases
    (``seed``), then the hard region (``hard`` cases, seed + 1) and the spin band (``spin``,
    seed + 2), each left out when it has no cases."""
    out = [("random", "The random set", random_cases(n, seed, AXES["full"]), seed)]
    for k, (name, title, make, m) in enumerate((("hard", "The hard region", hard_cases, hard),
                                                ("spin", "The spin band", spin_cases, spin)), 1):
        if m > 0:
            out.append((name, title, make(m, seed + k, AXES["full"]), seed + k))
    return out


def second_draw() -> list[tuple[str, str, list[dict[str, float]], int]]:
    """:func:`held_out_sets` drawn again with ``SECOND_DRAW``: the names with the suffix "2",
    the titles with "(second draw)"."""
    return [(name + "2", f"{title} (second draw)", cases, seed)
            for name, title, cases, seed in held_out_sets(**SECOND_DRAW)]


def errors(cases, ref: np.ndarray, method: str, **options) -> tuple[np.ndarray, np.ndarray]:
    """|F| errors in % of μN and Mz errors in % of μN·c of ``method`` on ``cases`` against
    ``ref`` ((Fx, Fy, Mz) per case, :func:`references`)."""
    res = np.array([[r.Fx, r.Fy, r.Mz] for r in (cc.solve(method, **kw, **options)
                                                  for kw in cases)])
    return result_errors(cases, ref, res)


def result_errors(cases, ref: np.ndarray, res: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The errors of :func:`errors` of results ``res`` ((Fx, Fy, Mz) per case, N and N·m): the
    vector error of (Fx, Fy) in % of μN, Mz in % of μN·c."""
    mun = np.array([kw["mu"] * kw["N"] for kw in cases])
    c = np.array([math.sqrt(kw["a"] * kw["b"]) for kw in cases])
    eF = np.hypot(res[:, 0] - ref[:, 0], res[:, 1] - ref[:, 1]) / mun * 100
    eM = np.abs(res[:, 2] - ref[:, 2]) / (mun * c) * 100
    return eF, eM


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m contact_tools.table check")
    p.add_argument("--cases", type=int, default=2000)
    p.add_argument("--seed", type=int, default=20261123)
    p.add_argument("--scheduler", default=None)
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--out", default="docs/reports/table_accuracy.md")
    p.add_argument("--no-progress", action="store_true")
    p.add_argument("--hard", type=int, default=2000, help="cases of the hard region (module "
                   "docstring; 0: none)")
    p.add_argument("--spin", type=int, default=300, help="cases of the spin band (module "
                   "docstring; 0: none)")
    p.add_argument("--references-only", action="store_true",
                   help=f"compute and keep the references ({KEPT}), no table needed yet")
    a = p.parse_args(argv)
    sets = held_out_sets(a.cases, a.seed, a.hard, a.spin)
    kept = [references(cases_k, a.scheduler, a.workers, not a.no_progress, KEPT)
            for _, _, cases_k, _ in sets]
    (_, _, cases, _), (ref, t_ref) = sets[0], kept[0]
    extra, extra_refs = sets[1:], kept[1:]
    if a.references_only:
        return 0
    t = data.load()
    err_table = errors(cases, ref, "table")
    err_fastsim = errors(cases, ref, "fastsim", nx=10, ny=10)

    # cost per call, both methods in this run (median of 5 passes over 200 states), three ways:
    # "random": the held-out states in turn, each pass with a/b moved in its last digits, so no
    # call meets an a/b seen before (nothing cached, the table read far from the last call);
    # "trajectory": a/b new at every call and the state close to the last one, as a contact
    # point moving over curved profiles; "repeated": every state at the first case's a/b and ν,
    # as on constant profiles (the table's slice)
    def per_call(method, sub, moved_by=None, **opt):
        ts = []
        for k in range(5):
            moved = ([{**kw, "a": kw["a"] * (1.0 + moved_by(k, i))} for i, kw in enumerate(sub)]
                     if moved_by else sub)
            t1 = time.perf_counter()
            for kw in moved:
                cc.solve(method, **kw, **opt)
            ts.append((time.perf_counter() - t1) / len(sub))
        return float(np.median(ts)) * 1e6

    shape = {k: cases[0][k] for k in ("a", "b", "nu")}
    path = [{**cases[0], **{v: cases[0][v] * (1.0 + 0.2 * math.sin(2.0 * math.pi * i / 200))
                            for v in ("xi", "eta", "phi")}} for i in range(200)]
    inward = -1.0 if cases[0]["a"] > cases[0]["b"] else 1.0     # a/b stays inside the table
    series = {"random": (cases[:200], lambda k, i: 1e-12 * (k + 1)),
              "trajectory": (path, lambda k, i: inward * (1e-4 * i / 200 + 1e-12 * (k + 1))),
              "repeated": ([{**kw, **shape} for kw in cases[:200]], None)}
    cc.solve("table", **cases[0])
    cc.solve("fastsim", **cases[0], nx=10, ny=10)
    us = {name: (per_call("table", sub, moved), per_call("fastsim", sub, moved, nx=10, ny=10))
          for name, (sub, moved) in series.items()}
    lines = ["# The table against the converged exact theory (held-out set)", "",
             f"Generated by `python -m contact_tools.table check {' '.join(argv or sys.argv[1:])}`"
             f" on {time.strftime('%Y-%m-%d')}: {a.cases} random cases, seed {a.seed} "
             f"(`contact_tools/table/check.py`), reference: exact on {', '.join(map(str, GRIDS))}"
             f" grids extrapolated to zero element size ({t_ref:.0f} s of exact solves). Table "
             f"built by `{t.meta.get('command', '?')}`.", "",
             "| method | \\|F\\| error median / p95 / max, % of μN | Mz error median / p95 / "
             "max, % of μN·c | µs per solve call |", "|---|---:|---:|---:|"]
    for name, (eF, eM), t_us in (("table", err_table, us["random"][0]),
                                 ("FASTSIM 10×10", err_fastsim, us["random"][1])):
        lines.append(f"| {name} | {np.median(eF):.2f} / {np.percentile(eF, 95):.2f} / "
                     f"{eF.max():.2f} | {np.median(eM):.2f} / {np.percentile(eM, 95):.2f} / "
                     f"{eM.max():.2f} | {t_us:.2f} |")
    eF, eM = err_table
    worst = np.argsort(eF)[-5:][::-1]
    lines += ["", "µs per solve call, table / FASTSIM 10×10, both in this run (200 states, "
              "median of 5 passes): " + "; ".join(
                  f"{t:.2f} / {f:.2f} = {t / f:.2f} {what}" for (t, f), what in zip(
                      us.values(), ("with the held-out states in turn, each at an a/b not seen "
                                    "before (the µs column above)",
                                    "along a trajectory, a/b new at every call and the state "
                                    "close to the last one (a contact point on curved profiles)",
                                    "with the a/b and ν of the first case at every call "
                                    "(constant profiles)"))) + ".", "",
              "The table per range of a/b (p95 / max):", "",
              "| a/b | cases | \\|F\\|, % of μN | Mz, % of μN·c |", "|---|---:|---:|---:|"]
    ab = np.array([kw["a"] / kw["b"] for kw in cases])
    edges = np.geomspace(AXES["full"].ab_lo, AXES["full"].ab_hi, 9)
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (ab >= lo) & (ab <= hi)
        if m.any():
            lines.append(f"| {lo:.3g}–{hi:.3g} | {int(m.sum())} | {np.percentile(eF[m], 95):.2f}"
                         f" / {eF[m].max():.2f} | {np.percentile(eM[m], 95):.2f} / "
                         f"{eM[m].max():.2f} |")
    lines += ["",
              "Largest |F| errors of the table:", "",
              "| a/b | ν | ξ | η | φ (1/m) | μ | N | \\|F\\| err % | Mz err % |",
              "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for i in worst:
        kw = cases[i]
        lines.append(f"| {kw['a'] / kw['b']:.3g} | {kw['nu']:.3f} | {kw['xi']:.3g} | "
                     f"{kw['eta']:.3g} | {kw['phi']:.3g} | {kw['mu']:.3g} | {kw['N']:.3g} | "
                     f"{eF[i]:.2f} | {eM[i]:.2f} |")
    for (name, title, cases_k, seed), (ref_k, t_k) in zip(extra, extra_refs):
        eF, eM = errors(cases_k, ref_k, "table")
        lines += ["", f"{title} (module docstring): {len(cases_k)} cases, seed {seed}, same "
                  f"reference ({t_k:.0f} s of exact solves). |F| error median / p95 / max "
                  f"{np.median(eF):.2f} / {np.percentile(eF, 95):.2f} / {eF.max():.2f} % of μN; "
                  f"Mz {np.median(eM):.2f} / {np.percentile(eM, 95):.2f} / {eM.max():.2f} % of "
                  "μN·c. Largest Mz errors:", "",
                  "| a/b | ν | ξ | η | φ (1/m) | μ | N | \\|F\\| err % | Mz err % |",
                  "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for i in np.argsort(eM)[-5:][::-1]:
            kw = cases_k[i]
            lines.append(f"| {kw['a'] / kw['b']:.3g} | {kw['nu']:.3f} | {kw['xi']:.3g} | "
                         f"{kw['eta']:.3g} | {kw['phi']:.3g} | {kw['mu']:.3g} | {kw['N']:.3g} | "
                         f"{eF[i]:.2f} | {eM[i]:.2f} |")
    text = "\n".join(lines) + "\n"
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(text, encoding="utf-8")
    print(text)
    return 0
