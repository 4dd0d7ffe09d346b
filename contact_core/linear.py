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

from .base import ContactMethod
from .coefficients import per_call_coefficients
from .result import make_result


class LinearTheory(ContactMethod):
    """Kalker's linear theory: exact for vanishing creepage and spin, never saturates."""

    name = "linear"
    code = 1
    default_options: dict = {}
    saturates = False

    def _check_options(self) -> None:
        self._coefficients = per_call_coefficients(self.effects.varying_geometry)

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        c11, c22, c23, c33 = self._coefficients(a / b, nu)
        c2 = a * b
        c = math.sqrt(c2)
        eff = self.effects
        Fx = -G * c2 * c11 * xi if eff.longitudinal else 0.0
        Fy = -G * (c2 * c22 * eta + c2 * c * c23 * phi) if eff.lateral else 0.0
        Mz = -G * c2 * c * (-c23 * eta + c * c33 * phi) if eff.spin else 0.0
        return make_result(Fx, Fy, Mz, self.name)
