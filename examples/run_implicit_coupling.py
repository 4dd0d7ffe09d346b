"""``make run`` driver: the linearly implicit coupling of ``wheelsets/master.py`` at communication
steps beyond the explicit (Gauss-Seidel) stability limit; a plot and a summary in ``out/``.

    python examples/run_implicit_coupling.py [--out out] [--dist dist/wheelsets] [--no-build]

Writes ``out/implicit_coupling.png`` and ``out/implicit_coupling_summary.md``:

1. critical speed of the reference tangent-track wheelset (linear contact FMUs): the growth rate
   of the hunting motion fitted at 0.95 and 1.05 V_c and its zero interpolated, for the explicit
   scheme at a small step (the reference) and for the explicit and the linearly implicit schemes
   (constant and linear hold) at 5 times the explicit limit; with the exact discrete maps of the
   three couplings of the linear model, which predict the critical speed for every step;
2. driven wheelset under a staircase of traction torques (FASTSIM contact FMUs): the steady creep
   force and creepage at each level, explicit at a small step against linearly implicit at 6.4
   and 32 times the explicit limit, and the explicit scheme at the large step;
3. hunting limit cycle at 1.1 V_c (FASTSIM contact FMUs, creep saturation alone and with a flange
   spring): the amplitude (RMS of y over the last 3 s of 8 s) against the step, for every scheme;
4. the cost of a communication step of each scheme.

The explicit limit is that of the exact discrete map of the explicit coupling of the linear
model (``wheelsets.linear_model``): the smallest step at which an eigenvalue other than the
hunting pair leaves the unit circle (≈ 2τ, ``examples/wheelsets/README.md``).
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

# the reference wheelset models, next to this script (its folder is on sys.path when it runs)
from wheelsets.analysis import fit_damped
from wheelsets.build import build_contact, build_wheelsets, contact_fmu_name
from wheelsets.linear_model import (
    LinearWheelset,
    creep_mode_excess,
    explicit_limit,
    hunting_multiplier,
)
from wheelsets.scripts import command_line, machine_note
from wheelsets.systems import driven_time_constant, make_system, recommended_step

CONTACTS = (("tangent_track", "linear"), ("full", "fastsim"), ("traction", "fastsim"))
#: (label, scheme, hold) of the couplings compared
SCHEMES = (("explicit (Gauss-Seidel)", "gauss-seidel", "constant"),
           ("linearly implicit, constant hold", "linearly-implicit", "constant"),
           ("linearly implicit, linear hold", "linearly-implicit", "linear"))
FLANGE = {"flange_gap": 8e-3, "k_flange": 15e6}
RATIO = 5.0                      # communication step / explicit limit asked for


# ------------------------------------------------------------------------------------------------
# Critical speed predicted by the exact discrete maps (wheelsets.linear_model)
# ------------------------------------------------------------------------------------------------
def map_critical_speed(lw: LinearWheelset, h: float, scheme: str, hold: str) -> float:
    """The speed at which the hunting multiplier of the exact discrete map of the coupling
    (``wheelsets.linear_model.coupling_map``) has modulus 1 (nan if none near V_c, or
    if the coupling is unstable there)."""
    Vc = lw.critical_speed()
    if creep_mode_excess(lw, Vc, h, scheme, hold) > 0:
        return math.nan
    def excess(V):
        return abs(hunting_multiplier(lw, V, h, scheme, hold)) - 1.0

    try:
        return brentq(excess, 0.7 * Vc, 1.4 * Vc, xtol=1e-8)
    except ValueError:
        return math.nan


# ------------------------------------------------------------------------------------------------
# Co-simulations
# ------------------------------------------------------------------------------------------------
def tangent(dist: Path, method: str, V: float, T: float, h: float, scheme: str, hold: str,
            scene: str = "full", record=("wheelset.y",), **params):
    sim = make_system(dist / "TangentTrackWheelset.fmu",
                      dist / f"{contact_fmu_name(scene, method)}.fmu",
                      dict(V=V, y0=1e-3, **params), scheme=scheme, hold=hold)
    try:
        return sim.run(round(T / h) * h, h, record=list(record),
                       abort_above={"wheelset.y": 0.2})
    finally:
        sim.free()


def critical_speed(dist: Path, lw: LinearWheelset, h: float, scheme: str, hold: str,
                   T: float = 3.0) -> tuple[float, dict]:
    """V_c from the co-simulation (module docstring, 1): (V_c, runs by speed factor)."""
    Vc = lw.critical_speed()
    sig, runs = {}, {}
    for fac in (0.95, 1.05):
        r = tangent(dist, "linear", fac * Vc, T, h, scheme, hold, scene="tangent_track")
        runs[fac] = r
        if r.aborted:
            return math.nan, runs
        m = r["time"] > 0.3
        sig[fac] = fit_damped(r["time"][m], r["wheelset.y"][m])[0]
    return Vc * (0.95 - sig[0.95] * 0.1 / (sig[1.05] - sig[0.95])), runs


MU, W, R0 = 0.3, 100e3, 0.46         # friction, wheelset load (N), rolling radius (m)
T_LIMIT = MU * W * R0                # the Coulomb adhesion limit of the driven wheelset, N m
LEVELS = (0.2, 0.5, 0.8, 0.95)       # torque levels, fractions of T_LIMIT
HOLD = 0.16                          # s per level
V_DRIVE = 20.0


def staircase(t: float) -> float:
    """The drive torque: LEVELS of T_LIMIT, HOLD seconds each, N m."""
    return LEVELS[min(int(t / HOLD + 1e-9), len(LEVELS) - 1)] * T_LIMIT


def driven(dist: Path, h: float, scheme: str, hold: str, torque=staircase,
           T: float = len(LEVELS) * HOLD,
           record=("wheelset.xi", "contact_L.Fx", "contact_R.Fx")):
    sim = make_system(dist / "DrivenWheelsetFMU.fmu",
                      dist / f"{contact_fmu_name('traction', 'fastsim')}.fmu", {"V": V_DRIVE},
                      inputs={"wheelset.torque": torque}, scheme=scheme, hold=hold)
    try:
        return sim.run(T, h, record=list(record), abort_above={"wheelset.xi": 1.0})
    finally:
        sim.free()


def steady(r) -> tuple[np.ndarray, np.ndarray]:
    """(creep force ΣFx over T/r0 - 1, creepage) at the end of each torque level."""
    t = r["time"]
    i = [np.searchsorted(t, (k + 1) * HOLD - 1e-9) for k in range(len(LEVELS))]
    force = (r["contact_L.Fx"] + r["contact_R.Fx"])[i]
    return force / (np.array(LEVELS) * T_LIMIT / R0) - 1.0, r["wheelset.xi"][i]


LC_T, LC_WINDOW = 8.0, 3.0


def amplitude(r) -> float:
    """RMS of y over the last LC_WINDOW seconds (the samples' phases are spread over the limit
    cycle, so the RMS of samples taken at any step estimates it without bias), m."""
    if r.aborted:
        return math.nan
    y = r["wheelset.y"][r["time"] > LC_T - LC_WINDOW]
    return float(np.sqrt(np.mean(y ** 2)))


# ------------------------------------------------------------------------------------------------
def main(argv=None) -> int:
    out, dist, build_fmus = command_line(__doc__, argv)
    if build_fmus:
        build_wheelsets(dist)
        for scene, method in CONTACTS:
            build_contact(scene, method, dist)
    lw = LinearWheelset()
    Vc = lw.critical_speed()
    L = ["# Linearly implicit coupling at large communication steps\n",
         "Generated by `python examples/run_implicit_coupling.py` (part of `make run`); the "
         "scheme: `examples/wheelsets/master.py` (module docstring). Reference tangent-track "
         "wheelset (`examples/wheelsets/README.md`: k_y = 1 MN/m, k_ψ = 2 MN m/rad, linear "
         f"V_c = {Vc:.2f} m/s) and driven wheelset (V = {V_DRIVE:g} m/s). *Explicit limit*: the "
         "step at which the explicit Gauss-Seidel coupling of the linear model becomes unstable "
         "(exact discrete map, ≈ 2τ).\n"]

    # 1. critical speed ----------------------------------------------------------------------------
    lim_c = explicit_limit(lw, Vc)
    lims = {f: explicit_limit(lw, f * Vc) for f in (0.95, 1.05)}
    h_big = math.ceil(RATIO * lim_c * 1e3) * 1e-3
    h_ref = recommended_step(lw.tau(0.95 * Vc))
    vc_ref, runs_ref = critical_speed(dist, lw, h_ref, "gauss-seidel", "constant")
    vc_runs = {}
    for label, scheme, hold in SCHEMES:
        vc_runs[label] = critical_speed(dist, lw, h_big, scheme, hold)
    ratios = np.linspace(0.2, 7.0, 69)
    predicted = {label: [map_critical_speed(lw, q * lim_c, scheme, hold) / Vc - 1.0
                         for q in ratios] for label, scheme, hold in SCHEMES}
    L.append("## 1. Critical speed (linear contact FMUs)\n")
    L.append(f"Explicit limit at V_c: {lim_c * 1e3:.2f} ms (at 0.95 V_c {lims[0.95] * 1e3:.2f} "
             f"ms, at 1.05 V_c {lims[1.05] * 1e3:.2f} ms). Large step h = {h_big * 1e3:.0f} ms "
             f"= {h_big / lim_c:.2f} × the limit at V_c ({h_big / lims[0.95]:.2f} × at 0.95 V_c, "
             f"{h_big / lims[1.05]:.2f} × at 1.05 V_c). Reference: explicit, h = "
             f"{h_ref * 1e3:g} ms. V_c from the growth rates fitted at 0.95 and 1.05 V_c "
             "(zero interpolated); the map's prediction: the exact discrete map of the coupling "
             "of the linear model.\n")
    L.append("| coupling | h (ms) | V_c co-sim (m/s) | vs reference | vs eigenvalues | map's "
             "prediction |")
    L.append("|---|---|---|---|---|---|")
    L.append(f"| explicit (reference) | {h_ref * 1e3:g} | {vc_ref:.3f} | — | "
             f"{(vc_ref / Vc - 1) * 100:+.2f} % | "
             f"{(map_critical_speed(lw, h_ref, 'gauss-seidel', 'constant') / Vc - 1) * 100:+.2f}"
             " % |")
    for label, scheme, hold in SCHEMES:
        v, runs = vc_runs[label]
        bad = [(fac, r["time"][-1]) for fac, r in runs.items() if r.aborted]
        fate = (f"{v:.3f} | {(v / vc_ref - 1) * 100:+.2f} % | {(v / Vc - 1) * 100:+.2f} %"
                if v == v else f"diverged (at {bad[0][0]:g} V_c, \|y\| > 0.2 m at t = "
                               f"{bad[0][1]:.2f} s) | — | —")
        pred = map_critical_speed(lw, h_big, scheme, hold)
        L.append(f"| {label} | {h_big * 1e3:.0f} | {fate} | "
                 + (f"{(pred / Vc - 1) * 100:+.2f} % |" if pred == pred else "unstable |"))
    L.append("")

    # 2. driven wheelset ---------------------------------------------------------------------------
    tau_d = driven_time_constant(V_DRIVE)
    lim_d = 2.0 * tau_d      # the creep mode's multiplier 1 - h/τ of the explicit coupling
    h_d_ref = 1e-4
    ref_d = driven(dist, h_d_ref, "gauss-seidel", "constant")
    F_ref, xi_ref = steady(ref_d)
    d_runs = {(8e-3, "explicit (Gauss-Seidel)"): driven(dist, 8e-3, "gauss-seidel", "constant")}
    for h in (8e-3, 4e-2):
        d_runs[(h, SCHEMES[1][0])] = driven(dist, h, "linearly-implicit", "constant")
    d_runs[(8e-3, SCHEMES[2][0])] = driven(dist, 8e-3, "linearly-implicit", "linear")
    L.append("## 2. Driven wheelset: steady creep force (FASTSIM contact FMUs)\n")
    L.append(f"τ = I_y V/(2 f11 r0²) = {tau_d * 1e3:.3f} ms, explicit limit 2τ = "
             f"{lim_d * 1e3:.3f} ms. Torque levels {', '.join(f'{x:g}' for x in LEVELS)} μWr0, "
             f"{HOLD:g} s each; at the end of each level: the creep force ΣFx against T/r0 "
             "(moment balance) and the creepage against the reference's (explicit, h = "
             f"{h_d_ref * 1e3:g} ms).\n")
    L.append("| coupling | h (ms) | h / limit | ΣFx r0/T − 1 (per level) | creepage vs reference "
             "(largest) |")
    L.append("|---|---|---|---|---|")
    L.append(f"| explicit (reference) | {h_d_ref * 1e3:g} | {h_d_ref / lim_d:.2f} | "
             + ", ".join(f"{x:+.1e}" for x in F_ref) + " | — |")
    for (h, label), r in d_runs.items():
        F, xi = steady(r)
        L.append(f"| {label} | {h * 1e3:g} | {h / lim_d:.1f} | "
                 + ", ".join(f"{x:+.1e}" for x in F)
                 + f" | {np.abs(xi / xi_ref - 1).max() * 100:.2g} % |")
    L.append("")

    # 3. limit cycle -----------------------------------------------------------------------------
    V_lc = 1.1 * Vc
    lim_lc = explicit_limit(lw, V_lc)
    h_lc_ref = recommended_step(lw.tau(V_lc))
    lc = {}
    for flange in (False, True):
        extra = FLANGE if flange else {}
        ref = tangent(dist, "fastsim", V_lc, LC_T, h_lc_ref, "gauss-seidel", "constant",
                      **extra)
        rows = []
        for label, scheme, hold in SCHEMES:
            steps = ((5e-3, 8e-3, 1e-2, 1.2e-2) if scheme == "gauss-seidel" else
                     (2e-3, 5e-3, 1e-2, 2e-2, 3e-2, 5e-2))
            for h in steps:
                rows.append((label, h, amplitude(tangent(dist, "fastsim", V_lc, LC_T, h, scheme,
                                                         hold, **extra))))
        lc[flange] = (amplitude(ref), rows)
    L.append("## 3. Hunting limit cycle at 1.1 V_c (FASTSIM contact FMUs)\n")
    L.append(f"V = {V_lc:.2f} m/s, explicit limit {lim_lc * 1e3:.2f} ms; amplitude: RMS of y "
             f"over the last {LC_WINDOW:g} s of {LC_T:g} s (from y0 = 1 mm); reference: "
             f"explicit, h = {h_lc_ref * 1e3:g} ms. Flange spring: gap 8 mm, 15 MN/m.\n")
    for flange, (a_ref, rows) in lc.items():
        L.append(f"**{'With the flange spring' if flange else 'Creep saturation alone'}**: "
                 f"reference {a_ref * 1e3:.3f} mm.\n")
        L.append("| coupling | h (ms) | h / limit | RMS y (mm) | vs reference |")
        L.append("|---|---|---|---|---|")
        for label, h, amp in rows:
            L.append(f"| {label} | {h * 1e3:g} | {h / lim_lc:.2f} | "
                     + (f"{amp * 1e3:.3f} | {(amp / a_ref - 1) * 100:+.1f} % |" if amp == amp
                        else "diverged | — |"))
        L.append("")

    # 4. cost -------------------------------------------------------------------------------------
    L.append("## 4. Cost of a communication step\n")
    L.append("Wall time per communication step (median of 3 runs of 200 steps at h = 1 ms; the "
             "master, fmpy and the FMUs, all in this process):\n")
    L.append("| system | " + " | ".join(label for label, _, _ in SCHEMES) + " |")
    L.append("|---|---|---|---|")
    for name, run in (("tangent track, linear contacts",
                       lambda s, hd: tangent(dist, "linear", Vc, 0.2, 1e-3, s, hd,
                                             scene="tangent_track")),
                      ("tangent track, FASTSIM contacts",
                       lambda s, hd: tangent(dist, "fastsim", Vc, 0.2, 1e-3, s, hd)),
                      ("driven wheelset, FASTSIM contacts",
                       lambda s, hd: driven(dist, 1e-3, s, hd, torque=lambda t: 0.5 * T_LIMIT,
                                            T=0.2, record=("wheelset.xi",)))):
        cells = []
        for _, scheme, hold in SCHEMES:
            walls = []
            for _ in range(3):
                r = run(scheme, hold)
                walls.append(r.wall_time / r.steps)
            cells.append(f"{np.median(walls) * 1e6:.0f} µs")
        L.append(f"| {name} | " + " | ".join(cells) + " |")
    L.append(machine_note(f"; {time.strftime('%Y-%m-%d')}"))

    plot(out, lw, lim_c, ratios, predicted, h_big, vc_runs, vc_ref, runs_ref, h_ref, ref_d,
         d_runs, lim_d, lc, lim_lc)
    text = "\n".join(L) + "\n"
    (out / "implicit_coupling_summary.md").write_text(text, encoding="utf-8")
    print(text)
    return 0


def plot(out, lw, lim_c, ratios, predicted, h_big, vc_runs, vc_ref, runs_ref, h_ref, ref_d,
         d_runs, lim_d, lc, lim_lc) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    Vc = lw.critical_speed()
    colors = {SCHEMES[0][0]: "C3", SCHEMES[1][0]: "C0", SCHEMES[2][0]: "C2"}
    fig, ax = plt.subplots(2, 2, figsize=(13, 9))

    a = ax[0, 0]
    for label, _, _ in SCHEMES:
        a.plot(ratios, np.abs(predicted[label]) * 100, color=colors[label], label=label)
        v = vc_runs[label][0]
        if v == v:
            a.plot(h_big / lim_c, abs(v / Vc - 1) * 100, "o", color=colors[label])
    a.axvline(1.0, color="0.5", ls=":")
    a.axvline(RATIO, color="0.5", ls="--")
    a.axhline(1.0, color="0.5", lw=0.8)
    a.set_yscale("log")
    a.set_ylim(1e-3, 100)
    a.set_xlabel("communication step / explicit limit at V_c")
    a.set_ylabel("|V_c error| (%)")
    a.set_title("Critical speed: exact discrete maps (lines), co-simulation (dots)",
                fontsize=10)
    a.legend(fontsize=8)

    a = ax[0, 1]
    r = runs_ref[1.05]
    a.plot(r["time"], r["wheelset.y"] * 1e3, color="k", lw=1.5,
           label=f"explicit, h = {h_ref * 1e3:g} ms (reference)")
    for label, _, _ in SCHEMES:
        run = vc_runs[label][1][1.05] if 1.05 in vc_runs[label][1] else vc_runs[label][1][0.95]
        a.plot(run["time"], np.clip(run["wheelset.y"] * 1e3, -10, 10), ".-",
               color=colors[label], ms=4, lw=0.8,
               label=f"{label}, h = {h_big * 1e3:.0f} ms" + (" (diverged)" if run.aborted
                                                              else ""))
    a.set_ylim(-10, 10)
    a.set_xlabel("t (s)")
    a.set_ylabel("y (mm)")
    a.set_title(f"Hunting at 1.05 V_c, linear contacts, h = {h_big / lim_c:.1f} × explicit "
                f"limit ({2 * math.pi / lw.hunting_eigenvalue(1.05 * Vc).imag / h_big:.1f} steps "
                "per period)", fontsize=10)
    a.legend(fontsize=7, loc="lower left")

    a = ax[1, 0]
    scale = R0 / T_LIMIT
    a.plot(ref_d["time"], (ref_d["contact_L.Fx"] + ref_d["contact_R.Fx"]) * scale, color="k",
           lw=1.5, label="explicit, h = 0.1 ms (reference)")
    for (h, label), r in d_runs.items():
        a.plot(r["time"], np.clip((r["contact_L.Fx"] + r["contact_R.Fx"]) * scale, -1.5, 1.5),
               ".-" if h > 1e-2 else "-", color=colors[label], lw=0.8, ms=4,
               alpha=0.6 if label == SCHEMES[0][0] else 1.0,
               label=f"{label}, h = {h * 1e3:g} ms ({h / lim_d:.1f} × limit)")
    a.set_xlabel("t (s)")
    a.set_ylabel("ΣFx r0 / (μ W r0)")
    a.set_title("Driven wheelset, torque staircase (FASTSIM contacts)", fontsize=10)
    a.legend(fontsize=7, loc="lower right")

    a = ax[1, 1]
    for flange, (a_ref, rows) in lc.items():
        for label, _, _ in SCHEMES:
            pts = [(h / lim_lc, abs(amp / a_ref - 1) * 100) for lab, h, amp in rows
                   if lab == label and amp == amp]
            if pts:
                x, y = zip(*pts)
                a.plot(x, np.maximum(y, 1e-3), "s-" if flange else "o-", color=colors[label],
                       label=f"{label}{', flange' if flange else ', saturation'}")
    a.axvline(1.0, color="0.5", ls=":")
    a.axvline(RATIO, color="0.5", ls="--")
    a.axhline(1.0, color="0.5", lw=0.8)
    a.set_xscale("log")
    a.set_yscale("log")
    a.set_xticks([0.2, 0.5, 1, 2, 3, 5], ["0.2", "0.5", "1", "2", "3", "5"])
    a.minorticks_off()
    a.set_xlabel("communication step / explicit limit at 1.1 V_c")
    a.set_ylabel("|limit-cycle amplitude error| (%)")
    a.set_title("Limit cycle at 1.1 V_c (FASTSIM contacts; missing: diverged)", fontsize=10)
    a.legend(fontsize=7)
    for x in ax.flat:
        x.grid(alpha=0.3)
    fig.suptitle("Linearly implicit coupling (master.py) against the explicit limit")
    fig.tight_layout()
    fig.savefig(out / "implicit_coupling.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
