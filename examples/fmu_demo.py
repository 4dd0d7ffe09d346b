"""Build the default (full-scene) WheelRailContact FMU and simulate it once with fmpy.

    python examples/fmu_demo.py [--out DIR]

A 2 s braking run driven by an input table: the longitudinal creepage ramps up to a slide, a
constant lateral creepage and spin, a normal load that oscillates, and a wet patch where μ drops
from 0.35 to 0.15 (variable_friction). Writes DIR/fmu_demo.csv and DIR/fmu_demo.png
(default DIR: out/) and checks the FMU's outputs against contact_core.solve.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import contact_core as cc  # noqa: E402
from build_fmu import build  # noqa: E402


def input_table(n: int = 201) -> np.ndarray:
    t = np.linspace(0.0, 2.0, n)
    sig = np.zeros(n, dtype=[("time", float), ("xi", float), ("eta", float), ("phi", float),
                             ("N", float), ("mu", float)])
    sig["time"] = t
    sig["xi"] = -0.006 * t           # braking: the wheel turns slower than it rolls
    sig["eta"] = 5e-4
    sig["phi"] = 0.15
    sig["N"] = 100e3 * (1.0 + 0.1 * np.sin(2 * np.pi * 3.0 * t))
    sig["mu"] = np.where((t > 0.8) & (t < 1.3), 0.15, 0.35)  # wet patch
    return sig


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
    G = cc.shear_modulus(210e9, 0.28)
    worst = 0.0
    for row in res:
        pt = cc.hertz_from_radii(row["N"], 0.46, float("inf"), 0.3, 210e9, 0.28)
        r = cc.solve(method, xi=row["xi"], eta=row["eta"], phi=row["phi"], N=row["N"],
                     mu=row["mu"], a=pt.a, b=pt.b, G=G, nu=0.28)
        for k in ("Fx", "Fy", "Mz"):
            worst = max(worst, abs(row[k] - getattr(r, k)) / max(abs(getattr(r, k)), 1e-300))
    print(f"simulated {len(res)} samples with method {method!r}; "
          f"max relative difference to contact_core.solve: {worst:.1e}")

    csv = out / "fmu_demo.csv"
    np.savetxt(csv, np.array(res.tolist()), delimiter=",", header=",".join(res.dtype.names),
               comments="")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
    ax[0].plot(res["time"], res["Fx"] / 1e3, label="Fx")
    ax[0].plot(res["time"], res["mu"] * res["N"] / 1e3, "k--", lw=0.8, label="μN")
    ax[0].set_ylabel("kN")
    ax[0].legend()
    ax[1].plot(res["time"], res["Fy"] / 1e3, label="Fy")
    ax[1].set_ylabel("kN")
    ax[1].legend()
    ax[2].plot(res["time"], res["slip_fraction"], label="slip fraction")
    ax[2].set_xlabel("time, s")
    ax[2].legend()
    fig.suptitle("WheelRailContact FMU (full scene) in fmpy: braking through a wet patch")
    fig.tight_layout()
    fig.savefig(out / "fmu_demo.png", dpi=110)
    print(f"wrote {csv.relative_to(ROOT) if csv.is_relative_to(ROOT) else csv} and fmu_demo.png")
    return 0 if worst <= 1e-12 else 1


if __name__ == "__main__":
    sys.exit(main())
