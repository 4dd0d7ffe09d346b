"""Contact geometry of new S1002 wheels on new UIC60 rails (1:40, gauge 1435 mm): the table of
vehicle codes (contact_core.geometry.contact_table) and its plots.

    python examples/contact_geometry.py [--load N] [--y-max MM]

Writes ``out/contact_geometry.png``: the rolling-radius difference Δr(y), the contact angles of
both wheels (tread and flange slots, with the flange patch's share of the load at the nominal
load), the equivalent conicity by harmonic linearisation (EN 15302) over the amplitude, and the
contact points on the rail and wheel profiles; prints the equivalent conicity at 3 mm, where the
flange starts to carry load and where the wheel runs on its flange, and how long a contact search
and a table evaluation take on this machine.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_core.geometry import benchmark_model, contact_search  # noqa: E402
from contact_core.geometry.table import contact_table  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "out"


def _time(fn, n: int) -> float:
    fn()
    t = time.perf_counter()
    for _ in range(n):
        fn()
    return (time.perf_counter() - t) / n


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--load", type=float, default=50e3, help="nominal load per wheel, N")
    ap.add_argument("--y-max", type=float, default=10.0, help="largest lateral shift, mm")
    args = ap.parse_args(argv)
    model = benchmark_model()
    table = contact_table(model, y_max=args.y_max * 1e-3, step=5e-5, load=args.load)
    y = np.linspace(table.y[0], table.y[-1], 4001)
    amp = np.linspace(0.25e-3, table.y[-1], 200)
    gamma = table.equivalent_conicity(amp)

    fig, ax = plt.subplots(2, 3, figsize=(16, 9))
    a = ax[0, 0]
    a.plot(y * 1e3, table.rolling_radius_difference(y) * 1e3)
    a.set(xlabel="lateral shift y (mm)", ylabel="Δr = r_right − r_left (mm)",
          title="rolling-radius difference (rigid contact)")
    a = ax[0, 1]
    for side, colour in (("left", "C0"), ("right", "C3")):
        for slot, style in ((0, "-"), (1, "--")):
            d = table.column(f"{side}.{slot}.delta", y)
            d[table.column(f"{side}.{slot}.present", y) < 0.5] = np.nan
            a.plot(y * 1e3, d, style, color=colour, label=f"{side}, {('tread', 'flange')[slot]}")
    a.set(xlabel="lateral shift y (mm)", ylabel="contact angle δ (rad)",
          title="contact angles (track z to the contact normal)")
    a.legend(fontsize=8)
    a = ax[0, 2]
    a.plot(y * 1e3, table.column("right.1.weight", y), color="C3")
    a.plot(y * 1e3, table.column("left.1.weight", y), color="C0")
    a.set(xlabel="lateral shift y (mm)", ylabel="share of the wheel's load",
          title=f"flange slot's share of the load at {args.load / 1e3:.0f} kN per wheel")
    a = ax[1, 0]
    a.plot(amp * 1e3, gamma)
    a.set(xlabel="amplitude (mm)", ylabel="equivalent conicity γ_e",
          title="equivalent conicity, harmonic linearisation (EN 15302)", ylim=(0, None))
    # contact points of the right wheel over y, on both profiles (canonical coordinates)
    ys = table.y[table.y >= 0.0]
    rp, wp = model.rail_profile, model.wheelset.wheel
    for a, prof, key, title in ((ax[1, 1], rp, "y_rail", "rail profile (right rail)"),
                                (ax[1, 2], wp, "y_wheel", "wheel profile (right wheel)")):
        a.plot(prof.y * 1e3, prof.z * 1e3, color="0.3")
        for slot, marker in ((0, "o"), (1, "s")):
            on = table.column(f"right.{slot}.present", ys) > 0.5
            pts = table.column(f"right.{slot}.{key}", ys[on])
            z = (model.rail.z(pts) if prof is rp else model.wheel.z(pts))
            sc = a.scatter(pts * 1e3, z * 1e3, c=ys[on] * 1e3, marker=marker, s=12,
                           cmap="viridis", vmin=0, vmax=ys[-1] * 1e3)
        a.invert_yaxis()
        a.set(xlabel="y (mm, towards the field side)", ylabel="z (mm, down)", title=title,
              aspect="equal", xlim=(-75, 65) if prof is wp else (-45, 32))
        fig.colorbar(sc, ax=a, label="lateral shift y (mm)", shrink=0.7)
    fig.suptitle("S1002 on UIC60 1:40, gauge 1435 mm: contact geometry (o tread, □ flange slot)")
    fig.tight_layout()
    OUT.mkdir(exist_ok=True)
    fig.savefig(OUT / "contact_geometry.png", dpi=110)
    print(f"wrote {OUT / 'contact_geometry.png'}")

    g3 = float(table.equivalent_conicity(3e-3)[0])
    print(f"equivalent conicity at 3 mm: {g3:.3f}")
    print(f"flange starts to carry load at y = {table.flange_onset() * 1e3:.2f} mm; the rigid "
          f"contact is on the flange face (|δ| >= 1 rad) from y = "
          f"{table.flange_contact() * 1e3:.2f} mm")
    t_search = _time(lambda: contact_search(model, 0.0031, 0.002), 50)
    t_given = _time(lambda: contact_search(model, 0.0031, 0.002, -2e-4, 0.0), 50)
    t_table = _time(lambda: table.values(0.0031), 2000)
    print(f"contact search: {t_search * 1e3:.2f} ms with roll and height from both wheels "
          f"touching, {t_given * 1e3:.2f} ms with both given; table evaluation (all "
          f"{table.data.shape[1]} columns): {t_table * 1e6:.1f} µs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
