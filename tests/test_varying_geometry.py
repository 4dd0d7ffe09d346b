"""The contact geometry as an input at every step (the effect ``varying_geometry``, issue 61):
Hertz's patch from the tabulated solution, the methods' per-call path, the evaluator, the
``vehicle`` scene's FMU (inputs A, B, or with ``--geometry-input semi_axes`` the host's a, b) in
fmpy and libcosim, its statuses and its FMU states.

References: Hertz's root of ``hertz_geometry`` (Brent's method) and Johnson's closed form for the
circle (Contact Mechanics, 1985, eq 4.28), Kalker's coefficients as ``creep_coefficients`` gives
them, ``contact_core.solve`` with the Hertz patch of each step's geometry, FMI 2.0's statuses."""
from __future__ import annotations

import importlib
import json
import math
import struct

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

import contact_core as cc
from conftest import options_for
from wheel_rail_fmu.host import FmuInstance, run_in_libcosim

hertz_module = importlib.import_module("contact_core.hertz")
coefficients = importlib.import_module("contact_core.coefficients")

E, NU = 210e9, 0.28
G = cc.shear_modulus(E, NU)
E_STAR = cc.contact_modulus(E, NU)
VARYING = cc.Effects(varying_geometry=True)
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3


def steps(n: int = 8) -> list[dict]:
    """A contact point moving over curved profiles: every input changes at every step, a/b too."""
    k = np.arange(n)
    cols = {"xi": 1e-3 * (1 + 0.3 * np.sin(k)), "eta": -4e-4 * (1 + 0.2 * np.cos(k)),
            "phi": 0.3 * np.sin(0.7 * k), "N": 1e5 * (1 + 0.1 * np.sin(1.3 * k)),
            "mu": 0.3 - 0.01 * k, "A": 1.09 * (1 + 0.4 * np.sin(0.9 * k)),
            "B": 1.67 * (1 + 0.5 * np.cos(0.6 * k))}
    return [{name: float(col[i]) for name, col in cols.items()} for i in range(n)]


def hertz_solve(method, s, warm=None, effects=None, **options):
    """contact_core.solve with Hertz's patch of the step's curvatures (Brent's root)."""
    p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
    r = cc.solve(method, xi=s["xi"], eta=s["eta"], phi=s["phi"], N=s["N"], mu=s["mu"], a=p.a,
                 b=p.b, G=G, nu=NU, effects=effects, warm_start=warm,
                 **(options_for(method) if not options else options))
    return r, p


# ---------------------------------------------------------------------------------------------
# Hertz's patch per call
# ---------------------------------------------------------------------------------------------

@pytest.mark.unit
@pytest.mark.parametrize("compiled", [False, True])
def test_tabulated_patch_is_the_root_of_hertz_equations(compiled):
    """The tabulated load-independent solution, interpreted and compiled, against the root of
    Hertz's curvature equation (hertz_geometry, Brent's method) over the supported curvature
    ratios, both orientations, ends included: within TABULATED_RTOL in a, b and p0."""
    patch = hertz_module.patch_kernel() if compiled else hertz_module.tabulated_patch
    lo, hi = hertz_module.CURVATURE_RATIO_RANGE
    ratios = np.concatenate([np.geomspace(lo, hi, 401), [1.0, 1.0 + 1e-9, 1.0 - 1e-9]])
    for q in ratios:
        for N, B in ((1e5, 1.7), (3.3e3, 0.04)):
            A = float(q) * B
            want = cc.hertz_geometry(A, B, E, NU).patch(N)
            got = patch(N, A, B, E_STAR)
            np.testing.assert_allclose(got, (want.a, want.b, want.p0),
                                       rtol=hertz_module.TABULATED_RTOL, atol=0)


@pytest.mark.unit
def test_tabulated_circle_is_johnsons_closed_form():
    # Johnson (1985) eq 4.28 for A = B = 1/(2R): a = b = (3NR/(4E*))^(1/3), p0 = 3N/(2πa²)
    for N, R in ((80e3, 0.46), (1.0, 1e-3), (1e7, 50.0)):
        a = (3 * N * R / (4 * E_STAR)) ** (1 / 3)
        got = hertz_module.patch_kernel()(N, 1 / (2 * R), 1 / (2 * R), E_STAR)
        np.testing.assert_allclose(got, (a, a, 3 * N / (2 * math.pi * a * a)), rtol=1e-14)


