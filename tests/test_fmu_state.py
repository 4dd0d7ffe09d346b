"""FMU states: get/set/serialize round-trip bit for bit (exact solver's warm start included); a
serialized state is data only and checked before use: crafted, foreign, truncated or corrupted
states are an fmi2Error that leaves the instance as it was, and never run code."""
from __future__ import annotations

import hashlib
import json
import math
import pickle
import struct
from ctypes import byref

import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2FMUstate

import contact_core as cc
from conftest import options_for
from wheel_rail_fmu.host import FmuInstance
from wheel_rail_fmu.state import FORMAT_VERSION, MAGIC

pytestmark = pytest.mark.host

INPUTS = [dict(xi=1e-3, eta=-5e-4, phi=0.2, N=1e5, mu=0.3),
          dict(xi=2e-3, eta=1e-4, phi=-0.1, N=8e4, mu=0.25),
          dict(xi=-5e-4, eta=3e-4, phi=0.4, N=1.2e5, mu=0.35),
          dict(xi=3e-3, eta=-2e-3, phi=0.0, N=9e4, mu=0.3)]
OUT = ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction")
WARNING, ERROR = 1, 3


def run(inst, inputs):
    out = []
    for u in inputs:
        inst.step(**u)
        out.append(inst.get(*OUT))
    return out


@pytest.mark.parametrize("method", cc.methods())
def test_state_round_trip_is_exact(fmus, method):
    start = {"method": method, **options_for(method)}
    with FmuInstance(fmus["full"], "a", start) as a, FmuInstance(fmus["full"], "b", start) as b:
        run(a, INPUTS[:2])
        state = a.fmu.getFMUstate()
        blob = a.fmu.serializeFMUstate(state)
        first = run(a, INPUTS[2:])
        a.fmu.setFMUstate(state)  # back in time, same instance
        assert run(a, INPUTS[2:]) == first  # bit for bit, warm start included
        # into another instance that has seen other inputs (a different warm start)
        run(b, [INPUTS[3], {**INPUTS[0], "N": 0.0}])
        b_state = b.fmu.deSerializeFMUstate(blob)
        b.fmu.setFMUstate(b_state)
        assert run(b, INPUTS[2:]) == first
        b.fmu.freeFMUstate(b_state)
        a.fmu.freeFMUstate(state)


def test_a_state_pointer_the_instance_does_not_own_is_refused(fmus):
    """FMI 2.0 sec. 2.1.8: a state belongs to the instance that gave it. A pointer the instance
    does not own (another instance's state, one already freed) is refused with fmi2Error and a
    message, and never dereferenced: a second fmi2FreeFMUstate, or fmi2SetFMUstate of a freed
    state, no longer touches freed memory. The owner's state is left as it was."""
    with FmuInstance(fmus["full"], "a", {"method": "linear"}) as a, \
            FmuInstance(fmus["full"], "b", {"method": "linear"}) as b:
        run(a, INPUTS[:1])
        state = a.fmu.getFMUstate()
        copy = fmi2FMUstate(state.value)
        after = run(a, INPUTS[1:2])
        for call in (b.fmu.setFMUstate, b.fmu.serializeFMUstate, b.fmu.freeFMUstate):
            with pytest.raises(FMICallException):
                call(copy)
            assert "is not one of this instance's" in b.errors()[-1]
        a.fmu.setFMUstate(state)                     # still a's, intact
        assert run(a, INPUTS[1:2]) == after
        a.fmu.freeFMUstate(state)
        assert state.value is None
        for call in (a.fmu.setFMUstate, a.fmu.serializeFMUstate, a.fmu.freeFMUstate):
            with pytest.raises(FMICallException):
                call(copy)                           # freed
            assert "is not one of this instance's" in a.errors()[-1]
        over = fmi2FMUstate(copy.value)              # a state to overwrite: only its own
        with pytest.raises(FMICallException):
            a.fmu.fmi2GetFMUstate(a.fmu.component, byref(over))
        assert over.value == copy.value
        assert run(a, INPUTS[1:2]) == after          # the instance works on


def test_state_restores_parameters_and_mode(fmus):
    with FmuInstance(fmus["full"], "a", {"method": "johnson_vermeulen", "E": 180e9}) as a, \
            FmuInstance(fmus["full"], "b", initialize=False) as b:
        run(a, INPUTS[:1])
        state = b.fmu.deSerializeFMUstate(a.fmu.serializeFMUstate(a.fmu.getFMUstate()))
        b.fmu.setFMUstate(state)  # b was never initialised: the state brings step mode
        assert run(b, INPUTS[1:2]) == run(a, INPUTS[1:2])
        assert b.get("method_used", "E") == [2, 180e9]


