"""The linearly implicit coupling of the wheelset master (examples/wheelsets/master.py, issue 62)
at communication steps of five and more times the explicit stability limit.

References, each derived here independently of the master and the FMUs: the exact discrete maps
of the explicit and of the linearly implicit couplings of the linear 4-state wheelset (the maps
and the matrices from ``wheelsets.linear_model``, Kalker's coefficients; the holds' response
integrals exact, by the matrix exponential), the eigenvalues' critical speed, the closed-form
motion of a spring-mass under a ramped force, the moment balance of the driven wheelset and the
law's own creep-force curve (``contact_core.solve``). The FMUs are built once for this module.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from scipy.optimize import brentq

import contact_core as cc
from wheel_rail_fmu.host import FmuInstance
from wheelsets.analysis import fit_damped
from wheelsets.build import build_contact, build_wheelsets
from wheelsets.linear_model import LinearWheelset, explicit_limit, hunting_multiplier
from wheelsets.master import CoSimulation
from wheelsets.systems import make_system

pytestmark = [pytest.mark.cosim]

R0, IY, W, MU, E, NU, R_RAIL = 0.46, 120.0, 100e3, 0.3, 210e9, 0.28, 0.3
LW = LinearWheelset()
VC = LW.critical_speed()


@pytest.fixture(scope="module")
def fmus(tmp_path_factory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("implicit_coupling_fmus")
    build_wheelsets(out)
    for scene, method in (("tangent_track", "linear"), ("traction", "fastsim")):
        build_contact(scene, method, out)
    return {p.stem: p for p in out.glob("*.fmu")}


def test_scheme_and_hold_are_checked():
    with pytest.raises(ValueError, match="scheme='implicit' is unknown"):
        CoSimulation({}, [], scheme="implicit")
    with pytest.raises(ValueError, match="hold='linear'"):
        CoSimulation({}, [], hold="linear")
    with pytest.raises(ValueError, match="hold='cubic'"):
        CoSimulation({}, [], scheme="linearly-implicit", hold="cubic")


# FMU state and the force ramp of the wheelset FMUs -------------------------------------------
def outputs(fmu: FmuInstance) -> list[float]:
    return fmu.get("y", "psi", "vy", "dpsi", "xi_L", "eta_L", "phi_R")


def test_wheelset_fmu_state_round_trip_and_refusal(fmus):
    """fmi2GetFMUstate/SetFMUstate roll a wheelset back exactly; a serialised state restores a
    fresh instance; a tampered one is refused (fmi2Error naming what is wrong) and leaves the
    instance as it was."""
    path = fmus["TangentTrackWheelset"]
    forces = dict(Fx_L=-800.0, Fy_L=1500.0, Mz_L=3.0, Fx_R=700.0, Fy_R=1400.0, Mz_R=-2.0)
    with FmuInstance(path, start={"V": 40.0, "y0": 2e-3}) as a:
        assert a.md.coSimulation.canGetAndSetFMUstate and a.md.coSimulation.canSerializeFMUstate
        a.step(0.01, **forces)
        state = a.fmu.getFMUstate()
        a.step(0.01, Fy_L=-900.0, Fy_L_rate=2e4)
        after = outputs(a)
        a.fmu.setFMUstate(state)
        a.t -= 0.01
        a.step(0.01, Fy_L=-900.0, Fy_L_rate=2e4)
        assert outputs(a) == after
        blob = bytes(a.fmu.serializeFMUstate(state))
        a.fmu.freeFMUstate(state)
        with FmuInstance(path, initialize=False) as b:       # never initialised
            b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
            b.initialized = True
            b.t = 0.01
            b.step(0.01, Fy_L=-900.0, Fy_L_rate=2e4)
            assert outputs(b) == after and b.get("V") == [40.0]
        before = outputs(a)
        for bad, what in ((blob.replace(b'"version": 1', b'"version": 2'), "version 2"),
                          (blob.replace(b'"psi0": 0.0, ', b""), "Real variables"),
                          (blob.replace(b'"model": {"t": ', b'"model": {"t": "x", "_": '),
                           "t='x' is not a float"),
                          (blob[:-7], "serialised state")):
            with pytest.raises(FMICallException) as e:
                a.fmu.deSerializeFMUstate(bad)
            assert e.value.status == 3 and what in a.errors()[-1]
        assert outputs(a) == before


def test_force_rate_inputs_apply_the_ramp(fmus):
    """``F_rate``: the force F + F_rate (t - t_k) over the step. Lateral wheelset, only Fy_L
    (no yaw moment: ψ stays 0): y(h) is the closed form of m ÿ + k_y y = F0 + Ḟ t; driven
    wheelset: Ω(h) = Ω0 + h (T - r0 (F0 + Ḟ h/2)) / I_y."""
    m, ky, y0, F0, Fd, h = 1500.0, 1e6, 1e-3, 2e3, 4e4, 0.05
    with FmuInstance(fmus["TangentTrackWheelset"], start={"V": 30.0, "y0": y0}) as fmu:
        fmu.step(h, Fy_L=F0, Fy_L_rate=Fd)
        y, psi = fmu.get("y", "psi")
    w = math.sqrt(ky / m)
    exact = (F0 / ky + Fd * h / ky + (y0 - F0 / ky) * math.cos(w * h)
             - Fd / (ky * w) * math.sin(w * h))
    assert psi == 0.0 and y == pytest.approx(exact, rel=1e-8)
    with FmuInstance(fmus["DrivenWheelsetFMU"], start={"V": 20.0}) as fmu:
        omega0 = fmu.get("omega")[0]
        fmu.step(1e-3, torque=5e3, Fx_L=1e3, Fx_L_rate=2e6, Fx_R=1e3, Fx_R_rate=2e6)
        omega = fmu.get("omega")[0]
    assert omega == pytest.approx(omega0 + 1e-3 * (5e3 - R0 * (2e3 + 4e6 * 0.5e-3)) / IY,
                                  rel=1e-12)


# Critical speed --------------------------------------------------------------------------------
def hunting_growth(V: float, h: float, hold: str) -> float:
    """Growth rate (1/s) of the hunting mode of the exact discrete map of the linearly implicit
    coupling with ``hold``."""
    return math.log(abs(hunting_multiplier(LW, V, h, "linearly-implicit", hold))) / h


def growth(fmus, V, h, scheme, hold="constant", T=3.0):
    sim = make_system(fmus["TangentTrackWheelset"], fmus["WheelRailContact_tangent_track_linear"],
                      dict(V=V, y0=1e-3), scheme=scheme, hold=hold)
    try:
        r = sim.run(round(T / h) * h, h, record=["wheelset.y"], abort_above={"wheelset.y": 0.2})
    finally:
        sim.free()
    if r.aborted:
        return None
    m = r["time"] > 0.3
    return fit_damped(r["time"][m], r["wheelset.y"][m])[0]


def zero_crossing(s_lo, s_hi, lo=0.95, hi=1.05):
    return VC * (lo - s_lo * (hi - lo) / (s_hi - s_lo))


@pytest.mark.slow
def test_critical_speed_at_five_times_the_explicit_limit(fmus):
    """Linear contact FMUs. At h >= 5 times the explicit limit at V_c the explicit scheme
    diverges where the motion decays (0.95 V_c); the linearly implicit one with linear hold
    gives the critical speed within 1 % of the explicit scheme at the small step (1 ms) and of
    the eigenvalues; both holds' growth rates are those of their exact discrete maps."""
    h_lim = explicit_limit(LW, VC)
    assert 0.9 * 2 * LW.tau(VC) < h_lim < 1.1 * 2 * LW.tau(VC)     # ≈ 2τ
    h = math.ceil(5 * h_lim * 1e3) * 1e-3
    assert h >= 5 * h_lim
    assert growth(fmus, 0.95 * VC, h, "gauss-seidel") is None
    ref = zero_crossing(growth(fmus, 0.95 * VC, 1e-3, "gauss-seidel"),
                        growth(fmus, 1.05 * VC, 1e-3, "gauss-seidel"))
    assert ref == pytest.approx(VC, rel=0.01)
    sig = {}
    for hold in ("constant", "linear"):
        for fac in (0.95, 1.05):
            s = growth(fmus, fac * VC, h, "linearly-implicit", hold)
            expected = hunting_growth(fac * VC, h, hold)
            assert s == pytest.approx(expected, rel=0.05, abs=0.01), (hold, fac)
            sig[hold, fac] = s
    vc = zero_crossing(sig["linear", 0.95], sig["linear", 1.05])
    assert vc == pytest.approx(ref, rel=0.01) and vc == pytest.approx(VC, rel=0.01)


