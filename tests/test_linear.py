"""Linear theory (Kalker 1979 eq 17) with the coefficients printed in its Table 1 (column C^K)."""
from __future__ import annotations

import math

import pytest

import contact_core as cc

pytestmark = pytest.mark.unit


@pytest.mark.parametrize("ab, c11, c22", [(0.2, 3.37, 2.63), (1.0, 4.12, 3.67), (5.0, 7.78, 8.14)])
def test_creep_forces_use_kalker_coefficients_and_ab(ab, c11, c22):
    # Fx = -ab G C11 ξ, Fy = -ab G C22 η (eq 17), coefficients from Table 1 (ν = 1/4).
    a, G, xi, eta = 6e-3, 80e9, 3e-4, -2e-4
    b = a / ab
    r = cc.solve("linear", xi=xi, eta=eta, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=0.25)
    assert r.Fx == pytest.approx(-a * b * G * c11 * xi, rel=2e-3)
    assert r.Fy == pytest.approx(-a * b * G * c22 * eta, rel=2e-3)


def test_spin_terms_and_their_signs():
    # Fy = -G c³ C23 φ and Mz = -G c⁴ C33 φ for pure spin; Mz = +G c³ C23 η for pure lateral
    # creepage (C32 = -C23, Kalker 1967 sec. 6.1). Kalker 1990 Table E.3, a/b = 1, ν = 1/4:
    # C23 = 1.47, C33 = 1.16.
    a = b = 5e-3
    G, c = 80e9, 5e-3
    spin = cc.solve("linear", xi=0.0, eta=0.0, phi=0.7, N=1e5, mu=0.3, a=a, b=b, G=G, nu=0.25)
    assert spin.Fy == pytest.approx(-G * c ** 3 * 1.47 * 0.7, rel=1e-9)
    assert spin.Mz == pytest.approx(-G * c ** 4 * 1.16 * 0.7, rel=1e-9)
    assert spin.Fx == 0.0
    lat = cc.solve("linear", xi=0.0, eta=1e-3, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=0.25)
    assert lat.Mz == pytest.approx(G * c ** 3 * 1.47 * 1e-3, rel=1e-9)


def test_unsaturated_by_definition(wheel_rail_case):
    c = wheel_rail_case
    small = cc.solve("linear", **(c | dict(xi=1e-4, eta=0.0, phi=0.0)))
    large = cc.solve("linear", **(c | dict(xi=1e-1, eta=0.0, phi=0.0)))
    assert large.Fx == pytest.approx(1e3 * small.Fx, rel=1e-12)
    assert abs(large.Fx) > 10 * c["mu"] * c["N"]
    assert large.slip_fraction == 0.0 and math.isfinite(large.Fx)
