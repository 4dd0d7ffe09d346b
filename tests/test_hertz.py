"""Hertz patch against closed forms, a published worked example and independent quadrature."""
from __future__ import annotations

import csv
import math

import pytest
from scipy.integrate import quad

import contact_core as cc

from conftest import REFERENCE_DIR as REFERENCE

pytestmark = pytest.mark.unit
E, NU = 210e9, 0.28


def test_circular_contact_matches_closed_form():
    # Hertz (Johnson, Contact Mechanics 1985, eqs 4.22-4.23): a = (3NR/(4E*))^(1/3),
    # p0 = 3N/(2πa²), approach δ = a²/R, for A = B = 1/(2R).
    N, R = 80e3, 0.46
    e_star = E / (2 * (1 - NU ** 2))
    p = cc.hertz(N, 1 / (2 * R), 1 / (2 * R), E, NU)
    a = (3 * N * R / (4 * e_star)) ** (1 / 3)
    assert p.a == pytest.approx(a, rel=1e-12)
    assert p.b == pytest.approx(a, rel=1e-12)
    assert p.p0 == pytest.approx(3 * N / (2 * math.pi * a * a), rel=1e-12)
    assert p.approach == pytest.approx(a * a / R, rel=1e-12)


def test_elliptic_case_matches_contact_tractcurv_output():
    # Published worked example: CONTACT's `tractcurv` example (Vollebregt & Kalker, open-source
    # CONTACT; Eurosprinter wheel after Polach 2005). Its output gives for curvatures A1, B1 (1/mm),
    # N, G, ν the semi-axes AA, BB (mm) and the approach (mm).
    with open(REFERENCE / "contact_tractcurv_example.csv") as f:
        row = next(csv.DictReader(f))
    G, nu = float(row["G_N_per_mm2"]) * 1e6, float(row["POISS"])
    p = cc.hertz(float(row["FN_N"]), float(row["A1_per_mm"]) * 1e3, float(row["B1_per_mm"]) * 1e3,
                 2 * G * (1 + nu), nu)
    # B1 is printed to 4 significant digits, which moves a and b by < 0.02 %.
    assert p.a * 1e3 == pytest.approx(float(row["AA_mm"]), rel=5e-4)
    assert p.b * 1e3 == pytest.approx(float(row["BB_mm"]), rel=5e-4)
    assert p.approach * 1e3 == pytest.approx(float(row["APPROACH_mm"]), rel=5e-4)


@pytest.mark.parametrize("ratio", [1e-3, 0.01, 0.3, 0.999999, 1.000001, 4.0, 100.0, 1e3])
def test_semi_axes_solve_hertz_equations_by_quadrature(ratio):
    # Independent check of the root: Johnson (1985) eq 4.39, B'/A' = (E(e)/g² - K(e))/(K(e) - E(e)),
    # with K and E evaluated by numerical quadrature instead of Carlson's integrals.
    A, B = ratio, 1.0
    p = cc.hertz(100e3, A, B, E, NU)
    g = min(p.a, p.b) / max(p.a, p.b)
    m = 1 - g * g
    K = quad(lambda t: 1 / math.sqrt(1 - m * math.sin(t) ** 2), 0, math.pi / 2, epsabs=0, epsrel=1e-13)[0]
    Ee = quad(lambda t: math.sqrt(1 - m * math.sin(t) ** 2), 0, math.pi / 2, epsabs=0, epsrel=1e-13)[0]
    if m > 1e-4:  # below, K - E cancels in the quadrature reference itself
        assert (Ee / g ** 2 - K) / (K - Ee) == pytest.approx(max(A, B) / min(A, B), rel=1e-7)
    # The major axis lies along the direction of smaller relative curvature.
    assert (p.a >= p.b) == (A <= B)


def test_orientation_swaps_with_curvatures():
    p1 = cc.hertz(100e3, 0.8, 0.28, E, NU)
    p2 = cc.hertz(100e3, 0.28, 0.8, E, NU)
    assert p1.a < p1.b
    assert (p2.a, p2.b) == pytest.approx((p1.b, p1.a), rel=1e-14)


