"""The uniform interface's errors and options: unknown methods, options and effects, an option's
type, and linear theory's independence of friction. The shared contract every registered method
meets (signs, symmetries, units, linear limit, zero forces, errors naming the argument, effects)
is ``tests/test_method_contract.py``.
"""
from __future__ import annotations

import pytest

import contact_core as cc

pytestmark = pytest.mark.unit


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
