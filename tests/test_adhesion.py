"""The driven wheelset at the adhesion limit (examples/wheelsets, issue 63): contact FMUs with
Coulomb friction (scene ``traction``) and falling friction (scene ``traction_falling``), the
rolling speed coupled from the wheelset, and the slip controller (``wheelsets.slip_control``).

References, derived here independently of the FMUs: the law's own creep-force curve
(``contact_core.solve``, Polach's method) for the steady creepage and the adhesion peak, and the
wheelset's equation of motion I_y dΩ/dt = T - r0 ΣFx for the runaway."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import contact_core as cc
from wheelsets.build import build_contact, build_wheelsets
from wheelsets.slip_control import SlipController
from wheelsets.systems import make_system

pytestmark = pytest.mark.cosim

R0, W, MU, V, IY = 0.46, 100e3, 0.3, 20.0, 120.0
T_LIMIT = MU * W * R0                 # Coulomb's adhesion limit of the wheelset, N m
LEVEL, RAMP, STOP, H = 0.98, 0.15, 0.6, 1e-4


@pytest.fixture(scope="module")
def fmus(tmp_path_factory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("adhesion_fmus")
    paths = build_wheelsets(out)
    for scene in ("traction", "traction_falling"):
        paths[scene] = build_contact(scene, "polach", out)
    return paths


def law(xi: float, falling: bool) -> float:
    """Fx of one wheel (N) at creepage ξ: the contact FMU's law, from contact_core itself."""
    p = cc.hertz_from_radii(W / 2, R0, math.inf, 0.3, 210e9, 0.28)
    eff = ("longitudinal", "saturation") + (("falling_friction",) if falling else ())
    return cc.solve("polach", xi=xi, eta=0.0, phi=0.0, N=W / 2, mu=MU, a=p.a, b=p.b,
                    G=cc.shear_modulus(210e9, 0.28), nu=0.28, effects=eff,
                    **({"V": V} if falling else {})).Fx


def peak() -> tuple[float, float]:
    """(creepage magnitude, Fx) of the falling curve's peak (traction: ξ < 0, Fx > 0)."""
    r = minimize_scalar(lambda x: -law(-x, True), bounds=(1e-4, 0.05), method="bounded",
                        options={"xatol": 1e-8})
    return r.x, law(-r.x, True)


def run(fmus, scene, xi_target=0.0):
    sim = make_system(fmus["DrivenWheelsetFMU"], fmus[scene],
                      {"V": V, "I_y": IY, "xi_target": xi_target},
                      inputs={"wheelset.torque": lambda t: LEVEL * T_LIMIT * min(1.0, t / RAMP)},
                      rolling_speed=scene == "traction_falling")
    try:
        return sim.run(STOP, H, record=["wheelset.xi", "wheelset.torque_applied",
                                        "contact_L.Fx", "contact_R.Fx"], record_every=10)
    finally:
        sim.free()


def test_the_torque_lies_between_the_two_adhesion_limits():
    # the scenario: above the falling curve's peak, below Coulomb's limit μ W r0
    _, f_peak = peak()
    assert 2 * R0 * f_peak < LEVEL * T_LIMIT < T_LIMIT


def test_coulomb_friction_the_creepage_settles(fmus):
    r = run(fmus, "traction")
    xi = r["wheelset.xi"]
    steady = brentq(lambda x: 2 * R0 * law(x, False) - LEVEL * T_LIMIT, -0.05, -1e-6,
                    xtol=1e-14)
    assert xi[-1] == pytest.approx(steady, rel=0.01)
    late = r["time"] > STOP - 0.2
    assert np.ptp(xi[late]) < 0.01 * abs(steady)


def test_falling_friction_the_wheel_runs_away_into_macro_slip(fmus):
    r = run(fmus, "traction_falling")
    t, xi = r["time"], r["wheelset.xi"]
    xi_peak, _ = peak()
    after = t > RAMP
    assert np.all(np.diff(xi[after]) < 0)               # |ξ| grows without a halt
    assert -xi[-1] > 20 * xi_peak
    # the wheelset's own equation: Ω accelerates by the torque the falling force leaves
    # unbalanced, I_y dΩ/dt = T - r0 ΣFx, so dξ/dt = -(r0/V) (T - r0 ΣFx)/I_y
    force = r["contact_L.Fx"] + r["contact_R.Fx"]
    k = np.searchsorted(t, 0.45)
    rate = np.gradient(xi, t)[k]
    assert rate == pytest.approx(-(R0 / V) * (LEVEL * T_LIMIT - R0 * force[k]) / IY, rel=0.02)
    # the adhesion drops towards the law's coefficient at the slip velocity V |ξ|
    assert force[-1] == pytest.approx(2 * law(xi[-1], True), rel=1e-3)


def test_the_slip_controller_holds_the_creepage_at_the_peak(fmus):
    xi_peak, f_peak = peak()
    r = run(fmus, "traction_falling", xi_target=xi_peak)
    t, xi = r["time"], r["wheelset.xi"]
    assert np.abs(xi).max() < 2 * xi_peak                    # no runaway
    assert -xi[-1] == pytest.approx(xi_peak, rel=0.02)
    # the torque it leaves is what the adhesion peak carries
    assert r["wheelset.torque_applied"][-1] == pytest.approx(2 * R0 * f_peak, rel=0.01)


def test_falling_friction_scene_declares_the_rolling_speed_and_the_law(fmus, tmp_path):
    from fmpy import read_model_description
    from wheel_rail_fmu.build import build
    by = {v.name: v for v in read_model_description(str(fmus["traction_falling"])).modelVariables}
    assert by["V"].causality == "input" and by["V"].unit == "m/s"
    assert by["friction_slip_half"].unit == "m/s"
    for name in ("friction_law", "friction_kinetic_ratio", "friction_slip_half", "mu"):
        assert by[name].causality == "parameter"
    plain = {v.name for v in read_model_description(str(fmus["traction"])).modelVariables}
    assert not {"V", "friction_law"} & plain
    for bad, match in (({"friction_kinetic_ratio": 1.5}, "friction_kinetic_ratio=1.5 is out of "
                                                          "range"),
                       ({"friction_law": "cubic"}, "friction_law='cubic' is invalid")):
        with pytest.raises(ValueError, match=match):
            build("traction_falling", "polach", tmp_path, parameters=bad)


def test_controller_cuts_only_beyond_its_target():
    c = SlipController(0.01, 1e5, 1e6)
    assert c.torque(5e3, -0.005, 1e-3) == 5e3              # below the target: as demanded
    cut = c.torque(5e3, -0.02, 1e-3)
    assert 0.0 <= cut < 5e3
    assert SlipController(0.01, 1e9, 0.0).torque(-5e3, 0.5, 1e-3) == 0.0   # clamped, not reversed
    with pytest.raises(ValueError, match="^k_p=-1.0 is out of range"):
        SlipController(0.01, -1.0, 0.0)
