"""Hard inputs swept through every method: ``python -m contact_tools.bench hard``.

Seeded random cases in six families, every method at its default options:

``documented``
    the documented physical range: a/b 0.05..20, c = √(ab) 0.1..50 mm, N 1 N..500 kN,
    μ 0.01..1, G 20..100 GPa, ν 0..0.49, normalised creepage |σ| 1e-8..1e4 (σ = creepage·G/(μ p0),
    spin as φ c), random direction and share of spin;
``large spin``
    the same contacts, spin dominating: |φ c σ-scale| 1..1e4, small ξ, η;
``full sliding``
    |σ| 1e3..1e300;
``near-zero load``
    N from 5e-324 (the smallest double) to 1e-3 N;
``extreme scales``
    every input log-uniform over its whole positive double range (creepages with a random sign),
    a/b inside the supported 0.005..200;
``any double``
    every input log-uniform over the double range, a and b independently (a/b may be outside).

Each case is solved as it is and with (ξ, η, φ) negated component-wise for the symmetry check.
Failure kinds counted per method: an exception other than ValueError; a ValueError that names
no argument; a non-finite output; |F| > μN (saturating methods); a result flagged not converged
(the exact solver warns); a force not opposing the slip (φ = 0); a broken symmetry (ξ -> -ξ
flips Fx only, (η, φ) -> (-η, -φ) flips Fy and Mz only). A ValueError naming an argument (a
refused input) is counted apart: it is the documented answer to an input outside the ranges.
Times: µs per call, percentiles over the cases a method solved. Every case has its own a/b and
ν, so Kalker's coefficients are interpolated anew at each call (a simulation reuses them: see
``contact_tools/bench_closed_form.py`` for the per-call cost there), and the exact solver computes
its normal problem and influence tables anew.
"""
from __future__ import annotations

import math
import time
import warnings
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from contact_core.api import METHODS, make_solver

FAMILIES = ("documented", "large spin", "full sliding", "near-zero load", "extreme scales",
            "any double")
FAILURES = ("exception", "unnamed ValueError", "non-finite", "|F| > μN", "not converged",
            "along the slip", "symmetry")
ARGS = ("xi", "eta", "phi", "N", "mu", "a", "b", "G", "nu")
_P0 = 3.0 / (2.0 * math.pi)


def _loguniform(rng: np.random.Generator, lo: float, hi: float, n: int) -> np.ndarray:
    return np.exp(rng.uniform(math.log(lo), math.log(hi), n))


