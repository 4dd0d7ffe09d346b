"""The FMI 2.0 state machine under random use (issue 62 item 5): a hypothesis stateful test that
drives single- and multi-contact FMUs at the C ABI through random sequences of FMI 2.0 calls.

What it calls, through fmpy's ctypes handles of the FMU's functions (so that every status is
seen, not only those fmpy raises on): ``fmi2Instantiate`` (also refused: a wrong GUID, Model
Exchange, no or a missing resource folder), ``fmi2FreeInstance``, ``fmi2SetupExperiment``,
``fmi2Enter/ExitInitializationMode``, ``fmi2Set/Get{Real,Integer,Boolean,String}`` of valid,
wrongly typed and unknown value references with random values (NaN, ±inf, ±1e308, subnormals,
signed zeros, negative loads, random and invalid UTF-8 strings), ``fmi2DoStep`` (step sizes also
0, negative, NaN; communication points also non-finite), ``fmi2Get/Set/FreeFMUstate``,
``fmi2SerializedFMUstateSize``, ``fmi2(De)SerializeFMUstate`` (also of another FMU's, of
truncated, flipped and re-checksummed edited bytes, and with a wrong size),
``fmi2GetDirectionalDerivative`` (valid and invalid references, non-finite seeds),
``fmi2GetRealStatus``, ``fmi2SetDebugLogging``, ``fmi2Reset``, ``fmi2Terminate``, and calls with
NULL arrays.

The model (:class:`Model`, one per instance) is the co-simulation state machine of FMI 2.0 sec.
4.2.4 (its table of the functions allowed per state; the Modelica Association's Reference FMUs
implement the same table) with this FMU's documented behaviour (``docs/guide/fmu.md``,
``docs/guide/multi_contact_and_jacobians.md``):

* states: instantiated, initialization, step (stepComplete; a refused step leaves it there: the
  FMU documents that ``fmi2Discard`` and ``fmi2Error`` change nothing and the instance stays
  usable, so stepFailed and the error state are not entered), terminated;
* a call outside its states is ``fmi2Error`` and changes nothing; extension: ``fmi2GetXXX`` before
  ``fmi2EnterInitializationMode`` returns the start values (outputs 0);
* inputs may be set in instantiated, initialization and step; fixed parameters before
  ``fmi2ExitInitializationMode``; outputs never;
* values: what was set is read back to the bit; outputs are finite, ``a, b, p0 >= 0``,
  ``0 <= slip_fraction <= 1``, zero before initialisation and for a lifted contact (N <= 0);
* the law's verdict on values: a NaN or infinite input refuses the step (``fmi2Discard``, or
  ``fmi2Error`` with ``invalid_input="error"``), a read of the outputs then warns and returns the
  last ones, ``fmi2ExitInitializationMode`` and ``fmi2GetDirectionalDerivative`` return
  ``fmi2Error``; plain inputs with the parameters' start values (any method) are solved (OK or
  warning); other finite values may go either way, and the model learns from the status;
* ``fmi2Fatal`` never; every status other than OK comes with a logged message, never "unexpected
  Python exception";
* a refused call (``fmi2Discard``, ``fmi2Error``, a read that warns instead of computing) leaves
  the instance as it was: its serialized FMU state is the same bytes, and every readable value
  (and status) is the same as read after ``fmi2SetFMUstate`` of the state saved before the call;
* ``fmi2SetFMUstate`` of a state of ``fmi2GetFMUstate`` (or of its serialized bytes) restores the
  model saved with it; a serialized state holds what the model holds.

The machine runs in a subprocess (this file run as a script), so that a crash of the host is a
test failure: the calls of the example that crashed are written to a trace file as they are
made, and the test prints it. ``HYPOTHESIS_PROFILE=deep`` runs many more examples
(``docs/guide/development.md``).
"""
from __future__ import annotations

import argparse
import ctypes
import faulthandler
import hashlib
import json
import math
import os
import struct
import subprocess
import sys
from collections import Counter, deque
from ctypes import byref, c_char_p, c_double, c_int, c_size_t, c_uint, c_void_p
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable

import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import (RuleBasedStateMachine, initialize, precondition, rule,
                                 run_state_machine_as_test)

from conftest import HYPOTHESIS_PROFILE, examples

pytestmark = [pytest.mark.host, pytest.mark.slow]

OK, WARNING, DISCARD, ERROR, FATAL = range(5)
NAMES = ("OK", "Warning", "Discard", "Error", "Fatal")
MODES = ("instantiated", "initialization", "step", "terminated")
ALL_MODES = frozenset(MODES)
#: FMI 2.0 sec. 4.2.4, co-simulation: the states in which each function is allowed (stepComplete
#: is "step"; the documented extension: fmi2GetXXX also in instantiated).
ALLOWED = {
    "fmi2SetupExperiment": {"instantiated"},
    "fmi2EnterInitializationMode": {"instantiated"},
    "fmi2ExitInitializationMode": {"initialization"},
    "fmi2Terminate": {"step"},
    "fmi2DoStep": {"step"},
    "fmi2Get": ALL_MODES,
    "fmi2Set": {"instantiated", "initialization", "step"},
    "fmi2GetDirectionalDerivative": {"initialization", "step", "terminated"},
    "fmi2GetRealStatus": {"step", "terminated"},
}
GOOD, BAD, UNKNOWN = "good", "bad", "unknown"
#: Build parameters of the FMUs under test: the exact method on a small grid (an exact solve of
#: the default 52 x 52 grid would dominate the run).
CHEAP = {"mx": 16, "my": 16}
MAX_INSTANCES = 4
#: Examples and steps per example, per profile (conftest.HYPOTHESIS_PROFILE).
EXAMPLES = examples(ci=200, deep=4000)
STEPS = examples(ci=40, deep=80)
fmi2LastSuccessfulTime = 2


# ---------------------------------------------------------------------------------------------
# The FMUs' variables and what the law makes of their values
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Var:
    vr: int
    name: str
    type: str
    causality: str
    start: Any
    contact: int       # 1..N for a contact's input or output, else 0
    local: str         # the contact's own name (xi of c[2].xi)


_ZERO = {"Real": 0.0, "Integer": 0, "Boolean": False, "String": ""}


def _start(v) -> Any:
    if v.start is None:
        return _ZERO[v.type]
    return {"Real": float, "Integer": int, "String": str,
            "Boolean": lambda s: s in ("true", "1")}[v.type](v.start)


