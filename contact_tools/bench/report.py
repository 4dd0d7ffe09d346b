"""Errors against the reference, statistics per setting × regime, the Markdown table and the plot.

Error metrics (per case; the reference from :mod:`.reference`):

* force: ``|F - F_ref| / (μN)`` with ``F = (Fx, Fy)`` — the error of the creep force vector,
  magnitude and direction, as a fraction of the friction limit (what a vehicle model's
  wheel-rail force is off by, in units it can compare across loads and friction). The error of
  the magnitude alone, ``| |F| - |F_ref| |``, is never larger and misses a method whose force
  points the wrong way (Johnson–Vermeulen's under combined creepage near saturation);
* moment: ``|Mz - Mz_ref| / (μN·c)``, ``c = √(ab)`` — μN·c is the natural scale of the spin
  moment (the moment of a friction-limited traction over the patch is a fraction of it).

Cases whose reference is not converged are excluded from every statistic (and listed); pure
longitudinal cases are left out of the moment statistics (Mz = 0 there by symmetry, for every
method, which would only dilute them).
Statistics per setting and regime: median, 95th percentile and maximum of each error; time per
call: median over the cases of each case's median over repeats, with the 10th–90th percentile
range over the cases as the spread.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .cases import REGIMES, Case
from .reference import Reference
from .settings import Setting

ALL = "all"


@dataclass
class SettingStats:
    label: str
    regime: str
    n: int
    eF: tuple[float, float, float]      # median, p95, max (fractions of μN)
    eM: tuple[float, float, float]      # (fractions of μN·c)
    t_in: tuple[float, float, float]    # median, p10, p90 seconds per call
    t_fmu: tuple[float, float, float] | None


def errors(cases: Sequence[Case], refs: Sequence[Reference],
           results: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(force error, moment error) per case of one setting's ``results`` (cases × [Fx, Fy, Mz,
    ...]): the error of the vector F over μN and of Mz over μN·c; NaN where the reference is not
    converged. ``refs``: objects with ``Fx``, ``Fy``, ``Mz`` and ``converged``."""
    eF = np.full(len(cases), np.nan)
    eM = np.full(len(cases), np.nan)
    for j, (c, r) in enumerate(zip(cases, refs)):
        if not r.converged:
            continue
        Fx, Fy, Mz = results[j, :3]
        eF[j] = math.hypot(Fx - r.Fx, Fy - r.Fy) / (c.mu * c.N)
        if c.kind != "longitudinal":  # pure ξ: Mz = 0 by symmetry for every method
            eM[j] = abs(Mz - r.Mz) / (c.mu * c.N * c.c)
    return eF, eM


def _tri(x: np.ndarray) -> tuple[float, float, float]:
    x = x[np.isfinite(x)]
    if x.size == 0:
        return (math.nan, math.nan, math.nan)
    return (float(np.median(x)), float(np.percentile(x, 95)), float(x.max()))


def _time(t: np.ndarray | None) -> tuple[float, float, float] | None:
    if t is None or t.size == 0:
        return None
    per_case = np.median(t, axis=1)
    return (float(np.median(per_case)), float(np.percentile(per_case, 10)),
            float(np.percentile(per_case, 90)))


def statistics(settings: Sequence[Setting], cases: Sequence[Case], refs: Sequence[Reference],
               results: dict[str, np.ndarray], t_in: dict[str, np.ndarray],
               t_fmu: dict[str, np.ndarray] | None) -> list[SettingStats]:
    """One :class:`SettingStats` per setting and regime (``"all"`` first)."""
    out = []
    regimes = np.array([c.regime for c in cases])
    ok = np.array([r.converged for r in refs])
    for s in settings:
        eF, eM = errors(cases, refs, results[s.label])
        for reg in (ALL,) + REGIMES:
            sel = ok & ((regimes == reg) if reg != ALL else True)
            tf = t_fmu.get(s.label) if t_fmu else None
            out.append(SettingStats(s.label, reg, int(sel.sum()), _tri(eF[sel]), _tri(eM[sel]),
                                    _time(t_in[s.label][sel]) or (math.nan,) * 3,
                                    _time(tf[sel]) if tf is not None else None))
    return out


