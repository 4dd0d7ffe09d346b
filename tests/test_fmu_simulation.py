"""The WheelRailContact FMU in fmpy: equality with the core, instances, reset, FMI 2.0 statuses
and variability, and isolation (each FMU runs the code it bundles).

References: contact_core.solve (the FMU must reproduce it to the last bit), the FMI 2.0
standard's statuses (sec. 2.1.3) and state machine (sec. 4.2.4)."""
from __future__ import annotations

import math
import os
import subprocess
import sys
import time
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException

import contact_core as cc
from conftest import options_for
from wheel_rail_fmu.build import build
from wheel_rail_fmu.entry import MAX_IDLE_DAYS, cache_root
from wheel_rail_fmu.host import FmuInstance

pytestmark = pytest.mark.host

GEOM = (0.46, math.inf, 0.3)
E, NU = 210e9, 0.28
OUTPUTS = ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction")
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
INPUTS = [dict(xi=1e-3, eta=-5e-4, phi=0.2, N=1e5, mu=0.3),
          dict(xi=2e-3, eta=1e-4, phi=-0.1, N=8e4, mu=0.25),
          dict(xi=-5e-4, eta=3e-4, phi=0.4, N=1.2e5, mu=0.35),
          dict(xi=3e-3, eta=-2e-3, phi=0.0, N=9e4, mu=0.3)]


def reference(method, xi=0.0, eta=0.0, phi=0.0, N=1e5, mu=0.3, warm=None, effects=None,
              options=None, E=E):
    """contact_core.solve with the Hertz patch of the FMU's default geometry: (result, outputs)."""
    if N <= 0.0:
        return warm, [0.0] * 7
    p = cc.hertz_from_radii(N, *GEOM, E, NU)
    r = cc.solve(method, xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=p.a, b=p.b,
                 G=cc.shear_modulus(E, NU), nu=NU, effects=effects, warm_start=warm,
                 **(options_for(method) if options is None else options))
    return r, [r.Fx, r.Fy, r.Mz, p.a, p.b, p.p0, r.slip_fraction]


def outputs(inst: FmuInstance) -> list:
    return inst.get(*[n for n in OUTPUTS if n in inst.vars])


def status_of(call, *args, **kwargs) -> int:
    """The FMI status of a call through fmpy (which raises above warning and returns the status
    of most calls, not of doStep: see :func:`do_step`)."""
    try:
        r = call(*args, **kwargs)
    except FMICallException as e:
        return e.status
    return r if type(r) is int else OK  # (a status is an int, never a bool or a list)


def do_step(inst: FmuInstance, h: float = 1e-3, **inputs: float) -> int:
    """Set ``inputs``, call fmi2DoStep and return its status (advancing the time if it is done)."""
    inst.set(**inputs)
    status = status_of(inst.fmu.fmi2DoStep, inst.fmu.component, inst.t, h, 1)
    if status <= WARNING:
        inst.t += h
    return status


def assert_rel(actual, expected, rtol=1e-12):
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=0.0)


def signal(names, n=12):
    """An input table over [0, 0.011] s: loaded, lifted (N = 0, N < 0) and reloaded rows."""
    t = np.arange(n) * 1e-3
    cols = {"xi": 1e-3 * np.cos(40 * t), "eta": -4e-4 + 1e-2 * t, "phi": 0.3 * np.sin(60 * t),
            "N": 1e5 * (1.0 + 5 * t), "mu": 0.3 - 2 * t}
    cols["N"][4], cols["N"][5] = 0.0, -2e3
    sig = np.zeros(n, dtype=[("time", float)] + [(k, float) for k in names])
    sig["time"] = t
    for k in names:
        sig[k] = cols[k]
    return sig


# ---------------------------------------------------------------------------------------------
# Simulation equals the core
# ---------------------------------------------------------------------------------------------