class Fmu:
    """One FMU under test: its variables by value reference and type, its contacts, and the
    classification of values (good: the law solves them; bad: documented refusals)."""

    def __init__(self, path: str) -> None:
        from fmpy import read_model_description
        import contact_core
        from wheel_rail_fmu.model_description import INVALID_INPUT_CHOICES
        self.path = path
        md = read_model_description(path)
        self.guid = md.guid
        self.label = Path(path).stem.replace("WheelRailContact_", "")
        self.vars: list[Var] = []
        for v in md.modelVariables:
            contact, local = 0, v.name
            if v.name.startswith("c["):
                k, local = v.name[2:].split("].", 1)
                contact = int(k)
            elif v.causality in ("input", "output"):
                contact = 1
            self.vars.append(Var(v.valueReference, v.name, v.type, v.causality, _start(v),
                                 contact, local))
        self.by_vr = {v.vr: v for v in self.vars}
        self.n = max(self.by_vr) + 1
        self.by_type = {t: [v for v in self.vars if v.type == t] for t in _ZERO}
        self.contacts = max(v.contact for v in self.vars)
        self.inputs = [v for v in self.vars if v.causality == "input"]
        self.params = [v for v in self.vars if v.causality == "parameter"]
        self.real_outputs = [v for v in self.vars if v.causality == "output" and v.type == "Real"]
        self.real_inputs = [v for v in self.inputs if v.type == "Real"]
        self.start = {v.vr: v.start for v in self.vars}
        self.methods = tuple(contact_core.METHODS)
        self.codes = {0} | {c.code for c in contact_core.METHODS.values()}
        self.choices = {"method": self.methods, "invalid_input": INVALID_INPUT_CHOICES}

    def name(self, vr: int) -> str:
        v = self.by_vr.get(vr)
        return f"{vr}:{v.name}" if v else f"{vr}:?"

    def contact_values(self, values: dict[int, Any], k: int) -> dict[str, Any]:
        return {v.local: values[v.vr] for v in self.inputs if v.contact == k}

    def inputs_class(self, values: dict[int, Any]) -> str:
        """bad: a contact has a NaN or infinite input (documented refusal); good: every contact
        is lifted (N <= 0, finite inputs, mu >= 0) or has plain inputs; else unknown."""
        verdicts = []
        for k in range(1, self.contacts + 1):
            u = self.contact_values(values, k)
            if not all(math.isfinite(x) for x in u.values()):
                return BAD
            lifted = u["N"] <= 0.0 and u.get("mu", 0.3) >= 0.0
            verdicts.append(lifted or all(_plain(n, x) for n, x in u.items()))
        return GOOD if all(verdicts) else UNKNOWN

    def params_class(self, values: dict[int, Any]) -> str:
        """good: every parameter at its start value, method and invalid_input any choice; bad:
        an unknown method or invalid_input, a NaN Real, a count (Integer) below 1, E <= 0
        (docs/guide/fmu.md); else unknown."""
        good = True
        for v in self.params:
            x = values[v.vr]
            if v.name in self.choices:
                if x not in self.choices[v.name]:
                    return BAD
            elif (v.type == "Real" and (math.isnan(x) or (v.name == "E" and not x > 0.0))) \
                    or (v.type == "Integer" and x < 1):
                return BAD
            elif not _same(x, v.start):
                good = False
        return GOOD if good else UNKNOWN

    def refusal(self, values: dict[int, Any]) -> int:
        """The status of a refused step (parameter invalid_input)."""
        return DISCARD if self.named(values, "invalid_input") == "discard" else ERROR

    def named(self, values: dict[int, Any], name: str) -> Any:
        return values[next(v.vr for v in self.vars if v.name == name)]


#: Plain inputs: ranges in which the law solves every value (Kalker 1979's domain of rolling
#: contact: small creepages, a Hertz patch of positive curvatures, loads of a wheel).
PLAIN = {"xi": (-0.02, 0.02), "eta": (-0.02, 0.02), "phi": (-3.0, 3.0), "N": (1e3, 3e5),
         "mu": (0.0, 0.8), "A": (0.3, 10.0), "B": (0.3, 10.0), "V": (1.0, 100.0)}


def _plain(name: str, x: float) -> bool:
    lo, hi = PLAIN.get(name, (0.0, -1.0))
    return lo <= x <= hi


def _same(a: Any, b: Any) -> bool:
    """Equal to the bit for floats (NaN equals NaN, 0.0 is not -0.0)."""
    if isinstance(a, float) and isinstance(b, float):
        if math.isnan(a) or math.isnan(b):
            return math.isnan(a) and math.isnan(b)
        return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)
    return type(a) is type(b) and a == b


# ---------------------------------------------------------------------------------------------
# The model of one instance
# ---------------------------------------------------------------------------------------------

@dataclass
class Model:
    """What an instance holds, as the model knows it.

    ``fresh``: the outputs are those of the current inputs (True), not (False), or it cannot
    tell (None); ``clean``: the evaluation that made them logged nothing (it converged);
    ``outputs``: the outputs last read, while nothing can have changed them."""

    mode: str
    values: dict[int, Any]
    time: float = 0.0
    fresh: bool | None = False
    clean: bool = True
    outputs: dict[int, Any] | None = None

    def copy(self) -> "Model":
        return replace(self, values=dict(self.values),
                       outputs=None if self.outputs is None else dict(self.outputs))


class Instance:
    """A live instance: fmpy's FMU2Slave (through wheel_rail_fmu.host.FmuInstance, for its
    loader and logger), its model and its FMU states (handle, model when saved)."""

    def __init__(self, fmu: Fmu, number: int, name: str, logging_on: bool) -> None:
        from wheel_rail_fmu.host import FmuInstance
        self.fmu = fmu
        self.number = number
        self.host = FmuInstance(fmu.path, name, initialize=False, logging_on=logging_on)
        self.c = self.host.fmu.component
        self.dll = self.host.fmu.dll
        self.model = Model("instantiated", dict(fmu.start))
        self.states: list[tuple[c_void_p, Model]] = []

    def __repr__(self) -> str:
        return f"i{self.number}<{self.fmu.label}>"

    def f(self, name: str) -> Callable:
        return getattr(self.dll, name)


@dataclass
class Blob:
    """Serialized state bytes, the FMU they belong to and the model they hold (None for edited
    bytes: then the model is read from their header)."""

    fmu: Fmu
    data: bytes
    model: Model | None


# ---------------------------------------------------------------------------------------------
# Values
# ---------------------------------------------------------------------------------------------

SPECIAL = [math.nan, math.inf, -math.inf, 1e308, -1e308, 1.7976931348623157e308, 5e-324,
           -5e-324, 2.2250738585072014e-308, 0.0, -0.0, 1.0, -1.0]
wild_reals = st.one_of(st.sampled_from(SPECIAL), st.floats())
wild_ints = st.one_of(st.sampled_from([0, -1, 1, 3, 4, 16, 401, 100001, 2 ** 31 - 1, -2 ** 31]),
                      st.integers(-2 ** 31, 2 ** 31 - 1))
wild_bools = st.sampled_from([0, 1, 1, 0, 2, -1, 255])
texts = st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"),
                max_size=12)
#: String values a host may pass that are no text: not UTF-8 (and, below, NULL)
INVALID_UTF8 = [b"\xff", b"\xc3(", b"table\xe2\x82", b"\xed\xa0\x80"]


