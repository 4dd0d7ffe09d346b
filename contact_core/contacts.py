"""Several independent contacts of one configuration, evaluated together: the contact law of a
whole vehicle (its wheels' patches) in one call, e.g. one step of a multi-contact FMU.

:class:`Contacts` holds one evaluator per contact (:class:`~contact_core.WheelRailEvaluator`,
or :class:`~contact_core.VaryingGeometryEvaluator` with the effect ``varying_geometry``): each
contact has its own inputs, patch, method state and warm start; the configuration (method,
material, options) is shared. The values live in one array of floats that the caller owns:
contact i reads its input j from ``values[index[i, j]]`` and writes its output k to
``values[index[i, len(inputs) + k]]`` (:attr:`Contacts.inputs`, :data:`OUTPUTS`), so a caller
that keeps its variables in such an array (the FMU, by value reference) hands them over without
copying, and an input or output the caller does not have points at a slot of its own (a zero,
a fixed friction coefficient, a scratch slot).

Atomic: :meth:`Contacts.evaluate` writes the outputs of every contact or of none. An input that
one contact refuses raises :class:`ContactInputError` (a ``ValueError`` naming the contact, its
message the evaluator's, naming the input and its range); a method that fails raises
:class:`ContactFailure`; either way every output and every warm start is left as it was.

The table with every effect of Coulomb friction (and no falling friction): one compiled call
evaluates every contact, Hertz's patch of its load and geometry and the table at ν
(:func:`contact_core.table.interp._step_rows`), with the evaluator's operations in its order
(the same bits). The states it leaves to the evaluator: a/b or the inputs outside the table's
fast path (the exact method's fallback, ``base._moderate``), a Coulomb bound to hold, and every
input the evaluator refuses (its message names it). A lifted contact (N <= 0) costs a finiteness
check there. The table's results carry no warm start (its fallback, the exact method, starts
only from an exact result), so a contact the kernel solved has ``last`` None: the chain of warm
starts is the evaluator's.
"""
from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from .api import METHODS
from .hertz import max_pressure, patch_kernel
from .wheel_rail import (VaryingGeometryConfig, VaryingGeometryEvaluator, WheelRailConfig,
                         WheelRailEvaluator, _semi_axes_patch, contact_inputs)

#: The outputs of a contact, in the order of the index's columns after the inputs:
#: forces (N) and moment (N·m), the patch (m, m, Pa), the slip fraction and the code of the
#: method that computed them (:attr:`ContactMethod.code`, as a float).
OUTPUTS = ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction", "method_code")
_N_OUT = len(OUTPUTS)


class ContactInputError(ValueError):
    """An input of contact ``index`` (0-based) that the law refuses; the message is the
    evaluator's (it names the input and its allowed range)."""

    def __init__(self, index: int, error: ValueError) -> None:
        super().__init__(str(error))
        self.index = index


class ContactFailure(RuntimeError):
    """Contact ``index`` (0-based) could not be evaluated (a method's failure)."""

    def __init__(self, index: int, error: Exception) -> None:
        super().__init__(f"{type(error).__name__}: {error}")
        self.index = index


Config = WheelRailConfig | VaryingGeometryConfig
Evaluator = WheelRailEvaluator | VaryingGeometryEvaluator


def evaluator_for(config: Config) -> Evaluator:
    """The evaluator of ``config``: a fixed geometry, or one given at every step."""
    if isinstance(config, VaryingGeometryConfig):
        return VaryingGeometryEvaluator(config)
    return WheelRailEvaluator(config)


