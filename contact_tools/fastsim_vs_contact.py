"""FASTSIM against CONTACT's FASTSIM, both against the converged exact theory (not a test).

CONTACT's results are data: ``tests/data/contact_fastsim_sets.csv`` (the program CONTACT's
default FASTSIM, M=3, with the parabolic and the elliptic traction bound on 20×20 and 48×44
grids; provenance in the file's header). They cover the benchmark's 400 cases
(``contact_tools.bench``, form "full"), the three held-out sets of
``python -m contact_tools.table check`` (2,000 random states, 2,000 in the hard region near full
sliding, 300 in the spin band) and a second draw of them (``check.second_draw``: 600, 600 and 300
states, other seeds; set names with the suffix "2"), on which choices made on the first draw are
checked. This script solves the same states with ``contact_core``'s FASTSIM on the same number
of elements (``nx`` × ``ny`` = CONTACT's MX × MY; strips here, a rectangle over the ellipse's
bounding box there) and writes p95 / max of both errors per series, bound and grid to
``docs/reports/fastsim_vs_contact.md``, counting the figures behind CONTACT's per draw; every series
over a range of grids (n × n, n = 14 .. 56; CONTACT's results on them in
``tests/data/contact_fastsim_grid_scan.csv.gz``); and the same figures for simplified theory
itself: FASTSIM with the same options at zero element size (``LIMIT_GRIDS``; its 24,800 solves
on 200×200 and 400×400 take most of the script's 5 minutes). A figure of either program below
that limit is first-order grid error cancelling part of the theory's.

Errors, in % of μN (forces) and of μN·c (Mz, c = √(ab)), against the references of the two
reports, the force's as the error of the vector (Fx, Fy), its magnitude and direction: on the
benchmark ``contact_tools.bench.report.errors``, its reference as ``python -m contact_tools.bench
--full`` computes it, with two finer grids, ``BENCH_REFERENCE_GRIDS``, kept in
``build/bench_reference``; on the held-out sets ``contact_tools.table.check.result_errors``,
references kept in ``build/table_check_reference`` by ``python -m contact_tools.table check``.
Both are computed again when the exact solver changes. Missing references are computed (hours on
two cores; ``--workers``, ``--scheduler`` as in those commands).

    python -m contact_tools.fastsim_vs_contact [--options '{"scheme": "midpoint"}']

``--export-references FILE`` writes the references it used as data (CSV, provenance in its
header): ``tests/data/exact_references_fastsim_sets.csv``, which the tests compare both FASTSIMs
against without the hours of exact solves. ``--references FILE`` reads them from such a file
instead of solving (a fresh clone: about 5 minutes, most of it simplified theory's limit):

    python -m contact_tools.fastsim_vs_contact \
        --references tests/data/exact_references_fastsim_sets.csv
"""
from __future__ import annotations

import argparse
import csv
import gzip
import json
import math
import os
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import contact_core as cc
from contact_tools.bench.cases import make_cases
from contact_tools.bench.reference import REFERENCE_GRIDS, compute_references
from contact_tools.bench.report import errors as bench_errors
from contact_tools.table.check import (GRIDS as CHECK_GRIDS, KEPT, held_out_sets, references,
                                      result_errors, second_draw)

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "contact_fastsim_sets.csv"
#: CONTACT's FASTSIM on the same states on further grids (n × n, n = 14 .. 56)
SCAN_DATA = DATA.with_name("contact_fastsim_grid_scan.csv.gz")
INPUTS = ("a", "b", "G", "nu", "mu", "N", "xi", "eta", "phi")
GRIDS = ((20, 20), (48, 44))
#: simplified theory's own error: the same options, "midpoint", on n×n and 2n×2n, extrapolated
#: to zero element size as a first-order error (Richardson). With spin "midpoint" is first order
#: in partial slip: on the benchmark's states |F| moves by at most 0.74, 0.39 and 0.19 % of μN from
#: 50 to 100, 200 and 400; the "kalker" scheme extrapolates to the same forces within 0.02 %.
LIMIT_GRIDS = (200, 400)
BOUNDS = ("parabolic", "elliptic")
#: the benchmark's reference grids: the full form's and two finer ones. The gaps between the two
#: programs are a few tenths of % of μN, about as large as the full form's references' 95 %
#: half-width per case; the two finer grids halve it (docs/notes/benchmark.md).
BENCH_REFERENCE_GRIDS = REFERENCE_GRIDS["full"] + (128, 160)
#: the benchmark's series (its case kinds), in the order of the report
KINDS = (("longitudinal", "pure ξ"), ("lateral", "pure η"), ("creepage", "ξ and η"),
         ("spin", "pure φ"), ("combined", "spin with creepage"))


