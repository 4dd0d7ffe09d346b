"""``make run`` driver: the tangent-track wheelset below and above its critical speed, coupled to
two contact FMUs by the Gauss-Seidel master; plots and a one-page summary in ``out/``.

    python examples/run_hunting.py [--out out] [--dist dist/wheelsets] [--no-build]

Writes ``out/hunting_y.png`` (y(t)), ``out/hunting_psi.png`` (ψ(t)), ``out/hunting_limit_cycle.png``
(phase portraits y-ψ and y-ẏ of the FASTSIM limit cycle), ``out/hunting_step.png`` (too large a
communication step) and ``out/hunting_summary.md``: V_c from the eigenvalues vs. the
co-simulation, Klingel's wavelength, the step-size limits, wall time per simulated second per
method.
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
# the reference wheelset models, next to this script (its folder is on sys.path when it runs)
from wheelsets.analysis import fit_damped
from wheelsets.build import build_contact, build_wheelsets, contact_fmu_name
from wheelsets.linear_model import LinearWheelset
from wheelsets.scripts import command_line, machine_note
from wheelsets.systems import (driven_time_constant, lateral_time_constant, make_system,
                               recommended_step)


CONTACTS = [("tangent_track", "linear"), ("full", "linear"), ("full", "johnson_vermeulen"),
            ("full", "fastsim"), ("full", "exact")]
BUILD = CONTACTS + [("traction", "fastsim"), ("traction", "exact")]
K_Y, K_PSI = 1.0e6, 2.0e6


def build(dist: Path) -> None:
    build_wheelsets(dist)
    for scene, method in BUILD:
        build_contact(scene, method, dist)


def time_per_second(run, h, budget=6.0):
    """Median wall time per simulated second of ``run(T)`` (3 repeats; fewer and shorter when a
    step is expensive, keeping each repeat near ``budget`` seconds). Returns (s per s, steps)."""
    warm = run(10 * h)                       # compiles (numba) and measures the cost of a step
    per_step = max(warm.wall_time / warm.steps, 1e-6)
    steps = int(min(1000, max(10, budget / per_step)))
    reps = 3 if per_step * steps * 3 < 3 * budget else 1
    walls = [run(steps * h).wall_time / (steps * h) for _ in range(reps)]
    return float(np.median(walls)), steps * reps


def wheelset_params(V, **extra):
    return dict(V=V, k_y=K_Y, k_psi=K_PSI, y0=1e-3, **extra)


def run_case(dist, method, V, T, h, scene="full", record=("wheelset.y", "wheelset.psi",
                                                           "wheelset.vy"), **extra):
    sim = make_system(dist / "TangentTrackWheelset.fmu",
                      dist / f"{contact_fmu_name(scene, method)}.fmu", wheelset_params(V, **extra))
    try:
        return sim.run(T, h, record=list(record), abort_above={"wheelset.y": 1.0})
    finally:
        sim.free()


def critical_speed(dist: Path, lw: LinearWheelset) -> tuple[list, float]:
    """1. Linear contact FMUs at 0.9..1.1 V_c: decay/growth and frequency against the
    eigenvalues, and V_c where the fitted growth rate crosses zero."""
    Vc = lw.critical_speed()
    rows = []
    sig = {}
    for fac in (0.9, 0.95, 1.0, 1.05, 1.1):
        V = fac * Vc
        h = recommended_step(lateral_time_constant(V))
        r = run_case(dist, "linear", V, 1.5, h, scene="tangent_track")
        m = r["time"] > 0.3
        s, w = fit_damped(r["time"][m], r["wheelset.y"][m])
        ev = lw.hunting_eigenvalue(V)
        sig[fac] = s
        rows.append((fac, V, h, ev.real, s, ev.imag / (2 * np.pi), w / (2 * np.pi),
                     (w - ev.imag) / ev.imag))
    facs = np.array(sorted(sig))
    sigs = np.array([sig[f] for f in facs])
    k = np.where(np.diff(np.sign(sigs)) > 0)[0][0]
    Vc_cosim = Vc * (facs[k] - sigs[k] * (facs[k + 1] - facs[k]) / (sigs[k + 1] - sigs[k]))

    return rows, Vc_cosim


def klingel(dist: Path) -> tuple[float, float, float, float]:
    """2. Klingel's kinematic wavelength on very soft springs: (V, h, wavelength, Klingel's)."""
    Vk = 10.0
    hk = recommended_step(lateral_time_constant(Vk))
    sim = make_system(dist / "TangentTrackWheelset.fmu",
                      dist / f"{contact_fmu_name('tangent_track', 'linear')}.fmu",
                      dict(V=Vk, k_y=1e3, k_psi=1e3, y0=2e-3))
    try:
        rk = sim.run(2.2, hk, record=["wheelset.y"])
    finally:
        sim.free()
    t, y = rk["time"], rk["wheelset.y"]
    i = np.where((y[:-1] < 0) & (y[1:] >= 0))[0]
    cross = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    wavelength = Vk * float(np.mean(np.diff(cross))) if len(cross) > 1 else float("nan")
    klingel = 2 * math.pi * math.sqrt(0.46 * 0.75 / 0.15)

    return Vk, hk, wavelength, klingel


def fastsim_runs(dist: Path, Vc: float) -> tuple[dict, object, float]:
    """3. FASTSIM contacts below and above V_c (a limit cycle), and with a flange spring."""
    T_fs = 6.0
    fs = {}
    for fac in (0.9, 1.1):
        V = fac * Vc
        h = recommended_step(lateral_time_constant(V))
        fs[fac] = run_case(dist, "fastsim", V, T_fs, h,
                           record=("wheelset.y", "wheelset.psi", "wheelset.vy", "contact_L.Fx",
                                   "contact_L.Fy", "contact_L.slip_fraction"))
    V = 1.1 * Vc
    fs_fl = run_case(dist, "fastsim", V, T_fs, recommended_step(lateral_time_constant(V)),
                     flange_gap=8e-3, k_flange=15e6,
                     record=("wheelset.y", "wheelset.psi", "wheelset.vy", "wheelset.F_flange"))

    return fs, fs_fl, T_fs


def step_runs(dist: Path, lw: LinearWheelset, Vc: float) -> tuple[float, float, float, float,
                                                                  dict]:
    """4. Communication steps around the stability limits of the coupling: (V, τ, Gauss-Seidel
    limit, Jacobi limit, runs by label)."""
    Vs = 0.9 * Vc
    tau = lw.tau(Vs)
    lim_gs, lim_j = lw.step_limit(Vs), lw.step_limit(Vs, "jacobi")
    runs = {}
    for label, h, scheme in ((f"Gauss-Seidel h = {0.25 * tau * 1e3:.2f} ms (τ/4)", 0.25 * tau, "gauss-seidel"),
                             (f"Jacobi h = {1.3 * lim_j * 1e3:.2f} ms (1.3× Jacobi limit)", 1.3 * lim_j, "jacobi"),
                             (f"Gauss-Seidel h = {1.3 * lim_j * 1e3:.2f} ms (same h)", 1.3 * lim_j, "gauss-seidel"),
                             (f"Gauss-Seidel h = {1.15 * lim_gs * 1e3:.2f} ms (1.15× GS limit)", 1.15 * lim_gs, "gauss-seidel")):
        n = int(round(0.6 / h))
        sim = make_system(dist / "TangentTrackWheelset.fmu",
                          dist / f"{contact_fmu_name('tangent_track', 'linear')}.fmu",
                          wheelset_params(Vs), scheme=scheme)
        try:
            runs[label] = (h, scheme, sim.run(n * h, h, record=["wheelset.y"],
                                                   abort_above={"wheelset.y": 0.05}))
        finally:
            sim.free()

    return Vs, tau, lim_gs, lim_j, runs


def wall_times(dist: Path, Vc: float) -> tuple[list, list]:
    """5. Wall time per simulated second per contact method (tangent track; driven wheelset)."""
    timing = []
    for scene, method in CONTACTS:
        V = 1.1 * Vc
        h = recommended_step(lateral_time_constant(V))
        timing.append((scene, method, h) + time_per_second(
            lambda T: run_case(dist, method, V, T, h, scene=scene), h))
    traction_timing = []
    Vd = 20.0
    hd = recommended_step(driven_time_constant(Vd))
    t_lim = 0.3 * 100e3 * 0.46
    for method in ("fastsim", "exact"):
        def drive(T, method=method):
            sim = make_system(dist / "DrivenWheelsetFMU.fmu",
                              dist / f"{contact_fmu_name('traction', method)}.fmu", {"V": Vd},
                              inputs={"wheelset.torque": lambda t: 0.8 * t_lim})
            try:
                return sim.run(T, hd, record=["wheelset.xi"])
            finally:
                sim.free()
        traction_timing.append(("traction", method, hd) + time_per_second(drive, hd))

    return timing, traction_timing


def plot(out: Path, Vc: float, fs: dict, fs_fl, T_fs: float, steps: dict, Vs: float,
         tau: float) -> None:
    """hunting_y.png, hunting_psi.png, hunting_limit_cycle.png, hunting_step.png."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    for fac, r in fs.items():
        ax[0].plot(r["time"], r["wheelset.y"] * 1e3, label=f"V = {fac:.1f} V_c = {fac * Vc:.1f} m/s")
        ax[1].plot(r["time"], r["wheelset.psi"] * 1e3, label=f"V = {fac:.1f} V_c")
    ax[0].plot(fs_fl["time"], fs_fl["wheelset.y"] * 1e3, lw=0.8, alpha=0.7,
               label="1.1 V_c, flange contact (gap 8 mm)")
    ax[0].set_ylabel("y (mm)"); ax[1].set_ylabel("ψ (mrad)"); ax[1].set_xlabel("t (s)")
    ax[0].legend(fontsize=8); ax[0].grid(alpha=0.3); ax[1].grid(alpha=0.3)
    fig.suptitle(f"Tangent-track wheelset + FASTSIM contact FMUs (linear V_c = {Vc:.1f} m/s)")
    fig.tight_layout(); fig.savefig(out / "hunting_y.png", dpi=110); plt.close(fig)

    fig, ax = plt.subplots(figsize=(9, 3.5))
    for fac, r in fs.items():
        ax.plot(r["time"], r["wheelset.psi"] * 1e3, label=f"V = {fac:.1f} V_c")
    ax.set_xlabel("t (s)"); ax.set_ylabel("ψ (mrad)"); ax.grid(alpha=0.3); ax.legend()
    fig.tight_layout(); fig.savefig(out / "hunting_psi.png", dpi=110); plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    r = fs[1.1]
    last = r["time"] > T_fs - 1.0
    ax[0].plot(r["wheelset.y"] * 1e3, r["wheelset.psi"] * 1e3, lw=0.5, color="0.7", label="transient")
    ax[0].plot(r["wheelset.y"][last] * 1e3, r["wheelset.psi"][last] * 1e3, lw=1.5, label="last 1 s (limit cycle)")
    l2 = fs_fl["time"] > T_fs - 1.0
    ax[0].plot(fs_fl["wheelset.y"][l2] * 1e3, fs_fl["wheelset.psi"][l2] * 1e3, lw=1.2,
               label="with flange contact")
    ax[0].set_xlabel("y (mm)"); ax[0].set_ylabel("ψ (mrad)"); ax[0].legend(fontsize=8)
    ax[1].plot(r["wheelset.y"][last] * 1e3, r["wheelset.vy"][last], lw=1.5)
    ax[1].plot(fs_fl["wheelset.y"][l2] * 1e3, fs_fl["wheelset.vy"][l2], lw=1.2)
    ax[1].set_xlabel("y (mm)"); ax[1].set_ylabel("ẏ (m/s)")
    for x in ax:
        x.grid(alpha=0.3)
    fig.suptitle(f"Limit cycle at V = 1.1 V_c = {1.1 * Vc:.1f} m/s (FASTSIM, μ = 0.3)")
    fig.tight_layout(); fig.savefig(out / "hunting_limit_cycle.png", dpi=110); plt.close(fig)

    fig, ax = plt.subplots(figsize=(9, 4))
    for label, (h, scheme, r) in steps.items():
        ax.semilogy(r["time"], np.maximum(np.abs(r["wheelset.y"]), 1e-9), label=label)
    ax.set_xlabel("t (s)"); ax.set_ylabel("|y| (m)"); ax.grid(alpha=0.3); ax.legend(fontsize=8)
    ax.set_title(f"Communication step at V = {Vs:.1f} m/s (τ = {tau * 1e3:.2f} ms): "
                 "linear contact FMUs")
    fig.tight_layout(); fig.savefig(out / "hunting_step.png", dpi=110); plt.close(fig)



