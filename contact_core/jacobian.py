"""Derivatives of a contact's outputs with respect to its inputs: the Jacobian of the law.

For implicit coupling (a co-simulation master, an implicit integrator) the law's sensitivities
∂(Fx, Fy, Mz)/∂(ξ, η, φ, N, ...) at the current state. ``solve(..., jacobian=True)`` returns
them as ``ContactResult.jacobian``, a :class:`Jacobian`: the derivatives of the outputs
:data:`OUTPUTS` (Fx, Fy in N, Mz in N·m, the slip fraction) with respect to the inputs
:data:`INPUTS` (ξ, η: 1; φ: 1/m; N: N; μ: 1; the semi-axes a, b: m) and, with the effect
``falling_friction``, the rolling speed V (m/s): entry (i, j) is ∂output_i/∂input_j in SI units
(e.g. ∂Fx/∂ξ in N, ∂Mz/∂φ in N·m², ∂Fx/∂a in N/m), the other inputs (and G, ν) held.

How (``Jacobian.how``):

* ``"analytic"``: the derivative of the method's own formula, for ``linear`` and
  ``johnson_vermeulen`` (their closed forms; Kalker's coefficients' slope in a/b from their
  spline, :func:`~contact_core.coefficients.creep_coefficient_slopes`) and ``table`` (its
  interpolant's: the derivatives of the local cubic Lagrange weights along every axis, chained
  through the table's coordinates; :meth:`contact_core.table.Table._jacobian_impl`). The
  derivative of a piecewise polynomial: continuous where the interpolant is, i.e. inside its
  cells (across a node it jumps, as the interpolant's slope does). Where a method's output has
  a kink (Coulomb's bound reached: |F| = μN held, the spin moment held to its bound; the
  saturation's |F_linear| at zero creepage; the slip fraction at zero creepage, which grows
  like |creepage|), the derivative is that of the branch taken there (documented per method).
* ``"central differences"`` of the method's own ``step`` (the public one), for every other
  method (``polach``, ``fastsim``, ``exact``, and any registered later), for states an analytic
  method leaves to another (the table's fallback to ``exact``) or solves in the units of
  Hertzian similarity (inputs outside ``base._moderate``), and with ``falling_friction``:
  [f(x + h) - f(x - h)]/(2h) per input, every perturbed solve warm-started from the state's
  result; the second-order one-sided form [-3f(x) + 4f(x + h) - f(x + 2h)]/(2h) where x - h is
  outside the input's range (μ = 0). The step is the input's natural scale times the relative
  step of the method (:data:`RELATIVE_STEPS`): for ξ and η the creepage at which the force
  saturates, μ p0/G (p0/G without saturation; p0 = 3N/(2πab) Hertz's peak pressure, Kalker
  1979 eq 3), for φ that over c = √(ab); for N, μ, a, b the value itself; for V, |V| but at
  least 1 m/s. ``Jacobian.steps`` holds the steps used.
* ``"zero"``: N = 0 (no contact): every derivative 0 by definition (the law is not
  differentiable there: the patch vanishes).

Inputs of effects a scene leaves out (they must be zero) have zero columns; outputs it leaves
out are zero rows.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from .hertz import max_pressure

#: The outputs of a method's Jacobian (rows).
OUTPUTS = ("Fx", "Fy", "Mz", "slip_fraction")
#: Its inputs (columns); "V" follows with the effect ``falling_friction``.
INPUTS = ("xi", "eta", "phi", "N", "mu", "a", "b")
#: Relative step of the central differences per method (module docstring): the closed form of
#: Polach (smooth: rounding limits, at about 1e-16/step), FASTSIM's strip march (a force
#: piecewise smooth between the creepages at which an element starts to slip: a step that
#: spans several of them), the exact solver (converged to its ``tol``, 1e-5 by default: the
#: error of a difference is about tol/step).
RELATIVE_STEPS = {"polach": 1e-6, "fastsim": 1e-3, "exact": 1e-3}
#: The relative step of a method not in :data:`RELATIVE_STEPS`.
DEFAULT_RELATIVE_STEP = 1e-3


@dataclass(frozen=True, eq=False)
class Jacobian:
    """∂outputs/∂inputs of one contact state (module docstring): ``matrix[i, j]`` is
    ∂``outputs[i]``/∂``inputs[j]`` in SI units; ``how`` says how it was obtained; ``steps``,
    with central differences, the step of each input (SI units), else empty.

    ``jacobian["Fx", "xi"]`` is one entry (a float)."""

    outputs: tuple[str, ...]
    inputs: tuple[str, ...]
    matrix: np.ndarray
    how: str
    steps: tuple[float, ...] = field(default=())

    def __post_init__(self) -> None:
        m = np.array(self.matrix, dtype=float)
        if m.shape != (len(self.outputs), len(self.inputs)):
            raise ValueError(f"matrix of shape {m.shape}: allowed ({len(self.outputs)}, "
                             f"{len(self.inputs)}) (outputs by inputs)")
        m.setflags(write=False)
        object.__setattr__(self, "matrix", m)

    def __getitem__(self, key: tuple[str, str]) -> float:
        output, name = key
        return float(self.matrix[self.outputs.index(output), self.inputs.index(name)])

    def __repr__(self) -> str:
        return (f"Jacobian(outputs={self.outputs}, inputs={self.inputs}, how={self.how!r}, "
                f"matrix={self.matrix.tolist()!r})")


def method_inputs(falling: bool) -> tuple[str, ...]:
    """The inputs of a method's Jacobian (with the rolling speed under ``falling``)."""
    return INPUTS + ("V",) if falling else INPUTS