def _rows(path: Path) -> list[dict[str, str]]:
    """The rows of a CSV file (gzip-compressed if its name ends in .gz), without "#" lines."""
    with (gzip.open(path, "rt", encoding="utf-8", newline="") if path.suffix == ".gz"
          else path.open(encoding="utf-8", newline="")) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def _forces(rows: list[dict[str, str]], keys) -> dict[str, np.ndarray]:
    """(Fx, Fy, Mz) of ``rows`` (in order) per key "<bound>_<mx>x<my>" of ``keys``."""
    return {key: np.array([[float(r[f"{key}_{q}"]) for q in ("Fx", "Fy", "Mz")] for r in rows])
            for key in keys}


def read_contact() -> dict[str, tuple[list[dict[str, float]], dict[str, np.ndarray]]]:
    """Per set: the inputs of each case and CONTACT's (Fx, Fy, Mz) (N, N·m) per
    "<bound>_<mx>x<my>", on ``GRIDS`` (``DATA``) and on the grids of the scan (``SCAN_DATA``, the
    grids its columns name; stored as fractions of μN and μN·c)."""
    rows, scan = _rows(DATA), _rows(SCAN_DATA)
    keys = [f"{b}_{mx}x{my}" for mx, my in GRIDS for b in BOUNDS]
    scan_keys = [c[:-3] for c in scan[0] if c.endswith("_Fx")]
    out = {}
    for name in dict.fromkeys(r["set"] for r in rows):
        sub, sub_scan = ([r for r in rs if r["set"] == name] for rs in (rows, scan))
        sub.sort(key=lambda r: int(r["id"]))
        sub_scan.sort(key=lambda r: int(r["id"]))
        if [r["id"] for r in sub_scan] != [r["id"] for r in sub]:
            raise SystemExit(f"set {name!r}: {SCAN_DATA.name} does not hold the states of "
                             f"{DATA.name}")
        inputs = [{k: float(r[k]) for k in INPUTS} for r in sub]
        mu_n = np.array([v["mu"] * v["N"] for v in inputs])
        unit = np.column_stack([mu_n, mu_n, mu_n * np.sqrt([v["a"] * v["b"] for v in inputs])])
        out[name] = (inputs, {**_forces(sub, keys),
                              **{k: f * unit for k, f in _forces(sub_scan, scan_keys).items()}})
    return out


def grid_of(key: str) -> tuple[int, int]:
    """(mx, my) of a key "<bound>_<mx>x<my>"."""
    mx, my = key.rsplit("_", 1)[1].split("x")
    return int(mx), int(my)


def same_states(name: str, stored: list[dict[str, float]], cases: list[dict[str, float]]) -> None:
    """CONTACT's results are only comparable on the states they were computed for."""
    if len(stored) != len(cases) or any(
            not math.isclose(s[k], c[k], rel_tol=1e-12, abs_tol=1e-300)
            for s, c in zip(stored, cases) for k in INPUTS):
        raise SystemExit(f"set {name!r}: the states in {DATA.name} differ from the ones this "
                         "package generates; CONTACT must be run again on them")


def cell(e: np.ndarray) -> tuple[float, float]:
    e = e[np.isfinite(e)]
    return float(np.percentile(e, 95)), float(e.max())


def marked(ours: tuple[float, float], theirs: tuple[float, float]
           ) -> tuple[str, list[tuple[str, float]]]:
    """Our "p95 / max", a figure behind CONTACT's (by more than the rounding) in bold, and the
    figures behind as (statistic, gap)."""
    marks, behind = [], []
    for j, what in enumerate(("p95", "max")):
        worse = ours[j] > theirs[j] + 0.005
        marks.append(f"**{ours[j]:.2f}**" if worse else f"{ours[j]:.2f}")
        if worse:
            behind.append((what, ours[j] - theirs[j]))
    return " / ".join(marks), behind


def held_series(title: str) -> tuple[str, str]:
    """The report's two series of a held-out set: the force (its vector error) and Mz."""
    return f"{title.lower()}, \\|F\\|", f"{title.lower()}, Mz"


def fastsim(states: list[dict[str, float]], **options) -> np.ndarray:
    """(Fx, Fy, Mz) of this package's FASTSIM with ``options`` per state."""
    return np.array([[r.Fx, r.Fy, r.Mz] for r in (cc.solve("fastsim", **k, **options)
                                                   for k in states)])


