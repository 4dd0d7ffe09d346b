"""Serialized FMU states: a data-only, versioned format that is checked before use (no pickle).

Hosts save FMU states to files and exchange them (restarts, snapshots), so a state is untrusted
input: it holds data only (JSON and raw numpy arrays, read with :func:`numpy.frombuffer`), and
:func:`read` checks everything before the slave uses any of it.

Layout (little-endian)::

    magic     8 bytes    b"WRCSTATE"
    version   uint32     FORMAT_VERSION
    length    uint32     length of the header in bytes
    header    JSON       {"guid", "mode", "time", "fresh", "values", "result", "arrays"}
    arrays    raw data   each array of header["arrays"] ([dtype, shape]) in order, C order
    checksum  32 bytes   SHA-256 of everything before it

``time``: the slave's last successful time (fmi2LastSuccessfulTime, a finite number).
``fresh``: whether the outputs are those of the current inputs (a boolean).
``values``: every FMU variable by name (Real as JSON numbers, which round-trip exactly; NaN or
infinite only for inputs and parameters, which a host may have set: the slave checks parameters
as at fmi2ExitInitializationMode when it restores a state of Step Mode or Terminated).
``result``: the contact result the next step starts from (the exact solver's warm start,
written by its ``to_record()`` and read back by the method's ``warm_state_from_record``, which
checks it), its arrays referenced as ``{"array": index}``; in an FMU of several contacts, a list
of one such result (or null) per contact.
"""
from __future__ import annotations

import hashlib
import json
import math
import struct
from dataclasses import dataclass
from typing import Any, Iterable, Mapping

import numpy as np

from .model_description import PYTHON_TYPES
from .runtime import contact_core

FORMAT_VERSION = 2  # 2: the header holds the time and the outputs' freshness
MAGIC = b"WRCSTATE"
#: Modes of the slave (FMI 2.0 sec. 4.2.4 state machine, co-simulation).
MODES = ("instantiated", "initialization", "step", "terminated")
_HEAD = struct.Struct("<8sII")
_CHECKSUM = 32
_DTYPES = {"<f8": np.float64, "|i1": np.int8}
_MAX_HEADER = 1 << 20
_MAX_ELEMENTS = 1 << 24
_RESULT_FLOATS = ("Fx", "Fy", "Mz", "slip_fraction", "residual")
_INT_MIN, _INT_MAX = -(1 << 31), (1 << 31) - 1  # fmi2Integer is a C int (32 bits)


class StateError(ValueError):
    """A serialized FMU state that cannot be used; the message says why."""


@dataclass(frozen=True)
class FmuState:
    """What a state holds: the FMU's GUID, the slave's mode, its last successful time (s),
    whether its outputs are those of its inputs, every variable's value by name, and the last
    contact result (None before the first loaded step; with several contacts a list of them)."""

    guid: str
    mode: str
    time: float
    fresh: bool
    values: Mapping[str, Any]
    result: Any = None


def write(state: FmuState) -> bytes:
    """Serialize ``state`` (see the module docstring)."""
    arrays: list[np.ndarray] = []
    result = ([_write_result(r, arrays) for r in state.result] if isinstance(state.result, list)
              else _write_result(state.result, arrays))
    specs = []
    for a in arrays:
        dtype = np.dtype(a.dtype).str
        if dtype not in _DTYPES:
            raise TypeError(f"warm state array of dtype {dtype} is not serializable")
        specs.append([dtype, list(a.shape)])
    header = json.dumps({"guid": state.guid, "mode": state.mode, "time": float(state.time),
                         "fresh": bool(state.fresh), "values": dict(state.values),
                         "result": result, "arrays": specs}, sort_keys=True).encode()
    body = b"".join([_HEAD.pack(MAGIC, FORMAT_VERSION, len(header)), header]
                    + [np.ascontiguousarray(a).tobytes() for a in arrays])
    return body + hashlib.sha256(body).digest()