class Contacts:
    """``len(index)`` contacts of ``config`` whose values live in ``values`` (module docstring).

    ``values``: a writable one-dimensional buffer of float64 (an ``array.array('d')``, a numpy
    array), kept and used at every :meth:`evaluate`; ``index``: one row per contact,
    ``len(inputs) + len(OUTPUTS)`` positions in ``values``.
    """

    def __init__(self, config: Config, values: Any, index: Sequence[Sequence[int]]) -> None:
        self.config = config
        self.inputs = contact_inputs(config)
        self._array = np.frombuffer(values, dtype=np.float64)
        if self._array.flags.writeable is False:
            raise ValueError("values: allowed a writable buffer of float64")
        self._index = np.array(index, dtype=np.int64, ndmin=2)
        n, width = self._index.shape
        if width != len(self.inputs) + _N_OUT or n == 0:
            raise ValueError(f"index of shape {self._index.shape}: allowed one row per contact "
                             f"of {len(self.inputs) + _N_OUT} positions")
        if not (0 <= self._index.min() and self._index.max() < self._array.size):
            raise ValueError(f"index: allowed positions 0 <= i < {self._array.size}")
        self._values = values
        self._rows = self._index.tolist()
        n_in = len(self.inputs)
        self._in_rows = [row[:n_in] for row in self._rows]
        self._out_rows = [row[n_in:] for row in self._rows]
        self._unsolved = [0.0] * n
        self.evaluators = tuple(evaluator_for(config) for _ in range(n))
        self._work = np.zeros((n, _N_OUT + 1))
        #: contacts whose evaluator holds a result (a kernel's step makes it None)
        self._warm: set[int] = set()
        self._kernel = _table_kernel(self)

    def __len__(self) -> int:
        return len(self.evaluators)

    def evaluate(self) -> list[tuple[int, Any]]:
        """Evaluate every contact from its inputs in ``values`` and write its outputs there
        (all or none: module docstring). Returns (contact, result) of the contacts the
        evaluators solved (the rest the compiled kernel, or lifted): the caller may report a
        fallback or an iteration that stopped early."""
        kernel = self._kernel
        if kernel is None and len(self.evaluators) == 1:
            return self._evaluate_one()
        if kernel is not None:
            fn, rows, params = kernel
            if fn(self._array, self._index, rows, params, self._work) == 0:  # all written
                if self._warm:
                    self._forget_warm()
                return []
            solved = self._work[:, _N_OUT].tolist()
        else:
            solved = self._unsolved
        values = self._values
        done = []
        saved = []
        try:
            for i, ev in enumerate(self.evaluators):
                if solved[i]:
                    continue
                saved.append((ev, ev.last))
                done.append((i, self._evaluate(i)))
        except Exception:
            for ev, last in saved:
                ev.last = last
            raise
        if kernel is not None:      # the kernel's contacts: written now
            for i, out in enumerate(self._out_rows):
                if solved[i]:
                    for j, v in zip(out, self._work[i, :_N_OUT].tolist()):
                        values[j] = v
            self._forget_warm()
        for i, r in done:
            self._write(i, r)
            if self.evaluators[i].last is not None:
                self._warm.add(i)
        return done

    def _evaluate_one(self) -> list[tuple[int, Any]]:
        """:meth:`evaluate` of a single contact without the kernel (the evaluator keeps its
        warm start when it refuses or fails)."""
        r = self._evaluate(0)
        self._write(0, r)
        return [(0, r)]

    def _evaluate(self, i: int) -> Any:
        """Contact ``i``'s evaluator at its inputs, its refusal raised as
        :class:`ContactInputError`, a method's failure as :class:`ContactFailure`."""
        try:
            return self.evaluators[i].evaluate(*self.input_values(i))
        except ValueError as e:
            raise ContactInputError(i, e) from None
        except Exception as e:  # a method's failure
            raise ContactFailure(i, e) from e

    def _write(self, i: int, r: Any) -> None:
        """Contact ``i``'s outputs (:data:`OUTPUTS`) of its evaluator's result ``r``."""
        ev = self.evaluators[i]
        values = self._values
        o = self._out_rows[i]
        values[o[0]] = r.Fx
        values[o[1]] = r.Fy
        values[o[2]] = r.Mz
        values[o[3]] = ev.a
        values[o[4]] = ev.b
        values[o[5]] = ev.p0
        values[o[6]] = r.slip_fraction
        values[o[7]] = ev.method_code

    def _forget_warm(self) -> None:
        """The contacts the kernel solved this time hold no warm start (module docstring)."""
        for i in [i for i in self._warm if self._work[i, _N_OUT] == 1.0]:
            self.evaluators[i].last = None
            self._warm.discard(i)

    def set_last(self, i: int, result: Any) -> None:
        """Set contact ``i``'s warm start (a restored FMU state's)."""
        self.evaluators[i].last = result
        if result is None:
            self._warm.discard(i)
        else:
            self._warm.add(i)

    def jacobian(self, i: int) -> Any:
        """Contact ``i``'s Jacobian at its inputs in ``values`` (its evaluator's ``jacobian``:
        the outputs by :attr:`inputs`); ``ValueError`` for inputs the law refuses."""
        return self.evaluators[i].jacobian(*self.input_values(i))

    def input_values(self, i: int) -> list[float]:
        """Contact ``i``'s inputs, in the order of :attr:`inputs`."""
        return [self._values[j] for j in self._in_rows[i]]


# ----------------------------------------------------------------------------------------------
# The table's kernel
# ----------------------------------------------------------------------------------------------

_THIRD = 1.0 / 3.0
#: The compiled patch and table step the kernel calls (numba resolves them when it compiles):
#: hertz.patch_kernel() and table.interp.step_rows_kernel().
_PATCH: Any = None
_STEP: Any = None


