"""Kalker's linear theory of rolling contact (Kalker 1979, sec. 3, eqs 14-18).

With c = √(ab) and Kalker's coefficients C_ij(a/b, ν) (:mod:`contact_core.coefficients`):

    Fx = -G c² C11 ξ,   Fy = -G (c² C22 η + c³ C23 φ),   Mz = -G (-c³ C23 η + c⁴ C33 φ)

(Kalker 1979 eq 17 for the forces; the spin moment with C32 = -C23, Kalker 1967 sec. 6.1).
The theory is the asymptote of the exact theory for vanishing creepage and spin: it assumes the
whole contact sticks, so it is **unsaturated by definition** — the forces grow without bound and
μ is not used. Use it only in the linear range (|F| well below μN), or as the slope at the origin.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from .base import ContactMethod, _moderate
from .cache import compiled_with_data
from .coefficients import (TABLE_A_OVER_B, creep_coefficient_slopes, creep_coefficients,
                           per_call_coefficients, table_coefficients)
from .result import make_result

#: numba's signature of :func:`_fused_step`: floats only (an int is converted, anything else
#: is refused and takes the general path, whose error names it).
_FUSED_SIGNATURE = "Tuple((boolean, float64, float64, float64))(" + ", ".join(["float64"] * 9) + ")"


def _fused_step(xi: float, eta: float, phi: float, N: float, mu: float, a: float, b: float,
                G: float, nu: float) -> tuple[bool, float, float, float]:
    """One state of :class:`LinearTheory` with every creepage selected and a/b inside Kalker's
    table, in one compiled call (the effect ``varying_geometry``, where the coefficients are
    computed per call: :func:`~contact_core.coefficients.table_coefficients`): (True, Fx, Fy,
    Mz), the operations of ``_step_impl`` in its order (the same bits); (False, ...) for a state
    the general path must solve (inputs outside ``base._moderate``, a/b outside the table)."""
    ab = a / b
    if not (_moderate(xi, eta, phi, N, mu, a, b, G, nu, False)
            and TABLE_A_OVER_B[0] <= ab <= TABLE_A_OVER_B[1]):
        return False, 0.0, 0.0, 0.0
    c11, c22, c23, c33 = table_coefficients(ab, nu)
    c2 = a * b
    c = math.sqrt(c2)
    return (True, -G * c2 * c11 * xi, -G * (c2 * c22 * eta + c2 * c * c23 * phi),
            -G * c2 * c * (-c23 * eta + c * c33 * phi))


_FUSED = None


def fused_step():
    """:func:`_fused_step` compiled (on first use; numba's disk cache, checked)."""
    global _FUSED
    if _FUSED is None:
        samples = [(1e-3, -4e-4, 0.3, 1e5, 0.3, a, 5e-3, 8e10, nu)
                   for a in (6e-4, 4e-3, 5e-3, 4.9e-2, 1.0) for nu in (0.0, 0.28)]
        _FUSED = compiled_with_data(_fused_step, samples, rtol=0.0, signature=_FUSED_SIGNATURE)
    return _FUSED


class LinearTheory(ContactMethod):
    """Kalker's linear theory: exact for vanishing creepage and spin, never saturates."""

    name = "linear"
    code = 1
    default_options: dict = {}
    saturates = False

    def _check_options(self) -> None:
        self._coefficients = per_call_coefficients(self.effects.varying_geometry)
        if self.effects.varying_geometry and self._all_inputs:
            # a new a/b at every call: one compiled call instead of the coefficients' and
            # this arithmetic in Python (the same results)
            self._fused = fused_step()
            self.step = self._step_fused

    def _step_fused(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start=None):
        """:meth:`step` by :func:`_fused_step` where it applies, else the general path."""
        try:
            done, fx, fy, mz = self._fused(xi, eta, phi, N, mu, a, b, G, nu)
        except (TypeError, ValueError, OverflowError):     # not floats: the general path says
            done = False
        if done:
            return make_result(fx, fy, mz, self.name)
        return ContactMethod.step(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start)

    def _jacobian_impl(self, xi, eta, phi, N, mu, a, b, G, nu, result):
        """The derivatives of the closed form (:mod:`contact_core.jacobian`): linear in the
        creepages, independent of N and μ; in a and b each term K a^p b^q C(a/b) x has
        ∂/∂a = term (p + l)/a and ∂/∂b = term (q - l)/b, l = d ln C/d ln(a/b)."""
        return linear_jacobian(xi, eta, phi, a, b, G, nu)

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        c11, c22, c23, c33 = self._coefficients(a / b, nu)
        c2 = a * b
        c = math.sqrt(c2)
        eff = self.effects
        Fx = -G * c2 * c11 * xi if eff.longitudinal else 0.0
        Fy = -G * (c2 * c22 * eta + c2 * c * c23 * phi) if eff.lateral else 0.0
        Mz = -G * c2 * c * (-c23 * eta + c * c33 * phi) if eff.spin else 0.0
        return make_result(Fx, Fy, Mz, self.name)


def linear_jacobian(xi: float, eta: float, phi: float, a: float, b: float, G: float,
                    nu: float, coefficients: Sequence[float] | None = None,
                    slopes: Sequence[float] | None = None) -> np.ndarray:
    """∂(Fx, Fy, Mz, slip fraction)/∂(ξ, η, φ, N, μ, a, b) of Kalker's linear theory
    (:meth:`LinearTheory._jacobian_impl`; the slip fraction is 0). ``coefficients``
    (C11, C22, C23, C33) and their ``slopes`` d ln C/d ln(a/b): others than Kalker's
    (Johnson–Vermeulen's, :mod:`.johnson_vermeulen`); None: Kalker's at a/b and ν."""
    r = a / b
    c11, c22, c23, c33 = creep_coefficients(r, nu) if coefficients is None else coefficients
    l11, l22, l23, l33 = creep_coefficient_slopes(r, nu) if slopes is None else slopes
    c2 = a * b
    c = math.sqrt(c2)
    J = np.zeros((4, 7))
    fx = -G * c2 * c11 * xi                         # a^1 b^1
    J[0, 0] = -G * c2 * c11
    J[0, 5] = fx * (1.0 + l11) / a
    J[0, 6] = fx * (1.0 - l11) / b
    fy_eta = -G * c2 * c22 * eta                    # a^1 b^1
    fy_phi = -G * c2 * c * c23 * phi                # a^1.5 b^1.5
    J[1, 1] = -G * c2 * c22
    J[1, 2] = -G * c2 * c * c23
    J[1, 5] = (fy_eta * (1.0 + l22) + fy_phi * (1.5 + l23)) / a
    J[1, 6] = (fy_eta * (1.0 - l22) + fy_phi * (1.5 - l23)) / b
    mz_eta = G * c2 * c * c23 * eta                 # a^1.5 b^1.5
    mz_phi = -G * c2 * c2 * c33 * phi               # a^2 b^2
    J[2, 1] = G * c2 * c * c23
    J[2, 2] = -G * c2 * c2 * c33
    J[2, 5] = (mz_eta * (1.5 + l23) + mz_phi * (2.0 + l33)) / a
    J[2, 6] = (mz_eta * (1.5 - l23) + mz_phi * (2.0 - l33)) / b
    return J