def good_input(local: str) -> st.SearchStrategy:
    if local == "N":
        return st.one_of(st.floats(*PLAIN["N"]), st.floats(-1e6, 0.0))
    return st.floats(*PLAIN.get(local, (-1.0, 1.0)))


def value_for(fmu: Fmu, v: Var | None, kind: str) -> st.SearchStrategy:
    """A value for variable ``v`` (None: an invalid reference) of C type ``kind``: mostly
    plain, sometimes anything."""
    if kind == "Real":
        plain = (good_input(v.local) if v is not None and v.causality == "input"
                 else st.just(v.start) if v is not None and v.type == "Real" else wild_reals)
        return st.one_of(plain, plain, plain, wild_reals)
    if kind == "Integer":
        plain = st.just(v.start) if v is not None and v.type == "Integer" else wild_ints
        return st.one_of(plain, wild_ints)
    if kind == "Boolean":
        return wild_bools
    choices = fmu.choices.get(v.name) if v is not None else None
    plain = st.sampled_from(choices) if choices else (
        st.just(v.start) if v is not None and v.type == "String" else texts)
    return st.one_of(plain, plain, texts, st.sampled_from(INVALID_UTF8 + [None]))


def refs(fmu: Fmu, preferred: list[Var], others: list[Var]) -> st.SearchStrategy:
    """A value reference: mostly of ``preferred``, sometimes of ``others`` or unknown."""
    unknown = st.sampled_from([fmu.n, fmu.n + 1, fmu.n + 3, 2 ** 31, 2 ** 32 - 1])
    pick = []
    if preferred:
        pick += [st.sampled_from([v.vr for v in preferred])] * 6
    if others:
        pick.append(st.sampled_from([v.vr for v in others]))
    return st.one_of(*pick, unknown)


# ---------------------------------------------------------------------------------------------
# The machine
# ---------------------------------------------------------------------------------------------

class Failure(AssertionError):
    """A call that broke the model or an invariant; the message lists the calls before it."""