def grid_limit(states: list[dict[str, float]], bound: str, options: dict) -> np.ndarray:
    """(Fx, Fy, Mz) of FASTSIM with ``options`` at zero element size (``LIMIT_GRIDS``)."""
    n, n2 = LIMIT_GRIDS
    r, r2 = (fastsim(states, bound=bound, **{**options, "scheme": "midpoint", "nx": m, "ny": m})
             for m in (n, n2))
    return r2 + (r2 - r) * n / (n2 - n)


def series_cells(bench, refs, bench_res: np.ndarray, held, held_refs,
                 held_res: list[np.ndarray]) -> dict[str, tuple[float, float]]:
    """p95 / max per series of one program's results on the benchmark (``bench_res``, its cases
    in order) and on the held-out sets (``held_res``, one array per set of ``held``)."""
    kind = np.array([c.kind for c in bench])
    eF, eM = bench_errors(bench, refs, bench_res)
    cells = {f"benchmark, {title}": cell(100 * eF[kind == k]) for k, title in KINDS}
    cells["benchmark, Mz (all but pure ξ)"] = cell(100 * eM)
    for (_, title, cases, _), ref, res in zip(held, held_refs, held_res):
        f_key, m_key = held_series(title)
        cells[f_key], cells[m_key] = (cell(e) for e in result_errors(cases, ref, res))
    return cells


@dataclass(frozen=True)
class StoredReference:
    """A benchmark reference as exported (``export_references``): Fx, Fy (N), Mz (N·m), and
    whether it converged; what ``contact_tools.bench.report.errors`` needs."""

    Fx: float
    Fy: float
    Mz: float
    converged: bool


def read_references(path: Path, held) -> tuple[list[StoredReference], list[np.ndarray]]:
    """The benchmark's references and the held-out sets' (Fx, Fy, Mz) from a file written by
    ``export_references``, per set in the order of ``held``."""
    by_set: dict[str, list[dict[str, str]]] = {}
    for r in _rows(path):
        by_set.setdefault(r["set"], []).append(r)
    for sub in by_set.values():
        sub.sort(key=lambda r: int(r["id"]))
    refs = [StoredReference(float(r["Fx"]), float(r["Fy"]), float(r["Mz"]),
                            r["converged"] == "1") for r in by_set.get("bench", [])]
    if any(r.converged and not math.isfinite(r.Fx + r.Fy) for r in refs):
        raise SystemExit(f"{path}: the benchmark's references have no Fx, Fy (a file written "
                         "before 2026-11-27 holds |F| only): export them again")
    held_refs = [np.array([[float(r[q]) for q in ("Fx", "Fy", "Mz")]
                           for r in by_set.get(name, [])]) for name, *_ in held]
    return refs, held_refs


