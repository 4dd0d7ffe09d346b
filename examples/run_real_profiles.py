"""``make run`` driver: the reference wheelsets on real profiles — new S1002 wheels on new UIC60
rails 1:40, gauge 1435 mm — each coupled to four contact FMUs (scene ``vehicle``: left and right
tread and flange patches, their geometry from the wheelset at every step); plots and a summary in
``out/``.

    python examples/run_real_profiles.py [--out out] [--dist dist/wheelsets] [--no-build]

Runs, every one with the ``table`` contact method and the main ones again with ``exact`` (16 × 16
grid, no extrapolation):

1. the critical speed: the linear estimate (``wheelsets.profile_linear``: the linear wheelset
   with the equivalent conicity, gravitational stiffness and contact-angle spin of the table, by
   harmonic linearisation, at the amplitude where it is lowest) against the co-simulation's
   nonlinear critical speed, the lowest speed at which a 1 mm disturbance does not die out;
2. hunting limit cycles above it (amplitude against speed, with the linear estimate's critical
   speed at each amplitude), up to flange contact;
3. a curve sweep at 15 m/s: the outer wheel's two-point contact, the flange patch's load and
   lateral force, and Y/Q against Nadal's limit.

Writes ``out/real_profile_hunting.png``, ``out/real_profile_bifurcation.png``,
``out/real_profile_curving.png`` and ``out/real_profile_summary.md``.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from contact_core.geometry.table import COLUMNS
# the reference wheelset models, next to this script (its folder is on sys.path when it runs)
from wheelsets.build import build_contact, build_profile_wheelsets, contact_fmu_name
from wheelsets.profile_linear import ProfileLinearWheelset
from wheelsets.profile_systems import (bundled_table, contact_start, make_system,
                                       recommended_step)
from wheelsets.scripts import command_line, machine_note

CONTACT = contact_fmu_name("vehicle", "table")
TANGENT, CURVING = "TangentTrackProfileWheelset", "CurvingProfileWheelset"
MU, W = 0.3, 100e3
#: below this amplitude over the last half second a disturbance has died out, m
DECAYED = 5e-5
#: a hunting motion whose amplitude over the last second is at least this fraction of the
#: second's before is sustained (a limit cycle); between the two: still decaying
SUSTAINED = 0.98
HUNT_RECORD = ("wheelset.y", "wheelset.psi", "wheelset.vy", "wheelset.F_flange",
               "wheelset.N_Lf", "wheelset.N_Rf", "wheelset.lifted", "wheelset.Q_L",
               "wheelset.Y_L", "wheelset.Q_R", "wheelset.Y_R")
CURVE_RECORD = ("wheelset.y", "wheelset.psi", "wheelset.F_flange", "wheelset.lifted",
                "wheelset.N_Lt", "wheelset.N_Lf", "wheelset.N_Rt", "wheelset.N_Rf",
                "wheelset.delta_Lf", "wheelset.delta_Rf", "wheelset.Q_L", "wheelset.Y_L",
                "wheelset.Q_R", "wheelset.Y_R", "contact_Lf.Fx", "contact_Lf.Fy", "contact_Lt.Fx",
                "contact_Lt.Fy", "contact_Rt.Fx", "contact_Rt.Fy")


def build(dist: Path) -> None:
    build_profile_wheelsets(dist)
    build_contact("vehicle", "table", dist)


def simulate(dist: Path, fmu: str, params: dict, method: str, T: float, h: float,
             record) -> tuple:
    """One run: (result, wall time per simulated second)."""
    n = max(1, math.ceil(T / h - 1e-9))
    sim = make_system(dist / f"{fmu}.fmu", dist / f"{CONTACT}.fmu", params, contact_start(method))
    try:
        r = sim.run(n * h, h, record=list(record))
    finally:
        sim.free()
    return r, r.wall_time / (n * h)


def amplitude(r, window: float = 0.5, before: float = 0.0) -> float:
    """max |y| over the ``window`` seconds that end ``before`` seconds before the end, m."""
    t = r["time"]
    end = t[-1] - before
    return float(np.abs(r["wheelset.y"][(t >= end - window) & (t <= end)]).max())


def fate(r) -> str:
    """"decayed", "hunting" (sustained) or "decaying" (neither yet)."""
    if amplitude(r) < DECAYED:
        return "decayed"
    return ("hunting" if amplitude(r, 1.0) >= SUSTAINED * amplitude(r, 1.0, before=1.0)
            else "decaying")


# -- 1, 2: critical speed and limit cycles --------------------------------------------------------
def linear_estimates(table, r0: float) -> tuple[np.ndarray, np.ndarray]:
    """The linear estimate's critical speed at each amplitude (m) of a grid up to the flange."""
    amps = np.arange(5e-5, 6.3e-3, 2e-5)
    return amps, np.array([ProfileLinearWheelset(table, a, r0).critical_speed() for a in amps])