def _batch(values: np.ndarray, index: np.ndarray, rows: np.ndarray, params: np.ndarray,
           work: np.ndarray) -> int:
    """Every contact of ``index`` whose state the table's fast path solves, into ``work`` (the
    outputs, then a status: 1 solved, 2 lifted, 0 left to the evaluator); when none is left,
    the outputs are written into ``values``. Returns the number left.

    ``params``: the rows' axes (four rows, :meth:`Table.rows_at`), then (geometry mode: 0 fixed,
    1 curvatures, 2 semi-axes; ka, kb of the fixed geometry; E*; G) and (ν, the table's code).
    The operations of the evaluators' ``evaluate`` in their order (the same bits)."""
    mode = params[4, 0]
    ka = params[4, 1]
    kb = params[4, 2]
    e_star = params[4, 3]
    G = params[4, 4]
    nu = params[5, 0]
    code = params[5, 1]
    n = index.shape[0]
    n_in = index.shape[1] - 8
    left = 0
    for i in range(n):
        ix = index[i]
        xi = values[ix[0]]
        eta = values[ix[1]]
        phi = values[ix[2]]
        N = values[ix[3]]
        mu = values[ix[4]]
        gx = values[ix[5]] if n_in > 5 else 0.0
        gy = values[ix[6]] if n_in > 6 else 0.0
        w = work[i]
        w[8] = 0.0
        if 0.0 < N < math.inf:
            if mode == 0.0:
                s = N ** _THIRD
                a = ka * s
                b = kb * s
                p0 = max_pressure(N, a, b)
            elif mode == 1.0:
                a, b, p0 = _PATCH(N, gx, gy, e_star)
            else:
                a, b, p0 = _semi_axes_patch(N, gx, gy, e_star)
            if a == a:
                done, fx, fy, mz, slip = _STEP(rows, params, xi, eta, phi, N, mu, a, b, G, nu)
                if done == 1:
                    w[0] = fx
                    w[1] = fy
                    w[2] = mz
                    w[3] = a
                    w[4] = b
                    w[5] = p0
                    w[6] = slip
                    w[7] = code
                    w[8] = 1.0
        elif (-math.inf < N <= 0.0 and math.isfinite(xi) and math.isfinite(eta)
              and math.isfinite(phi) and 0.0 <= mu < math.inf
              and (mode == 0.0 or (math.isfinite(gx) and math.isfinite(gy)))):
            for k in range(7):
                w[k] = 0.0
            w[7] = code
            w[8] = 2.0
        if w[8] == 0.0:
            left += 1
    if left == 0:
        for i in range(n):
            for k in range(8):
                values[index[i, n_in + k]] = work[i, k]
    return left


_BATCH: Any = None


def _batch_kernel(rows: np.ndarray, params: np.ndarray) -> Any:
    """:func:`_batch` compiled (on first use; numba's disk cache keys on this file only, and the
    kernel compiles the patch and the table step in: checked once per process against its
    interpreted self on contacts of every kind, and compiled afresh if they differ)."""
    global _BATCH, _PATCH, _STEP
    if _BATCH is None:
        import numba

        from .table.interp import step_rows_kernel
        _PATCH, _STEP = patch_kernel(), step_rows_kernel()
        kernel = numba.njit(cache=True, nogil=True, error_model="numpy")(_batch)
        values = np.array([1e-3, -4e-4, 0.3, 1e5, 0.3, 1.1, 1.7, 6e-3, 5e-3,
                           -2e-3, 0.0, -0.1, 0.0, 0.3, 0.0, -1.0, 0.0, 0.0]
                          + [0.0] * 32)
        index = np.array([list(range(7)) + list(range(18, 26)),
                          list(range(9, 16)) + list(range(26, 34))], dtype=np.int64)
        for mode in (0.0, 1.0, 2.0):
            p = params.copy()
            p[4, :4] = (mode, 5e-5, 4e-5, 1.15e11)
            got, want = values.copy(), values.copy()
            w1, w2 = np.zeros((2, 9)), np.zeros((2, 9))
            if ((kernel(got, index, rows, p, w1), got.tolist(), w1.tolist())
                    != (_batch(want, index, rows, p, w2), want.tolist(), w2.tolist())):
                kernel.recompile()
                break
        _BATCH = kernel
    return _BATCH


def _table_kernel(contacts: Contacts) -> tuple[Any, np.ndarray, np.ndarray] | None:
    """(kernel, rows, params) of :func:`_batch` for ``contacts`` of the table with every effect
    of Coulomb friction and ν inside the table, else None."""
    config = contacts.config
    eff = config.effects
    if (config.method != "table" or eff.falling_friction
            or not (eff.longitudinal and eff.lateral and eff.spin and eff.saturation)):
        return None
    ev = contacts.evaluators[0]
    got = ev.solver.rows_at(config.nu)
    if got is None:
        return None
    rows, axes = got
    if isinstance(config, VaryingGeometryConfig):
        mode, ka, kb = (1.0 if config.geometry_input == "curvatures" else 2.0), 0.0, 0.0
        e_star = ev._e_star
    else:
        mode, ka, kb, e_star = 0.0, ev.geometry.ka, ev.geometry.kb, 0.0
    params = np.vstack([axes, [mode, ka, kb, e_star, ev.G],
                        [config.nu, float(METHODS[config.method].code), 0.0, 0.0, 0.0]])
    return _batch_kernel(rows, params), rows, params


__all__ = ["OUTPUTS", "ContactFailure", "ContactInputError", "Contacts", "contact_inputs",
           "evaluator_for"]