@dataclass
class Results:
    """What :func:`summary` reports (the outputs of the five experiments)."""

    lw: LinearWheelset
    Vc: float
    rows: list
    Vc_cosim: float
    Vk: float
    hk: float
    wavelength: float
    klingel: float
    fs: dict
    fs_fl: object
    T_fs: float
    Vs: float
    tau: float
    lim_gs: float
    lim_j: float
    steps: dict
    timing: list
    traction_timing: list


def summary(res: Results) -> str:
    """The one-page summary (hunting_summary.md)."""
    lw, Vc, rows, Vc_cosim = res.lw, res.Vc, res.rows, res.Vc_cosim
    lam_c = lw.hunting_eigenvalue(Vc)
    Vk, hk, wavelength, klingel_wl = res.Vk, res.hk, res.wavelength, res.klingel
    fs, fs_fl, T_fs = res.fs, res.fs_fl, res.T_fs
    Vs, tau, lim_gs, lim_j = res.Vs, res.tau, res.lim_gs, res.lim_j
    timing, traction_timing = res.timing, res.traction_timing
    amp = {fac: float(np.abs(r["wheelset.y"][r["time"] > T_fs - 1.0]).max()) for fac, r in fs.items()}
    amp_fl = float(np.abs(fs_fl["wheelset.y"][fs_fl["time"] > T_fs - 1.0]).max())
    sat = float(np.hypot(fs[1.1]["contact_L.Fx"], fs[1.1]["contact_L.Fy"]).max() / (0.3 * 50e3))
    L = []
    L.append("# Reference wheelset on tangent track: hunting with the contact FMU\n")
    L.append(f"Wheelset (Wickens 2003): r0 = 0.46 m, b0 = 0.75 m, λ = 0.15, m = 1500 kg, "
             f"I_z = 800 kg m², axle load 100 kN, k_y = {K_Y:.0e} N/m, k_ψ = {K_PSI:.0e} N m/rad; "
             "contact E = 210 GPa, ν = 0.28, μ = 0.3, rail crown 0.3 m, conical tread "
             f"(a = {lw.f['a'] * 1e3:.2f} mm, b = {lw.f['b'] * 1e3:.2f} mm, "
             f"f11 = {lw.f['f11'] / 1e6:.2f} MN, f22 = {lw.f['f22'] / 1e6:.2f} MN). "
             "Two contact FMU instances (left, right), Gauss-Seidel master "
             "(`examples/wheelsets/master.py`), communication step ≈ τ/4.\n")
    L.append("## Critical speed (linear contact FMU)\n")
    L.append(f"- Eigenvalues of the 4-state linear model: **V_c = {Vc:.2f} m/s** "
             f"({Vc * 3.6:.0f} km/h), hunting frequency {lam_c.imag / 2 / np.pi:.2f} Hz.")
    L.append(f"- Co-simulation (growth rate fitted at 0.9…1.1 V_c, zero interpolated): "
             f"**V_c = {Vc_cosim:.2f} m/s** ({(Vc_cosim - Vc) / Vc * 100:+.2f} %).\n")
    L.append("| V/V_c | V (m/s) | h (ms) | σ eigen (1/s) | σ co-sim (1/s) | f eigen (Hz) | f co-sim (Hz) | f error |")
    L.append("|---|---|---|---|---|---|---|---|")
    for fac, V, h, se, sc, fe, fc, err in rows:
        L.append(f"| {fac:.2f} | {V:.2f} | {h * 1e3:.2f} | {se:+.3f} | {sc:+.3f} | {fe:.3f} | "
                 f"{fc:.3f} | {err * 100:+.2f} % |")
    L.append("\n## Kinematic oscillation (Klingel)\n")
    L.append(f"V = {Vk} m/s, k_y = k_ψ = 1e3 (very soft), h = {hk * 1e3:.2f} ms: wavelength "
             f"{wavelength:.3f} m vs Klingel 2π√(r0 b0/λ) = {klingel_wl:.3f} m "
             f"(**error {(wavelength - klingel_wl) / klingel_wl * 100:+.2f} %**).\n")
    L.append("## FASTSIM contact FMUs (`full` scene): below and above V_c\n")
    L.append(f"- 0.9 V_c: decays (max |y| over the last second {amp[0.9] * 1e6:.2f} µm, from y0 = 1 mm).")
    L.append(f"- 1.1 V_c: grows into a limit cycle bounded by creep saturation alone: amplitude "
             f"{amp[1.1] * 1e3:.1f} mm, max |F|/μN = {sat:.3f} on the left wheel. With a flange "
             f"spring (gap 8 mm, 15 MN/m) the limit cycle is {amp_fl * 1e3:.1f} mm.")
    L.append("- Plots: `hunting_y.png`, `hunting_psi.png`, `hunting_limit_cycle.png`.\n")
    L.append("## Communication step\n")
    L.append(f"At V = {Vs:.1f} m/s the shortest creep time constant is τ = min(mV/2f22, "
             f"I_zV/2f11b0²) = {tau * 1e3:.2f} ms. The exact discrete map of the zero-order-hold "
             f"coupling is unstable above h = {lim_gs * 1e3:.2f} ms (Gauss-Seidel, ≈ 2τ) and "
             f"h = {lim_j * 1e3:.2f} ms (Jacobi, as `fmpy.ssp.simulate_ssp`, ≈ τ). Runs "
             "(`hunting_step.png`):\n")
    for label, (h, scheme, run) in res.steps.items():
        fate = (f"diverged (|y| > 5 cm at t = {run['time'][-1]:.3f} s)" if run.aborted else
                f"|y(0.6 s)| = {abs(run['wheelset.y'][-1]) * 1e3:.3f} mm")
        L.append(f"- {label}: {fate}")
    L.append("\nDefault: h = the largest round step ≤ τ/4 (`systems.recommended_step`); τ ∝ V, so "
             "low speeds need small steps.\n")
    L.append("## Wall time per simulated second (median of up to 3 runs)\n")
    L.append("| system | contact FMU (scene, method) | h (ms) | wall s per simulated s | ms per step | steps timed |")
    L.append("|---|---|---|---|---|---|")
    for label, tab in (("tangent track, 1.1 V_c", timing),
                       ("driven wheelset, T = 0.8 μWr0", traction_timing)):
        for scene, method, h, per_s, steps in tab:
            L.append(f"| {label} | {scene}, {method} | {h * 1e3:.2f} | {per_s:.3g} | "
                     f"{per_s * h * 1e3:.3g} | {steps} |")
    L.append(machine_note())
    return "\n".join(L) + "\n"


def main(argv=None) -> int:
    out, dist, build_fmus = command_line(__doc__, argv)
    if build_fmus:
        build(dist)
    lw = LinearWheelset(k_y=K_Y, k_psi=K_PSI)
    Vc = lw.critical_speed()
    rows, Vc_cosim = critical_speed(dist, lw)
    Vk, hk, wavelength, klingel_wavelength = klingel(dist)
    fs, fs_fl, T_fs = fastsim_runs(dist, Vc)
    Vs, tau, lim_gs, lim_j, steps = step_runs(dist, lw, Vc)
    timing, traction_timing = wall_times(dist, Vc)
    plot(out, Vc, fs, fs_fl, T_fs, steps, Vs, tau)
    text = summary(Results(lw, Vc, rows, Vc_cosim, Vk, hk, wavelength, klingel_wavelength, fs,
                           fs_fl, T_fs, Vs, tau, lim_gs, lim_j, steps, timing, traction_timing))
    (out / "hunting_summary.md").write_text(text, encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