def _write_result(r: Any, arrays: list[np.ndarray]) -> dict[str, Any] | None:
    """A contact result as JSON data, its warm state's arrays appended to ``arrays``."""
    result = None
    if r is not None:
        warm = None
        if r.warm_state is not None:
            warm = {}
            for key, value in r.warm_state.to_record().items():
                if isinstance(value, np.ndarray):
                    warm[key] = {"array": len(arrays)}
                    arrays.append(value)
                elif isinstance(value, (bool, int, float, str)):
                    warm[key] = value
                else:
                    raise TypeError(f"warm state {key!r}: {type(value).__name__} is not "
                                    "serializable")
        result = {"method": r.method, "converged": bool(r.converged),
                  "iterations": int(r.iterations), "warm_state": warm,
                  **{k: float(getattr(r, k)) for k in _RESULT_FLOATS}}
    return result


def read(blob: bytes, guid: str, variables: Iterable[tuple[str, str, str]],
         contacts: int = 1) -> FmuState:
    """Parse and check a serialized state of the FMU ``guid`` whose variables are
    ``(name, type, causality)`` and which has ``contacts`` contacts; raises
    :class:`StateError` naming the first problem."""
    blob = bytes(blob)
    if len(blob) < _HEAD.size + _CHECKSUM:
        raise StateError(f"the state has {len(blob)} bytes: too short to be an FMU state")
    magic, version, n = _HEAD.unpack_from(blob)
    if magic != MAGIC:
        raise StateError("the bytes are not a WheelRailContact FMU state (wrong magic number)")
    if version != FORMAT_VERSION:
        raise StateError(f"state format version {version} is not supported: this FMU reads "
                         f"version {FORMAT_VERSION}")
    body, checksum = blob[:-_CHECKSUM], blob[-_CHECKSUM:]
    if hashlib.sha256(body).digest() != checksum:
        raise StateError("the state is truncated or corrupted (checksum mismatch)")
    if n > min(_MAX_HEADER, len(body) - _HEAD.size):
        raise StateError(f"the state's header length {n} is out of range")
    try:
        header = json.loads(body[_HEAD.size:_HEAD.size + n].decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as e:  # (nested too deep)
        raise StateError(f"the state's header is not valid JSON: {e}") from None
    _expect(isinstance(header, dict)
            and set(header) == {"guid", "mode", "time", "fresh", "values", "result", "arrays"},
            "the state's header does not have the fields guid, mode, time, fresh, values, result, "
            "arrays")
    _expect(header["guid"] == guid, f"the state belongs to the FMU with GUID {header['guid']!r}, "
            f"not to this one ({guid})")
    _expect(header["mode"] in MODES, f"mode {header['mode']!r} is unknown: allowed {MODES}")
    time = _finite(header["time"], "time")
    _expect(type(header["fresh"]) is bool, f"fresh={header['fresh']!r} in the state is not a "
            "boolean")
    values = _values(header["values"], list(variables))
    arrays = _arrays(header["arrays"], body[_HEAD.size + n:])
    used: set[int] = set()
    if contacts == 1:
        result = _result(header["result"], arrays, used)
    else:
        r = header["result"]
        _expect(isinstance(r, list) and len(r) == contacts,
                f"the state's result must be a list of {contacts} results (one per contact)")
        result = [_result(item, arrays, used) for item in r]
    _expect(len(used) == len(arrays), "the state has arrays its results do not use")
    return FmuState(guid, header["mode"], time, header["fresh"], values, result)


def _expect(condition: bool, message: str) -> None:
    if not condition:
        raise StateError(message)


def _finite(value: Any, name: str) -> float:
    """``value`` (a JSON number) as a finite float, else :class:`StateError`."""
    _expect(type(value) in (int, float), f"{name}={value!r} in the state is not a number")
    try:
        x = float(value)
    except OverflowError:  # an integer beyond the float range
        x = math.inf
    _expect(math.isfinite(x), f"{name}={value!r} in the state is not a finite number")
    return x


def _values(values: Any, variables: list[tuple[str, str, str]]) -> dict[str, Any]:
    _expect(isinstance(values, dict), "the state's values are not a mapping")
    names = [name for name, _, _ in variables]
    _expect(sorted(values) == sorted(names),
            f"the state's variables {sorted(values)} are not this FMU's {sorted(names)}")
    for name, typ, causality in variables:
        v = values[name]
        if typ == "Real" and type(v) is int:  # JSON may write a whole float without ".0"
            v = values[name] = _finite(v, name)
        _expect(type(v) is PYTHON_TYPES[typ], f"{name}={v!r} in the state is not of type {typ}")
        if typ == "Real" and causality == "output":
            _expect(math.isfinite(v), f"{name}={v!r} in the state is not finite")
        if typ == "Integer":
            _expect(_INT_MIN <= v <= _INT_MAX, f"{name}={v!r} in the state is out of range: "
                    f"allowed {_INT_MIN} <= {name} <= {_INT_MAX} (fmi2Integer)")
    return values


def _arrays(specs: Any, data: bytes) -> list[np.ndarray]:
    _expect(isinstance(specs, list) and len(specs) <= 64, "the state's array list is invalid")
    arrays, offset = [], 0
    for spec in specs:
        ok = (isinstance(spec, list) and len(spec) == 2 and spec[0] in _DTYPES
              and isinstance(spec[1], list) and len(spec[1]) <= 2
              and all(type(d) is int and 0 <= d <= _MAX_ELEMENTS for d in spec[1]))
        _expect(ok, f"array {spec!r} in the state is invalid: allowed [dtype, shape] with dtype "
                f"{list(_DTYPES)} and at most 2 dimensions")
        dtype = np.dtype(_DTYPES[spec[0]])
        count = math.prod(spec[1])
        _expect(count <= _MAX_ELEMENTS and offset + count * dtype.itemsize <= len(data),
                "the state's arrays are larger than its data")
        a = np.frombuffer(data, dtype, count, offset).reshape(spec[1]).copy()
        _expect(dtype.kind != "f" or bool(np.isfinite(a).all()),
                "an array in the state has non-finite values")
        arrays.append(a)
        offset += count * dtype.itemsize
    _expect(offset == len(data), "the state has data after its arrays")
    return arrays


def _result(r: Any, arrays: list[np.ndarray], used: set[int]) -> Any:
    """One contact result of the header; the arrays its warm state takes are added to
    ``used`` (each at most once)."""
    if r is None:
        return None
    keys = {"method", "converged", "iterations", "warm_state", *_RESULT_FLOATS}
    _expect(isinstance(r, dict) and set(r) == keys, f"the state's result must have the fields "
            f"{sorted(keys)}")
    methods = contact_core.METHODS
    _expect(r["method"] in methods, f"result method {r['method']!r} is unknown: allowed "
            f"{list(methods)}")
    _expect(type(r["converged"]) is bool and type(r["iterations"]) is int
            and r["iterations"] >= 0, "the state's result has an invalid converged/iterations")
    floats = {k: _finite(r[k], f"result {k}") for k in _RESULT_FLOATS}
    warm = r["warm_state"]
    if warm is not None:
        _expect(isinstance(warm, dict), "the state's warm state is not a mapping")
        warm = dict(warm)
        for key, value in warm.items():
            if isinstance(value, dict):
                i = value.get("array")
                _expect(set(value) == {"array"} and type(i) is int and 0 <= i < len(arrays)
                        and i not in used, f"warm state {key!r}: invalid array reference")
                used.add(i)
                warm[key] = arrays[i]
            else:
                _expect(type(value) in (bool, int, float, str),
                        f"warm state {key!r}={value!r} is not a number or a string")
                if type(value) in (int, float):
                    _finite(value, f"warm state {key!r}")
    try:
        warm = methods[r["method"]].warm_state_from_record(warm)
    except ValueError as e:
        raise StateError(f"the state's warm start does not fit method {r['method']!r}: {e}") \
            from None
    return contact_core.ContactResult(
        floats["Fx"], floats["Fy"], floats["Mz"], r["method"],
        slip_fraction=floats["slip_fraction"], converged=r["converged"],
        iterations=r["iterations"], residual=floats["residual"], warm_state=warm)
