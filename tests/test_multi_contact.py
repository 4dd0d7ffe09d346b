"""Several contacts in one FMU (``build-fmu --contacts N``, issue 62 item 1), the core's
:class:`contact_core.Contacts` under it, its compiled path for the table, and the effects
``varying_geometry`` and ``falling_friction`` together.

References: ``contact_core.solve`` with the Hertz patch of each contact's inputs (every contact
equals it, to the bit), the chain of warm starts of ``solve`` (``warm_start=``), FMI 2.0's
statuses (sec. 2.1.3: fmi2Discard refuses a step and leaves the state), structured naming
(sec. 2.2.9) and ModelStructure (sec. 2.2.8).
"""
from __future__ import annotations

import array
import json
import math
import struct

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import contact_core as cc
from wheel_rail_fmu.host import FmuInstance, run_in_libcosim

E, NU = 210e9, 0.28
G = cc.shear_modulus(E, NU)
VARYING = cc.Effects(varying_geometry=True)
DISCARD = 2
INPUTS = ("xi", "eta", "phi", "N", "mu", "A", "B")


def contact_inputs(n: int, steps: int, seed: int = 0) -> list[list[dict]]:
    """Per step, per contact: creepages, spin, load, friction and curvatures that change at
    every step, each contact its own."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(steps):
        out.append([{"xi": 1.5e-3 * rng.uniform(-1, 1), "eta": 8e-4 * rng.uniform(-1, 1),
                     "phi": 0.4 * rng.uniform(-1, 1), "N": 1e5 * rng.uniform(0.4, 1.6),
                     "mu": rng.uniform(0.15, 0.4), "A": 1.09 * rng.uniform(0.5, 2.0),
                     "B": 1.67 * rng.uniform(0.7, 1.4)} for _ in range(n)])
    return out


def solve_at(method: str, s: dict, a: float, b: float, warm=None, **options):
    return cc.solve(method, xi=s["xi"], eta=s["eta"], phi=s["phi"], N=s["N"], mu=s["mu"], a=a,
                    b=b, G=G, nu=NU, warm_start=warm, **options)


# ---------------------------------------------------------------------------------------------
# The core: Contacts
# ---------------------------------------------------------------------------------------------

def contacts(config, n: int) -> tuple[cc.Contacts, array.array]:
    """Contacts of ``config`` over one array: contact i's inputs, then its 8 outputs."""
    width = len(cc.contacts.contact_inputs(config)) + len(cc.contacts.OUTPUTS)
    values = array.array("d", bytes(8 * n * width))
    return cc.Contacts(config, values, [[i * width + j for j in range(width)]
                                        for i in range(n)]), values


def put(values, c: cc.Contacts, i: int, s: dict) -> None:
    width = len(c.inputs) + len(cc.contacts.OUTPUTS)
    for j, name in enumerate(c.inputs):
        values[i * width + j] = s[name]


def outputs(values, c: cc.Contacts, i: int) -> dict:
    width = len(c.inputs) + len(cc.contacts.OUTPUTS)
    start = i * width + len(c.inputs)
    return dict(zip(cc.contacts.OUTPUTS, values[start:start + len(cc.contacts.OUTPUTS)]))