@pytest.mark.unit
@pytest.mark.parametrize("A, B", [(math.nan, 1.0), (1.0, math.inf), (0.0, 1.0), (1.0, -2.0),
                                  (1.0, 1001.0), (1001.0, 1.0)])
def test_tabulated_patch_has_none_for_impossible_curvatures(A, B):
    assert all(math.isnan(v) for v in hertz_module.patch_kernel()(1e5, A, B, E_STAR))


# ---------------------------------------------------------------------------------------------
# The methods' per-call path
# ---------------------------------------------------------------------------------------------

@pytest.mark.unit
def test_per_call_coefficients_are_kalkers():
    """The coefficients a method takes per call with varying_geometry (compiled inside the
    table, Kalker's asymptotes outside it) are creep_coefficients' to the last bit."""
    per_call = coefficients.per_call_coefficients(True)
    rng = np.random.default_rng(3)
    lo, hi = coefficients.A_OVER_B_RANGE
    for x, nu in zip(rng.uniform(math.log(lo), math.log(hi), 3000), rng.uniform(0, 0.5, 3000)):
        ab = math.exp(x)
        if ab > 10.0:
            continue                # C33 held there, with a warning: checked below
        assert per_call(ab, float(nu)) == cc.creep_coefficients(ab, float(nu))
    cc.clear_caches()           # a cached coefficient warns only when first computed
    with pytest.warns(coefficients.CoefficientExtrapolationWarning):
        assert per_call(20.0, 0.28) == cc.creep_coefficients(20.0, 0.28)


@pytest.mark.unit
@pytest.mark.parametrize("method", ["linear", "johnson_vermeulen", "fastsim", "table", "exact"])
def test_methods_with_the_effect_give_the_same_forces(method):
    """With varying_geometry the methods compute per call what they cache per a/b otherwise:
    the same results, to the bit, a call after another at a new a/b (the table after its rows
    at ν exist: the third call at that ν)."""
    solver = cc.make_solver(method, VARYING, **options_for(method))
    for s in steps(6):
        p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
        args = (s["xi"], s["eta"], s["phi"], s["N"], s["mu"], p.a, p.b, G, NU)
        r = solver.step(*args)
        ref = cc.make_solver(method, **options_for(method)).step(*args)
        assert (r.Fx, r.Fy, r.Mz, r.slip_fraction) == (ref.Fx, ref.Fy, ref.Mz, ref.slip_fraction)
    if method == "table":
        assert list(solver._rows) == [NU]


@pytest.mark.unit
def test_exact_warm_start_survives_geometry_changes():
    """The exact solver's warm start from the previous step, whose a/b differs (its tractions are
    on the grid of the semi-axes, in units of μ p0), keeps its predictors: along a trajectory
    where a/b changes by about 1 % per step, under half the sweeps of cold starts, the same
    forces within the solver's tolerance."""
    opts = dict(mx=24, my=24, extrapolate=False)
    k = np.arange(12)
    warm, sweeps_warm, sweeps_cold = None, 0, 0
    for i in k:
        s = {"xi": 1.5e-3 * (1 + 0.05 * np.sin(0.3 * i)), "eta": -8e-4, "phi": 0.3,
             "N": 1e5 * (1 + 0.02 * i), "mu": 0.3, "A": 1.09 * (1 + 0.01 * i), "B": 1.67}
        s = {n: float(v) for n, v in s.items()}
        cold, p = hertz_solve("exact", s, **opts)
        warm, _ = hertz_solve("exact", s, warm=warm, **opts)
        if i:
            sweeps_warm += warm.iterations
            sweeps_cold += cold.iterations
            assert math.hypot(warm.Fx - cold.Fx, warm.Fy - cold.Fy) <= 1e-5 * s["mu"] * s["N"]
    assert 2 * sweeps_warm <= sweeps_cold