def _check_simulation(path, method, scene):
    md = read_model_description(str(path))
    names = [v.name for v in md.modelVariables if v.causality == "input"]
    outs = [v.name for v in md.modelVariables if v.name in ("Fx", "Fy", "Mz")]
    res = simulate_fmu(str(path), start_time=0.0, stop_time=0.011, output_interval=1e-3,
                       input=signal(names), start_values={"method": method, **options_for(method)},
                       output=list(names) + outs + ["a", "b", "p0", "slip_fraction", "method_used"])
    assert len(res) == 12
    warm = None
    for row in res:  # each row holds the inputs its outputs were computed from
        ins = {k: float(row[k]) for k in names}
        warm, ref = reference(method, warm=warm, effects=cc.load_scene(scene).effects, **ins)
        ref = dict(zip(OUTPUTS, ref))
        keys = outs + ["a", "b", "p0", "slip_fraction"]
        assert_rel([row[k] for k in keys], [ref[k] for k in keys])
        assert row["method_used"] == cc.METHODS[method].code
    assert np.isfinite(np.array(res.tolist())).all()
    return res


@pytest.mark.parametrize("method", cc.methods())
def test_input_table_simulation_equals_core(fmus, method):
    res = _check_simulation(fmus["full"], method, "full")
    lifted = res[res["N"] <= 0]
    assert len(lifted) == 2 and not lifted["Fx"].any() and not lifted["a"].any()


@pytest.mark.parametrize("scene", ["traction", "tangent_track", "curving"])
def test_scene_simulation_equals_core(fmus, scene):
    _check_simulation(fmus[scene], cc.load_scene(scene).default_method, scene)


def test_two_instances_are_independent(fmus):
    m2 = cc.methods()[-1]
    with FmuInstance(fmus["full"], "a", {"method": "linear", "E": 200e9}) as a, \
            FmuInstance(fmus["full"], "b", {"method": m2, **options_for(m2)}) as b:
        warm_b = None
        for k, u in enumerate(INPUTS):
            ua, ub = u, INPUTS[-1 - k]
            a.step(**ua)
            b.step(**ub)
            _, ref_a = reference("linear", E=200e9, **ua)
            assert_rel(outputs(a)[:3], ref_a[:3])
            warm_b, ref_b = reference(m2, warm=warm_b, **ub)
            assert_rel(outputs(b), ref_b)
        assert a.get("method_used") == [1] and b.get("method_used") == [cc.METHODS[m2].code]


def test_reset_restores_a_fresh_instance(fmus):
    with FmuInstance(fmus["full"], start={"method": "linear", "E": 150e9}) as inst:
        inst.step(**INPUTS[0])
        inst.fmu.reset()
        assert inst.get("Fx", "E") == [0.0, 210e9]  # start values again
        # Instantiated again: no last successful time before initialisation (FMI 2.0 4.2.4)
        assert status_of(inst.fmu.getRealStatus, 2) == ERROR
        inst.init({"method": "johnson_vermeulen"})
        inst.step(**INPUTS[1])
        assert_rel(outputs(inst), reference("johnson_vermeulen", **INPUTS[1])[1])
        assert inst.get("method_used") == [2]


