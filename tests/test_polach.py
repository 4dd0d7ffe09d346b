"""Polach's method (contact_core.polach) against independent references: Kalker's linear theory
(its small-creepage limit for pure ξ, η, φ; Kalker 1979 eq 17 with Kalker's table), Polach's
formulas as printed (1999: the spin's lateral force with K_M of δ; 2005: reduction factors and
falling friction), Coulomb's bound at full sliding, and Polach's own adhesion picture."""
from __future__ import annotations

import math

import numpy as np
import pytest

import contact_core as cc
from contact_core.friction import FrictionLaw

pytestmark = pytest.mark.unit

G, NU, N, MU = 8e10, 0.28, 1e5, 0.3
A, B = 6e-3, 4e-3
CASE = dict(N=N, mu=MU, a=A, b=B, G=G, nu=NU)
C11, C22, C23, C33 = cc.creep_coefficients(A / B, NU)


def pol(xi=0.0, eta=0.0, phi=0.0, **kw):
    return cc.solve("polach", xi=xi, eta=eta, phi=phi, **(CASE | kw))


def test_registered_with_its_own_code():
    assert cc.METHODS["polach"].code == 6
    assert cc.methods().index("johnson_vermeulen") < cc.methods().index("polach")


@pytest.mark.parametrize("inputs", [dict(xi=1e-9), dict(eta=-1e-9), dict(phi=1e-7)])
def test_pure_creepage_or_spin_is_kalkers_linear_theory_at_small_creepage(inputs):
    r, lin = pol(**inputs), cc.solve("linear", **(CASE | dict(xi=0.0, eta=0.0, phi=0.0) | inputs))
    assert r.Fx == pytest.approx(lin.Fx, rel=1e-7, abs=1e-15)
    assert r.Fy == pytest.approx(lin.Fy, rel=1e-7, abs=1e-15)


def test_combined_creepage_has_kalkers_magnitude_along_the_creepage():
    # Polach 1999: c_jj = |(C11 ξ, C22 η)|/s weights the coefficients, the force acts against
    # (ξ, η) (not along (C11 ξ, C22 η) as linear theory)
    xi, eta = 1e-9, 2e-9
    r = pol(xi, eta)
    c = math.sqrt(A * B)
    mag = G * c * c * math.hypot(C11 * xi, C22 * eta)
    assert math.hypot(r.Fx, r.Fy) == pytest.approx(mag, rel=1e-7)
    assert r.Fx / r.Fy == pytest.approx(xi / eta, rel=1e-9)


def test_spin_force_is_polachs_printed_formula():
    # Polach 1999 (our sign: against the spin): F_yS = (9/16) a μN K_M k_s φ/s_C with
    # K_M = |ε_M|(δ³/3 - δ²/2 + 1/6) - (1/3)√((1 - δ²)³), δ = (ε_M² - 1)/(ε_M² + 1),
    # ε_M = (8/3) G b √(ab) C23 |s_yC| / (k_s μN), k_s = 1 + 6.3 (1 - e^(-a/b)); pure spin:
    # s_yC = φ a = s_C
    ks = 1 + 6.3 * (1 - math.exp(-A / B))
    for phi in (0.05, 0.5, 2.0, 8.0, 50.0):
        s_yc = phi * A
        em = 8 / 3 * G * B * math.sqrt(A * B) * C23 * s_yc / (ks * MU * N)
        d = (em ** 2 - 1) / (em ** 2 + 1)
        km = em * (d ** 3 / 3 - d ** 2 / 2 + 1 / 6) - math.sqrt((1 - d * d) ** 3) / 3
        fy = 9 / 16 * A * MU * N * km * ks * phi / s_yc
        assert pol(phi=phi).Fy == pytest.approx(fy, rel=1e-9)