def test_state_saved_between_a_set_and_a_step_continues_bit_for_bit(fmus):
    """Whether the outputs are those of the inputs is part of the state: restored, the next
    step computes exactly what it computed after the save (warm start included)."""
    start = {"method": "exact", "mx": 12, "my": 12, "extrapolate": False}
    with FmuInstance(fmus["full"], "a", start) as a:
        run(a, INPUTS[:1])
        for read_first in (False, True):
            a.set(**INPUTS[1])
            if read_first:
                a.get(*OUT)                  # the outputs of the inputs set: computed here
            state = a.fmu.getFMUstate()
            a.fmu.doStep(a.t, 1e-3)
            after = a.get(*OUT)
            a.fmu.setFMUstate(state)
            a.fmu.doStep(a.t, 1e-3)
            assert a.get(*OUT) == after
            a.fmu.freeFMUstate(state)


def test_state_restores_the_last_successful_time(fmus):
    """fmi2LastSuccessfulTime (FMI 2.0 sec. 4.2.3) is part of the state (sec. 2.1.8): after
    fmi2SetFMUstate it is the saved one, in the same instance and in another one."""
    with FmuInstance(fmus["full"], "a", {"method": "linear"}, start_time=0.5) as a, \
            FmuInstance(fmus["full"], "b", {"method": "linear"}) as b:
        assert a.fmu.getRealStatus(2) == 0.5  # the start time before the first step
        run(a, INPUTS[:2])
        saved = a.fmu.getRealStatus(2)
        assert saved == 0.5 + 1e-3 + 1e-3
        state = a.fmu.getFMUstate()
        run(a, INPUTS[2:])
        assert a.fmu.getRealStatus(2) > saved
        a.fmu.setFMUstate(state)
        assert a.fmu.getRealStatus(2) == saved
        run(b, INPUTS[:1])
        b_state = b.fmu.deSerializeFMUstate(a.fmu.serializeFMUstate(state))
        b.fmu.setFMUstate(b_state)
        assert b.fmu.getRealStatus(2) == saved
        b.fmu.freeFMUstate(b_state)
        a.fmu.freeFMUstate(state)


def test_exact_warm_start_survives_serialization(fmus):
    """The state holds the exact solver's warm start: the solution and, after a warm-started
    step at the same a/b, the one before it (the secant predictor's)."""
    start = {"method": "exact", "mx": 12, "my": 12, "extrapolate": False}
    with FmuInstance(fmus["full"], "a", start) as a:
        run(a, [INPUTS[0], {**INPUTS[1], "N": INPUTS[0]["N"]}])
        blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
    n = struct.unpack_from("<8sII", blob)[2]
    header = json.loads(blob[16:16 + n])
    assert header["result"]["method"] == "exact"
    assert [s[1] for s in header["arrays"]] == [[12, 12], [12, 12], [3], [12, 12], [12, 12], [3]]


def test_states_of_values_the_fmu_has_not_checked_yet_are_restored(fmus):
    """fmi2SetFMUstate restores every state fmi2GetFMUstate gave (FMI 2.0 sec. 2.1.8): one with
    a non-finite parameter set before initialisation (checked at fmi2ExitInitializationMode),
    one with a friction input a step refused (each found by tests/test_fmi_state_machine.py)."""
    with FmuInstance(fmus["full"], "a", initialize=False) as a:
        a.set(E=math.inf, R_wheel=math.nan)
        state = a.fmu.getFMUstate()
        a.set(E=2e11, R_wheel=0.5)
        a.fmu.setFMUstate(state)
        assert a.get("E")[0] == math.inf and math.isnan(a.get("R_wheel")[0])
        a.fmu.freeFMUstate(state)
    with FmuInstance(fmus["full"], "b", {"method": "linear"}) as b, \
            FmuInstance(fmus["full"], "c", {"method": "linear"}) as c:
        run(b, INPUTS[:1])
        b.set(mu=-1.0)
        with pytest.raises(FMICallException):    # fmi2Discard: mu=-1.0 is out of range
            b.fmu.doStep(b.t, 1e-3)
        blob = b.fmu.serializeFMUstate(b.fmu.getFMUstate())
        b.set(**INPUTS[1])
        b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
        assert b.get("mu") == [-1.0]
        assert run(b, INPUTS[1:2]) == run(c, INPUTS[1:2])     # usable as ever