def test_semi_axes_scale_with_cube_root_of_load():
    # Kalker 1979, sec. 2: "a and b are proportional to N^(1/3)".
    g = cc.hertz_geometry(1.087, 1.667, E, NU)
    p1, p8 = g.patch(10e3), g.patch(80e3)
    assert (p8.a / p1.a, p8.b / p1.b) == pytest.approx((2.0, 2.0), rel=1e-14)
    assert p8.p0 / p1.p0 == pytest.approx(2.0, rel=1e-14)
    assert g.patch(0.0) == cc.HertzPatch(0.0, 0.0, 0.0, 0.0)
    # to the largest load (3N alone would overflow): p0 still follows N^(1/3)
    big, ref = g.patch(1.6e308), g.patch(1.6e308 / 8.0 ** 30)
    assert math.isfinite(big.p0) and big.p0 / ref.p0 == pytest.approx(2.0 ** 30, rel=1e-13)


def test_wheel_rail_helper():
    # Conical wheel (no transverse curvature) on a 0.3 m rail crown: A = 1/(2 r0), B = 1/(2·0.3).
    A, B = cc.wheel_rail_curvatures(0.46, math.inf, 0.3)
    assert (A, B) == pytest.approx((1 / 0.92, 1 / 0.6))
    p = cc.hertz_from_radii(100e3, 0.46, math.inf, 0.3, E, NU)
    assert p == cc.hertz(100e3, A, B, E, NU)
    # A hollow (concave) tread of transverse radius -0.5 m flattens the contact laterally.
    assert cc.hertz_from_radii(100e3, 0.46, -0.5, 0.3, E, NU).b > p.b


@pytest.mark.parametrize("kwargs, name", [
    (dict(A=0.0), "A"), (dict(B=-1.0), "B"), (dict(A=float("nan")), "A"), (dict(E=0.0), "E"),
    (dict(nu=0.5), "nu"), (dict(A=1e4), "A/B"), (dict(N=-1.0), "N"), (dict(N=float("inf")), "N"),
])
def test_bad_input_names_the_argument(kwargs, name):
    args = dict(N=1e5, A=1.0, B=1.0, E=E, nu=NU) | kwargs
    with pytest.raises(ValueError, match=rf"{name}=.*allowed"):
        cc.hertz(**args)


def test_bad_radii_name_the_argument():
    with pytest.raises(ValueError, match="R_wheel=.*allowed"):
        cc.wheel_rail_curvatures(-0.46, math.inf, 0.3)
    with pytest.raises(ValueError, match="R_rail_profile=.*allowed"):
        cc.wheel_rail_curvatures(0.46, math.inf, 0.0)
    with pytest.raises(ValueError, match="B=.*allowed"):  # concave wheel tighter than the rail
        cc.hertz_from_radii(1e5, 0.46, -0.2, 0.3, E, NU)


@pytest.mark.parametrize("ab", [0.05, 0.3, 1.0, 4.0, 20.0])
def test_coulomb_spin_moment_is_the_integral_of_mu_p_r(ab):
    # μ∫ p_n r dA over the Hertz ellipse (Kalker 1979, eq 3), integrated numerically in polar
    # coordinates of the ellipse; on a circle 3π/16 μNa.
    from scipy.integrate import dblquad
    from contact_core.hertz import coulomb_spin_moment, max_pressure
    mu_n, b = 3e4, 0.004
    a = ab * b
    p0 = max_pressure(1.0, a, b)  # per N of load
    integral, _ = dblquad(lambda rho, t: math.sqrt(1 - rho * rho) * rho * a * b * rho
                          * math.hypot(a * math.cos(t), b * math.sin(t)),
                          0.0, 2 * math.pi, 0.0, 1.0, epsabs=0.0, epsrel=1e-10)
    assert coulomb_spin_moment(mu_n, a, b) == pytest.approx(mu_n * p0 * integral, rel=1e-8)
    assert coulomb_spin_moment(mu_n, b, b) == pytest.approx(3 * math.pi / 16 * mu_n * b,
                                                            rel=1e-12)