class FmiMachine(RuleBasedStateMachine):
    """See the module docstring. ``FMUS`` and ``TRACE`` are set by :func:`run`."""

    FMUS: list[Fmu] = []
    TRACE: int | None = None     # file descriptor of the trace of the running example
    STATS: Counter = Counter()

    def __init__(self) -> None:
        super().__init__()
        self.live: list[Instance] = []
        self.blobs: list[Blob] = []
        self.numbers = 0
        self.log: deque[str] = deque(maxlen=120)
        if self.TRACE is not None:
            os.ftruncate(self.TRACE, 0)
            os.lseek(self.TRACE, 0, os.SEEK_SET)
        self.STATS["examples"] += 1

    # -- bookkeeping ---------------------------------------------------------------------------
    def note(self, text: str) -> None:
        self.log.append(text)
        if self.TRACE is not None:
            os.write(self.TRACE, (text + "\n").encode("utf-8", "replace"))

    def fail(self, inst: Instance | None, message: str) -> None:
        lines = "\n".join(self.log)
        logged = ""
        if inst is not None:
            logged = "\n".join(f"  [{NAMES[s] if 0 <= s < 5 else s}] {m[:300]}"
                               for s, m in list(inst.host.messages)[-8:])
        raise Failure(f"{inst}: {message}\ncalls so far (latest last):\n{lines}\n"
                      f"last messages of {inst}:\n{logged}")

    def pick(self, i: int) -> Instance:
        return self.live[i % len(self.live)]

    def call(self, inst: Instance, fname: str, args: tuple, text: str,
             expected: set[int] | frozenset[int], refused_means_unchanged: bool = True,
             unchanged_if: Callable[[int], bool] | None = None) -> int:
        """Call ``fname(c, *args)``; check the status against ``expected`` and the invariants;
        on a refusal check that nothing changed (module docstring)."""
        before = None
        may_refuse = any(s >= DISCARD for s in expected) or unchanged_if is not None
        if refused_means_unchanged and may_refuse:
            before = self.snapshot(inst)
        count = sum(inst.host.counts.values())
        status = inst.f(fname)(inst.c, *args)
        logged = list(inst.host.messages)[-(sum(inst.host.counts.values()) - count):] \
            if sum(inst.host.counts.values()) > count else []
        self.note(f"{inst} {fname}({text}) -> {NAMES[status] if 0 <= status < 5 else status}")
        self.STATS[f"{fname} {NAMES[status] if 0 <= status < 5 else status}"] += 1
        if status == FATAL:
            self.fail(inst, f"{fname} returned fmi2Fatal")
        if status not in expected:
            self.fail(inst, f"{fname} returned {NAMES[status] if 0 <= status < 5 else status}, "
                            f"expected {sorted(NAMES[s] for s in expected)} (mode "
                            f"{inst.model.mode})")
        if status != OK and not logged:
            self.fail(inst, f"{fname} returned {NAMES[status]} without logging a message")
        for s, m in logged:
            if "unexpected Python exception" in m:
                self.fail(inst, f"{fname} logged an unexpected Python exception")
        refused = status >= DISCARD or (unchanged_if is not None and unchanged_if(status))
        if before is not None and refused:
            self.check_unchanged(inst, before, fname)
        elif before is not None:
            self.raw_free_state(inst, before[0])
        return status

    # -- the instance as it is: state bytes and every readable value -----------------------------
    def raw_get_state(self, inst: Instance) -> c_void_p:
        state = c_void_p()
        s = inst.f("fmi2GetFMUstate")(inst.c, byref(state))
        if s != OK:
            self.fail(inst, f"fmi2GetFMUstate returned {NAMES[s]} in mode {inst.model.mode}")
        return state

    def raw_serialize(self, inst: Instance, state: c_void_p) -> bytes:
        size = c_size_t()
        s = inst.f("fmi2SerializedFMUstateSize")(inst.c, state, byref(size))
        buf = ctypes.create_string_buffer(max(size.value, 1))
        s2 = inst.f("fmi2SerializeFMUstate")(inst.c, state, buf, size.value) if s == OK else s
        if s != OK or s2 != OK:
            self.fail(inst, f"serializing a state returned {NAMES[max(s, s2)]}")
        return buf.raw[:size.value]

    def raw_set_state(self, inst: Instance, state: c_void_p) -> None:
        s = inst.f("fmi2SetFMUstate")(inst.c, state)
        if s != OK:
            self.fail(inst, f"fmi2SetFMUstate of a state of fmi2GetFMUstate returned {NAMES[s]}")

    def raw_free_state(self, inst: Instance, state: c_void_p) -> None:
        inst.f("fmi2FreeFMUstate")(inst.c, byref(state))

    def snapshot(self, inst: Instance) -> tuple[c_void_p, bytes]:
        state = self.raw_get_state(inst)
        return state, self.raw_serialize(inst, state)

    def read_all(self, inst: Instance) -> dict:
        """Every variable read one by one: (status, value) by value reference."""
        out = {}
        for v in inst.fmu.vars:
            out[v.vr] = self.raw_get(inst, v.type, [v.vr])
        return out

    def raw_get(self, inst: Instance, kind: str, vrs: list[int]) -> tuple[int, list]:
        ctype = {"Real": c_double, "Integer": c_int, "Boolean": c_int, "String": c_char_p}[kind]
        arr = (c_uint * len(vrs))(*vrs)
        values = (ctype * len(vrs))()
        s = inst.f(f"fmi2Get{kind}")(inst.c, arr, len(vrs), values)
        vals = list(values)
        if kind == "String":
            vals = [None if x is None else x.decode("utf-8") for x in vals]
        elif kind == "Boolean":
            vals = [bool(x) for x in vals]
        return s, vals

    def check_unchanged(self, inst: Instance, before: tuple[c_void_p, bytes], fname: str) -> None:
        """A refused call changed nothing: the same state bytes, and every value (and status)
        read now is what it is read in the state saved before the call."""
        state0, blob0 = before
        state1, blob1 = self.snapshot(inst)
        if blob1 != blob0:
            self.fail(inst, f"the refused {fname} changed the instance's state: "
                            f"{_state_diff(blob0, blob1)}")
        now = self.read_all(inst)
        self.raw_set_state(inst, state0)
        then = self.read_all(inst)
        self.raw_set_state(inst, state1)
        self.raw_free_state(inst, state0)
        self.raw_free_state(inst, state1)
        for vr, (s, v) in now.items():
            s0, v0 = then[vr]
            if s != s0 or not _same(v[0], v0[0]):
                self.fail(inst, f"the refused {fname} changed {inst.fmu.name(vr)}: read "
                                f"{v[0]!r} ({NAMES[s]}), before it {v0[0]!r} ({NAMES[s0]})")
        self.STATS["refusals checked"] += 1

    # -- the law's verdicts ---------------------------------------------------------------------
    def law(self, inst: Instance) -> str:
        """Whether an evaluation at the instance's values succeeds: good, bad or unknown."""
        m, fmu = inst.model, inst.fmu
        params = fmu.params_class(m.values)
        inputs = fmu.inputs_class(m.values)
        if inputs == BAD or (m.mode == "initialization" and params == BAD):
            return BAD
        return GOOD if inputs == GOOD and params == GOOD else UNKNOWN

    def evaluation(self, inst: Instance, refusal: int) -> set[int]:
        """Statuses of a call that evaluates the law, refused with ``refusal``."""
        verdict = self.law(inst)
        if verdict == GOOD:
            return {OK, WARNING}
        if verdict == BAD:
            return {refusal}
        return {OK, WARNING, refusal, ERROR}

    def evaluated(self, inst: Instance, status: int, verdict: str) -> None:
        """The model after a call that evaluated (or refused) the law."""
        m = inst.model
        if status == OK:
            m.fresh, m.clean = True, True
        elif status == WARNING:
            m.fresh = True if verdict == GOOD else (False if verdict == BAD else None)
            m.clean = False
        if status == OK or (status == WARNING and verdict != BAD):
            m.outputs = None

    def check_outputs(self, inst: Instance, values: dict[int, Any], status: int) -> None:
        """Invariants of outputs read with ``status`` OK or warning."""
        m, fmu = inst.model, inst.fmu
        for vr, x in values.items():
            v = fmu.by_vr[vr]
            if v.type == "Integer":
                if x not in fmu.codes:
                    self.fail(inst, f"{v.name}={x!r} is no method's code")
                continue
            if not math.isfinite(x):
                self.fail(inst, f"output {v.name}={x!r} is not finite")
            if (v.local in ("a", "b", "p0") and x < 0.0) or \
                    (v.local == "slip_fraction" and not 0.0 <= x <= 1.0):
                self.fail(inst, f"output {v.name}={x!r} is out of its range")
        if m.mode == "instantiated":
            for vr, x in values.items():
                if x != 0:
                    self.fail(inst, f"{fmu.by_vr[vr].name}={x!r} before initialisation: "
                                    "allowed 0")
        elif status == OK:      # the outputs of the current inputs
            for vr, x in values.items():
                v = fmu.by_vr[vr]
                u = fmu.contact_values(m.values, v.contact)
                if v.type == "Real" and u["N"] <= 0.0 and x != 0.0 \
                        and all(math.isfinite(y) for y in u.values()):
                    self.fail(inst, f"{v.name}={x!r} of a lifted contact (N={u['N']!r}): "
                                    "allowed 0")
        if m.outputs is not None:
            for vr, x in values.items():
                if vr in m.outputs and not _same(m.outputs[vr], x):
                    self.fail(inst, f"{fmu.by_vr[vr].name} changed from {m.outputs[vr]!r} to "
                                    f"{x!r} with nothing that can change it in between")

    # -- instances -----------------------------------------------------------------------------
    @initialize(k=st.integers(0, 2), name=texts, logging_on=st.booleans())
    def first_instance(self, k, name, logging_on):
        self.instantiate(k, name, logging_on)

    @precondition(lambda self: len(self.live) < MAX_INSTANCES)
    @rule(k=st.integers(0, 2), name=texts, logging_on=st.booleans())
    def instantiate(self, k, name, logging_on):
        fmu = self.FMUS[k % len(self.FMUS)]
        self.numbers += 1
        try:
            inst = Instance(fmu, self.numbers, name, logging_on)
        except Exception as e:
            self.note(f"fmi2Instantiate({fmu.label}, {name!r}) -> {e}")
            self.fail(None, f"fmi2Instantiate of {fmu.label} failed: {e}")
        self.note(f"{inst} = fmi2Instantiate({fmu.label}, {name!r}, loggingOn={logging_on})")
        self.STATS["fmi2Instantiate OK"] += 1
        self.live.append(inst)

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), how=st.sampled_from(["guid", "model exchange", "no resources",
                                                     "missing resources", "foreign resources"]))
    def instantiate_refused(self, i, how):
        """fmi2Instantiate that must return NULL, leaving every instance as it was."""
        inst = self.pick(i)
        other = next((f for f in self.FMUS if f.guid != inst.fmu.guid), inst.fmu)
        unzipped = Path(inst.host.fmu.unzipDirectory)
        resources = (unzipped / "resources").as_uri().encode()
        guid = inst.fmu.guid.encode()
        args = {"guid": (1, b"{00000000-0000-0000-0000-000000000000}", resources),
                "model exchange": (0, guid, resources),
                "no resources": (1, guid, None),
                "missing resources": (1, guid, (unzipped / "nowhere").as_uri().encode()),
                "foreign resources": (1, other.guid.encode(), resources)}[how]
        if how == "foreign resources" and other is inst.fmu:
            return
        before = self.snapshot(inst)
        count = sum(inst.host.counts.values())
        c = inst.f("fmi2Instantiate")(b"refused", args[0], args[1], args[2],
                                     byref(inst.host._callbacks), 0, 0)
        self.note(f"fmi2Instantiate({how}) -> {c}")
        logged = list(inst.host.messages)[count - sum(inst.host.counts.values()):] \
            if sum(inst.host.counts.values()) > count else []
        if not logged or any("unexpected Python exception" in m for _, m in logged):
            self.fail(inst, f"fmi2Instantiate with {how} logged no message or an unexpected "
                            "Python exception")
        self.STATS[f"fmi2Instantiate ({how}) NULL" if not c else "fmi2Instantiate (bad) !"] += 1
        if c:
            inst.f("fmi2FreeInstance")(c_void_p(c))
            self.fail(inst, f"fmi2Instantiate with {how} returned an instance")
        self.check_unchanged(inst, before, "fmi2Instantiate")

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), free_states=st.booleans())
    def free_instance(self, i, free_states):
        inst = self.pick(i)
        if free_states:
            for state, _ in inst.states:
                self.raw_free_state(inst, state)
        inst.states.clear()
        inst.host.fmu.freeInstance()
        self.note(f"fmi2FreeInstance({inst}) (states freed first: {free_states})")
        self.STATS["fmi2FreeInstance"] += 1
        self.live.remove(inst)

    def teardown(self) -> None:
        for inst in self.live:
            for state, _ in inst.states:
                self.raw_free_state(inst, state)
            inst.host.fmu.freeInstance()
        self.live.clear()

    # -- the state machine ---------------------------------------------------------------------
    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7),
          start=st.one_of(st.just(0.0), st.floats(-10.0, 10.0), wild_reals),
          stop=st.one_of(st.none(), wild_reals), tolerance=st.one_of(st.none(), wild_reals))
    def setup_experiment(self, i, start, stop, tolerance):
        inst = self.pick(i)
        m = inst.model
        ok = m.mode in ALLOWED["fmi2SetupExperiment"] and math.isfinite(start)
        args = (int(tolerance is not None), tolerance or 0.0, start, int(stop is not None),
                stop or 0.0)
        s = self.call(inst, "fmi2SetupExperiment", args,
                      f"tolerance={tolerance!r}, start={start!r}, stop={stop!r}",
                      {OK} if ok else {ERROR})
        if s == OK:
            m.time = start

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7))
    def enter_initialization_mode(self, i):
        inst = self.pick(i)
        m = inst.model
        ok = m.mode in ALLOWED["fmi2EnterInitializationMode"]
        if self.call(inst, "fmi2EnterInitializationMode", (), "", {OK} if ok else {ERROR}) == OK:
            m.mode, m.fresh, m.outputs = "initialization", False, None

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7))
    def exit_initialization_mode(self, i):
        inst = self.pick(i)
        m = inst.model
        if m.mode not in ALLOWED["fmi2ExitInitializationMode"]:
            self.call(inst, "fmi2ExitInitializationMode", (), "", {ERROR})
            return
        verdict = self.law(inst)
        expected = {OK} if m.fresh is True and m.clean else self.evaluation(inst, ERROR)
        s = self.call(inst, "fmi2ExitInitializationMode", (), f"[law: {verdict}]", expected)
        if s <= WARNING:
            if m.fresh is not True:
                self.evaluated(inst, s, verdict)
            m.mode = "step"
            if inst.fmu.params_class(m.values) == BAD:
                self.fail(inst, "fmi2ExitInitializationMode accepted an invalid parameter")

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7))
    def terminate(self, i):
        inst = self.pick(i)
        ok = inst.model.mode in ALLOWED["fmi2Terminate"]
        if self.call(inst, "fmi2Terminate", (), "", {OK} if ok else {ERROR}) == OK:
            inst.model.mode = "terminated"

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7))
    def reset(self, i):
        inst = self.pick(i)
        self.call(inst, "fmi2Reset", (), "", {OK}, refused_means_unchanged=False)
        inst.model = Model("instantiated", dict(inst.fmu.start))

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), on=st.booleans())
    def set_debug_logging(self, i, on):
        inst = self.pick(i)
        self.call(inst, "fmi2SetDebugLogging", (int(on), 0, None), f"loggingOn={on}", {OK})

    # -- values --------------------------------------------------------------------------------
    def _settable(self, inst: Instance, vr: int, kind: str) -> bool:
        v = inst.fmu.by_vr.get(vr)
        mode = inst.model.mode
        if v is None or v.type != kind or mode not in ALLOWED["fmi2Set"]:
            return False
        return v.causality == "input" or (v.causality == "parameter" and mode != "step")

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), kind=st.sampled_from(["Real", "Real", "Real", "Integer",
                                                      "Boolean", "String"]), data=st.data())
    def set_values(self, i, kind, data):
        inst = self.pick(i)
        fmu = inst.fmu
        typed = fmu.by_type[kind]
        preferred = [v for v in typed if v.causality != "output"]
        if kind == "Real" and data.draw(st.booleans(), "inputs only"):
            preferred = [v for v in typed if v.causality == "input"]
        vrs = data.draw(st.lists(refs(fmu, preferred, [v for v in fmu.vars if v not in
                                                       preferred]), max_size=5), "vrs")
        values = [data.draw(value_for(fmu, fmu.by_vr.get(vr), kind), "value") for vr in vrs]
        self.set(inst, kind, vrs, values)

    def set(self, inst: Instance, kind: str, vrs: list[int], values: list) -> int:
        fmu, m = inst.fmu, inst.model
        invalid_text = any(x is None or isinstance(x, bytes) for x in values)
        ok = (m.mode in ALLOWED["fmi2Set"] and not invalid_text
              and all(self._settable(inst, vr, kind) for vr in vrs))
        ctype = {"Real": c_double, "Integer": c_int, "Boolean": c_int, "String": c_char_p}[kind]
        raw = [x if x is None or isinstance(x, bytes) else x.encode("utf-8") for x in values] \
            if kind == "String" else values
        args = ((c_uint * len(vrs))(*vrs), len(vrs), (ctype * len(vrs))(*raw))
        text = ", ".join(f"{fmu.name(vr)}={x!r}" for vr, x in zip(vrs, values))
        s = self.call(inst, f"fmi2Set{kind}", args, text, {OK} if ok else {ERROR})
        if s == OK:
            for vr, x in zip(vrs, values):
                m.values[vr] = bool(x) if kind == "Boolean" else x
            m.fresh, m.outputs = False, None
        return s

    def plain_inputs(self, inst: Instance, data, odd: int | None = None) -> None:
        """Every contact's inputs set to plain values (one fmi2SetReal), as a host's step; with
        ``odd``, input number ``odd`` (modulo their number) to any value."""
        inputs = inst.fmu.real_inputs
        values = [data.draw(good_input(v.local), v.name) for v in inputs]
        if odd is not None:
            values[odd % len(inputs)] = data.draw(wild_reals, inputs[odd % len(inputs)].name)
        self.set(inst, "Real", [v.vr for v in inputs], values)

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), data=st.data(),
          method=st.one_of(st.none(), st.sampled_from(["table", "linear", "johnson_vermeulen",
                                                       "fastsim", "polach", "exact"])),
          refusal=st.sampled_from(["discard", "error"]))
    def initialize_plainly(self, i, data, method, refusal):
        """What a host does: reset, set up, enter initialisation, set the method, invalid_input
        and plain inputs, exit initialisation (each call checked like the others)."""
        inst = self.pick(i)
        self.reset(i)
        self.setup_experiment(i, 0.0, None, None)
        self.enter_initialization_mode(i)
        names = {v.name: v.vr for v in inst.fmu.params}
        if method is not None:
            self.set(inst, "String", [names["method"], names["invalid_input"]], [method, refusal])
        self.plain_inputs(inst, data)
        self.exit_initialization_mode(i)

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), data=st.data(), h=st.floats(1e-5, 1e-2),
          steps=st.integers(1, 4))
    def step_plainly(self, i, data, h, steps):
        """What a host does at each communication point: set the inputs and step (sometimes
        with one input of any value), on an instance in Step Mode if there is one."""
        stepping = [x for x in self.live if x.model.mode == "step"] or self.live
        inst = stepping[i % len(stepping)]
        for _ in range(steps):
            self.plain_inputs(inst, data, data.draw(st.one_of(st.none(), st.none(),
                                                              st.integers(0, 100)), "odd"))
            self.step(inst, inst.model.time, h)

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), kind=st.sampled_from(["Real", "Real", "Integer", "Boolean",
                                                      "String"]), data=st.data())
    def get_values(self, i, kind, data):
        inst = self.pick(i)
        fmu, m = inst.fmu, inst.model
        typed = fmu.by_type[kind]
        vrs = data.draw(st.lists(refs(fmu, typed, [v for v in fmu.vars if v.type != kind]),
                                 max_size=6), "vrs")
        valid = all(vr in fmu.by_vr and fmu.by_vr[vr].type == kind for vr in vrs)
        outputs = [vr for vr in vrs if vr in fmu.by_vr and fmu.by_vr[vr].causality == "output"]
        verdict = self.law(inst)
        if not valid:
            expected = {ERROR}
        elif not outputs or m.mode == "instantiated" or m.fresh is True:
            expected = {OK}
        else:
            refusal = ERROR if m.mode == "initialization" else WARNING
            expected = self.evaluation(inst, refusal)
        unchanged = (lambda s: s == WARNING) if verdict == BAD and m.mode != "initialization" \
            else None
        ctype = {"Real": c_double, "Integer": c_int, "Boolean": c_int, "String": c_char_p}[kind]
        out = (ctype * len(vrs))()
        s = self.call(inst, f"fmi2Get{kind}", ((c_uint * len(vrs))(*vrs), len(vrs), out),
                      ", ".join(fmu.name(vr) for vr in vrs), expected, unchanged_if=unchanged)
        if s > WARNING:
            return
        got = list(out)
        if kind == "String":
            got = [x.decode("utf-8") for x in got]
        elif kind == "Boolean":
            got = [bool(x) for x in got]
        for vr, x in zip(vrs, got):
            v = fmu.by_vr[vr]
            if v.causality != "output" and not _same(x, m.values[vr]):
                self.fail(inst, f"{v.name} read {x!r}, set {m.values[vr]!r}")
        if outputs:
            if m.fresh is not True and m.mode != "instantiated":
                self.evaluated(inst, s, verdict)
            read = {vr: x for vr, x in zip(vrs, got) if vr in outputs}
            self.check_outputs(inst, read, s)
            m.outputs = {**(m.outputs or {}), **read}

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), which=st.sampled_from(["get", "set", "get none", "set none"]),
          kind=st.sampled_from(["Real", "Integer", "Boolean", "String"]))
    def null_arrays(self, i, which, kind):
        """NULL arrays: an error with a count, allowed without one (FMI 2.0 sec. 2.1.7)."""
        inst = self.pick(i)
        m = inst.model
        n = 0 if which.endswith("none") else 2
        if which.startswith("get"):
            expected = {OK} if n == 0 else {ERROR}
            self.call(inst, f"fmi2Get{kind}", (None, n, None), f"NULL, {n}, NULL", expected)
            return
        expected = {OK} if n == 0 and m.mode in ALLOWED["fmi2Set"] else {ERROR}
        if self.call(inst, f"fmi2Set{kind}", (None, n, None), f"NULL, {n}, NULL",
                     expected) == OK:
            m.fresh, m.outputs = False, None

    # -- steps ---------------------------------------------------------------------------------
    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), data=st.data(),
          h=st.one_of(st.floats(1e-5, 1e-2), st.floats(1e-5, 1e-2), st.sampled_from(
              [0.0, -0.0, -1e-3, math.nan, math.inf, -math.inf, 5e-324, 1e308]), wild_reals))
    def do_step(self, i, data, h):
        inst = self.pick(i)
        m = inst.model
        t = data.draw(st.one_of(st.just(m.time), st.just(m.time), st.just(m.time),
                                wild_reals), "t")
        self.step(inst, t, h)

    def step(self, inst: Instance, t: float, h: float) -> None:
        m = inst.model
        text = f"t={t!r}, h={h!r}"
        if m.mode not in ALLOWED["fmi2DoStep"] or not (h > 0.0 and math.isfinite(t + h)):
            self.call(inst, "fmi2DoStep", (t, h, 1), text, {ERROR})
            return
        verdict = self.law(inst)
        expected = {OK} if m.fresh is True and m.clean else \
            self.evaluation(inst, inst.fmu.refusal(m.values))
        was_fresh = m.fresh is True and m.clean
        s = self.call(inst, "fmi2DoStep", (t, h, 1), text + f" [law: {verdict}]", expected)
        if s <= WARNING:
            m.time = t + h
            if not was_fresh:
                self.evaluated(inst, s, verdict)

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), kind=st.sampled_from([2, 2, 2, 0, 1, 3]))
    def get_real_status(self, i, kind):
        inst = self.pick(i)
        m = inst.model
        value = c_double(-7.0)
        if m.mode not in ALLOWED["fmi2GetRealStatus"]:
            expected = {ERROR}
        else:
            expected = {OK} if kind == fmi2LastSuccessfulTime else {DISCARD}
        s = self.call(inst, "fmi2GetRealStatus", (kind, byref(value)), f"kind={kind}",
                      expected)
        if s == OK and not _same(value.value, float(m.time)):
            self.fail(inst, f"fmi2LastSuccessfulTime is {value.value!r}, expected {m.time!r}")

    # -- directional derivatives ---------------------------------------------------------------
    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), data=st.data())
    def directional_derivative(self, i, data):
        inst = self.pick(i)
        fmu, m = inst.fmu, inst.model
        unknowns = data.draw(st.lists(refs(fmu, fmu.real_outputs, fmu.vars), max_size=4),
                             "unknowns")
        knowns = data.draw(st.lists(refs(fmu, fmu.real_inputs, fmu.vars), max_size=4), "knowns")
        seeds = data.draw(st.lists(st.one_of(st.just(1.0), st.floats(-10.0, 10.0),
                                             st.floats(-10.0, 10.0), wild_reals),
                                   min_size=len(knowns), max_size=len(knowns)), "seeds")
        valid = (all(vr in {v.vr for v in fmu.real_outputs} for vr in unknowns)
                 and all(vr in {v.vr for v in fmu.real_inputs} for vr in knowns)
                 and all(math.isfinite(x) for x in seeds))
        verdict = self.law(inst)
        if m.mode not in ALLOWED["fmi2GetDirectionalDerivative"] or not valid:
            expected = {ERROR}
        elif m.fresh is True:
            expected = {OK, WARNING} if verdict == GOOD else {OK, WARNING, ERROR}
        else:
            expected = self.evaluation(inst, ERROR)
        out = (c_double * len(unknowns))()
        args = ((c_uint * len(unknowns))(*unknowns), len(unknowns),
                (c_uint * len(knowns))(*knowns), len(knowns),
                (c_double * len(knowns))(*seeds), out)
        text = (f"unknowns=[{', '.join(fmu.name(v) for v in unknowns)}], knowns=["
                f"{', '.join(fmu.name(v) for v in knowns)}], seeds={seeds!r}")
        s = self.call(inst, "fmi2GetDirectionalDerivative", args, text + f" [law: {verdict}]",
                      expected)
        if s > WARNING:
            return
        if m.fresh is not True:
            self.evaluated(inst, s, verdict)
        for vr, d in zip(unknowns, out):
            v = fmu.by_vr[vr]
            own = [x for k, x in zip(knowns, seeds) if fmu.by_vr[k].contact == v.contact and x]
            u = fmu.contact_values(m.values, v.contact)
            if (not own or u["N"] <= 0.0) and d != 0.0:
                self.fail(inst, f"d{v.name} = {d!r}: allowed 0 (no seed of its own contact's "
                                f"inputs, or a lifted contact)")
            if math.isnan(d) or (not math.isfinite(d) and verdict == GOOD
                                 and max(map(abs, seeds), default=0.0) <= 1e6):
                self.fail(inst, f"d{v.name} = {d!r} is not finite")

    # -- FMU states ----------------------------------------------------------------------------
    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), reuse=st.booleans())
    def get_state(self, i, reuse):
        """fmi2GetFMUstate, into a new state or over one of the instance's (FMI 2.0 sec.
        2.1.8: a given state is overwritten)."""
        inst = self.pick(i)
        if reuse and inst.states:
            state, _ = inst.states.pop()
        else:
            state = c_void_p()
        self.call(inst, "fmi2GetFMUstate", (byref(state),), f"reuse={reuse}", {OK})
        inst.states.append((state, inst.model.copy()))

    @precondition(lambda self: any(inst.states for inst in self.live))
    @rule(i=st.integers(0, 7), j=st.integers(0, 7))
    def set_state(self, i, j):
        inst = self.pick(i)
        if not inst.states:
            return
        state, saved = inst.states[j % len(inst.states)]
        self.call(inst, "fmi2SetFMUstate", (state,), f"state {j % len(inst.states)}", {OK})
        self.restored(inst, saved)

    def restored(self, inst: Instance, saved: Model) -> None:
        m = saved.copy()
        if m.mode == "initialization":  # its outputs are computed again when read
            m.fresh, m.outputs = False, None
        inst.model = m

    @precondition(lambda self: any(inst.states for inst in self.live))
    @rule(i=st.integers(0, 7), j=st.integers(0, 7))
    def free_state(self, i, j):
        inst = self.pick(i)
        if not inst.states:
            return
        state, _ = inst.states.pop(j % len(inst.states))
        self.call(inst, "fmi2FreeFMUstate", (byref(state),), f"state {j}", {OK},
                  refused_means_unchanged=False)
        if state.value is not None:
            self.fail(inst, "fmi2FreeFMUstate left the state pointer set")

    @precondition(lambda self: any(inst.states for inst in self.live))
    @rule(i=st.integers(0, 7), j=st.integers(0, 7), size_error=st.sampled_from([0, 0, 0, 1,
                                                                                   -1]))
    def serialize(self, i, j, size_error):
        inst = self.pick(i)
        if not inst.states:
            return
        state, saved = inst.states[j % len(inst.states)]
        size = c_size_t()
        self.call(inst, "fmi2SerializedFMUstateSize", (state, byref(size)), "", {OK})
        n = max(size.value + size_error, 0)
        buf = ctypes.create_string_buffer(max(n, 1))
        s = self.call(inst, "fmi2SerializeFMUstate", (state, buf, n), f"size={n}",
                      {OK} if size_error == 0 else {ERROR})
        if s != OK:
            return
        data = buf.raw[:n]
        header = _header(data)
        fmu = inst.fmu
        problems = []
        if header["mode"] != saved.mode or header["time"] != saved.time:
            problems.append(f"mode/time {header['mode']}/{header['time']!r}, saved "
                            f"{saved.mode}/{saved.time!r}")
        for v in fmu.vars:
            if v.causality != "output" and not _same(_json_value(header["values"][v.name], v),
                                                     saved.values[v.vr]):
                problems.append(f"{v.name}={header['values'][v.name]!r}, saved "
                                f"{saved.values[v.vr]!r}")
        if problems:
            self.fail(inst, "the serialized state is not the saved one: " + "; ".join(problems))
        self.blobs.append(Blob(fmu, data, saved.copy()))

    @precondition(lambda self: self.blobs and self.live)
    @rule(i=st.integers(0, 7), j=st.integers(0, 63), data=st.data())
    def deserialize(self, i, j, data):
        """Serialized bytes of this FMU (restored as saved), of another FMU (refused), or edited
        (refused unless the edit is valid: then it holds what its header says)."""
        inst = self.pick(i)
        blob = self.blobs[j % len(self.blobs)]
        how = data.draw(st.sampled_from(["as is", "as is", "truncated", "bit flip", "edited",
                                         "edited", "empty"]), "how")
        payload, model = blob.data, blob.model
        if how == "truncated":
            payload = payload[:data.draw(st.integers(0, len(payload) - 1), "length")]
        elif how == "bit flip":
            k = data.draw(st.integers(0, len(payload) - 1), "byte")
            payload = payload[:k] + bytes([payload[k] ^ (1 << data.draw(st.integers(0, 7)))]) \
                + payload[k + 1:]
        elif how == "edited":
            payload, model = _edited(blob, data)
        elif how == "empty":
            payload = b""
        foreign = blob.fmu.guid != inst.fmu.guid
        if how in ("truncated", "bit flip", "empty") or foreign:
            expected = {ERROR}
        elif how == "as is":
            expected = {OK}
        else:
            expected = {OK, ERROR}
        state = c_void_p()
        buf = ctypes.create_string_buffer(payload, max(len(payload), 1))
        s = self.call(inst, "fmi2DeSerializeFMUstate", (buf, len(payload), byref(state)),
                      f"{how} bytes of {blob.fmu.label} ({len(payload)} bytes)", expected)
        if s != OK:
            return
        if model is None:
            model = _model_of(inst.fmu, payload)
        inst.states.append((state, model))

    @precondition(lambda self: self.live)
    @rule(i=st.integers(0, 7), what=st.sampled_from(["get NULL", "set NULL", "size of NULL",
                                                      "serialize NULL", "deserialize NULL"]))
    def null_states(self, i, what):
        inst = self.pick(i)
        size = c_size_t()
        buf = ctypes.create_string_buffer(8)
        fname, args = {
            "get NULL": ("fmi2GetFMUstate", (None,)),
            "set NULL": ("fmi2SetFMUstate", (None,)),
            "size of NULL": ("fmi2SerializedFMUstateSize", (None, byref(size))),
            "serialize NULL": ("fmi2SerializeFMUstate", (None, buf, 8)),
            "deserialize NULL": ("fmi2DeSerializeFMUstate", (None, 8, byref(c_void_p()))),
        }[what]
        self.call(inst, fname, args, what, {ERROR})