def test_a_refused_read_computes_nothing(fmus):
    """A read of an output and an unknown value reference is an error that leaves the state as
    it was, the outputs not computed (found by tests/test_fmi_state_machine.py)."""
    with FmuInstance(fmus["full"], "a", {"method": "linear"}) as a:
        run(a, INPUTS[:1])
        a.set(**INPUTS[1])
        before = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        with pytest.raises(FMICallException) as e:
            a.fmu.getReal([a.vr("Fx"), 10_000])
        assert e.value.status == ERROR
        assert "valueReference 10000 is not a Real variable" in a.errors()[-1]
        assert a.fmu.serializeFMUstate(a.fmu.getFMUstate()) == before


def test_serializing_into_a_buffer_of_another_size_says_so(fmus):
    # found by tests/test_fmi_state_machine.py: it was an "unexpected Python exception"
    from ctypes import create_string_buffer
    with FmuInstance(fmus["full"], "a") as a:
        state = a.fmu.getFMUstate()
        n = len(a.fmu.serializeFMUstate(state))
        status = a.fmu.dll.fmi2SerializeFMUstate(a.fmu.component, state,
                                                 create_string_buffer(n), n - 1)
        assert status == ERROR
        assert a.errors()[-1] == (f"fmi2SerializeFMUstate: the serialized state has {n} bytes, "
                                  f"the host gave {n - 1} (fmi2SerializedFMUstateSize tells)")
        a.fmu.freeFMUstate(state)


# ---------------------------------------------------------------------------------------------
# Untrusted states
# ---------------------------------------------------------------------------------------------

def _envelope(header: dict, data: bytes = b"") -> bytes:
    """A well-formed state around ``header`` (the layout of wheel_rail_fmu.state)."""
    h = json.dumps(header).encode()
    body = struct.pack("<8sII", MAGIC, FORMAT_VERSION, len(h)) + h + data
    return body + hashlib.sha256(body).digest()


class Payload:
    """Runs a shell command if unpickled."""

    def __reduce__(self):
        import os
        return os.system, ("touch PWNED",)