# ---------------------------------------------------------------------------------------------
# The evaluator
# ---------------------------------------------------------------------------------------------

def evaluator(method, **kw):
    return cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(
        method=method, E=E, nu=NU, options=options_for(method), **kw))


@pytest.mark.unit
@pytest.mark.parametrize("method", cc.methods())
def test_evaluator_equals_solve_with_the_hertz_patch_of_each_step(method):
    ev = evaluator(method)
    warm = None
    for s in steps():
        r = ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], s["A"], s["B"])
        p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
        np.testing.assert_allclose([ev.a, ev.b, ev.p0], [p.a, p.b, p.p0],
                                   rtol=hertz_module.TABULATED_RTOL, atol=0)
        # the forces: solve's at the step's patch (the chain of warm starts for exact)
        ref = cc.solve(method, xi=s["xi"], eta=s["eta"], phi=s["phi"], N=s["N"], mu=s["mu"],
                       a=ev.a, b=ev.b, G=G, nu=NU, warm_start=warm, **options_for(method))
        warm = ref
        assert (r.Fx, r.Fy, r.Mz, r.slip_fraction) == (ref.Fx, ref.Fy, ref.Mz, ref.slip_fraction)
        if method != "exact":       # an iteration's stop moves with the last digits of a, b
            ref_h, _ = hertz_solve(method, s)
            np.testing.assert_allclose([r.Fx, r.Fy, r.Mz], [ref_h.Fx, ref_h.Fy, ref_h.Mz],
                                       rtol=1e-12, atol=1e-9)
        assert ev.method_code == cc.METHODS[method].code
        ev.check_outputs(s["N"], s["mu"], r.Fx, r.Fy, ev.a, ev.b, ev.p0, r.slip_fraction,
                         s["A"], s["B"])


@pytest.mark.unit
def test_evaluator_with_the_hosts_patch():
    ev = evaluator("johnson_vermeulen", geometry_input="semi_axes")
    assert ev.geometry == ("a", "b")
    for s in steps(4):
        p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
        a, b = 1.1 * p.a, 0.9 * p.b                      # a patch of the host's own
        r = ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], a, b)
        ref = cc.solve("johnson_vermeulen", xi=s["xi"], eta=s["eta"], phi=s["phi"], N=s["N"],
                       mu=s["mu"], a=a, b=b, G=G, nu=NU)
        assert (r.Fx, r.Fy, r.Mz) == (ref.Fx, ref.Fy, ref.Mz)
        # Hertz's peak pressure of that ellipse (Kalker 1979 eq 3)
        assert (ev.a, ev.b) == (a, b)
        assert ev.p0 == pytest.approx(3 * s["N"] / (2 * math.pi * a * b), rel=1e-15)
        ev.check_outputs(s["N"], s["mu"], r.Fx, r.Fy, a, b, ev.p0, r.slip_fraction, a, b)


@pytest.mark.unit
@pytest.mark.parametrize("A, B, match", [
    (math.nan, 1.6, r"^A=nan is out of range: allowed 0 < A < inf \(relative curvature"),
    (1.0, math.inf, r"^B=inf is out of range: allowed 0 < B < inf"),
    (-1.0, 1.6, r"^A=-1.0 is out of range: .*A <= 0 is not Hertzian"),
    (1.0, 0.0, r"^B=0.0 is out of range: .*B <= 0 is not Hertzian"),
    (1.0, 1e4, r"^A=1.0, B=10000.0: A/B=0.0001 is out of range: allowed 0.001 <= A/B <= 1000"),
])
def test_impossible_curvatures_are_refused_naming_them(A, B, match):
    ev = evaluator("johnson_vermeulen")
    s = steps(1)[0]
    r = ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], s["A"], s["B"])
    before = (ev.a, ev.b, ev.p0, ev.last, ev.method_code)
    with pytest.raises(ValueError, match=match):
        ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], A, B)
    assert (ev.a, ev.b, ev.p0, ev.last, ev.method_code) == before and ev.last is r


