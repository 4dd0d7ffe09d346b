"""Reference wheelsets on real profiles (examples/wheelsets, ``profile_*``): new S1002 wheels on new
UIC60 rails 1:40 through the contact-geometry table, each wheelset FMU coupled to four contact FMUs
of the scene ``vehicle`` (tread and flange patch of each wheel, their geometry at every step).

References, independent of the wheelset code:

* the principle of virtual work: frictionless rigid contacts do no work on a motion that keeps
  both wheels on their rails, so the lateral force of the normal loads on a wheelset pressed down
  by W equals W dz/dy, z(y) the wheelset's height in the table (the contact search's);
* ``contact_core.geometry``: its load sharing between two patches (``share_load``, on the contact
  search's points) and its quasi-static solution of one wheel on its rail (``solve_wheel``: the
  contact search at the wheelset's yaw, creepages, the wheel's height for its load, the law);
* the describing function of an ideal relay, 4/(πA) (harmonic linearisation);
* the linear estimate of the critical speed (``wheelsets.profile_linear``: the linear wheelset of
  Wickens 2003 with the table's harmonically linearised conicity, gravitational stiffness and
  contact-angle spin) and Nadal's limit (Nadal 1896; EN 14363).

The FMUs are built once for the module; the co-simulations are short.
"""
from __future__ import annotations

import math
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from contact_core import hertz, shear_modulus, solve
from contact_core.geometry import (WheelsetMotion, WheelsetPosition, benchmark_model,
                                   contact_search, contact_table, creepages, share_load,
                                   touch_height, wheel_contact)
from contact_core.geometry.table import COLUMNS

from wheel_rail_fmu.host import unzipped

# examples/ is on the import path (pyproject: [tool.pytest.ini_options] pythonpath)
from wheelsets.build import (PROFILE_TABLE_STEP, PROFILE_TABLE_Y_MAX, build_contact,
                             build_profile_wheelsets)
from wheelsets.profile_dynamics import PATCHES, ProfileParams, ProfileWheelset
from wheelsets.profile_linear import ProfileLinearWheelset, harmonic_gain
from wheelsets.profile_systems import (bundled_table, contact_start, make_system,
                                       recommended_step)
from wheelsets.wheelset_dynamics import LateralState

pytestmark = [pytest.mark.cosim]

W, E, NU, MU = 100e3, 210e9, 0.28, 0.3


@pytest.fixture(scope="module")
def model():
    return benchmark_model()


@pytest.fixture(scope="module")
def table(model):
    """The table the wheelset FMUs ship (same set-up, built in process)."""
    return contact_table(model, PROFILE_TABLE_Y_MAX, PROFILE_TABLE_STEP)


def at_rest(table, y: float) -> ProfileWheelset:
    return ProfileWheelset(ProfileParams(axle_load=W), table, 0.46, LateralState(y=y))


# -- in process -----------------------------------------------------------------------------------
@pytest.mark.parametrize("y", [-3.1e-3, 0.6e-3, 1.05e-3, 2.05e-3, 3.55e-3, 4.25e-3, 5.5e-3])
def test_normal_loads_do_no_virtual_work(table, y):
    """Frictionless, at rest, one patch per wheel (tread; at 5.5 mm the flange root): the lateral
    force of the normal loads is W dz/dy (virtual work), to 0.1 % (between the table's grid points
    its contact angles and its heights are interpolated separately)."""
    loads = at_rest(table, y).loads()
    assert sum(n > 0.0 for n in loads.N) == 2
    force = -sum(loads.Y.values())
    slope = float(table.interpolant.derivative()(y)[COLUMNS.index("z")])
    assert force == pytest.approx(W * slope, rel=1e-3)
    assert sum(loads.Q.values()) == pytest.approx(W, rel=1e-12)


def test_centred_wheelset_is_symmetric(table):
    """y = 0: equal loads W/2 per wheel, the lateral forces of the two wheels cancel."""
    loads = at_rest(table, 0.0).loads()
    assert loads.Q["L"] == pytest.approx(W / 2, rel=1e-12)
    assert loads.Q["R"] == pytest.approx(W / 2, rel=1e-12)
    assert loads.Y["L"] == pytest.approx(-loads.Y["R"], rel=1e-9)
    assert loads.Y["R"] > 0.0      # each wheel pushes its rail outwards (the treads' slopes)


