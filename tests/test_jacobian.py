"""The contact law's Jacobian (issue 62 item 2): ``solve(..., jacobian=True)``, the evaluators'
(chained through Hertz's patch) and the FMU's ``fmi2GetDirectionalDerivative``.

References: central differences of ``contact_core.solve`` (of the evaluators' ``evaluate``) with
a small step, independent of the analytic derivatives; Kalker's linear theory (Kalker 1979
eq 17: ∂Fx/∂ξ = -G c² C11, ∂Fy/∂η = -G c² C22 at vanishing creepage, C from Kalker's table);
Coulomb's law at full sliding (|F| = μN: ∂F/∂N = μ F/|F|); Hertz's a, b ∝ N^{1/3} (Kalker 1979
sec. 2).

Errors are stated in the natural units of each entry: the output over μN (forces), μN c (Mz,
c = √(ab)) or 1 (slip fraction), the input over μ p0/G (ξ, η), μ p0/(G c) (φ), N, μ, a, b.
The analytic Jacobians (linear, johnson_vermeulen, table) and polach's differences are held to
1e-6 of central differences of solve (1e-4 on the spin axis, where those differences lose
digits); FASTSIM's and the exact method's differences to 2e-2 between steps a third and three
times the default."""
from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

import contact_core as cc
from conftest import options_for
from contact_core import jacobian as jac_module
from wheel_rail_fmu.host import FmuInstance

E, NU = 210e9, 0.28
G = cc.shear_modulus(E, NU)
NAMES = ("xi", "eta", "phi", "N", "mu", "a", "b")
OUTS = ("Fx", "Fy", "Mz", "slip_fraction")


def state(ratio: float, xi: float, eta: float, phi: float, N: float = 1e5,
          mu: float = 0.3) -> dict:
    """A contact of curvature ratio A/B = ``ratio`` (B of the default rail crown)."""
    p = cc.hertz(N, ratio * 1.67, 1.67, E, NU)
    return dict(xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=p.a, b=p.b, G=G, nu=NU)


def scales(s: dict) -> tuple[np.ndarray, np.ndarray]:
    """Natural scales of the outputs and the inputs (module docstring)."""
    c = math.sqrt(s["a"] * s["b"])
    p0 = 1.5 * s["N"] / (math.pi * s["a"] * s["b"])
    creep = s["mu"] * p0 / G
    mun = s["mu"] * s["N"]
    return (np.array([mun, mun, mun * c, 1.0]),
            np.array([creep, creep, creep / c, s["N"], s["mu"], s["a"], s["b"]]))


def differences(method: str, s: dict, rel: float = 1e-5, **options) -> np.ndarray:
    """Central differences of solve, each input's step ``rel`` times its natural scale."""
    _, inputs = scales(s)
    out = np.zeros((4, 7))
    for j, name in enumerate(NAMES):
        h = rel * inputs[j]
        up = cc.solve(method, **{**s, name: s[name] + h}, **options)
        down = cc.solve(method, **{**s, name: s[name] - h}, **options)
        out[:, j] = [(getattr(up, o) - getattr(down, o)) / (2 * h) for o in OUTS]
    return out


def normalised_error(J: np.ndarray, ref: np.ndarray, s: dict, rows: int = 4) -> float:
    """The largest error in natural units, of the first ``rows`` outputs."""
    outputs, inputs = scales(s)
    return float(np.max(np.abs(J - ref)[:rows] * inputs[None, :] / outputs[:rows, None]))


#: States inside the interpolant's cells, and on their boundaries where the slope is the mean of
#: either side's: zero creepage, pure spin, ξ = 0, η = 0, φ = 0 (a node of θ), a/b = 1 (a node
#: of a/b), near full sliding, large spin (the moment held to Coulomb's bound); each with the
#: relative step of its reference differences and the error allowed: at zero creepage the
#: saturation's |creepage| term makes a difference of step h off by about h, and
#: Johnson–Vermeulen's (1 - s³)/τ loses the digits of τ (so 1e-8: both about 1e-8); on the spin
#: axis the forces have a term in ξ|ξ| (the polar angle from the axis is |ξ|/|v|: a difference
#: is off by about its step), and the table's polar angle is acos of a number near 1, whose
#: rounding a step below about 1e-6 sees: 3e-6, and 1e-4 allowed there.
STATES = [(state(r, *c), rel, tol) for r, c, rel, tol in [
    (0.4, (1.2e-3, -5e-4, 0.3), 1e-6, 1e-6), (2.5, (-7e-4, 9e-4, -0.6), 1e-6, 1e-6),
    (1.0, (4e-4, 2e-4, 0.1), 1e-6, 1e-6), (0.65, (0.0, 0.0, 0.0), 1e-8, 1e-6),
    (0.65, (0.0, 0.0, 0.3), 3e-6, 1e-4), (0.65, (0.0, 6e-4, 0.2), 1e-6, 1e-6),
    (0.65, (8e-4, 0.0, -0.2), 1e-6, 1e-6), (1.6, (1e-3, -6e-4, 0.0), 1e-6, 1e-6),
    (0.65, (4e-2, -3e-2, 0.5), 1e-6, 1e-6), (0.65, (1e-4, 1e-4, 30.0), 1e-6, 1e-6)]]