# ---------------------------------------------------------------------------------------------
# Statuses: bad input is Discard, bad parameters and misuse are Error, nothing is Fatal
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("var", ["xi", "eta", "phi", "N", "mu"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_input_refuses_the_step(fmus, var, bad):
    with FmuInstance(fmus["full"], start={"method": "johnson_vermeulen"}) as inst:
        inst.step(**INPUTS[0])
        good = outputs(inst)
        assert status_of(inst.step, **{**INPUTS[1], var: bad}) == DISCARD
        assert inst.messages[-1][0] == DISCARD and f"{var}=" in inst.messages[-1][1]
        assert outputs(inst) == good  # last finite outputs kept, never NaN
        inst.step(**INPUTS[2])        # the instance is still usable
        assert_rel(outputs(inst), reference("johnson_vermeulen", **INPUTS[2])[1])


def test_invalid_input_error_option(fmus):
    """For hosts that go on after fmi2Discard (OMSimulator): invalid_input="error"."""
    with FmuInstance(fmus["full"], start={"invalid_input": "error"}) as inst:
        assert status_of(inst.step, **{**INPUTS[0], "xi": math.nan}) == ERROR
        assert "xi=nan" in inst.errors()[-1]


@pytest.mark.parametrize("scene", ["traction", "full"])
@pytest.mark.parametrize("N", [0.0, -1.0, -5e4])
def test_lifted_wheel_gives_zero_forces(fmus, scene, N):
    with FmuInstance(fmus[scene]) as inst:
        inputs = {k: v for k, v in INPUTS[0].items() if inst.vars.get(k) and
                  inst.vars[k].causality == "input"}
        inst.step(**inputs)
        assert any(outputs(inst))
        inst.step(**{**inputs, "N": N})
        assert outputs(inst) == [0.0] * len(outputs(inst))
        assert not inst.errors(WARNING)


INVALID = [("traction", "mu", -0.1, "mu=-0.1 is out of range: allowed 0 <= mu"),
           ("full", "E", -1.0, "E=-1.0 is out of range: allowed 0 < E"),
           ("full", "nu", 0.5, "nu=0.5 is out of range: allowed 0 <= nu < 0.5"),
           ("full", "R_wheel", 0.0, "R_wheel=0.0 is out of range"),
           ("full", "R_wheel_profile", -0.1, "allowed 0 < B"),
           ("full", "R_rail_profile", math.nan, "R_rail_profile=nan is out of range"),
           ("full", "method", "jv", "method='jv' is unknown: allowed ['linear'"),
           ("traction", "variant", "nope", "variant='nope' is invalid: allowed"),
           ("full", "invalid_input", "ignore", "invalid_input='ignore' is invalid: allowed"),
           # an option of a method other than the selected one is checked, not ignored
           ("traction", "nx", 0, "nx=0 is invalid: allowed an integer 1 <= nx <= 2000 (elements "
            "per strip) (a parameter of method 'fastsim', checked although "
            "method='johnson_vermeulen' is selected)"),
           ("full", "tol", 0.0, "tol=0.0 is invalid: allowed a number 0 < tol < 1 (a parameter "
            "of method 'exact', checked although method='table' is selected)")]
#: A valid value of each parameter above.
VALID = {"mu": 0.3, "E": 2e11, "nu": 0.3, "R_wheel": 0.5, "R_wheel_profile": 0.0,
         "R_rail_profile": 0.3, "method": "linear", "variant": "kalker", "invalid_input": "error",
         "nx": 20, "tol": 1e-5}


@pytest.mark.parametrize("scene, name, value, message", INVALID)
def test_invalid_parameter_is_an_error_not_fatal(fmus, scene, name, value, message):
    for k in range(3):  # repeatedly, in one process: failing and freeing must not crash the host
        inst = FmuInstance(fmus[scene], f"bad{k}", initialize=False, logging_on=False)
        assert status_of(inst.init, {name: value}) == ERROR
        # logged (even with logging off) before the status was returned
        assert any(message in m for m in inst.errors()), list(inst.messages)
        if k == 2:  # corrected, the same instance initialises
            inst.set(**{name: VALID[name]})
            assert status_of(inst.fmu.exitInitializationMode) == OK
            inst.step(**{k: v for k, v in INPUTS[0].items() if inst.vars.get(k) and
                         inst.vars[k].causality == "input"})
        inst.free()


def test_outputs_are_calculated_in_initialization_mode(fmus):
    # initial="calculated" (FMI 2.0 sec. 2.2.7): read in Initialization Mode, the outputs follow
    # the values set so far (hosts such as libcosim pass them on before the first step).
    with FmuInstance(fmus["traction"], initialize=False) as inst:
        inst.fmu.setupExperiment(startTime=0.0)
        inst.fmu.enterInitializationMode()
        for xi in (1e-3, -2e-3):
            inst.set(xi=xi, N=1e5)
            expected = reference("johnson_vermeulen", xi=xi, effects=cc.load_scene(
                "traction").effects)[1]
            assert inst.get("Fx", "a", "p0") == [expected[0], expected[3], expected[5]]
        inst.set(E=-1.0)
        assert status_of(inst.get, "Fx") == ERROR
        assert "E=-1.0 is out of range" in inst.errors()[-1]
        inst.set(E=E)
        inst.fmu.exitInitializationMode()
        inst.initialized = True
        assert inst.get("Fx", "a", "p0") == [expected[0], expected[3], expected[5]]


def test_non_finite_input_at_initialisation(fmus):
    with FmuInstance(fmus["full"], initialize=False) as inst:
        assert status_of(inst.init, {"N": math.nan}) == ERROR
        assert any("N=nan" in m for m in inst.errors())
        # refused again, and so is a read: the refused exit kept no outputs (found by
        # tests/test_fmi_state_machine.py: the repeated exit entered Step Mode with N=nan)
        assert status_of(inst.fmu.exitInitializationMode) == ERROR
        assert status_of(inst.get, "Fx") == ERROR
        inst.set(N=1e5)
        inst.fmu.exitInitializationMode()
        inst.initialized = True


@pytest.mark.parametrize("name, value", [("E", 1.0), ("R_rail_profile", 0.5),
                                         ("method", "linear"), ("nx", 30), ("tol", 1e-3)])
def test_fixed_parameter_after_initialisation_is_an_error(fmus, name, value):
    with FmuInstance(fmus["full"], start={"method": "johnson_vermeulen"}) as inst:
        inst.step(**INPUTS[0])
        before = inst.get(name)
        forces = outputs(inst)
        assert status_of(inst.set, **{name: value}) == ERROR
        assert inst.get(name) == before
        assert f"{name} is a fixed parameter" in inst.errors()[-1]
        inst.step(**INPUTS[0])
        assert outputs(inst) == forces  # the old value is the one in use


def test_misuse_is_an_error(fmus):
    with FmuInstance(fmus["full"], initialize=False) as inst:
        assert status_of(inst.fmu.doStep, 0.0, 1e-3) == ERROR     # not initialised
        assert "fmi2DoStep at t=0.0 is not allowed in instantiated mode" in inst.errors()[-1]
        inst.init()
        assert status_of(inst.set, Fx=1.0) == ERROR                # an output
        assert status_of(inst.fmu.setReal, [10_000], [1.0]) == ERROR  # no such variable
        assert status_of(inst.fmu.getInteger, [inst.vars["Fx"].valueReference]) == ERROR
        assert status_of(inst.fmu.enterInitializationMode) == ERROR
        assert inst.counts[FATAL] == 0
        inst.step(**INPUTS[0])  # none of it harmed the instance
        assert_rel(outputs(inst), reference(cc.load_scene("full").default_method,
                                            **INPUTS[0])[1])


def test_calls_outside_their_states_are_errors(fmus):
    """FMI 2.0 sec. 4.2.4's table: fmi2Terminate from Step Mode only, fmi2GetRealStatus in Step
    Mode and after fmi2Terminate, fmi2SetXXX never after fmi2Terminate, not even of no value
    (each found by tests/test_fmi_state_machine.py); each an error that changes nothing."""
    with FmuInstance(fmus["full"], initialize=False) as inst:
        assert status_of(inst.fmu.getRealStatus, 2) == ERROR          # Instantiated
        inst.fmu.setupExperiment(startTime=0.25)
        inst.fmu.enterInitializationMode()
        assert status_of(inst.fmu.getRealStatus, 2) == ERROR          # Initialization Mode
        assert status_of(inst.fmu.terminate) == ERROR
        assert "fmi2Terminate is not allowed in initialization mode" in inst.errors()[-1]
        inst.fmu.exitInitializationMode()                # the refused terminate left it so
        inst.initialized = True
        assert inst.fmu.getRealStatus(2) == 0.25
        assert status_of(inst.fmu.getRealStatus, 0) == DISCARD        # fmi2DoStepStatus
        assert "only fmi2LastSuccessfulTime" in inst.messages[-1][1]
        inst.fmu.terminate()
        assert inst.fmu.getRealStatus(2) == 0.25
        for set_none in (inst.fmu.setReal, inst.fmu.setInteger, inst.fmu.setString):
            assert status_of(set_none, [], []) == ERROR
            assert "not allowed after fmi2Terminate" in inst.errors()[-1]
        inst.initialized = False
        assert inst.counts[FATAL] == 0


@pytest.mark.parametrize("start", [math.nan, math.inf, -math.inf])
def test_start_time_must_be_finite(fmus, start):
    # the last successful time an FMU state holds (found by tests/test_fmi_state_machine.py)
    with FmuInstance(fmus["full"], initialize=False) as inst:
        assert status_of(inst.fmu.setupExperiment, startTime=start) == ERROR
        assert f"startTime={start!r} is out of range: allowed a finite number" in \
            inst.errors()[-1]
        inst.init()        # the start time is still the default, 0
        assert inst.fmu.getRealStatus(2) == 0.0


def test_text_that_is_not_utf8_is_an_error_naming_the_value(fmus):
    """fmi2SetString of bytes that are not UTF-8: an error that says which value, nothing set
    (found by tests/test_fmi_state_machine.py: it was an "unexpected Python exception")."""
    from ctypes import c_char_p, c_uint
    with FmuInstance(fmus["full"], initialize=False) as inst:
        vrs = (c_uint * 2)(inst.vr("method"), inst.vr("invalid_input"))
        status = inst.fmu.dll.fmi2SetString(inst.fmu.component, vrs, 2,
                                            (c_char_p * 2)(b"linear", b"discard\xff"))
        assert status == ERROR
        assert inst.errors()[-1] == (f"fmi2SetString: the value of valueReference "
                                     f"{inst.vr('invalid_input')} is not UTF-8: allowed UTF-8 "
                                     "text; nothing was set")
        assert inst.get("method", "invalid_input") == ["table", "discard"]


@pytest.mark.parametrize("how", ["guid", "missing resources"])
def test_refused_instantiation_says_why(fmus, how):
    """fmi2Instantiate with another FMU's GUID or a folder without this FMU's resources: NULL
    and a message about the argument, not a Python traceback (found by
    tests/test_fmi_state_machine.py)."""
    from ctypes import byref
    with FmuInstance(fmus["full"], initialize=False) as inst:
        resources = Path(inst.fmu.unzipDirectory) / "resources"
        guid, expected = inst.md.guid, "fmuResourceLocation"
        if how == "guid":
            guid, expected = "{00000000-0000-0000-0000-000000000000}", "is not the GUID"
        else:
            resources = resources.parent / "nowhere"
        c = inst.fmu.dll.fmi2Instantiate(b"refused", 1, guid.encode(),
                                         resources.as_uri().encode(), byref(inst._callbacks),
                                         0, 0)
        assert c is None
        assert expected in inst.errors()[-1]
        assert "Traceback" not in inst.errors()[-1]


@pytest.mark.parametrize("h", [0.0, -1e-3, math.nan, math.inf])
def test_step_size_must_be_positive(fmus, h):
    # FMI 2.0 sec. 4.2.2: a communication step has h > 0; the time stays finite
    with FmuInstance(fmus["full"], start={"method": "linear"}) as inst:
        inst.step(**INPUTS[0])
        assert do_step(inst, h, **INPUTS[1]) == ERROR
        assert "communicationStepSize" in inst.errors()[-1]
        assert inst.fmu.getRealStatus(2) == 1e-3  # the time of the last step done
        assert do_step(inst, 1e-3, **INPUTS[1]) == OK  # the instance goes on
        assert inst.fmu.getRealStatus(2) == 2e-3


@pytest.mark.parametrize("method", ["johnson_vermeulen", "exact"])
def test_outputs_follow_the_inputs_at_a_communication_point(fmus, method):
    """The ModelStructure declares the outputs directly dependent on the inputs (FMI 2.0 sec.
    2.2.8): read after a set, they are the law at the values set (a master that solves the
    loop at a communication point sees no delay), and the step that follows has nothing left to
    compute: "set, get, step" gives what "set, step, get" gives, to the last bit, warm start
    included."""
    start = {"method": method, **options_for(method)}
    with FmuInstance(fmus["full"], "a", start) as a, FmuInstance(fmus["full"], "b", start) as b:
        warm = None
        for u in INPUTS:
            a.set(**u)
            early = outputs(a)                 # before the step
            assert do_step(a) == OK
            assert outputs(a) == early          # the step computed nothing new
            b.step(**u)                         # the usual order
            assert outputs(b) == early
            warm, ref = reference(method, warm=warm, **u)
            assert_rel(early, ref)


def test_an_input_the_step_would_refuse_read_back_is_a_warning(fmus):
    # fmi2GetReal may not return fmi2Discard in co-simulation (FMI 2.0 sec. 2.1.3): a warning
    # naming the variable, the last outputs; the step then refuses as always
    with FmuInstance(fmus["full"], start={"method": "johnson_vermeulen"}) as inst:
        inst.step(**INPUTS[0])
        good = outputs(inst)
        inst.set(**{**INPUTS[1], "xi": math.nan})
        assert outputs(inst) == good  # fmpy raises above fmi2Warning
        assert inst.messages[-1][0] == WARNING and "xi=nan" in inst.messages[-1][1]
        assert do_step(inst) == DISCARD


# an a/b the core warns about (C33 held beyond Kalker's table; the table outside its a/b range)
WARNED = [("linear", 0.002, "CoefficientExtrapolationWarning: C33 for a/b > 10 is held"),
          ("table", 0.01, "TableDomainWarning: table: a/b=11.")]


@pytest.mark.parametrize("k, host_filter", list(enumerate(["default", "error", "ignore"])))
@pytest.mark.parametrize("method, rail, message", WARNED)
def test_core_warnings_go_to_the_logger_whatever_the_host_filters(fmus, k, host_filter, method,
                                                                  rail, message):
    """The core's Python warnings reach the FMI logger once, with fmi2Warning (FMI 2.0 sec.
    2.1.3), and never the host's warning machinery: under filters that raise them (python -W
    error) the steps are done as under any other."""
    rail *= 1.0 + 0.01 * k  # an a/b of its own: the core warns once per a/b and process
    with warnings.catch_warnings(record=True) as escaped:
        warnings.simplefilter(host_filter)
        with FmuInstance(fmus["full"], initialize=False) as inst:
            inst.fmu.setupExperiment(startTime=0.0)
            inst.fmu.enterInitializationMode()
            inst.set(method=method, R_rail_profile=rail)
            got = [status_of(inst.fmu.exitInitializationMode)]  # N = 0 (lifted) so far
            got += [do_step(inst, **u) for u in INPUTS]
            forces = outputs(inst)
            logged = [m for s, m in inst.messages if s == WARNING and message in m]
    assert escaped == []
    assert len(logged) == 1, list(inst.messages)
    assert got == [OK, WARNING, OK, OK, OK]  # the first loaded step logged it
    r = None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for u in INPUTS:  # the FMU's sequence of steps, each warm-started from the one before
            p = cc.hertz_from_radii(u["N"], 0.46, math.inf, rail, E, NU)
            r = cc.solve(method, **u, a=p.a, b=p.b, G=cc.shear_modulus(E, NU), nu=NU,
                         warm_start=r)
    assert_rel(forces[:3], [r.Fx, r.Fy, r.Mz])


NOT_CONVERGED = {"method": "exact", "maxit": 1, "mx": 12, "my": 12, "extrapolate": False}


def test_a_step_that_did_not_converge_returns_a_warning(fmus):
    with FmuInstance(fmus["full"], start=NOT_CONVERGED) as inst:
        assert do_step(inst, **INPUTS[0]) == WARNING
        assert "stopped after 1 iterations" in inst.messages[-1][1]


def test_reading_outputs_after_a_step_that_did_not_converge_changes_nothing(fmus):
    """Reads return the step's outputs, however often (FMI 2.0 sec. 4.2.4: getting values does
    not change the model); the next step, not a read, goes on iterating."""
    with FmuInstance(fmus["full"], "a", NOT_CONVERGED) as a, \
            FmuInstance(fmus["full"], "b", NOT_CONVERGED) as b:
        for u in INPUTS[:2]:
            do_step(a, **u)
            first = outputs(a)
            assert outputs(a) == first and outputs(a) == first
            b.set(**u)
            assert outputs(b) == first     # "set, get, step, get" = "set, step, get"
            do_step(b)
            assert outputs(b) != first     # the step iterated further from there
            do_step(a)                     # and so does a step without new inputs
            assert outputs(a) == outputs(b)


def test_outputs_read_after_terminate_are_those_of_the_last_inputs(fmus):
    with FmuInstance(fmus["full"], start={"method": "johnson_vermeulen"}) as inst:
        inst.step(**INPUTS[0])
        inst.set(**INPUTS[1])
        inst.fmu.terminate()
        inst.initialized = False
        assert_rel(outputs(inst), reference("johnson_vermeulen", **INPUTS[1])[1])


def test_core_warnings_reach_the_logger_whenever_they_arise(fmus):
    """Not only at the first loaded step: a later exact step that stops early, and the C33
    warning first met after a step with μ = 0 (whose forces need no coefficient)."""
    with warnings.catch_warnings(record=True) as escaped:
        warnings.simplefilter("always")
        with FmuInstance(fmus["full"], "e", {"method": "exact", "maxit": 3, "mx": 12, "my": 12,
                                             "extrapolate": False}) as inst:
            assert do_step(inst, **{**INPUTS[0], "xi": 0.0, "eta": 0.0, "phi": 0.0}) == OK
            assert do_step(inst, **INPUTS[0]) == WARNING
            assert any("ExactSolverWarning: exact: not converged" in m for _, m in inst.messages)
        with FmuInstance(fmus["full"], "c", {"method": "johnson_vermeulen",
                                             "R_rail_profile": 0.00213}) as inst:
            assert do_step(inst, **{**INPUTS[0], "mu": 0.0}) == OK
            assert do_step(inst, **INPUTS[0]) == WARNING
            assert any("CoefficientExtrapolationWarning" in m for _, m in inst.messages)
    assert escaped == []


def test_instances_in_threads_leave_the_hosts_warnings_alone(fmus):
    from concurrent.futures import ThreadPoolExecutor

    def run(name):
        with FmuInstance(fmus["full"], name, {**NOT_CONVERGED, "mx": 24, "my": 24}) as inst:
            for k in range(40):
                do_step(inst, **{**INPUTS[k % 4]})
            texts = [m for s, m in inst.messages if s == WARNING]
            return (sum("stopped after" in m for m in texts),
                    sum("ExactSolverWarning" in m for m in texts))

    filters, show = list(warnings.filters), warnings.showwarning
    with ThreadPoolExecutor(2) as pool:
        logged = list(pool.map(run, ["t1", "t2"]))
    # per instance, the FMU's own message at each step that stopped early, the core's once
    assert logged == [(40, 1), (40, 1)]
    assert warnings.filters == filters and warnings.showwarning is show
    with pytest.warns(UserWarning, match="the host's own"):
        warnings.warn("the host's own", UserWarning)


# ---------------------------------------------------------------------------------------------
# Isolation: each FMU runs the code it bundles
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_two_versions_side_by_side_and_one_after_another(fmus, other_version, tmp_path):
    v1 = build("traction", "linear", tmp_path, name="v1")
    ref = reference("linear", xi=1e-3, N=1e5, effects=cc.load_scene("traction").effects)[1][0]
    start = {"N": 1e5, "xi": 1e-3}
    for path, factor in ((v1, 1.0), (other_version, 2.0), (v1, 1.0)):   # one after another
        res = simulate_fmu(str(path), stop_time=2e-3, output_interval=1e-3, start_values=start)
        assert res["Fx"][-1] == factor * ref
    with FmuInstance(v1, "a") as a, FmuInstance(other_version, "b") as b:   # side by side
        a.step(xi=1e-3, N=1e5)
        b.step(xi=1e-3, N=1e5)
        assert (a.get("Fx")[0], b.get("Fx")[0]) == (ref, 2.0 * ref)


def test_scene_fmus_one_after_another_in_one_process(fmus):
    """The first FMU's extraction folder is deleted by fmpy before the second runs."""
    for scene, method in (("traction", "johnson_vermeulen"), ("curving", "fastsim"),
                          ("full", "fastsim"), ("traction", "johnson_vermeulen")):
        _check_simulation(fmus[scene], method, scene)
    # each load appends its resources/ folder to sys.path and drops those fmpy has deleted since:
    # only the last run's folder (deleted when it returned) is left
    gone = [p for p in sys.path if p.endswith("resources") and not os.path.isdir(p)]
    assert len(gone) <= 1, gone


def test_host_contact_core_is_not_used(fmus):
    """This process imported contact_core; the FMU must not run it (a fresh process shows what
    the FMU imports: its own digest-named package, run from the cache folder)."""
    code = (
        "import sys, fmpy, contact_core\n"
        "contact_core.solve = None  # the host's copy, sabotaged\n"
        f"r = fmpy.simulate_fmu({str(fmus['traction'])!r}, stop_time=1e-3, output_interval=1e-3,"
        " start_values={'N': 1e5, 'xi': 1e-3})\n"
        "mods = sorted(m for m in sys.modules if m.endswith('.contact_core'))\n"
        "print(mods[0]); print(sys.modules[mods[0]].__file__); print(repr(float(r['Fx'][-1])))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd="/").stdout.split()
    assert out[0].startswith("_wheel_rail_contact_") and out[0].endswith(".contact_core")
    assert out[1].startswith(str(cache_root()))
    _, ref = reference("johnson_vermeulen", xi=1e-3, N=1e5,
                       effects=cc.load_scene("traction").effects)
    assert float(out[2]) == ref[0]


@pytest.mark.slow
def test_cache_folder_drops_idle_copies(fmus, tmp_path):
    """A start removes the bundle copies no start has used for MAX_IDLE_DAYS days (also one a
    failed start left incomplete), keeps the recent ones and anything else in the folder, and
    marks its own copy as used, so a copy in use is never idle."""
    fmu = fmus["traction"]
    with zipfile.ZipFile(fmu) as z:
        own = "_" + z.read("resources/slavemodule.txt").decode().strip()
    cache = tmp_path / "cache"
    day = 86400.0
    idle = time.time() - (MAX_IDLE_DAYS + 1) * day
    recent = time.time() - (MAX_IDLE_DAYS - 1) * day
    ages = {"_wheel_rail_contact_00000000000000000000": idle,
            "_wheel_rail_contact_11111111111111111111.x7y_3": idle,   # an interrupted copy
            "_wheel_rail_contact_22222222222222222222": recent,
            "user_notes": idle}
    for name, t in ages.items():
        (cache / name / "pkg").mkdir(parents=True)
        (cache / name / "pkg" / "f.py").write_text("x = 1\n")
        os.utime(cache / name, (t, t))
    code = (f"import fmpy\nfmpy.simulate_fmu({str(fmu)!r}, stop_time=1e-3, output_interval=1e-3,"
            " start_values={'N': 1e5, 'xi': 1e-3})\n")
    env = {**os.environ, "CONTACT_CORE_FMU_CACHE": str(cache)}
    for _ in range(2):
        subprocess.run([sys.executable, "-c", code], check=True, env=env, capture_output=True)
        assert sorted(p.name for p in cache.iterdir()) == sorted(
            [own, "_wheel_rail_contact_22222222222222222222", "user_notes"])
        assert (cache / own).stat().st_mtime > recent + day
        os.utime(cache / own, (idle, idle))    # the second start finds its own copy idle