def _crafted(blob: bytes, tmp_path) -> dict[str, bytes]:
    n = struct.unpack_from("<8sII", blob)[2]
    header = json.loads(blob[16:16 + n])
    data = blob[16 + n:-32]
    flipped = bytearray(blob)
    flipped[len(blob) // 2] ^= 0x40

    def edit(**changes):
        return _envelope({**header, **changes}, data)

    values = dict(header["values"])
    return {
        "empty": b"",
        "pickle": pickle.dumps({"state": Payload()}),
        "pickle with our magic": MAGIC + pickle.dumps(Payload()),
        "truncated": blob[:-40],
        "bit flip": bytes(flipped),
        "future version": _envelope(header, data).replace(
            struct.pack("<I", FORMAT_VERSION), struct.pack("<I", FORMAT_VERSION + 1), 1),
        "foreign GUID": edit(guid="{00000000-0000-0000-0000-000000000000}"),
        "unknown mode": edit(mode="running"),
        "missing variable": edit(values={k: v for k, v in values.items() if k != "E"}),
        "wrong type": edit(values={**values, "method_used": "four"}),
        "non-finite parameter": edit(values={**values, "E": float("inf")}),
        "invalid parameter": edit(values={**values, "E": -1.0}),
        "unknown method": edit(values={**values, "method": "jv"}),
        "oversized array": edit(arrays=[["<f8", [1 << 20, 1 << 20]]] + header["arrays"][1:]),
        "bad dtype": edit(arrays=[["|O", [12, 12]]] + header["arrays"][1:]),
        "wrong array shape": edit(arrays=[["<f8", [144]]] + header["arrays"][1:]),
        "extra data": _envelope(header, data + b"\0" * 8),
        "header not JSON": _envelope_raw(b"{not json", data),
        "header nested too deep": _envelope_raw(b"[" * 100_000, data),
        "Integer beyond fmi2Integer": edit(values={**values, "method_used": 2 ** 32 + 2}),
        "huge Integer": edit(values={**values, "method_used": 2 ** 70}),
        "no time": _envelope({k: v for k, v in header.items() if k != "time"}, data),
        "infinite time": edit(time=float("inf")),
        "time not a number": edit(time="0.1"),
        "fresh not a boolean": edit(fresh=1),
        # integers beyond the float range, where JSON has numbers
        "huge integer time": edit(time=10 ** 400),
        "huge integer Real": edit(values={**values, "E": 10 ** 400}),
        "huge integer result": edit(result={**header["result"], "Fx": 10 ** 400}),
        "huge integer warm state": edit(result={**header["result"], "warm_state": {
            **header["result"]["warm_state"], "a_over_b": 10 ** 400}}),
        # outputs the next read would return as they are (fresh): Coulomb's bound and Hertz
        "force beyond mu N": edit(values={**values, "Fy": 1.01 * values["mu"] * values["N"]}),
        "patch not the load's": edit(values={**values, "a": 1.001 * values["a"]}),
        "outputs of another load": edit(values={**values, "N": 0.9 * values["N"]}),
        "lifted wheel with a patch": edit(values={**values, "N": -1.0}),
        "lifted wheel with a force": edit(values={**values, "N": -1.0, "a": 0.0, "b": 0.0,
                                                  "p0": 0.0}),
        "slip fraction above one": edit(values={**values, "slip_fraction": 1.5}),
        "outputs before initialization": edit(mode="instantiated"),
    }


def _envelope_raw(h: bytes, data: bytes) -> bytes:
    body = struct.pack("<8sII", MAGIC, FORMAT_VERSION, len(h)) + h + data
    return body + hashlib.sha256(body).digest()


def test_crafted_and_corrupted_states_are_errors(fmus, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    start = {"method": "exact", "mx": 12, "my": 12, "extrapolate": False}
    with FmuInstance(fmus["full"], "a", start) as a:
        run(a, INPUTS[:2])
        good = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        reference = run(a, INPUTS[2:3])
        for what, blob in _crafted(good, tmp_path).items():
            with pytest.raises(FMICallException) as e:
                a.fmu.deSerializeFMUstate(blob)
            assert e.value.status == ERROR, what
            assert "the instance keeps its state" in a.errors()[-1], (what, a.errors()[-1])
        assert not (tmp_path / "PWNED").exists()
        # nothing of it reached the instance: restoring the good state reproduces the run
        a.fmu.setFMUstate(a.fmu.deSerializeFMUstate(good))
        assert run(a, INPUTS[2:3]) == reference
        assert a.counts[4] == 0  # never fatal


def test_state_saved_in_initialization_mode_computes_its_outputs_again(fmus):
    # outputs read in Initialization Mode are computed when read (initial="calculated"), so a
    # restored state of that mode computes them again, from its parameters and inputs
    with FmuInstance(fmus["full"], "a", initialize=False) as a:
        a.fmu.setupExperiment(startTime=0.0)
        a.fmu.enterInitializationMode()
        a.set(**INPUTS[0])
        first = a.get(*OUT)
        blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        a.set(**INPUTS[1])
        assert a.get(*OUT) != first
        a.fmu.setFMUstate(a.fmu.deSerializeFMUstate(blob))
        assert a.get(*OUT) == first
        a.fmu.exitInitializationMode()
        a.initialized = True
        assert a.errors() == []


def test_state_of_another_fmu_is_refused(fmus):
    with FmuInstance(fmus["curving"], "a") as a, FmuInstance(fmus["full"], "b") as b:
        run(a, INPUTS[:1])
        blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        with pytest.raises(FMICallException):
            b.fmu.deSerializeFMUstate(blob)
        assert "belongs to the FMU with GUID" in b.errors()[-1]


def test_state_of_a_table_outside_its_domain_is_restored(fmus):
    # a/b = 11.5 (a 10 mm rail crown) is outside the table: the exact method solves the steps
    # (method_used 4), said once as a warning; the state, whose result is the exact method's,
    # is restored and continues the run bit for bit.
    with FmuInstance(fmus["full"], "t", {"method": "table", "R_rail_profile": 0.01}) as a:
        run(a, INPUTS[:1])
        assert a.get("method_used") == [cc.METHODS["exact"].code]
        blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        reference = run(a, INPUTS[1:2])
        a.fmu.setFMUstate(a.fmu.deSerializeFMUstate(blob))
        assert run(a, INPUTS[1:2]) == reference
        warnings = [m for s, m in a.messages if s == WARNING]
        assert len(warnings) == 2, warnings  # the FMU's and the core's (TableDomainWarning)
        assert "outside the domain of method 'table'" in warnings[1]
        assert "solved by method 'exact'" in warnings[1]
        assert "TableDomainWarning" in warnings[0]
        assert a.errors() == []