@pytest.mark.unit
@pytest.mark.parametrize("method, options", [
    ("linear", {}), ("johnson_vermeulen", {}), ("johnson_vermeulen", {"variant": "original"}),
    ("johnson_vermeulen", {"spin": "ignore"}), ("table", {})])
def test_analytic_jacobian_is_central_differences_of_solve(method, options):
    for s, rel, tol in STATES:
        if options.get("variant") == "original" and s["a"] == s["b"]:
            rel = 1e-4      # near a/b = 1 eq 11's C = (D - B)/m loses the digits of m ~ step
        if options.get("spin") == "ignore" and s["xi"] == s["eta"] == 0.0:
            rel, tol = 1e-8, 1e-6      # spin ignored: zero creepage
        r = cc.solve(method, **s, jacobian=True, **options)
        J = r.jacobian
        assert J.how == "analytic" and J.outputs == OUTS and J.inputs == NAMES
        assert normalised_error(J.matrix, differences(method, s, rel, **options), s) < tol
        # the result is solve's without the Jacobian
        plain = cc.solve(method, **s, **options)
        assert (r.Fx, r.Fy, r.Mz, r.slip_fraction) == \
            (plain.Fx, plain.Fy, plain.Mz, plain.slip_fraction)


@pytest.mark.unit
def test_polach_by_differences():
    for s, rel, tol in STATES:
        J = cc.solve("polach", **s, jacobian=True).jacobian
        assert J.how == "central differences"
        outputs, inputs = scales(s)
        np.testing.assert_allclose(J.steps, jac_module.RELATIVE_STEPS["polach"] * inputs,
                                   rtol=1e-12)
        assert normalised_error(J.matrix, differences("polach", s, rel), s) < tol


@pytest.mark.unit
@pytest.mark.parametrize("method", ["fastsim", "exact"])
def test_differenced_methods_converge_and_meet_linear_theory(method, monkeypatch):
    """FASTSIM's and the exact method's derivatives by differences of the method: stable under
    the step (a third and three times the default), and at small creepage Kalker's linear
    theory: ∂Fx/∂ξ = -G c² C11, ∂Fy/∂η = -G c² C22 (FASTSIM's scheme: (1 + 1/nx) times it;
    the exact solver on its default grid within 2 %, as its forces)."""
    opts = options_for(method)
    s = state(0.65, 1.2e-3, -5e-4, 0.3)
    J = cc.solve(method, **s, jacobian=True, **opts).jacobian
    assert J.how == "central differences"
    base = jac_module.RELATIVE_STEPS[method]
    for factor in (1 / 3, 3.0):
        monkeypatch.setitem(jac_module.RELATIVE_STEPS, method, base * factor)
        other = cc.solve(method, **s, jacobian=True, **opts).jacobian
        # the forces (a discretised method's slip fraction counts elements: a step function)
        assert normalised_error(J.matrix, other.matrix, s, rows=3) < 2e-2
    monkeypatch.setitem(jac_module.RELATIVE_STEPS, method, base)
    small = state(0.65, 1e-7, 1e-7, 0.0)
    if method == "exact":
        opts = {}           # its default grid (coarse grids are several % off Kalker's C22)
    J = cc.solve(method, **small, jacobian=True, **opts).jacobian
    c11, c22, _, _ = cc.creep_coefficients(small["a"] / small["b"], NU)
    c2 = small["a"] * small["b"]
    scale = 1.0 + 1.0 / opts["nx"] if method == "fastsim" else 1.0
    rtol = 0.01 if method == "fastsim" else 0.02
    assert J["Fx", "xi"] == pytest.approx(-G * c2 * c11 * scale, rel=rtol)
    assert J["Fy", "eta"] == pytest.approx(-G * c2 * c22 * scale, rel=rtol)


@pytest.mark.unit
@pytest.mark.parametrize("method", ["johnson_vermeulen", "polach", "fastsim", "table"])
def test_full_sliding_follows_coulomb(method):
    """At full sliding |F| = μN along the slip: ∂F/∂N = μ F/|F| and ∂F/∂μ = N F/|F|."""
    s = state(0.65, 0.3, -0.2, 0.0)
    r = cc.solve(method, **s, jacobian=True, **options_for(method))
    direction = np.array([r.Fx, r.Fy]) / math.hypot(r.Fx, r.Fy)
    J = r.jacobian
    np.testing.assert_allclose([J["Fx", "N"], J["Fy", "N"]], s["mu"] * direction,
                               atol=2e-3 * s["mu"])
    np.testing.assert_allclose([J["Fx", "mu"], J["Fy", "mu"]], s["N"] * direction,
                               atol=2e-3 * s["N"])