@pytest.mark.parametrize("y", [4.8e-3, 4.9e-3, 5.0e-3])
def test_two_point_contact_shares_the_load_as_the_contact_search(model, table, y):
    """Right wheel in two-point contact: the tread and flange loads at the wheel's vertical load
    are those of ``share_load`` on the contact search's points (a common approach, Hertz per
    patch)."""
    loads = at_rest(table, y).loads()
    N = dict(zip(PATCHES, loads.N))
    assert N["Rt"] > 0.0 and N["Rf"] > 0.0 and N["Lf"] == 0.0
    points = contact_search(model, y).right.points
    assert [p.slot for p in points] == [0, 1]
    vertical = N["Rt"] * math.cos(points[0].delta) + N["Rf"] * math.cos(points[1].delta)
    ref = share_load(points, vertical, E, NU)
    assert N["Rt"] == pytest.approx(ref[0], abs=2e-3 * vertical)
    assert N["Rf"] == pytest.approx(ref[1], abs=2e-3 * vertical)


def test_harmonic_gain_of_a_relay():
    """Describing function of an ideal relay of level M: 4M/(πA)."""
    assert harmonic_gain(np.sign, 2e-3, n=4096) == pytest.approx(4 / (math.pi * 2e-3), rel=1e-5)
    assert harmonic_gain(lambda y: 3.0 * y, 1e-3) == pytest.approx(3.0, rel=1e-12)


def test_linear_estimate_is_the_equivalent_conicity_model(table):
    """The estimate's conicity is the table's equivalent conicity, its restoring stiffness the
    describing function of the normal loads' lateral force (positive: restoring)."""
    lw = ProfileLinearWheelset(table, 3e-3)
    assert lw.lam == pytest.approx(float(table.equivalent_conicity(3e-3)[0]), rel=1e-12)
    assert lw.K_g > 0.0
    assert lw.K_phi_y < 0.0 and abs(lw.K_phi_y) < lw.K_g   # the spin counters, partly


# -- FMUs -----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    out = tmp_path_factory.mktemp("profile_wheelsets")
    paths = build_profile_wheelsets(out)
    paths["contact"] = build_contact("vehicle", "table", out)
    return paths


def run(fmus, name, params, method, T, h, record):
    n = int(round(T / h))
    sim = make_system(fmus[name], fmus["contact"], params, contact_start(method))
    try:
        return sim.run(n * h, h, record=record)
    finally:
        sim.free()


def last(r, window):
    return r["time"] >= r["time"][-1] - window


def test_fmu_ships_its_table_and_runs_its_own_code(fmus, table):
    """The archive holds the table (what the in-process table is) and contact_core without the
    exact theory's table; a run imports the wheelset's code from the FMU's bundle, under its
    digest name."""
    path = fmus["TangentTrackProfileWheelset"]
    shipped, r0 = bundled_table(path)
    assert r0 == 0.46
    np.testing.assert_array_equal(shipped.data, table.data)
    with zipfile.ZipFile(path) as z:
        names = z.namelist()
    assert not [n for n in names if n.endswith("exact_table.npz")]
    bundle = {n.split("/")[1] for n in names if n.startswith("resources/_wheelset_profiles_")}
    assert len(bundle) == 1
    r = run(fmus, "TangentTrackProfileWheelset", {"V": 30.0, "y0": 1e-3}, "table", 0.02, 4e-4,
            ["wheelset.y", "wheelset.N_Lt"])
    assert r["wheelset.N_Lt"][-1] > 0.0
    kinematics = sys.modules[f"{bundle.pop()}.contact_core.geometry.kinematics"]
    assert Path(kinematics.__file__).resolve().is_relative_to(Path(unzipped(path)).resolve())


