"""``make run``: adhesion with falling friction, the creep-force curve and the driven wheelset.

    python examples/adhesion.py [--out out] [--dist dist/wheelsets] [--no-build]

1. The adhesion curve Fx/(μ0 N) against the creepage of the driven wheelset's contact (a 0.46 m
   wheel on a 0.3 m rail crown, 50 kN, μ0 = 0.3) with the default falling-friction law
   (``contact_core.FrictionLaw()``: Polach's exponential law, A = 0.38, B = 0.7 s/m, as in
   CONTACT's tractcurv example) at several rolling speeds, every method that takes the effect
   (Polach's method, FASTSIM with the local law and with one coefficient at the creep velocity,
   the table and the exact theory with the local law), and Coulomb friction:
   ``out/adhesion_curve.png``.
2. The driven wheelset (``wheelsets.driven_wheel``, V = 20 m/s held) under a drive torque
   ramped to 98 % of the Coulomb adhesion limit μ0 W r0, above the peak of the falling curve,
   coupled to two contact FMUs with Polach's method: with Coulomb friction (scene
   ``traction``) the creepage settles; with falling friction (scene ``traction_falling``, the
   rolling speed from the wheelset) the wheel runs away into macro-slip; with the slip controller
   (``wheelsets.slip_control``, holding the creepage at the falling curve's peak) it does not,
   at the cost of the torque it cuts: ``out/adhesion_runs.png`` and a summary on stdout.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from wheelsets.build import build_contact, build_wheelsets, contact_fmu_name  # noqa: E402
from wheelsets.scripts import command_line  # noqa: E402
from wheelsets.systems import make_system  # noqa: E402

import contact_core as cc  # noqa: E402

E, NU, MU, N_WHEEL, R0, R_RAIL = 210e9, 0.28, 0.3, 50e3, 0.46, 0.3
V_DRIVE, I_Y = 20.0, 120.0
T_LIMIT = MU * 2 * N_WHEEL * R0            # Coulomb adhesion limit of the wheelset, N m
LEVEL, RAMP, STOP, STEP = 0.98, 0.2, 0.8, 1e-4
FALLING = ("longitudinal", "saturation", "falling_friction")
#: The methods of the adhesion curve: (label, method, options).
CURVES = (("Polach", "polach", {}), ("FASTSIM, local law", "fastsim", {}),
          ("FASTSIM, creep velocity", "fastsim", {"falling": "creep"}),
          ("table (creep velocity)", "table", {}),
          ("exact 32x32, local law", "exact", {"mx": 32, "my": 32, "extrapolate": False}))


def contact() -> dict:
    p = cc.hertz_from_radii(N_WHEEL, R0, math.inf, R_RAIL, E, NU)
    return dict(eta=0.0, phi=0.0, N=N_WHEEL, mu=MU, a=p.a, b=p.b, G=cc.shear_modulus(E, NU),
                nu=NU)


def adhesion(method: str, xis: np.ndarray, V: float | None, **options) -> np.ndarray:
    """Fx/(μ0 N) of ``method`` along ``xis`` (braking creepage, ξ > 0) at rolling speed V
    (None: Coulomb friction), warm-started along the curve."""
    case = contact()
    effects = FALLING if V is not None else ("longitudinal", "saturation")
    out, r = [], None
    for xi in xis:
        kw = dict(V=V) if V is not None else {}
        r = cc.solve(method, xi=float(xi), effects=effects, warm_start=r, **case, **kw,
                     **options)
        out.append(-r.Fx / (MU * N_WHEEL))
    return np.array(out)


def plot_curves(out: Path) -> dict:
    xis = np.linspace(0.0, 0.06, 121)
    peaks = {}
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 4.8))
    ax1.plot(100 * xis, adhesion("polach", xis, None), "k--", label="Coulomb (Polach)")
    for label, method, opts in CURVES:
        f = adhesion(method, xis, V_DRIVE, **opts)
        peaks[label] = (float(f.max()), float(xis[int(np.argmax(f))]))
        ax1.plot(100 * xis, f, label=label)
    ax1.set(xlabel="creepage ξ, %", ylabel="Fx / (μ0 N)",
            title=f"falling friction at V = {V_DRIVE:g} m/s")
    ax1.legend(fontsize=8)
    for V in (5.0, 10.0, 20.0, 40.0):
        ax2.plot(100 * xis, adhesion("polach", xis, V), label=f"V = {V:g} m/s")
    ax2.set(xlabel="creepage ξ, %", ylabel="Fx / (μ0 N)",
            title="Polach's method: the curve falls faster at higher speed")
    ax2.legend(fontsize=8)
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "adhesion_curve.png", dpi=120)
    plt.close(fig)
    return peaks


def torque(t: float) -> float:
    return LEVEL * T_LIMIT * min(1.0, t / RAMP)


def run(dist: Path, scene: str, xi_target: float = 0.0):
    params = {"V": V_DRIVE, "I_y": I_Y, "xi_target": xi_target}
    sim = make_system(dist / "DrivenWheelsetFMU.fmu",
                      dist / f"{contact_fmu_name(scene, 'polach')}.fmu", params,
                      inputs={"wheelset.torque": torque},
                      rolling_speed=scene == "traction_falling")
    try:
        return sim.run(STOP, STEP, record=["wheelset.xi", "wheelset.torque_applied",
                                           "wheelset.adhesion"], record_every=10)
    finally:
        sim.free()


def main(argv: list[str] | None = None) -> int:
    out, dist, build_fmus = command_line(__doc__, argv)
    peaks = plot_curves(out)
    print(f"adhesion peaks at V = {V_DRIVE:g} m/s (Fx/(mu0 N) at creepage):")
    for label, (f, xi) in peaks.items():
        print(f"  {label:<26} {f:.3f} at {100 * xi:.2f} %")
    if build_fmus:
        build_wheelsets(dist)
        for scene in ("traction", "traction_falling"):
            build_contact(scene, "polach", dist)
    f_peak, xi_peak = peaks["Polach"]
    runs = {"Coulomb friction": run(dist, "traction"),
            "falling friction": run(dist, "traction_falling"),
            "falling friction, slip control": run(dist, "traction_falling", xi_peak)}
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for label, r in runs.items():
        t = r["time"]
        axes[0].plot(t, -100 * r["wheelset.xi"], label=label)
        axes[1].plot(t, r["wheelset.torque_applied"] / T_LIMIT, label=label)
        axes[2].plot(t, r["wheelset.adhesion"] / MU, label=label)
    axes[0].axhline(100 * xi_peak, color="k", lw=0.6, ls=":")
    axes[0].set(xlabel="t, s", ylabel="-ξ, %", title="creepage (traction: ξ < 0)", yscale="log")
    axes[1].set(xlabel="t, s", ylabel="T / (μ0 W r0)", title="drive torque applied")
    axes[2].axhline(f_peak, color="k", lw=0.6, ls=":")
    axes[2].set(xlabel="t, s", ylabel="ΣFx / (μ0 W)", title="adhesion used")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "adhesion_runs.png", dpi=120)
    plt.close(fig)
    print(f"driven wheelset, torque {LEVEL:.2f} mu0 W r0 (falling peak {f_peak:.3f} at "
          f"{100 * xi_peak:.2f} %), V = {V_DRIVE:g} m/s, step {STEP:g} s:")
    for label, r in runs.items():
        print(f"  {label:<32} creepage at {STOP:g} s: {-100 * r['wheelset.xi'][-1]:7.3f} %, "
              f"torque {r['wheelset.torque_applied'][-1] / T_LIMIT:.3f} mu0 W r0")
    print(f"-> {out / 'adhesion_curve.png'}, {out / 'adhesion_runs.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