@pytest.mark.unit
def test_jacobian_of_effects_no_load_and_falling_friction():
    s = state(0.65, 1e-3, 0.0, 0.0)
    J = cc.solve("table", **s, effects=("longitudinal", "saturation"), jacobian=True).jacobian
    assert not J.matrix[1:3].any() and not J.matrix[:, 1:3].any()     # unselected: zero
    assert J["Fx", "xi"] < 0
    J = cc.solve("johnson_vermeulen", **{**s, "N": 0.0}, jacobian=True).jacobian
    assert J.how == "zero" and not J.matrix.any()
    falling = ("longitudinal", "saturation", "falling_friction")
    r = cc.solve("polach", **s, effects=falling, V=20.0, jacobian=True)
    J = r.jacobian
    assert J.inputs == NAMES + ("V",) and J.how == "central differences"
    h = 1e-4
    up = cc.solve("polach", **s, effects=falling, V=20.0 + h)
    down = cc.solve("polach", **s, effects=falling, V=20.0 - h)
    # beyond the adhesion peak friction falls with the slip velocity: Fx < 0 shrinks
    assert J["Fx", "V"] == pytest.approx((up.Fx - down.Fx) / (2 * h), rel=1e-5)
    assert J["Fx", "V"] > 0
    with pytest.raises(ValueError, match="V=3.0 is given but the effect 'falling_friction'"):
        cc.solve("polach", **s, V=3.0, jacobian=True)


# ---------------------------------------------------------------------------------------------
# The evaluators: the law chained through the patch
# ---------------------------------------------------------------------------------------------

def evaluator_differences(ev, args: list[float], outputs: tuple[str, ...]) -> np.ndarray:
    def values(x):
        r = ev.evaluate(*x)
        d = {"Fx": r.Fx, "Fy": r.Fy, "Mz": r.Mz, "a": ev.a, "b": ev.b, "p0": ev.p0,
             "slip_fraction": r.slip_fraction}
        return np.array([d[o] for o in outputs])
    cols = []
    for j, x in enumerate(args):
        h = 1e-6 * (abs(x) if x else 1e-3)
        up, down = list(args), list(args)
        up[j] += h
        down[j] -= h
        cols.append((values(up) - values(down)) / (2 * h))
    return np.column_stack(cols)


@pytest.mark.unit
@pytest.mark.parametrize("kind", ["fixed", "curvatures", "semi_axes"])
@pytest.mark.parametrize("method", ["table", "johnson_vermeulen"])
def test_evaluator_jacobian_is_differences_of_evaluate(kind, method):
    if kind == "fixed":
        ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method=method, E=E, nu=NU))
        args = [1e-3, -4e-4, 0.2, 9e4, 0.3]
    else:
        ev = cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(
            method=method, E=E, nu=NU, geometry_input=kind))
        args = [1e-3, -4e-4, 0.2, 9e4, 0.3] + ([1.2, 1.5] if kind == "curvatures"
                                                 else [7e-3, 5e-3])
    J = ev.jacobian(*args)
    assert J.inputs == cc.contacts.contact_inputs(ev.config)
    ref = evaluator_differences(ev, args, J.outputs)
    # relative to each output's size and each input's
    ev.evaluate(*args)
    size = {"Fx": 0.3 * 9e4, "Fy": 0.3 * 9e4, "Mz": 0.3 * 9e4 * math.sqrt(ev.a * ev.b),
            "a": ev.a, "b": ev.b, "p0": ev.p0, "slip_fraction": 1.0}
    err = np.abs(J.matrix - ref) * np.abs(np.array(args))[None, :] \
        / np.array([size[o] for o in J.outputs])[:, None]
    assert err.max() < 1e-6
    if kind == "fixed":     # Hertz: a ∝ N^(1/3)
        assert J["a", "N"] == pytest.approx(ev.a / (3 * 9e4), rel=1e-12)
    assert ev.jacobian(*(args[:3] + [-1.0] + args[4:])).how == "zero"


# ---------------------------------------------------------------------------------------------
# The FMU: fmi2GetDirectionalDerivative
# ---------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    from wheel_rail_fmu.build import build
    out = tmp_path_factory.mktemp("jacobian_fmus")
    return {"vehicle3": build("vehicle", out=out, contacts=3),
            "traction": build("traction", "table", out=out)}