def difference_steps(method: str, values: Sequence[float], G: float,
                     saturates: bool) -> list[float]:
    """The central differences' step of each input (module docstring) at ``values`` (in the
    order of :func:`method_inputs`) for the results of ``method``."""
    xi, eta, phi, N, mu, a, b = values[:7]
    delta = RELATIVE_STEPS.get(method, DEFAULT_RELATIVE_STEP)
    p0 = max_pressure(N, a, b)
    scale = (mu if saturates and mu > 0.0 else 1.0) * p0 / G
    steps = [delta * scale, delta * scale, delta * scale / math.sqrt(a * b), delta * N,
             delta * (mu if mu > 0.0 else 1.0), delta * a, delta * b]
    if len(values) > 7:
        steps.append(delta * max(abs(values[7]), 1.0))
    return steps


def central_differences(f: Callable[[list[float]], Sequence[float]], values: Sequence[float],
                        steps: Sequence[float], lower: Sequence[float | None],
                        skip: Sequence[bool]) -> np.ndarray:
    """The matrix of the derivatives of ``f`` (a function of the inputs' list, returning the
    :data:`OUTPUTS`) at ``values`` by central differences of ``steps``, one-sided (second order)
    where ``values[j] - steps[j]`` is below ``lower[j]``; columns with ``skip`` are zero."""
    base = None
    cols = []
    for j, (x, h, lo, off) in enumerate(zip(values, steps, lower, skip)):
        if off or h == 0.0:
            cols.append(None)
            continue
        def at(v: float) -> np.ndarray:
            args = list(values)
            args[j] = v
            return np.asarray(f(args), dtype=float)
        if lo is not None and x - h < lo:
            if base is None:
                base = np.asarray(f(list(values)), dtype=float)
            cols.append((-3.0 * base + 4.0 * at(x + h) - at(x + 2.0 * h)) / (2.0 * h))
        else:
            cols.append((at(x + h) - at(x - h)) / (2.0 * h))
    return np.column_stack([np.zeros(len(OUTPUTS)) if c is None else c for c in cols])


def method_differences(method: Any, xi: float, eta: float, phi: float, N: float, mu: float,
                       a: float, b: float, G: float, nu: float, result: Any,
                       V: float | None) -> Jacobian:
    """The Jacobian of ``method.step`` (a :class:`~contact_core.base.ContactMethod`) at this
    state by central differences (module docstring), every perturbed solve warm-started from
    ``result`` (the state's)."""
    falling = method.friction is not None
    values = [xi, eta, phi, N, mu, a, b] + ([V if V is not None else 0.0] if falling else [])
    steps = difference_steps(result.method, values, G, method._saturates)
    eff = method.effects
    skip = [not eff.longitudinal, not eff.lateral, not eff.spin, False,
            not method._saturates, False, False] + ([False] if falling else [])
    lower: list[float | None] = [None, None, None, 0.0, 0.0, 0.0, 0.0] \
        + ([None] if falling else [])
    step = method.step

    def f(x: list[float]) -> tuple[float, float, float, float]:
        if falling:
            r = step(*x[:7], G, nu, result, x[7])
        else:
            r = step(*x, G, nu, result)
        return r.Fx, r.Fy, r.Mz, r.slip_fraction

    matrix = central_differences(f, values, steps, lower, skip)
    return Jacobian(OUTPUTS, method_inputs(falling), matrix, "central differences",
                    tuple(steps))


def zero(falling: bool) -> Jacobian:
    """The Jacobian at N = 0 (module docstring)."""
    inputs = method_inputs(falling)
    return Jacobian(OUTPUTS, inputs, np.zeros((len(OUTPUTS), len(inputs))), "zero")