# ---------------------------------------------------------------------------------------------
# Serialized states (the layout of wheel_rail_fmu.state, read here to know what a valid edited
# state holds)
# ---------------------------------------------------------------------------------------------

_HEAD = struct.Struct("<8sII")


def _header(data: bytes) -> dict:
    n = _HEAD.unpack_from(data)[2]
    return json.loads(data[_HEAD.size:_HEAD.size + n])


def _json_value(x: Any, v: Var) -> Any:
    return float(x) if v.type == "Real" else x


def _model_of(fmu: Fmu, data: bytes) -> Model:
    h = _header(data)
    values = {v.vr: _json_value(h["values"][v.name], v) for v in fmu.vars}
    return Model(h["mode"], values, float(h["time"]), h["fresh"], clean=False)


def _edited(blob: Blob, data) -> tuple[bytes, None]:
    """The blob with one field of its header (a variable's value, the mode, the time, the
    freshness, a result's field or the GUID) replaced by a random JSON value, its checksum made
    good."""
    d = blob.data
    magic, version, n = _HEAD.unpack_from(d)
    header = json.loads(d[_HEAD.size:_HEAD.size + n])
    arrays = d[_HEAD.size + n:-32]
    json_values = st.one_of(st.none(), st.booleans(), wild_reals, wild_ints, texts,
                            st.sampled_from(list(MODES)), st.integers(-10 ** 30, 10 ** 30))
    key = data.draw(st.sampled_from(["values", "values", "values", "mode", "time", "fresh",
                                     "result", "guid"]), "field")
    if key == "values":
        name = data.draw(st.sampled_from(sorted(header["values"])), "variable")
        header["values"][name] = data.draw(json_values, "value")
    elif key == "result" and header["result"] is not None:
        r = header["result"]
        r = r[data.draw(st.integers(0, len(r) - 1))] if isinstance(r, list) else r
        if r is not None:
            field_name = data.draw(st.sampled_from(sorted(r)), "result field")
            r[field_name] = data.draw(json_values, "value")
    else:
        header[key] = data.draw(json_values, "value")
    h = json.dumps(header).encode()
    body = _HEAD.pack(magic, version, len(h)) + h + arrays
    return body + hashlib.sha256(body).digest(), None