@pytest.mark.unit
@pytest.mark.parametrize("a, b, match", [
    (-1e-3, 5e-3, r"^a=-0.001 is out of range: allowed 0 < a < inf"),
    (6e-3, 0.0, r"^b=0.0 is out of range: allowed 0 < b < inf"),
    (math.nan, 5e-3, r"^a=nan is out of range"),
    (6e-3, 1.5, r"a/b=0.004 is out of range: allowed 0.005 <= a/b <= 200"),
])
def test_impossible_semi_axes_are_refused_naming_them(a, b, match):
    ev = evaluator("linear", geometry_input="semi_axes")
    s = steps(1)[0]
    ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], 6e-3, 5e-3)
    before = (ev.a, ev.b, ev.p0, ev.last)
    with pytest.raises(ValueError, match=match):
        ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], a, b)
    assert (ev.a, ev.b, ev.p0, ev.last) == before


@pytest.mark.unit
def test_lifted_wheel_takes_any_finite_geometry():
    ev = evaluator("johnson_vermeulen")
    for N in (0.0, -1e3):
        for A, B in ((0.0, 0.0), (-1.0, 5.0), (1.0, 1e6)):
            r = ev.evaluate(1e-3, 0.0, 0.1, N, 0.3, A, B)
            assert (r.Fx, r.Fy, r.Mz, ev.a, ev.b, ev.p0) == (0.0,) * 6
        host = evaluator("johnson_vermeulen", geometry_input="semi_axes")
        assert host.evaluate(1e-3, 0.0, 0.1, N, 0.3, 0.0, -1.0).Fx == 0.0
        with pytest.raises(ValueError, match=r"^B=nan is out of range: allowed a finite number"):
            ev.evaluate(1e-3, 0.0, 0.1, N, 0.3, 1.0, math.nan)
        with pytest.raises(ValueError, match=r"^a=inf is out of range: allowed a finite number"):
            host.evaluate(1e-3, 0.0, 0.1, N, 0.3, math.inf, 1.0)


@pytest.mark.unit
def test_check_outputs_refuses_a_patch_of_other_curvatures():
    ev = evaluator("table")
    s = steps(1)[0]
    r = ev.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], s["A"], s["B"])
    with pytest.raises(ValueError, match=r"^a=.* is not the Hertz patch of N=.*, A=.*, B=.*"):
        ev.check_outputs(s["N"], s["mu"], r.Fx, r.Fy, ev.a, ev.b, ev.p0, r.slip_fraction,
                         1.01 * s["A"], s["B"])
    host = evaluator("table", geometry_input="semi_axes")
    r = host.evaluate(s["xi"], s["eta"], s["phi"], s["N"], s["mu"], 6e-3, 5e-3)
    host.check_outputs(s["N"], s["mu"], r.Fx, r.Fy, 6e-3, 5e-3, host.p0, r.slip_fraction, 6e-3,
                       5e-3)
    with pytest.raises(ValueError, match=r"^p0=.* is not the Hertz patch of N=.*, a=.*, b=.*"):
        host.check_outputs(s["N"], s["mu"], r.Fx, r.Fy, 6e-3, 5.05e-3, host.p0,
                           r.slip_fraction, 6e-3, 5.05e-3)


@pytest.mark.unit
def test_configurations_say_which_geometry_they_take():
    with pytest.raises(ValueError, match="needs the effect 'varying_geometry'"):
        cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(effects=cc.ALL_EFFECTS))
    with pytest.raises(ValueError, match="use VaryingGeometryConfig"):
        cc.WheelRailEvaluator(cc.WheelRailConfig(effects=VARYING))
    with pytest.raises(ValueError, match=r"E=-1.0 is out of range"):
        cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(E=-1.0))
    with pytest.raises(ValueError, match=r"geometry_input='radii' is invalid: allowed "
                                         r"'curvatures' or 'semi_axes'"):
        cc.VaryingGeometryEvaluator(cc.VaryingGeometryConfig(geometry_input="radii"))


# ---------------------------------------------------------------------------------------------
# The scene and its variables
# ---------------------------------------------------------------------------------------------