def make_cases(n: int, seed: int) -> list[tuple[str, dict[str, float]]]:
    """``n`` cases (family, solve keyword arguments), the families in equal shares."""
    rng = np.random.default_rng(seed)
    out = []
    per = -(-n // len(FAMILIES))
    for fam in FAMILIES:
        if fam in ("documented", "large spin", "full sliding", "near-zero load"):
            ab = _loguniform(rng, 0.05, 20.0, per)
            c = _loguniform(rng, 1e-4, 5e-2, per)
            N = (_loguniform(rng, 5e-324, 1e-3, per) if fam == "near-zero load"
                 else _loguniform(rng, 1.0, 5e5, per))
            mu = _loguniform(rng, 0.01, 1.0, per)
            G = rng.uniform(2e10, 1e11, per)
            nu = rng.uniform(0.0, 0.49, per)
            a, b = c * np.sqrt(ab), c / np.sqrt(ab)
            with np.errstate(over="ignore"):                          # σ per unit creepage
                scale = G * a * b / (_P0 * np.maximum(N, 1e-300) * mu)
            size = (_loguniform(rng, 1e3, 1e300, per) if fam == "full sliding"
                    else _loguniform(rng, 1e-8, 1e4, per))
            d = rng.normal(size=(per, 3))
            if fam == "large spin":
                d[:, :2] *= 0.05
                size = _loguniform(rng, 1.0, 1e4, per)
            d /= np.linalg.norm(d, axis=1)[:, None]
            with np.errstate(over="ignore", under="ignore"):
                sig = d * (size / scale)[:, None]
            xi, eta, phi = sig[:, 0], sig[:, 1], sig[:, 2] / c
        else:
            def lu(lo=1e-300, hi=1e300):
                return _loguniform(rng, lo, hi, per)

            def signed(x):
                return x * rng.choice([-1.0, 1.0], per)
            xi, eta, phi = signed(lu()), signed(lu()), signed(lu())
            N, mu, G = lu(5e-324, 1e308), lu(1e-300, 1e300), lu(1e-300, 1e300)
            nu = rng.uniform(0.0, 0.4999, per)
            if fam == "extreme scales":
                a = lu()
                b = a / _loguniform(rng, 0.005, 200.0, per)
            else:
                a, b = lu(5e-324, 1e308), lu(5e-324, 1e308)
        for k in range(per):
            out.append((fam, dict(xi=float(xi[k]), eta=float(eta[k]), phi=float(phi[k]),
                                  N=float(N[k]), mu=float(mu[k]), a=float(a[k]), b=float(b[k]),
                                  G=float(G[k]), nu=float(nu[k]))))
    return out[:n] if len(out) > n else out


@dataclass
class MethodStats:
    """Counts and times of one method over the sweep."""

    cases: int = 0
    solved: int = 0
    refused: int = 0
    failures: Counter = field(default_factory=Counter)
    examples: dict = field(default_factory=dict)      # failure kind -> one (family, case, detail)
    times: list = field(default_factory=list)         # µs per solved call
    by_family: Counter = field(default_factory=Counter)  # failures per family


def _fail(st: MethodStats, kind: str, fam: str, kw: dict, detail: str) -> None:
    st.failures[kind] += 1
    st.by_family[fam] += 1
    st.examples.setdefault(kind, (fam, kw, detail))


def _check(method: str, saturates: bool, r, kw: dict) -> list[tuple[str, str]]:
    """Failure kinds of one result."""
    out = []
    if not all(math.isfinite(v) for v in (r.Fx, r.Fy, r.Mz)):
        return [("non-finite", f"Fx={r.Fx!r}, Fy={r.Fy!r}, Mz={r.Mz!r}")]
    if saturates and math.hypot(r.Fx, r.Fy) > kw["mu"] * kw["N"] * (1 + 1e-9):
        out.append(("|F| > μN", f"|F|/μN = {math.hypot(r.Fx, r.Fy) / (kw['mu'] * kw['N'])!r}"))
    if not r.converged:
        out.append(("not converged", f"{r.iterations} iterations, residual {r.residual!r}"))
    if kw["phi"] == 0.0:
        s = math.hypot(kw["xi"], kw["eta"])
        if s > 0.0 and (r.Fx * (kw["xi"] / s) + r.Fy * (kw["eta"] / s)) > \
                1e-9 * math.hypot(r.Fx, r.Fy):
            out.append(("along the slip", f"F = ({r.Fx!r}, {r.Fy!r})"))
    return out


def _symmetric(r, rx, ry, kw: dict, saturates: bool) -> bool:
    """The symmetries to 1e-9 of the force scale: μN for a saturating method (noise below it
    is rounding), the forces themselves otherwise."""
    big = max(abs(r.Fx), abs(r.Fy), abs(rx.Fx), abs(ry.Fy), 1e-300)
    tol = 1e-9 * (max(kw["mu"] * kw["N"], big) if saturates else big)
    tol_m = 1e-9 * max(abs(r.Mz), abs(rx.Mz), abs(ry.Mz), 1e-300) + tol * math.sqrt(kw["a"]) \
        * math.sqrt(kw["b"])
    return (abs(rx.Fx + r.Fx) <= tol and abs(rx.Fy - r.Fy) <= tol and abs(rx.Mz - r.Mz) <= tol_m
            and abs(ry.Fx - r.Fx) <= tol and abs(ry.Fy + r.Fy) <= tol
            and abs(ry.Mz + r.Mz) <= tol_m)


def sweep(n: int = 100_000, n_exact: int = 5_000, seed: int = 20261123,
          progress: bool = True) -> tuple[dict[str, MethodStats], dict[str, int]]:
    """Run the sweep: per method its statistics; and cases per family. ``n_exact`` = 0 leaves
    the exact method and the table out."""
    from tqdm.auto import tqdm

    cases = make_cases(n, seed)
    fams = Counter(f for f, _ in cases)
    stats: dict[str, MethodStats] = {}
    for name in METHODS:
        # the exact method, and the table, which falls back to it outside its a/b and ν range
        dear = name in ("exact", "table")
        if dear and n_exact == 0:
            continue
        solver = make_solver(name)
        saturates = solver.saturates
        solver.step(1e-3, 1e-4, 0.1, 1e5, 0.3, 6e-3, 4e-3, 8e10, 0.28)  # compiled code, tables
        st = stats[name] = MethodStats()
        todo = cases[::max(1, len(cases) // n_exact)][:n_exact] if dear else cases
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # extrapolated coefficients, unconverged sweeps
            for fam, kw in tqdm(todo, desc=f"hard cases: {name}", disable=not progress,
                                leave=False):
                st.cases += 1
                args = [kw[k] for k in ARGS]
                try:
                    t0 = time.perf_counter()
                    r = solver.step(*args)
                    dt = time.perf_counter() - t0
                    rx = solver.step(-args[0], *args[1:])
                    ry = solver.step(args[0], -args[1], -args[2], *args[3:])
                except ValueError as e:
                    if any(f"{a}=" in str(e) for a in ARGS):
                        st.refused += 1
                    else:
                        _fail(st, "unnamed ValueError", fam, kw, str(e))
                    continue
                except Exception as e:  # a failure: any other exception
                    _fail(st, "exception", fam, kw, f"{type(e).__name__}: {e}")
                    continue
                st.solved += 1
                st.times.append(dt * 1e6)
                for kind, detail in _check(name, saturates, r, kw):
                    _fail(st, kind, fam, kw, detail)
                if not _symmetric(r, rx, ry, kw, saturates):
                    _fail(st, "symmetry", fam, kw, f"{r}, {rx}, {ry}")
    return stats, dict(fams)


def report(stats: dict[str, MethodStats], families: dict[str, int], n: int, n_exact: int,
           seed: int, seconds: float, docs: str | None = None) -> str:
    """The Markdown summary (docs/reports/hard_cases.md; ``docs``: the folder ``--docs`` named,
    stated in the command that regenerates it)."""
    import platform

    lines = ["# Hard cases: every method on extreme inputs", "",
             f"Generated by `python -m contact_tools.bench hard --cases {n} --exact-cases "
             f"{n_exact} --seed {seed}" + (f" --docs {docs}" if docs else "")
             + f"` on {time.strftime('%Y-%m-%d')}: "
             f"{platform.machine()}, Python {platform.python_version()}, numpy "
             f"{np.__version__}. Run time {seconds:.0f} s. Families and checks: "
             "`contact_tools/bench/hard.py`; every method at its default options; the exact "
             "solver on an evenly spaced subset.", "",
             "Cases per family: " + ", ".join(f"{f} {families.get(f, 0)}" for f in FAMILIES)
             + ".", "",
             "## Failures (count per kind)", "",
             "| method | cases | solved | refused (ValueError naming the argument) | "
             + " | ".join(k.replace("|", "\\|") for k in FAILURES) + " |",
             "|---|" + "---:|" * (3 + len(FAILURES))]
    for name, st in stats.items():
        lines.append(f"| {name} | {st.cases} | {st.solved} | {st.refused} | "
                     + " | ".join(str(st.failures.get(k, 0)) for k in FAILURES) + " |")
    lines += ["", "## Time per call (µs, solved cases)", "",
              "| method | p50 | p90 | p99 | max |", "|---|---:|---:|---:|---:|"]
    for name, st in stats.items():
        if st.times:
            q = np.percentile(st.times, [50, 90, 99, 100])
            lines.append(f"| {name} | " + " | ".join(f"{v:,.3g}" for v in q) + " |")
    bad = [(name, kind, ex) for name, st in stats.items() for kind, ex in st.examples.items()]
    lines += ["", "## One example of each failure", ""]
    if not bad:
        lines.append("None: every case was solved with a finite, bounded, symmetric answer "
                     "or refused with a ValueError naming the argument.")
    for name, kind, (fam, kw, detail) in bad:
        lines.append(f"- {name}, {kind} ({fam}): {kw} -> {detail[:300]}")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    import argparse
    p = argparse.ArgumentParser(prog="python -m contact_tools.bench hard",
                                description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", type=int, default=100_000, help="cases (>= 1)")
    p.add_argument("--exact-cases", type=int, default=5_000,
                   help="of them for the exact method and the table (0: neither; default 5000)")
    p.add_argument("--seed", type=int, default=20261123)
    p.add_argument("--out", default="out", help="output folder (default: out)")
    p.add_argument("--docs", default=None, help="also write the summary here (e.g. docs/reports)")
    p.add_argument("--no-progress", action="store_true")
    a = p.parse_args(argv)
    if a.cases < 1:
        p.error(f"--cases must be >= 1, got {a.cases}")
    if a.exact_cases < 0:
        p.error(f"--exact-cases must be >= 0, got {a.exact_cases}")
    t0 = time.perf_counter()
    stats, fams = sweep(a.cases, a.exact_cases, a.seed, progress=not a.no_progress)
    text = report(stats, fams, a.cases, a.exact_cases, a.seed, time.perf_counter() - t0, a.docs)
    for folder in filter(None, (a.out, a.docs)):
        Path(folder).mkdir(parents=True, exist_ok=True)
        (Path(folder) / "hard_cases.md").write_text(text, encoding="utf-8")
    print(text)
    return 0 if all(not st.failures for st in stats.values()) else 1