def pareto(stats: Sequence[SettingStats], key: str = "eF") -> list[str]:
    """Labels not dominated in (95th-percentile error over all cases, in-process median time)."""
    pts = [(s.label, getattr(s, key)[1], s.t_in[0]) for s in stats if s.regime == ALL]
    front = []
    for lab, e, t in pts:
        if not (math.isfinite(e) and math.isfinite(t)):
            continue
        dominated = any((e2 <= e and t2 <= t) and (e2 < e or t2 < t)
                        for l2, e2, t2 in pts if l2 != lab)
        if not dominated:
            front.append(lab)
    return sorted(front, key=lambda lab: next(t for l, _, t in pts if l == lab))


# ---------------------------------------------------------------------------------------------
# Markdown
# ---------------------------------------------------------------------------------------------

def _pct(x: float) -> str:
    if not math.isfinite(x):
        return "–"
    if x >= 10:
        return f"{100 * x:.0f}"
    if x >= 0.1:
        return f"{100 * x:.1f}"
    return f"{100 * x:.2f}"


def _us(t: float) -> str:
    if not math.isfinite(t):
        return "–"
    us = t * 1e6
    return f"{us:.3g}" if us < 1000 else f"{us:,.0f}"


def _tcell(t: tuple[float, float, float] | None) -> str:
    if t is None or not math.isfinite(t[0]):
        return "–"
    return f"{_us(t[0])} ({_us(t[1])}–{_us(t[2])})"