@pytest.mark.unit
def test_vehicle_scene_and_its_variables():
    s = cc.load_scene("vehicle")
    assert set(s.effects.names()) == set(cc.ALL_EFFECTS.names()) | {"varying_geometry"}
    assert s.default_method == "table"
    for geometry, inputs in (("curvatures", {"A", "B"}), ("semi_axes", {"a", "b"})):
        table = {v.name: v for v in cc.scene_variables(s.effects, geometry)}
        assert {n for n, v in table.items() if v.causality == "input"} == \
            {"xi", "eta", "phi", "N", "mu"} | inputs
        assert not {"R_wheel", "R_wheel_profile", "R_rail_profile"} & set(table)
        assert set(inputs) <= set(table["p0"].depends) and set(inputs) <= \
            set(table["method_used"].depends)
    # without the effect nothing changes
    assert "A" not in {v.name for v in cc.scene_variables(cc.load_scene("full").effects)}
    with pytest.raises(ValueError, match="geometry_input='radii' is invalid"):
        cc.scene_variables(s.effects, "radii")


# ---------------------------------------------------------------------------------------------
# The FMU: fmpy, libcosim, statuses, states
# ---------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def vehicle(tmp_path_factory) -> dict:
    from wheel_rail_fmu.build import build
    out = tmp_path_factory.mktemp("vehicle")
    return {"curvatures": build("vehicle", out=out),
            "semi_axes": build("vehicle", out=out, geometry_input="semi_axes")}


@pytest.mark.fmu_build
def test_vehicle_fmus_validate_and_declare_their_geometry(vehicle):
    assert vehicle["curvatures"].name == "WheelRailContact_vehicle_table.fmu"
    assert vehicle["semi_axes"].name == "WheelRailContact_vehicle_table_semi_axes.fmu"
    for geometry, inputs, outputs in (("curvatures", {"A", "B"}, {"a", "b", "p0"}),
                                      ("semi_axes", {"a", "b"}, {"p0"})):
        path = vehicle[geometry]
        assert validate_fmu(str(path)) == []
        md = read_model_description(str(path))
        by = {}
        for v in md.modelVariables:
            by.setdefault(v.causality, set()).add(v.name)
        assert inputs <= by["input"] and not inputs & by["output"]
        assert outputs <= by["output"]
        assert not {"R_wheel", "R_wheel_profile", "R_rail_profile"} & by["parameter"]
        units = {v.name: v.unit for v in md.modelVariables}
        assert {units[n] for n in inputs} == ({"1/m"} if geometry == "curvatures" else {"m"})
        # ModelStructure: every output depends on the geometry (the patch and method_used on
        # N and the geometry only)
        for u in md.outputs:
            deps = {d.name for d in u.dependencies}
            assert inputs <= deps, u.variable.name
            if u.variable.name in ("a", "b", "p0", "method_used"):
                assert deps == {"N"} | inputs, u.variable.name


@pytest.mark.fmu_build
def test_geometry_input_needs_the_effect(tmp_path):
    from wheel_rail_fmu.build import build, main
    with pytest.raises(ValueError, match="needs a scene with the effect 'varying_geometry'"):
        build("full", out=tmp_path, geometry_input="semi_axes")
    with pytest.raises(SystemExit):
        main(["--scene", "vehicle", "--geometry-input", "radii", "--out", str(tmp_path)])
    with pytest.raises(ValueError, match=r"unknown parameter\(s\) \['R_wheel'\]"):
        build("vehicle", out=tmp_path, parameters={"R_wheel": 0.5})
    assert not list(tmp_path.glob("*.fmu"))


def _signal(names: list[str], rows: list[dict]) -> np.ndarray:
    sig = np.zeros(len(rows), dtype=[("time", float)] + [(n, float) for n in names])
    sig["time"] = np.arange(len(rows)) * 1e-3
    for n in names:
        sig[n] = [r[n] for r in rows]
    return sig