@pytest.mark.unit
@pytest.mark.filterwarnings("ignore::contact_core.table.method.TableDomainWarning")
@pytest.mark.parametrize("geometry", ["curvatures", "semi_axes", "fixed"])
def test_every_contact_equals_solve(geometry):
    """Table contacts (the compiled path), lifted ones and one outside the table (a/b ~ 0.06:
    the exact method's fallback, by its evaluator), each equal to solve at its patch."""
    if geometry == "fixed":
        config = cc.WheelRailConfig(method="table", E=E, nu=NU)
    else:
        config = cc.VaryingGeometryConfig(method="table", E=E, nu=NU, geometry_input=geometry)
    c, values = contacts(config, 5)
    fixed = cc.hertz_geometry(*config.curvatures(), E, NU) if geometry == "fixed" else None
    warm: dict[int, cc.ContactResult] = {}
    for step, row in enumerate(contact_inputs(5, 3)):
        row[1]["N"] = -1.0 if step == 1 else row[1]["N"]        # lifted at step 1
        if geometry != "fixed":
            row[3].update(A=60.0, B=1.0)                          # a/b ~ 0.06: exact's
        for s in row:
            p = cc.hertz(s["N"], s["A"], s["B"], E, NU) if s["N"] > 0 else None
            s["a"], s["b"] = (1.1 * p.a, 0.9 * p.b) if p else (6e-3, 5e-3)
        for i, s in enumerate(row):
            put(values, c, i, s)
        notes = c.evaluate()
        for i, s in enumerate(row):
            out = outputs(values, c, i)
            if s["N"] <= 0:
                assert [out[k] for k in cc.contacts.OUTPUTS[:7]] == [0.0] * 7
                assert out["method_code"] == cc.METHODS["table"].code
                continue
            if geometry == "curvatures":
                p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
                np.testing.assert_allclose([out["a"], out["b"]], [p.a, p.b], rtol=1e-14)
            elif geometry == "semi_axes":
                assert (out["a"], out["b"]) == (s["a"], s["b"])
            else:
                p = fixed.patch(s["N"])
                assert (out["a"], out["b"], out["p0"]) == (p.a, p.b, p.p0)
            r = solve_at("table", s, out["a"], out["b"], warm.get(i))
            warm[i] = r                     # (the exact fallback's chain of warm starts)
            assert (out["Fx"], out["Fy"], out["Mz"], out["slip_fraction"]) == \
                (r.Fx, r.Fy, r.Mz, r.slip_fraction)
            assert out["method_code"] == cc.METHODS[r.method].code
        assert {i for i, _ in notes} == ({3} if geometry != "fixed" else set())


ANY = st.floats(allow_nan=True, allow_infinity=True)