def summary_table(stats: Sequence[SettingStats], regime: str = ALL) -> str:
    """The summary: one row per setting (``regime``'s cases)."""
    head = ("| setting | n | F err median | p95 | max | Mz err median | p95 | max "
            "| µs/call in-process | µs/step FMU |\n"
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    rows = []
    for s in stats:
        if s.regime != regime:
            continue
        rows.append(f"| {s.label} | {s.n} | {_pct(s.eF[0])} | {_pct(s.eF[1])} | {_pct(s.eF[2])} "
                    f"| {_pct(s.eM[0])} | {_pct(s.eM[1])} | {_pct(s.eM[2])} "
                    f"| {_tcell(s.t_in)} | {_tcell(s.t_fmu)} |")
    return head + "\n".join(rows) + "\n"


def regime_table(stats: Sequence[SettingStats]) -> str:
    """Compact: per setting (rows) and regime (columns), F error median / p95 / max."""
    regs = list(REGIMES)
    head = ("| setting | " + " | ".join(regs) + " |\n|---|" + "---:|" * len(regs) + "\n")
    by = {(s.label, s.regime): s for s in stats}
    labels = list(dict.fromkeys(s.label for s in stats))
    rows = []
    for lab in labels:
        cells = []
        for r in regs:
            s = by[(lab, r)]
            cells.append("–" if s.n == 0 else
                         f"{_pct(s.eF[0])} / {_pct(s.eF[1])} / {_pct(s.eF[2])}")
        rows.append(f"| {lab} | " + " | ".join(cells) + " |")
    return head + "\n".join(rows) + "\n"


def kind_table(settings: Sequence[Setting], cases: Sequence[Case], refs: Sequence[Reference],
               results: dict[str, np.ndarray]) -> str:
    """Per setting (rows) and kind of creepage (columns), F error median / p95 / max."""
    kinds = list(dict.fromkeys(c.kind for c in cases))
    kind_of = np.array([c.kind for c in cases])
    head = "| setting | " + " | ".join(kinds) + " |\n|---|" + "---:|" * len(kinds) + "\n"
    rows = []
    for s in settings:
        eF, _ = errors(cases, refs, results[s.label])
        cells = []
        for k in kinds:
            e = eF[kind_of == k]
            t = _tri(e)
            cells.append("–" if not np.isfinite(e).any() else
                         f"{_pct(t[0])} / {_pct(t[1])} / {_pct(t[2])}")
        rows.append(f"| {s.label} | " + " | ".join(cells) + " |")
    return head + "\n".join(rows) + "\n"


def long_table(stats: Sequence[SettingStats]) -> str:
    """Every setting × regime with every column."""
    head = ("| setting | regime | n | F err median | p95 | max | Mz err median | p95 | max "
            "| µs/call in-process | µs/step FMU |\n"
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    rows = [f"| {s.label} | {s.regime} | {s.n} | {_pct(s.eF[0])} | {_pct(s.eF[1])} "
            f"| {_pct(s.eF[2])} | {_pct(s.eM[0])} | {_pct(s.eM[1])} | {_pct(s.eM[2])} "
            f"| {_tcell(s.t_in)} | {_tcell(s.t_fmu)} |" for s in stats if s.regime != ALL]
    return head + "\n".join(rows) + "\n"


def convergence_table(conv: Sequence[dict[str, Any]], grids: Sequence[int]) -> str:
    head = ("| a/b | cases | converged | u_F median / max | u_M median / max "
            "| finest − ref F median / max | finest − ref Mz median / max | CPU s |\n"
            "|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    rows = [f"| {r['a_over_b']:g} | {r['n']} | {r['converged']} "
            f"| {r['uF_median']:.3f} / {r['uF_max']:.3f} | {r['uM_median']:.3f} / {r['uM_max']:.3f} "
            f"| {r['dF_median']:.3f} / {r['dF_max']:.3f} | {r['dM_median']:.3f} / {r['dM_max']:.3f} "
            f"| {r['seconds']:.0f} |" for r in conv]
    return head + "\n".join(rows) + "\n"


def markdown(*, stats: Sequence[SettingStats], cases: Sequence[Case], refs: Sequence[Reference],
             conv: Sequence[dict[str, Any]], meta: dict[str, Any],
             fmu_agreement: dict[str, float] | None, png_name: str,
             by_kind: str = "") -> str:
    """The whole report."""
    grids = refs[0].grids if refs else ()
    n_bad = sum(not r.converged for r in refs)
    front = pareto(stats)
    lines = [
        "# What accuracy costs in time",
        "",
        f"Generated by `python -m contact_tools.bench{meta.get('cli', '')}` "
        f"({meta['form']} form) on {meta['date']}: {meta['machine']}. "
        f"Run time {meta['runtime']:.0f} s.",
        "",
        f"**Cases:** {meta['cases_desc']}; seed {meta['seed']} "
        "(`contact_tools/bench/cases.toml`). **Reference:** exact solver on grids "
        f"{', '.join(f'{m}×{m}' for m in grids)}, extrapolated to zero element size; "
        f"{len(refs) - n_bad} of {len(refs)} references converged "
        f"(u ≤ {meta['tol_force'] * 100:g} % of μN for F, ≤ {meta['tol_moment'] * 100:g} % "
        "of μN·c for Mz), the others are listed below and excluded.",
        "",
        f"![Pareto plot: error vs time per call]({png_name})",
        "",
        "Errors in % (F: the force vector's, |F − F_ref| with F = (Fx, Fy), direction "
        "included, of μN; Mz: of μN·c, c = √(ab)), over all cases with a converged reference "
        "(Mz: without the pure longitudinal cases, where Mz = 0 by symmetry). Times in µs: "
        "median over the cases (10th–90th percentile), each case the "
        f"median of {meta['repeats']} repeats; in-process = one `contact_core.solve` call, FMU = "
        "`setReal + doStep + getReal` through fmpy's `FMU2Slave`"
        + ("" if meta.get("fmu") else " (not measured in this run: `--no-fmu`)") + ".",
        "",
        "## Summary (all regimes)",
        "",
        summary_table(stats),
        f"Pareto-optimal (p95 F error vs in-process time): {', '.join(front)}.",
        "",
        "## F error per regime: median / p95 / max, % of μN",
        "",
        "Regimes by Kalker-normalised creepage τ (see `cases.toml`): linear τ < "
        f"{meta['regimes']['linear_below']:g}, partial slip up to {meta['regimes']['saturation_from']:g}, "
        "near saturation beyond (full sliding included), spin-dominated when spin's share of the "
        "linear force exceeds the creepages'. Cases per regime: "
        + ", ".join(f"{r}: {sum(1 for c, ref in zip(cases, refs) if c.regime == r and ref.converged)}"
                    for r in REGIMES) + ".",
        "",
        regime_table(stats),
    ]
    if by_kind:
        lines += ["## F error per kind of creepage: median / p95 / max, % of μN", "",
                  "Kinds as in `cases.toml`: pure ξ, pure η, pure φ, (ξ, η) together "
                  "(`creepage`), (ξ, η) with spin (`combined`); all regimes.", "", by_kind]
    lines += [
        "## Every setting × regime",
        "",
        long_table(stats),
        "## Reference convergence per a/b",
        "",
        "u: 95 % half-width of the extrapolated value (fit q(m) = q∞ + C/m over the grids, scatter "
        "pooled per a/b and kind; F: √(u_Fx² + u_Fy²)); "
        "finest − ref: how far the finest grid alone is from the extrapolation (the two-grid "
        "check). All in % of μN (F) and μN·c (Mz). CPU s: exact-solver time of the reference.",
        "",
        convergence_table(conv, grids),
    ]
    bad = [(c, r) for c, r in zip(cases, refs) if not r.converged]
    lines += ["### Cases whose reference is not converged (excluded)", ""]
    if bad:
        lines += ["| case | a/b | kind | regime | τ | reason |", "|---:|---:|---|---|---:|---|"]
        lines += [f"| {c.id} | {c.a_over_b:g} | {c.kind} | {c.regime} | {c.tau:.3g} "
                  f"| {r.reason.replace('|', '&#124;')} |" for c, r in bad]
    else:
        lines += ["None."]
    lines += [""]
    nc = meta.get("not_converged") or {}
    if any(nc.values()):
        lines += ["Solves of a setting that stopped before their tolerance (result used as "
                  "returned, as a simulation would): " + ", ".join(
                      f"{k}: {v} of {len(cases)}" for k, v in nc.items() if v) + ".", ""]
    if fmu_agreement:
        worst = max(fmu_agreement.values())
        lines += ["## FMU vs in-process",
                  "",
                  "Largest difference between the FMU's outputs and the in-process results over "
                  f"all cases and settings: {worst * 100:.2g} % of μN (forces) — the FMU computes "
                  "the same thing (exact-solver steps warm-start from the previous step, so they "
                  "differ within the solver's tolerance).", ""]
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Plot
# ---------------------------------------------------------------------------------------------

_STYLE = {  # family -> (colour, marker)
    "linear": ("#444444", "s"),
    "johnson_vermeulen kalker": ("#1f77b4", "D"),
    "johnson_vermeulen original": ("#17becf", "d"),
    "fastsim parabolic": ("#2ca02c", "o"),
    "fastsim elliptic": ("#bcbd22", "^"),
    "fastsim parabolic blended-contact": ("#98df8a", "o"),
    "fastsim parabolic separate": ("#8c564b", "o"),
    "fastsim elliptic blended-contact": ("#dbdb8d", "^"),
    "fastsim elliptic separate": ("#c49c94", "^"),
    "exact": ("#d62728", "P"),
    "exact extrapolated": ("#9467bd", "X"),
    "table": ("#ff7f0e", "*"),
}


_FAMILY_NAMES = {
    "linear": "linear (Kalker)",
    "johnson_vermeulen kalker": "Johnson–Vermeulen, Kalker's C11, C22",
    "johnson_vermeulen original": "Johnson–Vermeulen, original",
    "fastsim parabolic": "FASTSIM, parabolic bound (n×n)",
    "fastsim elliptic": "FASTSIM, elliptic bound (n×n)",
    "fastsim parabolic blended-contact": "FASTSIM, parabolic, CONTACT's blend",
    "fastsim parabolic separate": "FASTSIM, parabolic, flexibilities unblended",
    "fastsim elliptic blended-contact": "FASTSIM, elliptic, CONTACT's blend",
    "fastsim elliptic separate": "FASTSIM, elliptic, flexibilities unblended",
    "exact": "exact (m×m, one grid)",
    "exact extrapolated": "exact (m×m and m/2, extrapolated)",
    "table": "table (exact theory tabulated)",
}


def _tag(s: Setting) -> str:
    """Short annotation of a setting in the plot (the legend names the family)."""
    o = dict(s.options)
    if s.call is None and "nx" in o:
        return f"{o['nx']}×{o['ny']}"
    if s.call is None and "mx" in o:
        return f"{o['mx']}×{o['my']}"
    if s.call is None and s.method == "johnson_vermeulen":
        return ""
    return s.label if s.call is not None else ""


def plot(stats: Sequence[SettingStats], settings: Sequence[Setting], path, title: str = "") -> None:
    """Pareto plot: p95 error vs median time per call, log–log, one marker per setting;
    in-process filled, FMU hollow (same y), joined by a thin line; the settings of one family
    (grid refinements) joined by a line."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    by_label = {s.label: s for s in settings}
    allst = [s for s in stats if s.regime == ALL]
    fig, axes = plt.subplots(1, 2, figsize=(13, 6.2))
    extra = ["#9467bd", "#8c564b", "#e377c2", "#7f7f7f"]
    styles: dict[str, tuple[str, str]] = dict(_STYLE)
    floor = 1e-3
    for ax, key, what in ((axes[0], "eF", "F error (vector), % of μN"),
                          (axes[1], "eM", "Mz error, % of μN·c")):
        families: dict[str, list[tuple[float, float]]] = {}
        for st in allst:
            s = by_label[st.label]
            if s.family not in styles:
                styles[s.family] = (extra[(len(styles) - len(_STYLE)) % len(extra)], "X")
            color, marker = styles[s.family]
            e = max(getattr(st, key)[1] * 100, floor)
            t_in = st.t_in[0] * 1e6
            if not (math.isfinite(e) and math.isfinite(t_in)):
                continue
            first = s.family not in families
            families.setdefault(s.family, []).append((t_in, e))
            ax.plot([t_in], [e], marker=marker, color=color, ms=8, ls="none", zorder=3,
                    label=_FAMILY_NAMES.get(s.family, s.family) if (first and ax is axes[0])
                    else None)
            tag = _tag(s)
            if tag:
                ax.annotate(tag, (t_in, e), textcoords="offset points", xytext=(5, 4),
                            fontsize=7, color=color)
            if st.t_fmu is not None and math.isfinite(st.t_fmu[0]):
                t_f = st.t_fmu[0] * 1e6
                ax.plot([t_in, t_f], [e, e], color=color, lw=0.6, alpha=0.4, ls=":")
                ax.plot([t_f], [e], marker=marker, color=color, mfc="white", ms=7, ls="none",
                        zorder=3)
        for f, pts in families.items():
            if len(pts) > 1:
                pts.sort()
                ax.plot([p[0] for p in pts], [p[1] for p in pts], color=styles[f][0], lw=0.8,
                        alpha=0.6)
        front = pareto(stats, key)
        pts = sorted((st.t_in[0] * 1e6, max(getattr(st, key)[1] * 100, floor))
                     for st in allst if st.label in front)
        if pts:
            ax.step([p[0] for p in pts], [p[1] for p in pts], where="post", color="k",
                    lw=0.8, ls="--", alpha=0.5,
                    label="Pareto front (in-process)" if ax is axes[0] else None)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time per call, µs (median over the cases)")
        ax.set_ylabel(f"95th percentile of the {what}")
        ax.grid(True, which="both", alpha=0.25)
    axes[0].plot([], [], marker="o", color="k", ls="none", label="in-process (contact_core.solve)")
    axes[0].plot([], [], marker="o", color="k", mfc="white", ls="none",
                 label="FMU step (fmpy FMU2Slave)")
    fig.legend(loc="lower center", ncol=5, fontsize=8, frameon=False)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    fig.savefig(path, dpi=130)
    plt.close(fig)
