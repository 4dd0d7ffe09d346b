"""contact_core.wheel_rail: the per-step evaluation the FMU wraps, against contact_core.solve."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

import contact_core as cc
from conftest import options_for

pytestmark = pytest.mark.unit

GEOM = dict(R_wheel=0.46, R_wheel_profile=math.inf, R_rail_profile=0.3)
E, NU = 210e9, 0.28
STEPS = [(1e-3, -5e-4, 0.2, 1e5, 0.3), (2e-3, 1e-4, -0.1, 8e4, 0.25),
         (5e-4, 0.0, 0.5, 1.2e5, 0.3), (-1e-3, 3e-4, 0.0, 6e4, 0.2)]


def reference(method, xi, eta, phi, N, mu, warm=None, effects=None):
    p = cc.hertz_from_radii(N, GEOM["R_wheel"], GEOM["R_wheel_profile"], GEOM["R_rail_profile"],
                            E, NU)
    return cc.solve(method, xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=p.a, b=p.b,
                    G=cc.shear_modulus(E, NU), nu=NU, effects=effects, warm_start=warm,
                    **options_for(method)), p


@pytest.mark.parametrize("method", cc.methods())
def test_evaluator_equals_solve_chain(method):
    ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method=method, E=E, nu=NU, **GEOM,
                                                  options=options_for(method)))
    warm = None
    for xi, eta, phi, N, mu in STEPS:
        r = ev.evaluate(xi, eta, phi, N, mu)
        ref, p = reference(method, xi, eta, phi, N, mu, warm)
        warm = ref
        np.testing.assert_allclose([r.Fx, r.Fy, r.Mz], [ref.Fx, ref.Fy, ref.Mz], rtol=1e-12, atol=0)
        np.testing.assert_allclose([ev.a, ev.b, ev.p0], [p.a, p.b, p.p0], rtol=1e-12, atol=0)
        assert r.slip_fraction == ref.slip_fraction
        assert ev.method_code == cc.METHODS[method].code


@pytest.mark.parametrize("method", cc.methods())
def test_outputs_pass_their_own_check(method):
    # check_outputs (for outputs read back from a saved FMU state) accepts what evaluate gives:
    # full sliding on Coulomb's bound, linear theory far beyond it, a lifted wheel
    ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method=method, E=E, nu=NU, **GEOM,
                                                  options=options_for(method)))
    sliding = (0.05, -0.03, 2.0, 1e5, 0.3)
    for xi, eta, phi, N, mu in STEPS + [sliding, (1e-3, 0.0, 0.0, -1.0, 0.3)]:
        r = ev.evaluate(xi, eta, phi, N, mu)
        ev.check_outputs(N, mu, r.Fx, r.Fy, ev.a, ev.b, ev.p0, r.slip_fraction)
        if (xi, eta, phi, N, mu) == sliding:
            assert (math.hypot(r.Fx, r.Fy) > mu * N) == (method == "linear")


@pytest.mark.parametrize("N", [0.0, -0.0, -1e3])
def test_lifted_wheel(N):
    ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method="johnson_vermeulen"))
    ev.evaluate(1e-3, 0.0, 0.0, 1e5, 0.3)
    r = ev.evaluate(1e-3, -2e-4, 0.1, N, 0.3)
    assert (r.Fx, r.Fy, r.Mz, ev.a, ev.b, ev.p0, r.slip_fraction) == (0.0,) * 7


@pytest.mark.parametrize("i, name", list(enumerate(["xi", "eta", "phi", "N", "mu"])))
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_input_names_the_variable(i, name, bad):
    ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method="johnson_vermeulen"))
    args = [1e-3, -5e-4, 0.2, 1e5, 0.3]
    args[i] = bad
    with pytest.raises(ValueError, match=rf"^{name}="):
        ev.evaluate(*args)
    args[3] = 0.0  # lifted: other inputs must still be finite
    if name != "N":
        with pytest.raises(ValueError, match=rf"^{name}="):
            ev.evaluate(*args)


@pytest.mark.parametrize("field, value, match", [
    ("method", "nope", r"method='nope' is unknown: allowed \["),
    ("mu", -0.1, r"mu=-0.1 is out of range: allowed 0 <= mu"),
    ("E", 0.0, r"E=0.0 is out of range: allowed 0 < E"),
    ("nu", 0.5, r"nu=0.5 is out of range: allowed 0 <= nu < 0.5"),
    ("R_wheel", -0.46, r"R_wheel=-0.46 is out of range"),
    ("R_wheel_profile", -0.2, r"R_wheel_profile=-0.2.*allowed 0 < B"),
    ("R_rail_profile", math.nan, r"R_rail_profile=nan is out of range"),
])
def test_invalid_configuration_names_parameter_and_range(field, value, match):
    with pytest.raises(ValueError, match=match):
        cc.WheelRailEvaluator(cc.WheelRailConfig(**{field: value}))


def test_config_is_hashable_and_normalised():
    a = cc.WheelRailConfig(method="johnson_vermeulen",
                           options={"variant": "original", "spin": "she"})
    b = cc.WheelRailConfig(method="johnson_vermeulen",
                           options={"spin": "she", "variant": "original"},
                           effects=list(cc.ALL_EFFECTS.names()))
    assert a == b and hash(a) == hash(b)


@pytest.mark.parametrize("name", ["mu", "E", "nu", "R_wheel"])
def test_configuration_checks_are_the_variable_table(name):
    """WheelRailConfig accepts exactly the range contact_core.variables states (just inside each
    finite bound) and names the variable and range outside it."""
    r = cc.variables.BY_NAME[name].range
    base = dict(mu=0.3, E=E, nu=NU, R_wheel=0.46)
    for bound, inward, is_open in ((r.lo, math.inf, r.lo_open), (r.hi, -math.inf, r.hi_open)):
        if math.isinf(bound):
            continue
        inside = math.nextafter(bound, inward) if is_open else bound
        outside = bound if is_open else math.nextafter(bound, -inward)
        cc.WheelRailConfig(**{**base, name: inside}).check()
        with pytest.raises(ValueError, match=rf"{name}=.* is out of range: allowed "
                                             rf".*{name}.*\({re.escape(r.what)}"):
            cc.WheelRailConfig(**{**base, name: outside}).check()
    assert cc.WheelRailConfig().__getattribute__(name) == cc.variables.DEFAULTS[name]
