"""The uniform interface: every registered method, same inputs, outputs, signs and errors.

Symmetries of steady rolling (Kalker 1967 sec. 4.2; Kalker 1979 sec. 2): Fx is odd in ξ,
Fy and Mz are even in ξ; (η, φ) -> (-η, -φ) flips Fy and Mz and keeps Fx.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import contact_core as cc
from conftest import options_for

pytestmark = pytest.mark.unit

METHODS = cc.methods()
CASES = [  # (xi, eta, phi): linear range, partial slip, near saturation, spin-dominated
    (2e-4, 0.0, 0.0), (1e-3, -5e-4, 0.0), (3e-3, 2e-3, 0.4), (0.0, 1e-4, 2.0), (-1e-3, 2e-4, -0.3),
]


def _solve(method, case, **kw):
    return cc.solve(method, **(case | kw), **options_for(method))


def _close(r, s, case, rtol=1e-9):
    scale = case["mu"] * case["N"]
    np.testing.assert_allclose([r.Fx, r.Fy], [s.Fx, s.Fy], rtol=rtol, atol=rtol * scale)
    np.testing.assert_allclose(r.Mz, s.Mz, rtol=rtol, atol=rtol * scale * math.sqrt(case["a"] * case["b"]))


def test_registry():
    assert METHODS[:2] == ("linear", "johnson_vermeulen")
    assert set(cc.METHODS) == set(METHODS)
    assert sorted(cls.code for cls in cc.METHODS.values()) == list(range(1, len(METHODS) + 1))


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("xi, eta, phi", CASES)
def test_symmetries_of_steady_rolling(method, wheel_rail_case, xi, eta, phi):
    c = wheel_rail_case
    r = _solve(method, c, xi=xi, eta=eta, phi=phi)
    r_xi = _solve(method, c, xi=-xi, eta=eta, phi=phi)
    r_lat = _solve(method, c, xi=xi, eta=-eta, phi=-phi)
    assert all(math.isfinite(v) for v in (r.Fx, r.Fy, r.Mz))
    _close(cc.ContactResult(-r_xi.Fx, r_xi.Fy, r_xi.Mz, method), r, c)  # Fx odd, Fy Mz even in ξ
    if eta == 0.0 and phi == 0.0:
        return
    _close(cc.ContactResult(r_lat.Fx, -r_lat.Fy, -r_lat.Mz, method), r, c)


@pytest.mark.parametrize("method", METHODS)
def test_units_si_and_millimetres_give_the_same_forces(method, wheel_rail_case):
    # Same physical case with lengths in mm and G in N/mm² (= MPa): forces in N agree, the
    # moment comes out in N·mm, the spin is entered in 1/mm.
    c = wheel_rail_case
    xi, eta, phi = 1e-3, -4e-4, 0.5
    si = _solve(method, c, xi=xi, eta=eta, phi=phi)
    mm = cc.solve(method, xi=xi, eta=eta, phi=phi / 1e3, N=c["N"], mu=c["mu"], a=c["a"] * 1e3,
                  b=c["b"] * 1e3, G=c["G"] / 1e6, nu=c["nu"], **options_for(method))
    _close(cc.ContactResult(mm.Fx, mm.Fy, mm.Mz / 1e3, method), si, c)


@pytest.mark.parametrize("method", METHODS)
def test_small_creepage_agrees_with_linear_theory(method, wheel_rail_case):
    # All methods share linear theory as their small-creepage limit (Kalker 1979, eq 18). The
    # discretised methods run here on coarse grids (16-20 elements per axis), within a few percent;
    # their own tests check the convergence to Kalker's coefficients.
    c = wheel_rail_case
    tol = 1e-6 if method in ("linear", "johnson_vermeulen") else 0.06
    for inp in (dict(xi=1e-9, eta=0.0, phi=0.0), dict(xi=0.0, eta=1e-9, phi=0.0)):
        r, lin = _solve(method, c, **inp), cc.solve("linear", **(c | inp))
        assert r.Fx == pytest.approx(lin.Fx, rel=tol, abs=1e-14)
        assert r.Fy == pytest.approx(lin.Fy, rel=tol, abs=1e-14)


@pytest.mark.parametrize("method", METHODS)
def test_zero_load_and_zero_creepage_give_zero_forces(method, wheel_rail_case):
    c = wheel_rail_case
    lifted = _solve(method, c | dict(N=0.0), xi=1e-3, eta=1e-3, phi=1.0)
    assert (lifted.Fx, lifted.Fy, lifted.Mz) == (0.0, 0.0, 0.0)
    rest = _solve(method, c, xi=0.0, eta=0.0, phi=0.0)
    assert (rest.Fx, rest.Fy, rest.Mz) == (0.0, 0.0, 0.0)


BAD = [("xi", math.nan), ("eta", math.inf), ("phi", -math.inf), ("N", -1.0), ("N", math.nan),
       ("mu", -0.1), ("mu", math.inf), ("a", 0.0), ("a", -1e-3), ("b", math.nan), ("G", 0.0),
       ("G", math.inf), ("nu", 0.5), ("nu", -0.01), ("nu", math.nan)]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name, value", BAD)
def test_bad_input_is_a_value_error_naming_the_argument(method, wheel_rail_case, name, value):
    case = wheel_rail_case | dict(xi=1e-3, eta=0.0, phi=0.0) | {name: value}
    with pytest.raises(ValueError, match=rf"^{name}=.*allowed"):
        _solve(method, case)


def test_unknown_method_and_option():
    case = dict(xi=0.0, eta=0.0, phi=0.0, N=1.0, mu=0.3, a=1e-3, b=1e-3, G=8e10, nu=0.28)
    with pytest.raises(ValueError, match="method='kalker'.*allowed"):
        cc.solve("kalker", **case)
    with pytest.raises(ValueError, match="unknown option.*'nx'"):
        cc.solve("linear", nx=10, **case)
    with pytest.raises(ValueError, match=r"^effects=3 is invalid: allowed"):
        cc.solve("linear", effects=3, **case)


@pytest.mark.parametrize("accepted, refused", [(4, True), (4, 4.0), (1, True)])
def test_an_option_refused_stays_refused_after_an_equal_value_was_accepted(accepted, refused):
    # True == 1 == 1.0 in Python: a solver made for the accepted value must not serve the other.
    case = dict(xi=1e-3, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=6e-3, b=5e-3, G=8e10, nu=0.28)
    cc.solve("fastsim", nx=accepted, **case)
    with pytest.raises(ValueError, match=rf"^nx={refused!r} is invalid"):
        cc.solve("fastsim", nx=refused, **case)


@pytest.mark.parametrize("effects", [None, ("longitudinal", "lateral", "saturation")])
@pytest.mark.parametrize("N", [1e5, 1e13])
def test_linear_theory_does_not_depend_on_friction(effects, N):
    # Kalker 1979, eq 17: Fx = -G c² C11 ξ, without μ, also with μ = 0 and the saturation effect
    # selected (which linear theory ignores), on the fast path (N = 1e5) and off it (1e13).
    case = dict(xi=1e-3, eta=0.0, phi=0.0, N=N, a=6e-3, b=5e-3, G=8e10, nu=0.28)
    c11 = cc.creep_coefficients(6e-3 / 5e-3, 0.28)[0]
    for mu in (0.0, 0.3):
        r = cc.solve("linear", mu=mu, effects=effects, **case)
        assert r.Fx == pytest.approx(-8e10 * 6e-3 * 5e-3 * c11 * 1e-3, rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_effect_subsets_compute_only_their_outputs(method, wheel_rail_case):
    c = wheel_rail_case
    full = _solve(method, c, xi=1e-3, eta=0.0, phi=0.0)
    lon = _solve(method, c, xi=1e-3, eta=0.0, phi=0.0, effects=("longitudinal", "saturation"))
    assert (lon.Fy, lon.Mz) == (0.0, 0.0)
    # With the omitted inputs truly zero, the longitudinal-only solve is the full solve.
    assert lon.Fx == pytest.approx(full.Fx, rel=1e-9)
    with pytest.raises(ValueError, match="eta is non-zero"):
        _solve(method, c, xi=1e-3, eta=1e-4, phi=0.0, effects=("longitudinal",))
    with pytest.raises(ValueError, match="unknown effect"):
        _solve(method, c, xi=1e-3, eta=0.0, phi=0.0, effects=("traction",))
    # any iterable of names, as the signature says: a list, a set, a generator
    for spec in (["longitudinal", "saturation"], {"longitudinal", "saturation"},
                 (e for e in ("longitudinal", "saturation"))):
        assert _solve(method, c, xi=1e-3, eta=0.0, phi=0.0, effects=spec).Fx == lon.Fx


@pytest.mark.parametrize("method", METHODS)
def test_without_saturation_the_linear_range_is_not_bounded(method, wheel_rail_case):
    # Effect 'saturation' absent = the μ -> ∞ limit: forces keep growing past μN.
    c = wheel_rail_case
    eff = ("longitudinal", "lateral", "spin")
    r = _solve(method, c, xi=0.02, eta=0.0, phi=0.0, effects=eff)
    assert abs(r.Fx) > 2 * c["mu"] * c["N"]