def export_references(path: Path, refs, held, held_refs) -> None:
    """The converged exact references of the benchmark (Fx, Fy, Mz and whether it converged,
    ``contact_tools.bench.reference``) and of the held-out sets (Fx, Fy, Mz) as CSV."""
    header = (
        "The converged exact theory (contact_core's exact solver, Kalker's half-space boundary "
        "elements, solved on several square grids, each alone, and fitted to q(m) = q_inf + C/m) "
        "on the states of contact_fastsim_sets.csv (same set and id). set 'bench': grids "
        f"{', '.join(map(str, BENCH_REFERENCE_GRIDS))} (contact_tools.bench.reference: Fx, Fy "
        "and Mz fitted each), converged = 0 where a solve did not converge or the fit's "
        "uncertainty exceeds 0.5 % of mu N (of mu N c for Mz; such cases are left out of the "
        "statistics); the held-out sets and their second draw (sets with the suffix 2): grids "
        f"{', '.join(map(str, CHECK_GRIDS))} "
        "(contact_tools.table.check.references), Fx, Fy, Mz. SI units (N, N m), Kalker's sign "
        "convention. Written by python -m contact_tools.fastsim_vs_contact --export-references "
        "FILE from the references it keeps (the benchmark's, contact_tools.bench.reference) and "
        "the ones kept by python -m contact_tools.table check.")
    lines = textwrap.wrap(header, 90, initial_indent="# ", subsequent_indent="# ",
                          break_on_hyphens=False)
    lines.append("set,id,Fx,Fy,F,Mz,converged")
    lines += [f"bench,{i},{r.Fx:.10g},{r.Fy:.10g},{math.hypot(r.Fx, r.Fy):.10g},{r.Mz:.10g},"
              f"{int(r.converged)}" for i, r in enumerate(refs)]
    for (name, _, _, _), ref in zip(held, held_refs):
        lines += [f"{name},{i},{fx:.10g},{fy:.10g},{math.hypot(fx, fy):.10g},{mz:.10g},1"
                  for i, (fx, fy, mz) in enumerate(ref)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def grid_range_section(per_grid: dict[tuple[int, int, str], dict[str, tuple]]) -> list[str]:
    """The report's section on every grid of ``per_grid`` ((mx, my, bound): {series: (ours
    (p95, max), CONTACT's (p95, max))}): the benchmark's figures in a table per bound, and per
    series the figures of ours behind CONTACT's."""
    grids = list(dict.fromkeys((mx, my) for mx, my, _ in per_grid))
    series = list(next(iter(per_grid.values())))
    bench_series = [s for s in series if s.startswith("benchmark, ")]
    # per (bound, series): the figures of ours behind CONTACT's, as text
    behind: dict[tuple[str, str], list[str]] = {}
    cells: dict[tuple[int, int, str, str], str] = {}
    for (mx, my, bound), figures in per_grid.items():
        for s, (o, c) in figures.items():
            text, gaps = marked(o, c)
            cells[(mx, my, bound, s)] = f"{text} ({c[0]:.2f} / {c[1]:.2f})"
            behind.setdefault((bound, s), []).extend(f"{what} at {mx} × {my} by {d:.2f}"
                                                     for what, d in gaps)
    n_fig = 2 * len(grids)
    lines = ["## Over a range of grids", "",
             f"Every series on {len(grids)} grids, "
             + ", ".join(f"{mx} × {my}" for mx, my in grids) + " (CONTACT's results: "
             f"`tests/data/{SCAN_DATA.name}` and the grids above). Both programs converge to "
             "simplified theory (its own error: the next section); on each grid their "
             "first-order errors cancel different parts of it.", "",
             "The benchmark: p95 / max of ours, CONTACT's in brackets, a figure of ours in bold "
             "behind CONTACT's.", ""]
    names = [s.removeprefix("benchmark, ") for s in bench_series]
    for bound in BOUNDS:
        lines += [f"### The benchmark, {bound} bound", "",
                  "| grid | " + " | ".join(names) + " |", "|---|" + "---:|" * len(names)]
        lines += [f"| {mx} × {my} | " + " | ".join(cells[(mx, my, bound, s)]
                                                  for s in bench_series) + " |"
                  for mx, my in grids]
        lines.append("")
    lines += ["### Figures of ours behind CONTACT's", "",
              f"Per series and bound, of its {n_fig} (p95 and max on each grid):", "",
              "| series | " + " | ".join(BOUNDS) + " |", "|---" * (1 + len(BOUNDS)) + "|"]
    for s in series:
        lines.append(f"| {s} | " + " | ".join(
            f"{len(behind[(b, s)])}" + (f": {', '.join(behind[(b, s)])}" if behind[(b, s)]
                                        else "") for b in BOUNDS) + " |")
    lines.append("")
    for bound in BOUNDS:
        for what, group in (("the benchmark", bench_series),
                            ("the held-out sets (both draws)",
                             [s for s in series if s not in bench_series])):
            total = sum(len(behind[(bound, s)]) for s in group)
            lines.append(f"{bound.capitalize()} bound, {what}: ours behind CONTACT in {total} "
                         f"of {n_fig * len(group)} figures.")
        lines.append("")
    return lines


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--options", default="{}", help="FASTSIM options as JSON (default: none, the "
                   "method's defaults)")
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--scheduler", default=None)
    p.add_argument("--out", default="docs/reports/fastsim_vs_contact.md")
    p.add_argument("--export-references", metavar="FILE", default=None,
                   help="also write the references as CSV (module docstring)")
    p.add_argument("--references", metavar="FILE", default=None,
                   help="read the references from such a CSV instead of solving them")
    a = p.parse_args()
    options = json.loads(a.options)
    contact = read_contact()

    bench = make_cases("full")
    states = [c.solve_kwargs() for c in bench]
    same_states("bench", contact["bench"][0], states)
    second = second_draw()
    second_names = {name for name, *_ in second}
    held = held_out_sets() + second
    for name, _, cases, _ in held:
        same_states(name, contact[name][0], cases)
    if a.references:
        refs, held_refs = read_references(Path(a.references), held)
        if len(refs) != len(bench) or any(len(r) != len(cases)
                                          for r, (_, _, cases, _) in zip(held_refs, held)):
            raise SystemExit(f"{a.references}: not the references of these states")
    else:
        refs = compute_references(bench, BENCH_REFERENCE_GRIDS,
                                  jobs=a.workers or os.cpu_count() or 1, scheduler=a.scheduler,
                                  cache="build/bench_reference")
        held_refs = [references(cases, a.scheduler, a.workers, folder=KEPT)[0]
                     for _, _, cases, _ in held]
    if a.export_references:
        export_references(Path(a.export_references), refs, held, held_refs)

    # per (mx, my, bound): {series: (ours (p95, max), CONTACT's (p95, max))}, on every grid of
    # CONTACT's results, by number of elements
    per_grid: dict[tuple[int, int, str], dict[str, tuple]] = {}
    for mx, my in sorted({grid_of(k) for k in contact["bench"][1]},
                         key=lambda g: (g[0] * g[1], g)):
        for bound in BOUNDS:
            key = f"{bound}_{mx}x{my}"
            opts = dict(nx=mx, ny=my, bound=bound, **options)
            ours = series_cells(bench, refs, fastsim(states, **opts), held, held_refs,
                                [fastsim(cases, **opts) for _, _, cases, _ in held])
            theirs = series_cells(bench, refs, contact["bench"][1][key], held, held_refs,
                                  [contact[name][1][key] for name, *_ in held])
            per_grid[(mx, my, bound)] = {s: (ours[s], theirs[s]) for s in ours}
    second_series = {k for name, title, *_ in held if name in second_names
                     for k in held_series(title)}
    # simplified theory's own error per (bound, series): p95 / max at zero element size
    limit = {bound: series_cells(bench, refs, grid_limit(states, bound, options), held,
                                 held_refs, [grid_limit(cases, bound, options)
                                             for _, _, cases, _ in held])
             for bound in BOUNDS}
    series = list(next(iter(per_grid.values())))
    behind = []
    lines = ["# FASTSIM against CONTACT's FASTSIM", "",
             "Generated by `python -m contact_tools.fastsim_vs_contact"
             + (f" --options '{a.options}'" if options else "")
             + (f" --references {a.references}" if a.references else "") + "` (see its docstring): "
             "p95 / max error against the converged exact theory, the force F = (Fx, Fy) by "
             "its vector error |F − F_ref| in % of μN (\\|F\\| in the series' names), Mz in % of "
             "μN·c; the benchmark's 400 cases by series, the held-out sets of `python -m "
             "contact_tools.table check` and a second draw of them (fewer states, other seeds). "
             "*ours* = `contact_core`'s FASTSIM"
             + (f" with {options}" if options else " (default options)") + " on nx × ny strips "
             "× elements, CONTACT = the program CONTACT's FASTSIM (M=3) on MX × MY over the "
             "ellipse's bounding box. A figure of ours in bold is behind CONTACT's.", ""]
    for mx, my in GRIDS:
        lines += [f"## {mx} × {my}", "",
                  "| series | parabolic, ours | parabolic, CONTACT | elliptic, ours | "
                  "elliptic, CONTACT |", "|---|---:|---:|---:|---:|"]
        for s in series:
            row = [s]
            for bound in BOUNDS:
                o, c = per_grid[(mx, my, bound)][s]
                text, gaps = marked(o, c)
                behind += [(d, f"{mx}×{my} {bound}, {s} {what}", s) for what, d in gaps]
                row += [text, f"{c[0]:.2f} / {c[1]:.2f}"]
            lines.append("| " + " | ".join(row) + " |")
        lines.append("")
    for in_second, what in ((False, "the benchmark and the held-out sets"),
                            (True, "the second draw")):
        n = 2 * len(BOUNDS) * len(GRIDS) * sum((s in second_series) == in_second for s in series)
        gaps = sorted(((d, w) for d, w, s in behind if (s in second_series) == in_second),
                      reverse=True)
        lines.append(f"On {what}: ours behind CONTACT in {len(gaps)} of {n} figures"
                     + (": " + "; ".join(f"{w} by {d:.2f}" for d, w in gaps) if gaps else "")
                     + ".")
        lines.append("")
    lines += grid_range_section(per_grid)
    n, n2 = LIMIT_GRIDS
    lines += ["## Simplified theory's own error", "",
              "The same states and options, FASTSIM at zero element size (`scheme=\"midpoint\"` "
              f"on {n} × {n} and {n2} × {n2}, extrapolated as a first-order error): the error of "
              "the theory (the spring bed, the flexibilities, the traction bound), not of a grid. "
              "A figure above, of either program, that is lower is first-order grid error "
              "cancelling part of it.", "", "| series | parabolic | elliptic |",
              "|---|---:|---:|"]
    lines += [f"| {s} | " + " | ".join(f"{limit[b][s][0]:.2f} / {limit[b][s][1]:.2f}"
                                       for b in BOUNDS) + " |" for s in series]
    text = "\n".join(lines) + "\n"
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