def test_full_sliding_reaches_mu_n_against_the_creepage():
    for xi, eta in ((1.0, 0.0), (0.3, -0.4), (0.0, 2.0)):
        r = pol(xi, eta)
        assert math.hypot(r.Fx, r.Fy) == pytest.approx(MU * N, rel=1e-4)
        assert (r.Fx * xi + r.Fy * eta) / (MU * N * math.hypot(xi, eta)) == pytest.approx(-1.0)
        assert math.hypot(r.Fx, r.Fy) <= MU * N


def test_adhesion_area_of_polachs_picture():
    # Polach 1999: on each strip the linear stress ε(1 - x) meets the bound √(1 - x²) at
    # x = (ε² - 1)/(ε² + 1); integrating gives F = (2μN/π)(ε/(1 + ε²) + arctan ε). Found here by
    # quadrature over the strip (normalised), and the slip fraction is the slipping share.
    from scipy.integrate import quad
    c = math.sqrt(A * B)
    for xi in (2e-4, 1e-3, 4e-3):
        eps = math.pi / 4 * G * c * c * C11 * xi / (MU * N)
        stress = lambda x: min(eps * (1 - x), math.sqrt(max(1 - x * x, 0.0)))   # noqa: E731
        x0 = (eps ** 2 - 1) / (eps ** 2 + 1)
        integral = quad(stress, -1, 1, points=[x0], epsabs=1e-13)[0]
        r = pol(xi)
        assert -r.Fx == pytest.approx(2 * MU * N / math.pi * integral, rel=1e-9)
        assert r.slip_fraction == pytest.approx((x0 + 1) / 2, rel=1e-9)


def test_reduction_factors_polach_2005():
    # Polach 2005: F = (2μN/π)(k_A ε/(1 + (k_A ε)²) + arctan(k_S ε)): initial slope
    # (k_A + k_S)/2 of Kalker's; k_S well below k_A gives the curve a local maximum below μN
    # (the adhesion term's peak at k_A ε = 1 before the slip term takes over), and full sliding
    # still reaches μN
    lin = cc.solve("linear", xi=1e-9, eta=0.0, phi=0.0, **CASE).Fx
    assert pol(1e-9, k_A=0.8, k_S=0.3).Fx == pytest.approx(0.55 * lin, rel=1e-7)
    xs = np.linspace(1e-4, 0.05, 400)
    f = np.array([-pol(x, k_A=1.0, k_S=0.1).Fx for x in xs])
    falls = np.flatnonzero(np.diff(f) < 0)
    assert falls.size and f[falls[0]] < MU * N and f[falls[0] + 1:].min() < f[falls[0]]
    assert -pol(1e6, k_A=1.0, k_S=0.1).Fx == pytest.approx(MU * N, rel=1e-5)
    with pytest.raises(ValueError, match=r"^k_S=0.5 is invalid with k_A=0.4"):
        pol(1e-3, k_A=0.4, k_S=0.5)
    with pytest.raises(ValueError, match=r"^k_A=0.0 is invalid"):
        pol(1e-3, k_A=0.0)


def test_falling_friction_is_polachs_law_at_the_creep_velocity():
    # Polach 2005: μ = μ0 [(1 - A) e^(-B w) + A], w = V s_C: the same formula as with Coulomb
    # friction at that μ; at full sliding |F| = μ(w) N
    law = FrictionLaw.polach(0.4, 0.6)
    eff = ("longitudinal", "lateral", "spin", "saturation", "falling_friction")
    for xi, eta, phi, V in ((3e-3, 0.0, 0.0, 20.0), (2e-3, -1e-3, 0.4, 30.0), (0.5, 0.0, 0.0, 5.0)):
        eta_c = eta + phi * A if abs(eta + phi * A) > abs(eta) else eta
        w = V * math.hypot(xi, eta_c)
        mu = MU * ((1 - 0.4) * math.exp(-0.6 * w) + 0.4)
        r = pol(xi, eta, phi, V=V, friction=law, effects=eff)
        c = pol(xi, eta, phi, mu=mu)
        assert (r.Fx, r.Fy) == pytest.approx((c.Fx, c.Fy), rel=1e-12)
        if xi == 0.5:
            assert -r.Fx == pytest.approx(mu * N, rel=1e-4)