@pytest.mark.host
@pytest.mark.parametrize("method", cc.methods())
def test_fmpy_simulation_with_curvatures_varying_equals_the_core(vehicle, method):
    rows = steps(10)
    rows[4] = {**rows[4], "N": 0.0, "A": 0.0, "B": -1.0}     # lifted: any finite geometry
    names = ["xi", "eta", "phi", "N", "mu", "A", "B"]
    res = simulate_fmu(str(vehicle["curvatures"]), stop_time=9e-3, output_interval=1e-3,
                       input=_signal(names, rows),
                       start_values={"method": method, **options_for(method)},
                       output=names + ["Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction",
                                       "method_used"])
    assert len(res) == 10
    warm = None
    for row in res:     # each row holds the inputs its outputs were computed from
        s = {n: float(row[n]) for n in names}
        if s["N"] <= 0.0:
            assert not any(row[n] for n in ("Fx", "Fy", "Mz", "a", "b", "p0"))
            continue
        p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
        np.testing.assert_allclose([row["a"], row["b"], row["p0"]], [p.a, p.b, p.p0],
                                   rtol=hertz_module.TABULATED_RTOL, atol=0)
        ref = cc.solve(method, xi=s["xi"], eta=s["eta"], phi=s["phi"], N=s["N"], mu=s["mu"],
                       a=float(row["a"]), b=float(row["b"]), G=G, nu=NU, warm_start=warm,
                       **options_for(method))
        warm = ref
        assert [row["Fx"], row["Fy"], row["Mz"], row["slip_fraction"]] == \
            [ref.Fx, ref.Fy, ref.Mz, ref.slip_fraction]
        if method != "exact":       # an iteration's stop moves with the last digits of a, b
            ref_h, _ = hertz_solve(method, s)
            np.testing.assert_allclose([row["Fx"], row["Fy"], row["Mz"]],
                                       [ref_h.Fx, ref_h.Fy, ref_h.Mz], rtol=1e-12, atol=1e-9)
        assert row["method_used"] == cc.METHODS[method].code


@pytest.mark.host
def test_fmpy_simulation_with_the_hosts_semi_axes(vehicle):
    rows = []
    for s in steps(6):
        p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
        rows.append({**s, "a": 1.05 * p.a, "b": 0.95 * p.b})
    names = ["xi", "eta", "phi", "N", "mu", "a", "b"]
    res = simulate_fmu(str(vehicle["semi_axes"]), stop_time=5e-3, output_interval=1e-3,
                       input=_signal(names, rows), output=names + ["Fx", "Fy", "Mz", "p0"])
    for row in res:
        s = {n: float(row[n]) for n in names}
        ref = cc.solve("table", G=G, nu=NU, **s)
        assert [row["Fx"], row["Fy"], row["Mz"]] == [ref.Fx, ref.Fy, ref.Mz]
        assert row["p0"] == pytest.approx(3 * s["N"] / (2 * math.pi * s["a"] * s["b"]),
                                          rel=1e-15)


def status_of(inst: FmuInstance, **inputs) -> int:
    inst.set(**inputs)
    try:
        inst.fmu.doStep(inst.t, 1e-3)
    except FMICallException as e:
        return e.status
    inst.t += 1e-3
    return OK


@pytest.mark.host
@pytest.mark.parametrize("geometry, bad, message", [
    ("curvatures", {"A": math.nan}, "A=nan is out of range: allowed 0 < A < inf"),
    ("curvatures", {"B": math.inf}, "B=inf is out of range"),
    ("curvatures", {"A": -0.5}, "A=-0.5 is out of range: allowed 0 < A < inf (relative "
                                "curvature along the rolling direction x, 1/m; A <= 0 is not "
                                "Hertzian)"),
    ("curvatures", {"A": 1.0, "B": 1e4}, "A/B=0.0001 is out of range: allowed 0.001 <= A/B"),
    ("semi_axes", {"a": math.nan}, "a=nan is out of range"),
    ("semi_axes", {"b": -1e-3}, "b=-0.001 is out of range: allowed 0 < b < inf"),
])
def test_fmu_refuses_bad_geometry_and_keeps_its_state(vehicle, geometry, bad, message):
    s = steps(2)
    geo = (lambda r: {"A": r["A"], "B": r["B"]}) if geometry == "curvatures" else \
        (lambda r: {"a": 6e-3, "b": 5e-3})
    base = [{k: r[k] for k in ("xi", "eta", "phi", "N", "mu")} | geo(r) for r in s]
    outs = ["Fx", "Fy", "Mz", "p0", "slip_fraction"]
    for choice, status in (("discard", DISCARD), ("error", ERROR)):
        with FmuInstance(vehicle[geometry], start={"invalid_input": choice}) as inst:
            assert status_of(inst, **base[0]) == OK
            good = inst.get(*outs)
            assert status_of(inst, **{**base[1], **bad}) == status
            assert message in inst.messages[-1][1] and inst.messages[-1][0] == status
            assert inst.get(*outs) == good          # outputs keep their last values
            assert status_of(inst, **base[1]) == OK  # and the instance goes on
            assert inst.get(*outs) != good