@pytest.mark.slow
def test_nonlinear_critical_speed_agrees_with_the_linear_estimate(fmus, table):
    """The linear estimate: the lowest critical speed of ``ProfileLinearWheelset`` over small
    amplitudes (its minimum lies just beyond the contact-point jump near 0.25 mm, where the
    equivalent conicity is largest). The co-simulation's nonlinear critical speed: the lowest
    speed at which a 1 mm disturbance does not die out. Tolerance 7 %, from what the estimate
    leaves out: the creep forces' saturation lifts the co-simulated limit cycles above the
    estimate's speed at their amplitude, least at the fold and by up to about 10 % at a few
    millimetres (out/real_profile_summary.md, docs/guide/vehicle_models.md)."""
    amps = np.arange(2.5e-4, 1.0e-3, 1e-5)
    vc = [ProfileLinearWheelset(table, a).critical_speed() for a in amps]
    k = int(np.argmin(vc))
    assert 0 < k < amps.size - 1
    V_lin = vc[k]
    rec = ["wheelset.y"]
    below = run(fmus, "TangentTrackProfileWheelset", {"V": 0.93 * V_lin, "y0": 1e-3}, "table",
                3.0, recommended_step(table, 0.93 * V_lin), rec)
    above = run(fmus, "TangentTrackProfileWheelset", {"V": 1.07 * V_lin, "y0": 1e-3}, "table",
                3.0, recommended_step(table, 1.07 * V_lin), rec)
    assert np.abs(below["wheelset.y"][last(below, 0.5)]).max() < 5e-5
    hunting = np.abs(above["wheelset.y"][last(above, 0.5)]).max()
    before = np.abs(above["wheelset.y"][(above["time"] >= 2.0) & (above["time"] < 2.5)]).max()
    assert hunting > 2e-4 and hunting > 0.95 * before


@pytest.mark.slow
def test_hunting_limit_cycle_stays_within_the_flangeway(fmus, table):
    """Far above the critical speed the limit cycle reaches the flanges: the flange patches
    stop it, within the flangeway (|y| < 10 mm), and it neither grows nor dies out."""
    V = 75.0
    r = run(fmus, "TangentTrackProfileWheelset", {"V": V, "y0": 1e-3}, "table", 1.5,
            recommended_step(table, V), ["wheelset.y", "wheelset.N_Lf", "wheelset.N_Rf"])
    y = np.abs(r["wheelset.y"])
    assert np.isfinite(y).all()
    assert y.max() < 0.010
    late, earlier = y[last(r, 0.5)].max(), y[(r["time"] >= 0.5) & (r["time"] < 1.0)].max()
    assert late == pytest.approx(earlier, rel=0.05)
    assert late > table.flange_onset()
    assert r["wheelset.N_Lf"].max() > 0.0 and r["wheelset.N_Rf"].max() > 0.0


CURVE = dict(V=15.0, R=300.0)
CURVE_RECORD = ["wheelset.y", "wheelset.psi", "wheelset.Q_L", "wheelset.Y_L"] + [
    f"wheelset.{q}_{p}" for p in PATCHES for q in ("N", "delta")] + [
    f"contact_{p}.{q}" for p in ("Lt", "Lf", "Rt") for q in ("Fx", "Fy")]


@pytest.fixture(scope="module")
def curve_runs(fmus, table):
    """The curve with the table from the centred wheelset, then with the exact method from the
    table's steady state (each must settle: :func:`steady`)."""
    h = recommended_step(table, CURVE["V"])
    runs = {"table": run(fmus, "CurvingProfileWheelset", CURVE, "table", 0.6, h, CURVE_RECORD)}
    start = {"y0": float(runs["table"]["wheelset.y"][-1]),
             "psi0": float(runs["table"]["wheelset.psi"][-1])}
    runs["exact"] = run(fmus, "CurvingProfileWheelset", {**CURVE, **start}, "exact", 0.3, h,
                        CURVE_RECORD)
    return runs


def steady(r):
    assert np.ptp(r["wheelset.y"][last(r, 0.1)]) < 1e-6      # settled
    return {k: float(v[-1]) for k, v in r.data.items()}