def hunt(dist, table, V, method, T=4.0, y0=1e-3):
    r, cost = simulate(dist, TANGENT, {"V": V, "y0": y0}, method, T,
                       recommended_step(table, V), HUNT_RECORD)
    return {"V": V, "method": method, "r": r, "amplitude": amplitude(r), "fate": fate(r),
            "cost": cost}


def critical_speed(dist, table, V_lin) -> dict:
    """Table runs at speeds around the estimate from a 1 mm disturbance (5 s); the nonlinear
    critical speed lies between the fastest whose motion is not sustained and the slowest whose
    motion is (:func:`fate`); the two bracketing speeds again with the exact method."""
    runs = [hunt(dist, table, f * V_lin, "table", T=5.0)
            for f in (0.97, 1.0, 1.02, 1.04, 1.07)]
    hunting = [h["V"] for h in runs if h["fate"] == "hunting"]
    hi = min(hunting)
    lo = max(h["V"] for h in runs if h["V"] < hi)
    exact = [hunt(dist, table, V, "exact", T=5.0) for V in (lo, hi)]
    return {"runs": runs, "lo": lo, "hi": hi, "exact": exact}


# -- 3: curving -----------------------------------------------------------------------------------
def curve(dist, table, R, method, V=15.0, T=2.5, L_transition=3.0, start=None) -> dict:
    """The curve entered over ``L_transition`` (m) from the centred wheelset, or from the state
    ``start`` ({"y0": ..., "psi0": ...}) already in the curve."""
    params = {"V": V, "R": R, "L_transition": L_transition if start is None else 0.0,
              **(start or {})}
    r, cost = simulate(dist, CURVING, params, method, T, recommended_step(table, V),
                       CURVE_RECORD)
    last = {k: float(v[-1]) for k, v in r.data.items()}
    outer, inner = ("L", "R") if R > 0 else ("R", "L")
    sign = -1.0 if outer == "L" else 1.0         # the outer wheel pushes its rail outwards
    return {"R": R, "method": method, "r": r, "cost": cost, "last": last, "outer": outer,
            "Y/Q": sign * last[f"wheelset.Y_{outer}"] / last[f"wheelset.Q_{outer}"],
            "settled": float(np.ptp(r["wheelset.y"][r["time"] >= T - 0.1]))}


def nadal(delta: float, mu: float = MU) -> float:
    """Nadal's limit (Y/Q)_lim = (tan δ − μ)/(1 + μ tan δ) (Nadal 1896; EN 14363)."""
    t = math.tan(delta)
    return (t - mu) / (1.0 + mu * t)


def steepest_flange_angle(table) -> float:
    """The largest contact angle of a flange patch in the table (the flange face), rad."""
    d = table.data
    present = d[:, COLUMNS.index("right.1.present")] > 0.5
    return float(np.abs(d[present, COLUMNS.index("right.1.delta")]).max())


def tread_end(table) -> float:
    """The smallest shift beyond the flange's onset at which the right wheel's tread slot is
    absent (its gap has no minimum of its own), m."""
    d = table.data
    absent = (d[:, COLUMNS.index("right.0.present")] < 0.5) & (table.y > table.flange_onset())
    return float(table.y[absent][0])


def steepest_climb(table) -> float:
    """The largest rise of the wheelset per lateral shift with both wheels on their rails,
    −dz/dy (the rigid contact's climb up a flange)."""
    return float(-table.interpolant.derivative()(table.y)[:, COLUMNS.index("z")].min())