@pytest.mark.unit
@pytest.mark.filterwarnings("ignore::contact_core.coefficients.CoefficientExtrapolationWarning")
@pytest.mark.filterwarnings("ignore::contact_core.table.method.TableDomainWarning")
@settings(max_examples=300, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(method=st.sampled_from(["linear", "table"]),
       xi=st.one_of(st.floats(-2e-2, 2e-2), ANY), eta=st.one_of(st.floats(-2e-2, 2e-2), ANY),
       phi=st.one_of(st.floats(-5.0, 5.0), ANY), N=st.one_of(st.floats(1.0, 3e5), ANY),
       mu=st.one_of(st.floats(0.0, 1.0), ANY), a=st.one_of(st.floats(1e-4, 3e-2), ANY),
       b=st.one_of(st.floats(1e-4, 3e-2), ANY))
def test_compiled_step_is_the_general_path(method, xi, eta, phi, N, mu, a, b):
    """With varying_geometry, linear and the table take one compiled call where it applies
    (``_step_fused``): the same result, or the same error, as the general path, on any inputs."""
    solver = cc.make_solver(method, VARYING)
    if method == "table":                       # its rows at ν are made at the second call
        for _ in range(2):
            solver.step(1e-3, 0.0, 0.0, 1e5, 0.3, 6e-3, 5e-3, G, NU)
    x = (xi, eta, phi, N, mu, a, b, G, NU)
    try:
        want = cc.ContactMethod.step(solver, *x)
    except ValueError as e:
        with pytest.raises(ValueError) as got:
            solver.step(*x)
        assert str(got.value) == str(e)
        return
    got = solver.step(*x)
    assert (got.Fx, got.Fy, got.Mz, got.slip_fraction, got.method) == \
        (want.Fx, want.Fy, want.Mz, want.slip_fraction, want.method)


@pytest.mark.unit
def test_a_refused_input_leaves_every_contact_as_it_was():
    """An input one contact refuses: ContactInputError naming it (its index, the evaluator's
    message), no output written, every warm start kept, so the next steps are those of contacts
    that never saw it (the exact method's warm starts, solve's chain)."""
    config = cc.VaryingGeometryConfig(method="exact", E=E, nu=NU,
                                      options={"mx": 12, "my": 12, "extrapolate": False})
    a, va = contacts(config, 3)
    b, vb = contacts(config, 3)
    rows = contact_inputs(3, 4, seed=1)
    for c, values in ((a, va), (b, vb)):
        for i, s in enumerate(rows[0]):
            put(values, c, i, s)
        c.evaluate()
    before = list(va)
    lasts = [ev.last for ev in a.evaluators]
    bad = [dict(s) for s in rows[1]]
    bad[2]["B"] = -1.0
    for i, s in enumerate(bad):
        put(va, a, i, s)
    with pytest.raises(cc.ContactInputError, match=r"B=-1.0 is out of range") as e:
        a.evaluate()
    assert e.value.index == 2
    assert [ev.last for ev in a.evaluators] == lasts
    width = len(a.inputs) + len(cc.contacts.OUTPUTS)
    assert [va[i * width + len(a.inputs) + k] for i in range(3) for k in range(8)] == \
        [before[i * width + len(a.inputs) + k] for i in range(3) for k in range(8)]
    warm = [ev.last for ev in b.evaluators]
    for row in rows[1:]:
        for c, values in ((a, va), (b, vb)):
            for i, s in enumerate(row):
                put(values, c, i, s)
            c.evaluate()
        assert list(va) == list(vb)
        for i, s in enumerate(row):         # solve's chain of warm starts, per contact
            out = outputs(va, a, i)
            r = solve_at("exact", s, out["a"], out["b"], warm[i], mx=12, my=12,
                         extrapolate=False)
            warm[i] = r
            assert (out["Fx"], out["Fy"]) == (r.Fx, r.Fy)


@pytest.mark.unit
def test_contacts_refuse_an_index_that_does_not_fit():
    config = cc.VaryingGeometryConfig(method="table", E=E, nu=NU)
    values = array.array("d", bytes(8 * 10))
    with pytest.raises(ValueError, match="allowed one row per contact of 15 positions"):
        cc.Contacts(config, values, [[0] * 7])
    with pytest.raises(ValueError, match="allowed positions 0 <= i < 10"):
        cc.Contacts(config, values, [list(range(15))])


# ---------------------------------------------------------------------------------------------
# The FMU
# ---------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    from wheel_rail_fmu.build import build
    out = tmp_path_factory.mktemp("multi_fmus")
    scene = out / "vehicle_falling.toml"
    scene.write_text('description = "A vehicle\'s traction on real geometry"\n'
                     'effects = ["longitudinal", "lateral", "spin", "saturation", '
                     '"variable_friction", "falling_friction", "varying_geometry"]\n'
                     'default_method = "polach"\n')
    return {"vehicle4": build("vehicle", out=out, contacts=4),
            "traction2": build("traction", "johnson_vermeulen", out=out, contacts=2),
            "falling": build(scene, out=out)}


@pytest.mark.fmu_build
def test_variables_are_named_per_contact_and_depend_on_their_own(fmus):
    md = read_model_description(str(fmus["vehicle4"]))
    assert md.variableNamingConvention == "structured"
    assert md.coSimulation.providesDirectionalDerivative
    names = {v.name: v for v in md.modelVariables}
    for k in range(1, 5):
        for n in INPUTS:
            assert names[f"c[{k}].{n}"].causality == "input"
        for n in ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction", "method_used"):
            assert names[f"c[{k}].{n}"].causality == "output"
    assert not {"xi", "Fx"} & set(names)                      # no unindexed contact variable
    assert names["method"].causality == "parameter" and "c[1].E" not in names   # shared
    for out in md.outputs:
        k = out.variable.name[:5]
        assert out.dependencies and all(d.name.startswith(k) for d in out.dependencies)
    assert str(fmus["vehicle4"]).endswith("WheelRailContact_vehicle_table_4contacts.fmu")
    traction = {v.name for v in read_model_description(str(fmus["traction2"])).modelVariables}
    assert {"c[1].xi", "c[2].N", "c[2].Fx", "mu"} <= traction and "c[1].eta" not in traction


@pytest.mark.fmu_build
def test_build_refuses_a_number_of_contacts(tmp_path, capsys):
    from wheel_rail_fmu.build import build, main
    with pytest.raises(ValueError, match=r"contacts=0 is invalid: allowed an integer 1 <= "
                                         r"contacts <= 1000"):
        build("vehicle", out=tmp_path, contacts=0)
    with pytest.raises(SystemExit) as e:
        main(["--contacts", "-2", "--out", str(tmp_path)])
    assert e.value.code != 0 and "contacts=-2 is invalid" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def _signal(rows: list[list[dict]]) -> np.ndarray:
    names = [f"c[{k}].{n}" for k in range(1, len(rows[0]) + 1) for n in INPUTS]
    sig = np.zeros(len(rows), dtype=[("time", float)] + [(n, float) for n in names])
    sig["time"] = np.arange(len(rows)) * 1e-3
    for n in names:
        k, local = int(n[2]) - 1, n.split(".", 1)[1]
        sig[n] = [r[k][local] for r in rows]
    return sig


@pytest.mark.host
def test_fmpy_every_contact_equals_solve(fmus):
    rows = contact_inputs(4, 6, seed=2)
    rows[2][1] = {**rows[2][1], "N": 0.0, "A": -1.0}        # lifted: any finite geometry
    outs = [f"c[{k}].{n}" for k in range(1, 5) for n in
            INPUTS + ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction", "method_used")]
    res = simulate_fmu(str(fmus["vehicle4"]), stop_time=5e-3, output_interval=1e-3,
                       input=_signal(rows), output=outs)
    assert len(res) == 6
    lifted = 0
    for row in res:     # each row holds the inputs its outputs were computed from
        for k in range(1, 5):
            s = {n: float(row[f"c[{k}].{n}"]) for n in INPUTS}
            lifted += s["N"] <= 0
            got = {n: float(row[f"c[{k}].{n}"]) for n in ("Fx", "Fy", "Mz", "a", "b",
                                                          "slip_fraction")}
            if s["N"] <= 0:
                assert not any(got.values())
                continue
            p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
            np.testing.assert_allclose([got["a"], got["b"]], [p.a, p.b], rtol=1e-14)
            r = solve_at("table", s, got["a"], got["b"])
            assert [got["Fx"], got["Fy"], got["Mz"], got["slip_fraction"]] == \
                [r.Fx, r.Fy, r.Mz, r.slip_fraction]
            assert row[f"c[{k}].method_used"] == cc.METHODS["table"].code
    assert lifted == 1


def _step(inst: FmuInstance, row: list[dict]) -> int:
    inst.set(**{f"c[{k}].{n}": v for k, s in enumerate(row, start=1) for n, v in s.items()})
    try:
        inst.fmu.doStep(inst.t, 1e-3)
    except FMICallException as e:
        return e.status
    inst.t += 1e-3
    return 0


ALL_OUTS = [f"c[{k}].{n}" for k in range(1, 5) for n in ("Fx", "Fy", "Mz", "a", "b", "p0",
                                                          "slip_fraction")]
EXACT = {"method": "exact", "mx": 12, "my": 12, "extrapolate": False}


@pytest.mark.host
def test_a_bad_input_refuses_the_step_naming_the_contact(fmus):
    """fmi2Discard, a message naming the contact and the variable, every contact's outputs as
    they were, and the warm starts: the following steps are those of an instance that never
    saw the bad input."""
    rows = contact_inputs(4, 4, seed=3)
    with FmuInstance(fmus["vehicle4"], "a", EXACT) as a, \
            FmuInstance(fmus["vehicle4"], "b", EXACT) as b:
        for inst in (a, b):
            assert _step(inst, rows[0]) == 0
        before = a.get(*ALL_OUTS)
        bad = [dict(s) for s in rows[1]]
        bad[2]["xi"] = math.nan
        assert _step(a, bad) == DISCARD
        assert a.messages[-1][0] == DISCARD
        assert "refused: c[3]: xi=nan is out of range: allowed a finite number" in \
            a.messages[-1][1]
        assert a.get(*ALL_OUTS) == before
        for row in rows[1:]:
            assert _step(a, row) == _step(b, row) == 0
            assert a.get(*ALL_OUTS) == b.get(*ALL_OUTS)


@pytest.mark.host
def test_fmu_state_holds_every_contact(fmus):
    """get/set/serialise FMU state: every contact's values and warm start (the exact method's),
    continued bit for bit; a state whose contact's patch is not its load's is refused naming
    that contact."""
    rows = contact_inputs(4, 5, seed=4)
    with FmuInstance(fmus["vehicle4"], "a", EXACT) as a, \
            FmuInstance(fmus["vehicle4"], "b", EXACT) as b:
        for row in rows[:2]:
            _step(a, row)
        state = a.fmu.getFMUstate()
        blob = a.fmu.serializeFMUstate(state)

        def run(inst):
            got = []
            for row in rows[2:]:
                _step(inst, row)
                got.append(inst.get(*ALL_OUTS))
            return got
        first = run(a)
        a.fmu.setFMUstate(state)
        assert run(a) == first
        _step(b, rows[4])
        b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
        assert run(b) == first
        n = struct.unpack_from("<8sII", blob)[2]
        header = json.loads(blob[16:16 + n])
        assert isinstance(header["result"], list) and len(header["result"]) == 4
        assert all(r["method"] == "exact" for r in header["result"])
        from test_fmu_state import _envelope
        values = {**header["values"], "c[3].a": 1.01 * header["values"]["c[3].a"]}
        with pytest.raises(FMICallException):
            b.fmu.deSerializeFMUstate(_envelope({**header, "values": values}, blob[16 + n:-32]))
        assert "c[3]: a=" in b.errors()[-1] and "is not the Hertz patch of" in b.errors()[-1]
        a.fmu.freeFMUstate(state)


@pytest.mark.host
def test_fixed_geometry_contacts_with_a_friction_parameter(fmus):
    """The traction scene with 2 contacts: inputs c[k].xi, c[k].N, the parameter mu shared."""
    with FmuInstance(fmus["traction2"], "t", {"mu": 0.2}) as inst:
        inst.step(**{"c[1].xi": 2e-3, "c[1].N": 9e4, "c[2].xi": -5e-4, "c[2].N": 1.1e5})
        ev = cc.WheelRailEvaluator(cc.WheelRailConfig(
            method="johnson_vermeulen", effects=cc.load_scene("traction").effects, mu=0.2,
            E=E, nu=NU))
        for k, (xi, N) in enumerate(((2e-3, 9e4), (-5e-4, 1.1e5)), start=1):
            r = ev.evaluate(xi, 0.0, 0.0, N)
            assert inst.get(f"c[{k}].Fx", f"c[{k}].a") == [r.Fx, ev.a]


@pytest.mark.host
def test_falling_friction_on_a_varying_geometry(fmus):
    """Both effects together (a vehicle's traction on real geometry): the rolling speed V and
    the curvatures A, B inputs; each step solve's with the friction law at V."""
    effects = cc.Effects(varying_geometry=True, falling_friction=True)
    names = {v.name for v in read_model_description(str(fmus["falling"])).modelVariables}
    assert {"V", "A", "B", "friction_law"} <= names and "R_wheel" not in names
    with FmuInstance(fmus["falling"], "f") as inst:
        for xi, V in ((2e-3, 10.0), (8e-3, 30.0), (-4e-3, 0.0)):
            s = {"xi": xi, "eta": 1e-4, "phi": 0.05, "N": 1e5, "mu": 0.3, "A": 1.2, "B": 1.5}
            inst.step(**s, V=V)
            a, b, Fx, Fy = inst.get("a", "b", "Fx", "Fy")
            r = cc.solve("polach", **{k: s[k] for k in ("xi", "eta", "phi", "N", "mu")}, a=a,
                         b=b, G=G, nu=NU, effects=effects, V=V)
            assert (Fx, Fy) == (r.Fx, r.Fy)
        inst.set(V=math.inf)
        with pytest.raises(FMICallException):
            inst.fmu.doStep(inst.t, 1e-3)
        assert "V=inf is out of range" in inst.messages[-1][1]


@pytest.mark.host
@pytest.mark.slow
def test_libcosim_runs_the_contacts(fmus):
    row = contact_inputs(4, 1, seed=5)[0]
    inputs = {f"c[{k}].{n}": v for k, s in enumerate(row, start=1) for n, v in s.items()}
    (got,) = run_in_libcosim([fmus["vehicle4"]], inputs, outputs=[
        f"c[{k}].{n}" for k in range(1, 5) for n in ("Fx", "Fy", "Mz")])
    for k, s in enumerate(row, start=1):
        p = cc.hertz(s["N"], s["A"], s["B"], E, NU)
        r = solve_at("table", s, p.a, p.b)
        np.testing.assert_allclose([got[f"c[{k}].{n}"] for n in ("Fx", "Fy", "Mz")],
                                   [r.Fx, r.Fy, r.Mz], rtol=1e-12)