@pytest.mark.host
@pytest.mark.parametrize("geometry", ["curvatures", "semi_axes"])
def test_fmu_state_round_trip_with_geometry_inputs(vehicle, geometry):
    start = {"method": "exact", "mx": 12, "my": 12, "extrapolate": False}
    rows = steps(5)
    if geometry == "semi_axes":
        rows = [{**r, "a": 6e-3 * (1 + 0.1 * i), "b": 5e-3} for i, r in enumerate(rows)]
    names = ("xi", "eta", "phi", "N", "mu") + (("A", "B") if geometry == "curvatures"
                                                else ("a", "b"))
    rows = [{n: r[n] for n in names} for r in rows]
    outs = ("Fx", "Fy", "Mz", "p0", "slip_fraction")

    def run(inst, part):
        got = []
        for r in part:
            inst.step(**r)
            got.append(inst.get(*outs))
        return got

    with FmuInstance(vehicle[geometry], "a", start) as a, \
            FmuInstance(vehicle[geometry], "b", start) as b:
        run(a, rows[:2])
        state = a.fmu.getFMUstate()
        blob = a.fmu.serializeFMUstate(state)
        first = run(a, rows[2:])
        a.fmu.setFMUstate(state)
        assert run(a, rows[2:]) == first                  # bit for bit, warm start included
        run(b, rows[3:])
        b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
        assert run(b, rows[2:]) == first
        assert b.get(*names) == list(rows[-1].values())    # the geometry inputs came back

        # a state whose outputs are not those of its geometry is refused, nothing changed
        n = struct.unpack_from("<8sII", blob)[2]
        header = json.loads(blob[16:16 + n])
        values = header["values"]
        changed = {"A": 1.01 * values["A"]} if geometry == "curvatures" else \
            {"a": 1.01 * values["a"]}
        from test_fmu_state import _envelope
        crafted = _envelope({**header, "values": {**values, **changed}}, blob[16 + n:-32])
        with pytest.raises(FMICallException):
            b.fmu.deSerializeFMUstate(crafted)
        assert "is not the Hertz patch of" in b.errors()[-1]
        assert "the instance keeps its state" in b.errors()[-1]
        a.fmu.freeFMUstate(state)


@pytest.mark.host
@pytest.mark.slow
def test_libcosim_runs_both_geometry_inputs(vehicle):
    """DNV's libcosim with the two vehicle FMUs in one execution, each given its geometry."""
    s = steps(1)[0]
    p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
    inputs = {**s, "a": 0.9 * p.a, "b": 1.1 * p.b}
    curv, semi = run_in_libcosim([vehicle["curvatures"], vehicle["semi_axes"]], inputs)
    ref, _ = hertz_solve("table", s)
    np.testing.assert_allclose([curv[k] for k in ("Fx", "Fy", "Mz")], [ref.Fx, ref.Fy, ref.Mz],
                               rtol=1e-12)
    ref = cc.solve("table", xi=s["xi"], eta=s["eta"], phi=s["phi"], N=s["N"], mu=s["mu"],
                   a=inputs["a"], b=inputs["b"], G=G, nu=NU)
    np.testing.assert_allclose([semi[k] for k in ("Fx", "Fy", "Mz")], [ref.Fx, ref.Fy, ref.Mz],
                               rtol=1e-12)
