"""Reference wheelset models (examples/wheelsets) driven by fmpy, coupled to the contact FMU.

Every reference here is derived in this file, independently of the FMU code: the eigenvalues of
the linearised 4-state wheelset with Kalker's coefficients (numpy), Klingel's wavelength, the
linear steady-state curving solution, the exact discrete map of the zero-order-hold coupling
(scipy expm), and the law's own Fx(ξ) curve (contact_core.solve) for traction. The FMUs are built
once per session (wheelsets.build: the wheelset FMUs with pythonfmu, the contact FMUs with
wheel_rail_fmu.build) into a temporary folder. Simulated times are short.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

import contact_core as cc

# examples/ is on the import path (pyproject: [tool.pytest.ini_options] pythonpath)
from wheelsets.analysis import fit_damped
from wheelsets.build import build_contact, build_wheelsets
from wheelsets.systems import CONNECTIONS, make_system

# every test builds (once per session) and simulates the wheelset FMUs: all slow
pytestmark = [pytest.mark.cosim, pytest.mark.slow]

# Reference parameters (issue 6) -------------------------------------------------------------
R0, B0, LAM, M, IZ, W = 0.46, 0.75, 0.15, 1500.0, 800.0, 100e3
E, NU, MU, R_RAIL = 210e9, 0.28, 0.3, 0.3
KY, KPSI = 1.0e6, 2.0e6
N_WHEEL = W / 2
IY = 120.0

CONTACTS = [("tangent_track", "linear"), ("full", "linear"), ("full", "fastsim"),
            ("traction", "fastsim"), ("traction", "exact"), ("full", "exact"),
            ("curving", "linear"), ("curving", "fastsim")]


@pytest.fixture(scope="session")
def fmus(tmp_path_factory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("wheelset_fmus")
    build_wheelsets(out)
    for scene, method in CONTACTS:
        build_contact(scene, method, out)
    paths = {p.stem: p for p in out.glob("*.fmu")}
    assert {"TangentTrackWheelset", "CurvingWheelset", "DrivenWheelsetFMU"} <= set(paths)
    return paths


def contact(fmus, scene, method):
    return fmus[f"WheelRailContact_{scene}_{method}"]


# Independent linear model ---------------------------------------------------------------------
def kalker_f():
    """Kalker's linear coefficients of the nominal contact (Hertz for a conical tread on a
    0.3 m rail crown, 50 kN)."""
    p = cc.hertz_from_radii(N_WHEEL, R0, math.inf, R_RAIL, E, NU)
    G = cc.shear_modulus(E, NU)
    c11, c22, c23, c33 = cc.creep_coefficients(p.a / p.b, NU)
    c2 = p.a * p.b
    c = math.sqrt(c2)
    return G * c2 * c11, G * c2 * c22, G * c2 * c * c23, G * c2 * c2 * c33


F11, F22, F23, F33 = kalker_f()


def forces_matrix(V, ky=KY, kpsi=KPSI):
    """Mass, stiffness and damping of  M q'' + C q' + K q = 0,  q = (y, ψ): Wickens (2003)
    single wheelset with linear creep (incl. spin: f23, f33) and primary stiffness."""
    Mm = np.diag([M, IZ])
    K = np.array([[ky, -2 * F22], [2 * F11 * B0 * LAM / R0, 2 * F23 + kpsi]])
    C = np.array([[2 * F22 / V, 2 * F23 / V], [-2 * F23 / V, (2 * F11 * B0 ** 2 + 2 * F33) / V]])
    return Mm, C, K


def state_matrix(V, ky=KY, kpsi=KPSI):
    Mm, C, K = forces_matrix(V, ky, kpsi)
    Mi = np.linalg.inv(Mm)
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ K, -Mi @ C]])


def hunting_eigenvalue(V, **k):
    ev = np.linalg.eigvals(state_matrix(V, **k))
    ev = ev[ev.imag > 0]
    return ev[np.argmax(ev.real)]


def critical_speed():
    return brentq(lambda V: np.linalg.eigvals(state_matrix(V)).real.max(), 5.0, 300.0,
                  xtol=1e-10)


def creep_tau(V):
    """Shortest creep time constant of the lateral wheelset, s."""
    return min(M * V / (2 * F22), IZ * V / (2 * F11 * B0 ** 2))


def run_tangent(fmus, V, T, h, scene="tangent_track", method="linear", scheme="gauss-seidel",
                abort=None, **params):
    pars = dict(V=V, k_y=KY, k_psi=KPSI, y0=1e-3)
    pars.update(params)
    sim = make_system(fmus["TangentTrackWheelset"], contact(fmus, scene, method), pars,
                      scheme=scheme)
    try:
        return sim.run(T, h, record=["wheelset.y", "wheelset.psi"],
                       abort_above={"wheelset.y": abort} if abort else None)
    finally:
        sim.free()


# ------------------------------------------------------------------------------------------------
def test_kinematic_oscillation_klingel(fmus):
    """Very soft suspension, low speed: wavelength within 3 % of Klingel's 2π√(r0 b0/λ); the
    displaced wheelset is steered back towards the centre (closed-loop sign check)."""
    V = 10.0
    h = 1e-4  # ≈ τ/8 at 10 m/s
    assert h < creep_tau(V) / 4
    sim = make_system(fmus["TangentTrackWheelset"], contact(fmus, "tangent_track", "linear"),
                      dict(V=V, k_y=1e3, k_psi=1e3, y0=2e-3))
    try:
        r = sim.run(2.2, h, record=["wheelset.y", "wheelset.psi"])
    finally:
        sim.free()
    t, y, psi = r["time"], r["wheelset.y"], r["wheelset.psi"]
    # Sign check: y0 > 0 (right) -> nose turns left (ψ < 0) -> y decreases.
    early = t < 0.1
    assert psi[early][-1] < 0 and y[early][-1] < y[0]
    i = np.where((y[:-1] < 0) & (y[1:] >= 0))[0]
    cross = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    assert len(cross) >= 2
    wavelength = V * np.mean(np.diff(cross))
    klingel = 2 * math.pi * math.sqrt(R0 * B0 / LAM)
    assert abs(wavelength - klingel) / klingel < 0.03


@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_critical_speed_linear(fmus, factor):
    """Linear contact FMU: decays at 0.9 V_c, grows at 1.1 V_c (V_c from the eigenvalues);
    frequency within 2 % of the eigenvalue's; growth rate within 10 % of the eigenvalue's real
    part (the O(h) coupling error at h = τ/4 is about 2 %)."""
    Vc = critical_speed()
    V = factor * Vc
    lam = hunting_eigenvalue(V)
    h = 1e-3
    assert h <= creep_tau(V) / 4
    r = run_tangent(fmus, V, 1.5, h)
    t, y = r["time"], r["wheelset.y"]
    m = t > 0.3  # the creep modes (|Re λ| > 300 1/s) have died out
    sigma, omega = fit_damped(t[m], y[m])
    amp_first = np.abs(y[(t > 0.3) & (t < 0.6)]).max()
    amp_last = np.abs(y[t > 1.2]).max()
    if factor < 1:
        assert sigma < 0 and amp_last < amp_first
    else:
        assert sigma > 0 and amp_last > amp_first
    assert abs(omega - lam.imag) / lam.imag < 0.02
    assert abs(sigma - lam.real) < 0.1 * abs(lam.real)


def zoh_spectral_radius(V, h, scheme):
    """Exact discrete map of the co-simulation of the linear model: suspension integrated
    exactly over h with the creep forces held (GS: forces of x_k; Jacobi: of x_{k-1})."""
    Mm, C, K = forces_matrix(V)
    Ks = np.diag([KY, KPSI])  # suspension part of K, integrated inside the wheelset
    Kc = -np.hstack([K - Ks, C])  # creep forces (Fy, Mz totals) = Kc @ x
    Mi = np.linalg.inv(Mm)
    As = np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ Ks, np.zeros((2, 2))]])
    Bs = np.vstack([np.zeros((2, 2)), Mi])
    aug = np.zeros((6, 6))
    aug[:4, :4], aug[:4, 4:] = As * h, Bs * h
    Ex = expm(aug)
    Phi, Gam = Ex[:4, :4], Ex[:4, 4:]
    T = Phi + Gam @ Kc if scheme == "gauss-seidel" else \
        np.block([[Phi, Gam @ Kc], [np.eye(4), np.zeros((4, 4))]])
    return np.abs(np.linalg.eigvals(T)).max()


def step_limit(V, scheme):
    g = lambda h: zoh_spectral_radius(V, h, scheme) - 1.0
    hs = np.geomspace(1e-4, 5e-2, 120)
    i = next(i for i, h in enumerate(hs) if g(h) > 0)
    return brentq(g, hs[i - 1], hs[i], xtol=1e-10)


@pytest.mark.parametrize("scheme", ["gauss-seidel", "jacobi"])
def test_communication_step_limit(fmus, scheme):
    """Too large a step: the explicit coupling diverges just above the limit of the exact
    discrete map (≈ 2τ Gauss-Seidel, ≈ τ Jacobi) and is stable just below it, at 0.9 V_c where
    the physical motion decays."""
    V = 0.9 * critical_speed()
    tau = creep_tau(V)
    h_lim = step_limit(V, scheme)
    expected = 2 * tau if scheme == "gauss-seidel" else tau
    assert 0.8 * expected < h_lim < 1.2 * expected
    # Enough steps for the predicted unstable growth to amplify by 1e6 (the start excites the
    # unstable creep mode only weakly: y0 = 1 mm, abort at 5 cm).
    n = int(math.ceil(math.log(1e6) / math.log(zoh_spectral_radius(V, 1.15 * h_lim, scheme))))
    assert n < 3000
    ok = run_tangent(fmus, V, n * 0.85 * h_lim, 0.85 * h_lim, scheme=scheme, abort=0.05)
    bad = run_tangent(fmus, V, n * 1.15 * h_lim, 1.15 * h_lim, scheme=scheme, abort=0.05)
    assert not ok.aborted and np.abs(ok["wheelset.y"]).max() <= 1e-3 * (1 + 1e-6)
    assert bad.aborted  # |y| > 5 cm: numerical blow-up, the physical system decays


def test_jacobi_master_matches_fmpy_simulate_ssp(fmus, tmp_path):
    """The master's Jacobi scheme is fmpy.ssp.simulate_ssp's: same trajectories on an SSP of the
    tangent-track system (this validates the master against fmpy's own mechanism)."""
    from fmpy.ssp.simulation import simulate_ssp

    from wheelsets.ssp import parameter_set, write_ssp
    c, w = contact(fmus, "tangent_track", "linear"), fmus["TangentTrackWheelset"]
    ssp = write_ssp(tmp_path / "hunting.ssp", {"contact_L": c, "contact_R": c, "wheelset": w},
                    CONNECTIONS, extra_outputs={"wheelset": ["y", "psi"]})
    pars = {"wheelset": {"V": 40.0, "y0": 1e-3, "k_y": KY, "k_psi": KPSI}}
    res = simulate_ssp(str(ssp), stop_time=0.2, step_size=1e-3, parameter_set=parameter_set(pars))
    sim = make_system(w, c, pars["wheelset"], scheme="jacobi", initial_exchange=False)
    try:
        r = sim.run(0.2, 1e-3, record=["wheelset.y", "wheelset.psi", "contact_L.Fx"])
    finally:
        sim.free()
    n = len(res)  # simulate_ssp labels the values after step k with the step's start time
    for name in ("wheelset.y", "wheelset.psi", "contact_L.Fx"):
        np.testing.assert_allclose(r[name][1:n + 1], res[name], rtol=1e-12, atol=1e-15)
    assert np.abs(res["wheelset.y"]).max() > 1e-4


# Traction ---------------------------------------------------------------------------------------
T_LIMIT = MU * W * R0          # adhesion limit of the wheelset, N m
LEVELS = (0.2, 0.4, 0.6, 0.8, 0.9, 0.95)
HOLD = 0.04
V_DRIVE = 20.0


def torque(t):
    k = int(t / HOLD + 1e-9)
    if k < len(LEVELS):
        return LEVELS[k] * T_LIMIT
    return T_LIMIT * min(1.3, 1.0 + 0.3 * (t - len(LEVELS) * HOLD) / 0.05)


def run_driven(fmus, scene, method, h, T=len(LEVELS) * HOLD + 0.12):
    sim = make_system(fmus["DrivenWheelsetFMU"], contact(fmus, scene, method),
                      {"V": V_DRIVE, "I_y": IY}, inputs={"wheelset.torque": torque})
    try:
        return sim.run(T, h, record=["wheelset.xi", "wheelset.omega", "contact_L.Fx",
                                     "contact_R.Fx"])
    finally:
        sim.free()


@pytest.mark.parametrize("method,h", [("fastsim", 1e-4), ("exact", 5e-4)])
def test_traction_follows_law_and_slips_beyond_limit(fmus, method, h):
    """Steady creepage at each torque level = root of 2 r0 Fx_law(ξ) = T (contact_core.solve,
    the law's own curve); beyond T = μ W r0 the wheelset spins up: ξ decreases without bound at
    the rate set by the excess torque; no NaN, no failure."""
    tau = IY * V_DRIVE / (2 * F11 * R0 ** 2)
    assert h < 2 * tau  # explicit coupling stable (monotone for h < τ)
    r = run_driven(fmus, "traction", method, h)
    t, xi, om = r["time"], r["wheelset.xi"], r["wheelset.omega"]
    assert np.isfinite(xi).all() and np.isfinite(om).all()
    p = cc.hertz_from_radii(N_WHEEL, R0, math.inf, R_RAIL, E, NU)
    G = cc.shear_modulus(E, NU)
    law = lambda x: cc.solve(method, xi=x, eta=0.0, phi=0.0, N=N_WHEEL, mu=MU, a=p.a, b=p.b,
                             G=G, nu=NU, effects=("longitudinal", "saturation")).Fx
    for k, level in enumerate(LEVELS):
        i = np.searchsorted(t, (k + 1) * HOLD - 1e-9)
        xi_law = brentq(lambda x: 2 * R0 * law(x) - level * T_LIMIT, -0.05, 0.0, xtol=1e-14)
        assert xi[i] == pytest.approx(xi_law, rel=0.01), (level, xi[i], xi_law)
    # Beyond the limit: the forces saturate at μN, Ω grows at (T - μ W r0)/I_y.
    hold = t > len(LEVELS) * HOLD + 0.06
    assert np.all(np.diff(xi[t > len(LEVELS) * HOLD + 0.01]) < 0)
    rate = np.polyfit(t[hold], xi[hold], 1)[0]
    expected = -(1.3 * T_LIMIT - T_LIMIT) / IY * R0 / V_DRIVE
    assert rate == pytest.approx(expected, rel=0.02)
    assert xi[-1] < -0.05
    assert np.abs(r["contact_L.Fx"]).max() <= MU * N_WHEEL * (1 + 1e-9)


@pytest.mark.parametrize("method,h", [("fastsim", 1e-4), ("exact", 5e-4)])
def test_scene_fmu_equals_full_fmu(fmus, method, h):
    """Driven wheelset on straight track (η = φ = 0): the traction-scene FMU and the full FMU
    give the same trajectories (1e-9) — the scene only removes work. What it saves per step is
    measured by ``python -m contact_tools.bench_fmu`` (each scene against ``full``), not asserted
    here."""
    T = 0.3 if method == "fastsim" else len(LEVELS) * HOLD + 0.12
    a = run_driven(fmus, "traction", method, h, T=T)
    b = run_driven(fmus, "full", method, h, T=T)
    for name in ("wheelset.xi", "wheelset.omega", "contact_L.Fx", "contact_R.Fx"):
        np.testing.assert_allclose(a[name], b[name], rtol=1e-9, atol=1e-12 if "xi" in name else 1e-9)


def test_scene_fmu_without_needed_effect_is_refused(fmus):
    """The traction-scene FMU has no eta/phi inputs: coupling it to the tangent-track wheelset,
    whose η and φ are not zero, is an error, not a silent omission."""
    sim = make_system(fmus["TangentTrackWheelset"], contact(fmus, "traction", "fastsim"),
                      dict(V=30.0, k_y=KY, k_psi=KPSI))
    try:
        with pytest.raises(RuntimeError, match="phi"):
            sim.run(0.01, 1e-3)
    finally:
        sim.free()


def test_tangent_track_scene_equals_full_scene_linear(fmus):
    """Linear theory never saturates: the tangent_track scene (no saturation) and the full scene
    give the same hunting trajectories."""
    V = 1.1 * critical_speed()
    a = run_tangent(fmus, V, 0.3, 1e-3, scene="tangent_track", method="linear")
    b = run_tangent(fmus, V, 0.3, 1e-3, scene="full", method="linear")
    np.testing.assert_allclose(a["wheelset.y"], b["wheelset.y"], rtol=1e-9, atol=1e-15)


# Curving ----------------------------------------------------------------------------------------
def linear_curving(R, ky=KY, kpsi=KPSI):
    """Steady state of the linear model in a curve (balance speed): with ẏ = ψ̇ = 0,
    η = -ψ, ξ_L = -ξ_R = λy/r0 + b0/R, φ_L + φ_R = 2/R:
        lateral: 2 f22 ψ - 2 f23/R - k_y y = 0
        yaw:    -2 f11 b0 (λy/r0 + b0/R) - 2 f23 ψ - 2 f33/R - k_ψ ψ = 0."""
    A = np.array([[-ky, 2 * F22], [-2 * F11 * B0 * LAM / R0, -2 * F23 - kpsi]])
    rhs = np.array([2 * F23 / R, 2 * F11 * B0 ** 2 / R + 2 * F33 / R])
    return np.linalg.solve(A, rhs)


def test_curving_large_radius_linear(fmus):
    """R = 2000 m, linear contact FMU: steady y and ψ within 2 % of the linear solution."""
    R, V = 2000.0, 30.0
    h = 5e-4
    assert h <= creep_tau(V) / 4
    y_ref, psi_ref = linear_curving(R)
    assert y_ref < 0  # a right-hand curve: the wheelset moves outwards (left)
    sim = make_system(fmus["CurvingWheelset"], contact(fmus, "curving", "linear"),
                      dict(V=V, R=R, L_transition=30.0, k_y=KY, k_psi=KPSI))
    try:
        r = sim.run(4.0, h, record=["wheelset.y", "wheelset.psi"])
    finally:
        sim.free()
    assert r["wheelset.y"][-1] == pytest.approx(y_ref, rel=0.02)
    assert r["wheelset.psi"][-1] == pytest.approx(psi_ref, rel=0.02)


def test_curving_tight_radius_fastsim_saturates(fmus):
    """R = 150 m with FASTSIM and a flange spring: the creep forces saturate (|F| <= μN, and
    reach it within 10 %), the flange carries the rest; the run completes without NaN."""
    R, V = 150.0, 15.0
    h = 2e-4
    assert h <= creep_tau(V) / 4
    sim = make_system(fmus["CurvingWheelset"], contact(fmus, "curving", "fastsim"),
                      dict(V=V, R=R, L_transition=15.0, k_y=KY, k_psi=KPSI, flange_gap=8e-3,
                           k_flange=15e6))
    try:
        r = sim.run(2.0, h, record=["wheelset.y", "wheelset.psi", "wheelset.F_flange"]
                    + [f"contact_{s}.{v}" for s in "LR" for v in ("Fx", "Fy")])
    finally:
        sim.free()
    F = np.array([np.hypot(r[f"contact_{s}.Fx"], r[f"contact_{s}.Fy"]) for s in "LR"])
    assert np.isfinite(F).all() and np.isfinite(r["wheelset.y"]).all()
    assert F.max() <= MU * N_WHEEL * (1 + 1e-9)
    assert F.max() >= 0.9 * MU * N_WHEEL
    assert r["wheelset.y"][-1] < -8e-3 and r["wheelset.F_flange"][-1] > 0


# Start from rest, brake to standstill --------------------------------------------------------
M_VEHICLE = 1000.0        # kg moved by the driven wheelset
H_LOW = 2e-5              # communication step of the low-speed runs


def run_start_stop(fmus, method, h=H_LOW, v_reg_factor=1.0, contact_params=None,
                   t_drive=0.05, T=0.35):
    """From rest: drive torque 0.6 μ W r0 until ``t_drive``, then a brake torque μ W r0 (at the
    adhesion limit) until T. V_reg from the communication step (systems.regularisation_speed)
    times ``v_reg_factor``."""
    from wheelsets.systems import regularisation_speed
    v_reg = v_reg_factor * regularisation_speed(h, I_y=IY, r0=R0, m_vehicle=M_VEHICLE)
    drive = 0.6 * MU * W * R0
    sim = make_system(fmus["DrivenWheelsetFMU"], contact(fmus, "traction", method),
                      {"V": 0.0, "I_y": IY, "m_vehicle": M_VEHICLE, "V_reg": v_reg},
                      contact_params=contact_params,
                      inputs={"wheelset.torque": lambda t: drive if t < t_drive else 0.0,
                              "wheelset.brake": lambda t: 0.0 if t < t_drive else drive / 0.6})
    try:
        return sim.run(T, h, record=["wheelset.speed", "wheelset.omega", "wheelset.xi",
                                     "contact_L.Fx", "contact_R.Fx"])
    finally:
        sim.free()


def chatter(F, threshold):
    """Steps where the force changes direction from one step to the next by more than
    ``threshold`` both times (a force oscillating at the communication step)."""
    d = np.diff(F)
    big = np.abs(d) > threshold
    return int(np.sum((d[1:] * d[:-1] < 0) & big[1:] & big[:-1]))


@pytest.mark.parametrize("method, options", [
    ("fastsim", None), ("exact", {"mx": 12, "my": 12, "extrapolate": False})])
def test_start_from_rest_and_brake_to_standstill(fmus, method, options):
    """V = 0 at t = 0: the creepage is regularised below V_reg (xi = (V - Ω r0)/max(|V|, V_reg),
    V_reg from the step, see wheelset_dynamics.DrivenWheelset). The wheelset pulls away, then
    brakes to standstill: finite, bounded forces, forward then backward, no oscillation of the
    creep force at the communication step, speed down to rest and never reversed."""
    r = run_start_stop(fmus, method, contact_params=options)
    t, V, om = r["time"], r["wheelset.speed"], r["wheelset.omega"]
    F = r["contact_L.Fx"]
    assert np.isfinite(np.array([V, om, F, r["wheelset.xi"]])).all()
    assert np.abs(F).max() <= MU * N_WHEEL * (1 + 1e-9)
    drive, brake = t <= 0.05, t > 0.06
    # forces lag one step (zero-order hold): zero at the first two samples, forward after
    assert V[0] == 0.0 and np.all(np.diff(V[drive]) >= 0) and F[drive][2:].min() > 0
    assert np.all(np.diff(V[brake]) <= 1e-12) and F[brake].max() < 0
    assert V.min() >= -1e-9                                    # never rolls backwards
    assert V[-1] < 0.02 * V.max() and abs(om[-1] * R0) < 0.02 * V.max()
    assert chatter(F, 1e-4 * MU * N_WHEEL) == 0


def test_too_small_regularisation_chatters(fmus):
    """The regularisation speed is what keeps the coupling calm: a fifth of it, at the same
    step, makes the creep force flip at every step near standstill."""
    r = run_start_stop(fmus, "fastsim", v_reg_factor=0.2)
    assert chatter(r["contact_L.Fx"], 1e-4 * MU * N_WHEEL) > 1000