@pytest.mark.slow
def test_curve_two_point_contact_against_the_library(model, table, curve_runs):
    """R = 300 m: the outer (left) wheel runs on its tread and its flange root, the inner one on
    its tread. The outer wheel's two patches are what the library gives for that wheel without
    the table and without FMUs: the contact search at the wheelset's yaw (rigid contact, the
    table's roll), the load sharing of ``share_load`` at the wheel's vertical normal load, the
    creepages of ``creepages`` and the forces of ``contact_core.solve``: normal loads within 1 %
    of the wheel's load, creep forces within 1 % of μN (the table is the contact search at yaw 0,
    interpolated, with the contact point's lead per unit yaw)."""
    s = steady(curve_runs["table"])
    assert s["wheelset.N_Lt"] > 0.0 and s["wheelset.N_Lf"] > 0.0
    assert s["wheelset.N_Rt"] > 0.0 and s["wheelset.N_Rf"] == 0.0
    assert s["wheelset.y"] < -table.flange_onset()
    y, psi = s["wheelset.y"], s["wheelset.psi"]
    roll = float(table.column("roll", y))
    z = touch_height(model, "left", y, roll, psi)
    points = wheel_contact(model, "left", y, z, roll, psi).points
    assert [p.slot for p in points] == [0, 1]
    vertical = sum(s[f"wheelset.N_{n}"] * math.cos(s[f"wheelset.delta_{n}"]) for n in ("Lt", "Lf"))
    loads = share_load(points, vertical, E, NU)
    centre = 0.5 * float(table.column("left.radius_contact", 0.0)
                         + table.column("right.radius_contact", 0.0))
    V = CURVE["V"]
    motion = WheelsetMotion(speed=V, pitch_rate=-V / centre, yaw_rate=V / CURVE["R"])
    position = WheelsetPosition(y, z, roll, psi)
    G = shear_modulus(E, NU)
    for p, N, name in zip(points, loads, ("Lt", "Lf")):
        assert s[f"wheelset.N_{name}"] == pytest.approx(N, abs=0.01 * vertical)
        c = creepages(position, p, motion, 0.46)
        patch = hertz(N, p.A, p.B, E, NU)
        ref = solve("table", xi=c.xi, eta=c.eta, phi=c.phi, N=N, mu=MU, a=patch.a, b=patch.b,
                    G=G, nu=NU)
        for q in ("Fx", "Fy"):
            assert s[f"contact_{name}.{q}"] == pytest.approx(getattr(ref, q), abs=0.01 * MU * N)


@pytest.mark.slow
def test_curve_outer_wheel_below_nadals_limit(table, curve_runs):
    """Y/Q of the outer wheel (its lateral force pushing the rail outwards over its vertical
    force) against Nadal's limit (tan δ − μ)/(1 + μ tan δ) at the steepest contact angle of the
    flange (the flange face of S1002 on UIC60, about 70°)."""
    s = steady(curve_runs["table"])
    present = table.data[:, COLUMNS.index("left.1.present")] > 0.5
    delta = float(np.abs(table.data[present, COLUMNS.index("left.1.delta")]).max())
    assert 1.1 < delta < 1.3
    limit = (math.tan(delta) - MU) / (1 + MU * math.tan(delta))
    ratio = -s["wheelset.Y_L"] / s["wheelset.Q_L"]
    assert 0.0 < ratio < limit


@pytest.mark.slow
def test_curve_table_and_exact_agree(curve_runs):
    """The same curve with every patch by the exact method (16 × 16, one grid): the loaded
    patches' creep forces agree with the table's within the exact method's largest error on that
    grid in the accuracy benchmark (6.3 % of μN; ``python -m contact_tools.bench --full``); the
    flange pins the wheelset's lateral position (within 1 %), and the patches' loads, which follow
    from it, agree within 3 % of the wheel's load."""
    t, e = steady(curve_runs["table"]), steady(curve_runs["exact"])
    assert e["wheelset.y"] == pytest.approx(t["wheelset.y"], rel=0.01)
    for name in ("Lt", "Lf", "Rt"):
        muN = MU * t[f"wheelset.N_{name}"]
        assert e[f"wheelset.N_{name}"] == pytest.approx(t[f"wheelset.N_{name}"],
                                                        abs=0.03 * W / 2)
        for q in ("Fx", "Fy"):
            assert e[f"contact_{name}.{q}"] == pytest.approx(t[f"contact_{name}.{q}"],
                                                             abs=0.063 * muN)