# -- plots and summary ----------------------------------------------------------------------------
def plot(out, table, crit, cycles, amps, vc, curves, R_exact, limit):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    pick = [h for h in crit["runs"] if h["V"] in (crit["lo"], crit["hi"])]
    for h in pick + [c for c in cycles if c["method"] == "table"][-2:]:
        r = h["r"]
        ax[0].plot(r["time"], r["wheelset.y"] * 1e3, lw=0.8,
                   label=f"V = {h['V']:.1f} m/s ({h['method']})")
    face = table.flange_contact() * 1e3
    ax[0].axhline(face, color="0.5", ls=":", lw=0.8)
    ax[0].axhline(-face, color="0.5", ls=":", lw=0.8, label=f"flange face (±{face:.2f} mm)")
    ax[0].set_ylabel("y (mm)")
    ax[0].legend(fontsize=7, ncol=2)
    fast = [c for c in cycles if c["method"] == "table"][-1]
    r = fast["r"]
    ax[1].plot(r["time"], r["wheelset.N_Lf"] / 1e3, lw=0.8, label="left flange N")
    ax[1].plot(r["time"], r["wheelset.N_Rf"] / 1e3, lw=0.8, label="right flange N")
    ax[1].plot(r["time"], r["wheelset.F_flange"] / 1e3, lw=0.8,
               label="flange patches' lateral force")
    ax[1].set_ylabel(f"kN (V = {fast['V']:.0f} m/s)")
    ax[1].legend(fontsize=7)
    for c in cycles:
        if c["V"] == cycles[-2]["V"]:
            ax[2].plot(c["r"]["time"], c["r"]["wheelset.y"] * 1e3, lw=0.8,
                       label=f"V = {c['V']:.0f} m/s, {c['method']}")
    ax[2].set_ylabel("y (mm)")
    ax[2].set_xlabel("t (s)")
    ax[2].legend(fontsize=7)
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle("Wheelset on S1002/UIC60 1:40, four contact FMUs: hunting")
    fig.tight_layout()
    fig.savefig(out / "real_profile_hunting.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 5))
    ax.plot(vc, amps * 1e3, color="0.3", label="linear estimate at amplitude A")
    for method, marker in (("table", "o"), ("exact", "s")):
        pts = [(h["V"], h["amplitude"]) for h in crit["runs"] + crit["exact"] + cycles
               if h["method"] == method]
        ax.plot([p[0] for p in pts], [p[1] * 1e3 for p in pts], marker, mfc="none",
                label=f"co-simulation, {method}: amplitude at the end")
    ax.axvspan(crit["lo"], crit["hi"], color="C2", alpha=0.2, label="nonlinear critical speed")
    ax.set(xlabel="V (m/s)", ylabel="hunting amplitude (mm)", xlim=(20, 90), ylim=(0, 7))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Limit cycles against the linear estimate (harmonic linearisation)")
    fig.tight_layout()
    fig.savefig(out / "real_profile_bifurcation.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(2, 2, figsize=(12, 8))
    for c in curves:
        if c["R"] == R_exact:
            r = c["r"]
            ax[0, 0].plot(r["time"], r["wheelset.y"] * 1e3, label=f"y, {c['method']}")
            ax[0, 0].plot(r["time"], r["wheelset.psi"] * 1e3, "--",
                          label=f"ψ (mrad), {c['method']}")
            for p in ("Lt", "Lf", "Rt"):
                ax[0, 1].plot(r["time"], r[f"wheelset.N_{p}"] / 1e3,
                              "-" if c["method"] == "table" else "--",
                              label=f"N_{p}, {c['method']}")
    ax[0, 0].set(xlabel="t (s)", ylabel="mm",
                 title=f"R = {R_exact:.0f} m, V = 15 m/s, entry over 3 m")
    ax[0, 1].set(xlabel="t (s)", ylabel="normal load (kN)",
                 title="patches: left = outer (t tread, f flange)")
    table_curves = sorted((c for c in curves if c["method"] == "table"), key=lambda c: -c["R"])
    Rs = [c["R"] for c in table_curves]
    for p, label in (("Lt", "outer tread"), ("Lf", "outer flange"), ("Rt", "inner tread")):
        ax[1, 0].plot(Rs, [c["last"][f"wheelset.N_{p}"] / 1e3 for c in table_curves], "o-",
                      label=label)
    ax[1, 0].set(xscale="log", xlabel="curve radius R (m)", ylabel="normal load (kN)",
                 title="steady curving: two-point contact on the outer wheel")
    ax[1, 1].plot(Rs, [c["Y/Q"] for c in table_curves], "o-", label="outer wheel Y/Q")
    ax[1, 1].set(xscale="log", xlabel="curve radius R (m)", ylabel="Y/Q",
                 title=f"outer wheel's Y/Q (Nadal's limit {limit:.2f}, off the scale)")
    for a in ax.flat:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "real_profile_curving.png", dpi=110)
    plt.close(fig)


def summary(table, r0, A_fold, V_lin, crit, cycles, amps, vc, curves, R_exact, delta_max,
            climb, timings) -> str:
    L = ["# Wheelsets on real profiles: S1002 on UIC60 1:40 with four contact FMUs\n"]
    gam = table.equivalent_conicity([3e-4, 1e-3, 3e-3])
    L.append(
        "Set-up: new S1002 wheels, new UIC60 rails inclined 1:40, gauge 1435 mm at 14 mm below the "
        f"top of rail, flange-back distance 1360 mm, r0 = {r0:.2f} m (the Manchester Contact "
        f"Benchmark's), contact-geometry table ±{table.y[-1] * 1e3:.0f} mm every "
        f"{(table.y[1] - table.y[0]) * 1e3:.2f} mm shipped in the wheelset FMUs. "
        "Wheelset m = 1500 kg, I_z = 800 kg m², axle load 100 kN, k_y = 1 MN/m, "
        "k_ψ = 2 MN m/rad, no damping. Contact FMUs: scene `vehicle` (A, B inputs), μ = 0.3, "
        "E = 210 GPa, ν = 0.28; `table` (patches with a/b > 10, on the flange face, solved by "
        "the exact method as the table always does) and `exact` 16 × 16 without extrapolation. "
        "Gauss-Seidel master (contacts, then wheelset).\n")
    L.append(f"Equivalent conicity (EN 15302): {gam[0]:.3f} at 0.3 mm, {gam[1]:.3f} at 1 mm, "
             f"{gam[2]:.3f} at 3 mm; the rolling-radius difference jumps near y = ±0.25 mm "
             f"(contact-point jump), the flange starts to carry load at "
             f"{table.flange_onset() * 1e3:.2f} mm.\n")
    L.append("## 1. Critical speed\n")
    L.append(f"- Linear estimate (the linear wheelset with γ_e(A), the gravitational stiffness and "
             f"the contact-angle spin of the table at amplitude A, Kalker's coefficients of the "
             f"centred contact), lowest over A ≤ 3 mm: **V = {V_lin:.2f} m/s at A = "
             f"{A_fold * 1e3:.2f} mm** (just beyond the jump; "
             f"{vc[np.argmin(np.abs(amps - 3e-3))]:.1f} m/s at 3 mm).")
    L.append(f"- Co-simulation (table), 1 mm disturbance, 5 s: not sustained at "
             f"{crit['lo']:.2f} m/s, a limit cycle at {crit['hi']:.2f} m/s: **nonlinear critical "
             f"speed {crit['lo']:.2f} … "
             f"{crit['hi']:.2f} m/s**, {100 * (crit['lo'] / V_lin - 1):+.1f} … "
             f"{100 * (crit['hi'] / V_lin - 1):+.1f} % from the estimate.")
    ex = ", ".join(f"{h['V']:.2f} m/s: {h['amplitude'] * 1e3:.3f} mm, {h['fate']}"
                   for h in crit["exact"])
    L.append(f"- Exact (5 s) at the two bracketing speeds: {ex}.\n")
    L.append("Fate: decayed below 0.05 mm; hunting if the amplitude over the last second is at "
             f"least {SUSTAINED:.0%} of the second's before; else still decaying.\n")
    L.append("| V (m/s) | V / estimate | method | amplitude, last 0.5 s (mm) | fate |")
    L.append("|---|---|---|---|---|")
    for h in crit["runs"] + crit["exact"]:
        L.append(f"| {h['V']:.2f} | {h['V'] / V_lin:.2f} | {h['method']} | "
                 f"{h['amplitude'] * 1e3:.3f} | {h['fate']} |")
    L.append("\n## 2. Limit cycles above the critical speed\n")
    L.append("| V (m/s) | method | amplitude (mm) | estimate's V at that amplitude (m/s) | "
             "max flange N (kN) | max flange lateral force (kN) | wheel lifted |")
    L.append("|---|---|---|---|---|---|---|")
    for c in cycles:
        r = c["r"]
        a = c["amplitude"]
        v_at = float(np.interp(a, amps, vc)) if a <= amps[-1] else math.nan
        last = r["time"] >= r["time"][-1] - 0.5
        nf = max(r["wheelset.N_Lf"][last].max(), r["wheelset.N_Rf"][last].max())
        L.append(f"| {c['V']:.0f} | {c['method']} | {a * 1e3:.2f} | {v_at:.1f} | {nf / 1e3:.0f} | "
                 f"{np.abs(r['wheelset.F_flange'][last]).max() / 1e3:.0f} | "
                 f"{'yes' if r['wheelset.lifted'][last].max() > 0 else 'no'} |")
    top = max(c["amplitude"] for c in cycles)
    L.append(
        f"\nLargest amplitude {top * 1e3:.2f} mm: within the flangeway. Where the cycle reaches "
        f"the flange the rigid contact geometry climbs steeply (the wheelset rises up to "
        f"{climb:.0f} mm per mm of lateral shift at the flange face): the impacts are stopped by "
        "the flange patch's normal load, with the other wheel unloaded (`lifted`: the roll "
        "equilibrium cannot hold both wheels down); their peak forces are those of a rigid "
        "track, an upper bound (the track's lateral flexibility is not modelled).\n")
    L.append("## 3. Curving (15 m/s, balance speed, curve entered over 3 m, 2.5 s; exact: "
             "0.5 s from the table's steady state)\n")
    lim = nadal(delta_max)
    L.append(f"Nadal's limit (Y/Q)_lim = (tan δ − μ)/(1 + μ tan δ) (Nadal 1896; EN 14363) at the "
             f"steepest flange contact angle of the table, δ = {delta_max:.3f} rad "
             f"({math.degrees(delta_max):.1f}°), μ = {MU}: **{lim:.2f}**.\n")
    L.append("| R (m) | method | y (mm) | ψ (mrad) | N outer tread (kN) | N outer flange (kN) | "
             "δ flange (rad) | flange lateral force (kN) | N inner tread (kN) | Q outer (kN) | "
             "Y outer (kN) | Y/Q outer | settled (µm) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for c in sorted(curves, key=lambda c: (-c["R"], c["method"])):
        s, o = c["last"], c["outer"]
        inner = "R" if o == "L" else "L"
        L.append(f"| {c['R']:.0f} | {c['method']} | {s['wheelset.y'] * 1e3:.3f} | "
                 f"{s['wheelset.psi'] * 1e3:.3f} | {s[f'wheelset.N_{o}t'] / 1e3:.2f} | "
                 f"{s[f'wheelset.N_{o}f'] / 1e3:.2f} | "
                 f"{s[f'wheelset.delta_{o}f'] if s[f'wheelset.N_{o}f'] > 0 else math.nan:.3f} | "
                 f"{s['wheelset.F_flange'] / 1e3:.2f} | {s[f'wheelset.N_{inner}t'] / 1e3:.2f} | "
                 f"{s[f'wheelset.Q_{o}'] / 1e3:.2f} | {s[f'wheelset.Y_{o}'] / 1e3:.2f} | "
                 f"{c['Y/Q']:.3f} | {c['settled'] * 1e6:.1f} |")
    tab = {c["R"]: c for c in curves if c["method"] == "table"}
    exa = [c for c in curves if c["method"] == "exact"][0]
    t_ = tab[R_exact]["last"]
    e_ = exa["last"]
    dF = max(abs(t_[f"contact_{p}.{q}"] - e_[f"contact_{p}.{q}"]) / (MU * max(
        t_[f"wheelset.N_{p}"], 1.0)) for p in ("Lt", "Lf", "Rt") for q in ("Fx", "Fy"))
    L.append(f"\nR = {R_exact:.0f} m, table against exact: y {t_['wheelset.y'] * 1e3:.3f} / "
             f"{e_['wheelset.y'] * 1e3:.3f} mm, ψ {t_['wheelset.psi'] * 1e3:.3f} / "
             f"{e_['wheelset.psi'] * 1e3:.3f} mrad, outer Y/Q {tab[R_exact]['Y/Q']:.4f} / "
             f"{exa['Y/Q']:.4f}; creep forces of the loaded patches within "
             f"{100 * dF:.2f} % of μN of each other.\n")
    two = [c["R"] for c in tab.values() if c["last"][f"wheelset.N_{c['outer']}t"] > 0.0
           and c["last"][f"wheelset.N_{c['outer']}f"] > 0.0]
    end = tread_end(table)
    at_end = sorted((c["R"] for c in tab.values()
                     if abs(abs(c["last"]["wheelset.y"]) - end) <= table.y[1] - table.y[0]),
                    reverse=True)
    if at_end:
        L.append(f"At R = {', '.join(f'{R:.0f}' for R in at_end)} m the wheelset settles within "
                 f"a grid step of |y| = {end * 1e3:.2f} mm, where the outer tread's own gap "
                 "minimum vanishes (the end of the two-point contact): the table's gap of the "
                 "tread jumps there to its absent value within one grid step, so the split "
                 "between tread and flange depends on that step; the wheel's lateral force, "
                 "which balances the creep forces, does not.\n")
    L.append(f"Two-point contact on the outer wheel (tread and flange loaded) at R = "
             f"{', '.join(f'{R:.0f}' for R in sorted(two, reverse=True)) or 'none'} m. Largest "
             f"outer-wheel Y/Q {max(c['Y/Q'] for c in curves):.3f}, "
             f"{max(c['Y/Q'] for c in curves) / lim:.3f} of Nadal's limit (this wheelset's "
             "frame follows the track tangent, so its angle of attack stays small).\n")
    L.append("## Run times\n")
    L.append("| run | method | wall s per simulated s |")
    L.append("|---|---|---|")
    for label, method, cost in timings:
        L.append(f"| {label} | {method} | {cost:.2f} |")
    L.append(machine_note())
    return "\n".join(L) + "\n"


def main(argv=None) -> int:
    out, dist, build_fmus = command_line(__doc__, argv)
    t0 = time.perf_counter()
    if build_fmus:
        build(dist)
    table, r0 = bundled_table(dist / f"{TANGENT}.fmu")
    amps, vc = linear_estimates(table, r0)
    small = amps <= 3e-3
    k = int(np.argmin(np.where(small, vc, np.inf)))
    A_fold, V_lin = float(amps[k]), float(vc[k])
    crit = critical_speed(dist, table, V_lin)
    cycles = [hunt(dist, table, V, "table") for V in (35.0, 45.0, 55.0, 62.0, 75.0)]
    cycles.append(hunt(dist, table, 62.0, "exact"))
    cycles.sort(key=lambda c: (c["V"], c["method"]))
    R_exact = 150.0
    curves = [curve(dist, table, R, "table")
              for R in (1000.0, 600.0, 400.0, 300.0, 250.0, 200.0, 150.0)]
    ref = next(c for c in curves if c["R"] == R_exact)
    curves.append(curve(dist, table, R_exact, "exact", T=0.5,
                        start={"y0": ref["last"]["wheelset.y"],
                               "psi0": ref["last"]["wheelset.psi"]}))
    timings = ([(f"tangent {h['V']:.1f} m/s", h["method"], h["cost"])
                for h in crit["runs"] + crit["exact"] + cycles]
               + [(f"curve R = {c['R']:.0f} m", c["method"], c["cost"]) for c in curves])
    delta_max = steepest_flange_angle(table)
    plot(out, table, crit, cycles, amps, vc, curves, R_exact, nadal(delta_max))
    text = summary(table, r0, A_fold, V_lin, crit, cycles, amps, vc, curves, R_exact,
                   delta_max, steepest_climb(table), timings)
    text += f"\nTotal: {time.perf_counter() - t0:.0f} s (`python examples/run_real_profiles.py`).\n"
    (out / "real_profile_summary.md").write_text(text, encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