# Driven wheelset ------------------------------------------------------------------------------
LEVELS, HOLD = (0.2, 0.5, 0.8), 0.16
T_LIMIT = MU * W * R0


def run_driven(fmus, h, scheme, hold="constant"):
    sim = make_system(fmus["DrivenWheelsetFMU"], fmus["WheelRailContact_traction_fastsim"],
                      {"V": 20.0, "I_y": IY},
                      inputs={"wheelset.torque": lambda t: LEVELS[min(int(t / HOLD + 1e-9),
                                                                      len(LEVELS) - 1)] * T_LIMIT},
                      scheme=scheme, hold=hold)
    try:
        r = sim.run(len(LEVELS) * HOLD, h, record=["wheelset.xi", "contact_L.Fx",
                                                   "contact_R.Fx"])
    finally:
        sim.free()
    i = [np.searchsorted(r["time"], (k + 1) * HOLD - 1e-9) for k in range(len(LEVELS))]
    return (r["contact_L.Fx"] + r["contact_R.Fx"])[i], r["wheelset.xi"][i]


@pytest.mark.slow
def test_driven_wheelset_steady_creep_force_at_large_step(fmus):
    """Torque staircase at h = 8 ms, over 6 times the explicit limit 2τ (τ = I_y V/(2 f11 r0²),
    Kalker's f11): the linearly implicit scheme settles at each level on the moment balance
    ΣFx = T/r0 and on the creepage of the law's own curve (within 1 %), as the explicit scheme
    at 0.1 ms does; the explicit scheme at 8 ms does not."""
    p = cc.hertz_from_radii(W / 2, R0, math.inf, R_RAIL, E, NU)
    G = cc.shear_modulus(E, NU)
    f11 = G * p.a * p.b * cc.creep_coefficients(p.a / p.b, NU)[0]
    tau = IY * 20.0 / (2 * f11 * R0 ** 2)
    h = 8e-3
    assert h > 6 * 2 * tau
    torques = np.array(LEVELS) * T_LIMIT
    def law(xi):
        return cc.solve("fastsim", xi=xi, eta=0.0, phi=0.0, N=W / 2, mu=MU, a=p.a, b=p.b, G=G,
                        nu=NU, effects=("longitudinal", "saturation")).Fx

    xi_law = [brentq(lambda x: 2 * R0 * law(x) - T, -0.05, 0.0, xtol=1e-14) for T in torques]
    F_ref, xi_ref = run_driven(fmus, 1e-4, "gauss-seidel")
    F, xi = run_driven(fmus, h, "linearly-implicit")
    np.testing.assert_allclose(F, torques / R0, rtol=1e-6)
    np.testing.assert_allclose(xi, xi_law, rtol=0.01)
    np.testing.assert_allclose(F, F_ref, rtol=0.01)
    np.testing.assert_allclose(xi, xi_ref, rtol=0.01)
    F_bad, _ = run_driven(fmus, h, "gauss-seidel")
    assert abs(F_bad[0] * R0 / torques[0] - 1.0) > 0.5