@pytest.mark.host
@pytest.mark.fmu_build
def test_fmu_directional_derivatives_are_the_evaluators_jacobian(fmus):
    """fmi2GetDirectionalDerivative (fmpy's getDirectionalDerivative) of every Real output by
    every Real input: each contact's Jacobian of the law at its inputs, zero across contacts
    (block-diagonal), for a seed of any inputs."""
    from fmpy import read_model_description
    md = read_model_description(str(fmus["vehicle3"]))
    assert md.coSimulation.providesDirectionalDerivative
    rng = np.random.default_rng(4)
    inputs = ("xi", "eta", "phi", "N", "mu", "A", "B")
    values = {}
    for k in (1, 2, 3):
        values.update({f"c[{k}].{n}": v for n, v in zip(inputs, (
            1e-3 * rng.uniform(-1, 1), 5e-4 * rng.uniform(-1, 1), 0.3 * rng.uniform(-1, 1),
            1e5 * rng.uniform(0.6, 1.4), 0.3, 1.1 * rng.uniform(0.7, 1.3), 1.67))})
    with FmuInstance(fmus["vehicle3"], "d") as inst:
        inst.step(**values)
        outs = [v.name for v in inst.vars.values()
                if v.causality == "output" and v.type == "Real"]
        knowns = [n for n in values]
        unknown_vrs = [inst.vr(n) for n in outs]
        ev = cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(method="table", E=E, nu=NU))
        J = {k: ev.jacobian(*[values[f"c[{k}].{n}"] for n in inputs]) for k in (1, 2, 3)}
        seed = rng.normal(size=len(knowns))
        got = inst.fmu.getDirectionalDerivative(unknown_vrs, [inst.vr(n) for n in knowns],
                                                list(seed))
        want = []
        for name in outs:
            k, out = int(name[2]), name.split(".", 1)[1]
            want.append(sum(J[k][out, kn.split(".", 1)[1]] * sd
                            for kn, sd in zip(knowns, seed) if int(kn[2]) == k))
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-300)
        # one input's column: its contact's, zero for the others (block-diagonal)
        col = inst.fmu.getDirectionalDerivative(unknown_vrs, [inst.vr("c[2].N")], [1.0])
        for name, v in zip(outs, col):
            k, out = int(name[2]), name.split(".", 1)[1]
            assert v == (J[2][out, "N"] if k == 2 else 0.0)

        # refusals: fmi2Error, a message, nothing changed
        for unknown, known, s, text in (
                ([inst.vr("c[1].xi")], [inst.vr("c[1].xi")], [1.0], "is not a Real output"),
                ([inst.vr("c[1].Fx")], [inst.vr("E")], [1.0], "is not a Real input"),
                ([inst.vr("c[1].Fx")], [inst.vr("c[1].xi")], [math.nan],
                 "is not finite")):
            with pytest.raises(FMICallException) as e:
                inst.fmu.getDirectionalDerivative(unknown, known, s)
            assert e.value.status == 3 and text in inst.errors()[-1]
        assert inst.get("c[1].Fx") == [inst.get("c[1].Fx")[0]]


@pytest.mark.host
@pytest.mark.fmu_build
def test_fmu_directional_derivative_of_a_fixed_geometry_and_its_modes(fmus):
    """The traction scene (inputs ξ, N; μ a parameter): ∂Fx/∂ξ, ∂Fx/∂N (through a, b ∝ N^{1/3})
    as the evaluator's; in Initialization Mode from the inputs set so far; before it refused."""
    with FmuInstance(fmus["traction"], "t", initialize=False) as inst:
        fx, xi, N = inst.vr("Fx"), inst.vr("xi"), inst.vr("N")
        with pytest.raises(FMICallException):
            inst.fmu.getDirectionalDerivative([fx], [xi], [1.0])
        assert "not allowed in instantiated mode" in inst.errors()[-1]
        inst.fmu.setupExperiment(startTime=0.0)
        inst.fmu.enterInitializationMode()
        inst.set(xi=2e-3, N=8e4)
        d = inst.fmu.getDirectionalDerivative([fx, inst.vr("a")], [xi, N], [0.0, 1.0])
        ev = cc.WheelRailEvaluator(cc.WheelRailConfig(
            method="table", effects=cc.load_scene("traction").effects, E=E, nu=NU))
        J = ev.jacobian(2e-3, 0.0, 0.0, 8e4)
        assert d == [J["Fx", "N"], J["a", "N"]]
        inst.fmu.exitInitializationMode()
        inst.initialized = True
        inst.step(xi=-1e-3, N=1.2e5)
        d = inst.fmu.getDirectionalDerivative([fx], [xi], [1.0])
        assert d == [ev.jacobian(-1e-3, 0.0, 0.0, 1.2e5)["Fx", "xi"]]