def _state_diff(a: bytes, b: bytes) -> str:
    try:
        ha, hb = _header(a), _header(b)
    except Exception:     # not the layout: say so
        return "(not readable as states)"
    diffs = [f"{k}: {ha[k]!r} -> {hb[k]!r}" for k in ha if k != "values" and ha[k] != hb[k]]
    diffs += [f"{k}: {ha['values'][k]!r} -> {hb['values'][k]!r}" for k in ha["values"]
              if repr(ha["values"][k]) != repr(hb["values"][k])]
    return "; ".join(diffs)[:2000] or "(the same header, other arrays)"


# ---------------------------------------------------------------------------------------------
# Running it: in a subprocess (this file as a script), from the test below
# ---------------------------------------------------------------------------------------------

def machine_settings() -> settings:
    return settings(settings.get_profile(HYPOTHESIS_PROFILE), max_examples=EXAMPLES,
                    stateful_step_count=STEPS, deadline=None,
                    database=None if HYPOTHESIS_PROFILE == "ci" else settings.default.database,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])


def run(paths: list[str], trace: str, stats: str) -> None:
    """Run the machine over the FMUs ``paths``; the calls of the running example go to the file
    ``trace``, counts of calls and statuses to the JSON file ``stats``."""
    faulthandler.enable()
    FmiMachine.FMUS = [Fmu(p) for p in paths]
    FmiMachine.TRACE = os.open(trace, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    try:
        run_state_machine_as_test(FmiMachine, settings=machine_settings())
    finally:
        Path(stats).write_text(json.dumps(dict(sorted(FmiMachine.STATS.items())), indent=1))


@pytest.fixture(scope="module")
def machine_fmus(tmp_path_factory) -> list[Path]:
    """The full scene and the vehicle scene (inputs A, B) of one contact, the vehicle scene of
    three contacts (build-fmu --contacts 3)."""
    from wheel_rail_fmu.build import build
    out = tmp_path_factory.mktemp("state_machine")
    return [build("full", out=out, parameters=CHEAP),
            build("vehicle", out=out, parameters=CHEAP),
            build("vehicle", out=out, parameters=CHEAP, contacts=3)]


def test_random_fmi_call_sequences(machine_fmus, tmp_path):
    """The machine (module docstring) over the three FMUs, in a subprocess: a failure prints
    hypothesis's failing sequence, a crash the calls of the example that crashed; with -s, the
    counts of calls and statuses."""
    trace, stats = tmp_path / "trace.txt", tmp_path / "stats.json"
    proc = subprocess.run([sys.executable, __file__, "--trace", str(trace), "--stats",
                           str(stats), *map(str, machine_fmus)], capture_output=True,
                          text=True, timeout=None if HYPOTHESIS_PROFILE == "deep" else 900)
    counts = json.loads(stats.read_text()) if stats.exists() else {}
    print(json.dumps(counts, indent=1))
    if proc.returncode != 0:
        calls = trace.read_text(errors="replace") if trace.exists() else ""
        pytest.fail(f"the state machine failed (exit status {proc.returncode}"
                    f"{', killed by a signal' if proc.returncode < 0 else ''}).\n"
                    f"stdout:\n{proc.stdout[-20000:]}\nstderr:\n{proc.stderr[-20000:]}\n"
                    f"calls of the last example:\n{calls[-20000:]}")
    assert counts["examples"] >= EXAMPLES


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("fmus", nargs="+")
    parser.add_argument("--trace", required=True)
    parser.add_argument("--stats", required=True)
    a = parser.parse_args()
    run(a.fmus, a.trace, a.stats)
