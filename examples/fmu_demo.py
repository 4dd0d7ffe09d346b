"""Build the default (full-scene) WheelRailContact FMU and simulate it once with fmpy.

    python examples/fmu_demo.py [--out DIR]

A 2 s braking run driven by an input table: the longitudinal creepage ξ ramps from 0 to 1.2 %
(braking: the wheel turns slower than it rolls, ξ > 0, and the rail pulls it back, Fx < 0) into
a slide, with a constant lateral creepage and spin, a normal load that oscillates, and a wet
patch where μ drops from 0.35 to 0.15 (variable_friction). Writes DIR/fmu_demo.csv and
DIR/fmu_demo.png (default DIR: out/) and checks the FMU's outputs against contact_core.solve:
the FMU runs the copy of contact_core it bundles, this script the installed one.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import contact_core as cc
from wheel_rail_fmu.build import build

ROOT = Path(__file__).resolve().parents[1]
GEOMETRY = dict(R_wheel=0.46, R_wheel_profile=float("inf"), R_rail_profile=0.3, E=210e9, nu=0.28)


def input_table(n: int = 201) -> np.ndarray:
    t = np.linspace(0.0, 2.0, n)
    sig = np.zeros(n, dtype=[("time", float), ("xi", float), ("eta", float), ("phi", float),
                             ("N", float), ("mu", float)])
    sig["time"] = t
    sig["xi"] = 0.006 * t            # braking: the wheel turns slower than it rolls
    sig["eta"] = 5e-4
    sig["phi"] = 0.15
    sig["N"] = 100e3 * (1.0 + 0.1 * np.sin(2 * np.pi * 3.0 * t))
    sig["mu"] = np.where((t > 0.8) & (t < 1.3), 0.15, 0.35)  # wet patch
    return sig


def _right_axis(ax, t: np.ndarray, y: np.ndarray, style: str, label: str, ylabel: str) -> None:
    """Plot ``y`` on a second y axis on the right of ``ax``; a legend for each axis."""
    twin = ax.twinx()
    twin.plot(t, y, style, label=label)
    twin.set_ylabel(ylabel)
    ax.legend(loc="upper left")
    twin.legend(loc="lower right")


def plot(res: np.ndarray, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = res["time"]
    fig, ax = plt.subplots(4, 1, sharex=True, figsize=(7.5, 9))
    ax[0].plot(t, 100 * res["xi"], label="ξ (longitudinal)")
    ax[0].plot(t, 100 * res["eta"], label="η (lateral)")
    ax[0].set_ylabel("creepage, %")
    _right_axis(ax[0], t, res["phi"], "C2", "φ (spin)", "spin φ, 1/m")
    ax[1].plot(t, res["N"] / 1e3, "k", label="N")
    ax[1].set_ylabel("normal load N, kN")
    _right_axis(ax[1], t, res["mu"], "C3", "μ", "friction μ")
    ax[2].plot(t, res["Fx"] / 1e3, label="Fx")
    ax[2].plot(t, res["Fy"] / 1e3, label="Fy")
    ax[2].plot(t, -res["mu"] * res["N"] / 1e3, "k--", lw=0.8, label="−μN")
    ax[2].set_ylabel("creep force, kN")
    ax[2].legend(loc="lower left")
    ax[3].plot(t, res["slip_fraction"], "C4")
    ax[3].set_ylabel("slip fraction of the area")
    ax[3].set_ylim(-0.02, 1.02)
    ax[3].set_xlabel("time, s")
    fig.suptitle("WheelRailContact FMU (full scene) in fmpy: braking through a wet patch\n"
                 "ξ > 0 (wheel slower than the train) gives Fx < 0; |F| saturates at μN")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    from fmpy import simulate_fmu

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default=str(ROOT / "out"))
    a = p.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)

    fmu = build("full", out=ROOT / "dist")
    print(f"built {fmu.relative_to(ROOT)} (scene 'full')")
    names = ["xi", "eta", "phi", "N", "mu", "Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction",
             "method_used"]
    res = simulate_fmu(str(fmu), start_time=0.0, stop_time=2.0, output_interval=0.01,
                       input=input_table(), output=names)

    # Each row holds the inputs its outputs were computed from: check against the core.
    method = cc.load_scene("full").default_method
    G = cc.shear_modulus(GEOMETRY["E"], GEOMETRY["nu"])
    worst = 0.0
    for row in res:
        pt = cc.hertz_from_radii(row["N"], **GEOMETRY)
        r = cc.solve(method, xi=row["xi"], eta=row["eta"], phi=row["phi"], N=row["N"],
                     mu=row["mu"], a=pt.a, b=pt.b, G=G, nu=GEOMETRY["nu"])
        for k in ("Fx", "Fy", "Mz"):
            worst = max(worst, abs(row[k] - getattr(r, k)) / max(abs(getattr(r, k)), 1e-300))
    braking = res[res["xi"] > 0]
    print(f"simulated {len(res)} samples with method {method!r}; max relative difference to "
          f"contact_core.solve: {worst:.1e}; braking (ξ > 0) gives Fx < 0 at every sample: "
          f"{bool((braking['Fx'] < 0).all())}")

    csv = out / "fmu_demo.csv"
    np.savetxt(csv, np.array(res.tolist()), delimiter=",", header=",".join(res.dtype.names),
               comments="")
    plot(res, out / "fmu_demo.png")
    print(f"wrote {csv} and {out / 'fmu_demo.png'}")
    return 0 if worst <= 1e-12 and (braking["Fx"] < 0).all() else 1


if __name__ == "__main__":
    sys.exit(main())
