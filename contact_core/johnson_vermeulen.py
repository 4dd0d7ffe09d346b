"""Johnson & Vermeulen's creep-force law (Kalker 1979, sec. 3, eqs 10-13, 19-22).

Johnson & Vermeulen (1964) extended Carter's solution to an elliptic contact with an elliptic
adhesion area touching the leading edge. With normalised creepages (ξ', η') and τ = |(ξ', η')|:

    F/(μN) = ((1 - τ/3)³ - 1) (ξ', η')/τ    for τ <= 3,     F/(μN) = -(ξ', η')/τ    for τ >= 3.

The seed prints the switch of eq 13 once as τ <= 1 and once as τ <= 3. Continuity of F decides:
at τ = 3 the cubic gives (1 - 1)³ - 1 = -1, equal to the sliding branch, whereas at τ = 1 it gives
(2/3)³ - 1 = -0.704 ≠ -1. Also d/dτ (1 - τ/3)³ = 0 at τ = 3, so the switch at 3 is C¹ and the
force saturates smoothly; τ <= 1 is a misprint.

Two normalisations (option ``variant``):

``"kalker"`` (default)
    eq 22: ξ' = ab G C11 ξ/(μN), η' = ab G C22 η/(μN) with Kalker's coefficients, so the slope at
    the origin equals linear theory (for small τ the cubic is -τ).
``"original"``
    eq 12: ξ' = π ab G ξ/(μN Φ), η' = π ab G η/(μN ψ1), with Φ, ψ1 from the complete elliptic
    integrals B, C, D of eq 10 (eq 11a for a <= b, 11b for a >= b); i.e. C11^JV = π/Φ and
    C22^JV = π/ψ1 (eq 19; Kalker 1979, Table 1 lists them for ν = 1/4).

Johnson–Vermeulen has no spin. Option ``spin``:

``"she"`` (default)
    the Shen–Hedrick–Elkins combination (Shen, Hedrick & Elkins, *A comparison of alternative
    creep-force models for rail vehicle dynamic analysis*, Proc. 8th IAVSD Symposium, 1983):
    compute the linear forces including the spin term c³ C23 φ of Fy (and the linear spin moment),
    then scale all of them by ε = F_JV(τ)/(μN τ) where τ = |F_linear|/(μN) and F_JV is the cubic
    above. For φ = 0 and ``variant="kalker"`` this is exactly eqs 13 and 22. With
    ``variant="original"`` the linear force uses C11^JV, C22^JV and Kalker's C23, C33.
    The scaled moment is held to Coulomb's bound μ∫ p_n r dA = 3μN P/32 (P the ellipse's
    perimeter; ``hertz.coulomb_spin_moment``), which no traction with |p| <= μ p_n exceeds: the
    scaling alone goes beyond it at large spin (ε -> μN/|F_linear| while the linear moment's
    lever is c C33/C23) and where the η and φ terms of the linear lateral force cancel (ε -> 1):
    on large spin with and without η, a/b 0.05-20, it gave 2.4 to 56 times the bound (the most at
    a/b = 0.05), where the exact theory reaches 0.99 of it.
``"ignore"``
    the strict original: φ is ignored and Mz = 0 (the theory has no spin moment).

``slip_fraction`` is that of the Johnson–Vermeulen picture (Kalker 1979, fig. 6; Johnson
1958a): the adhesion area is an ellipse similar to the contact ellipse, scaled by 1 - τ/3, so the
slip fraction is 1 - (1 - τ/3)² (1 for τ >= 3).

The elliptic integrals of eq 10 (k² = m) are evaluated with Carlson's symmetric integrals
(DLMF 19.25.1): D = (K - E)/m = R_D(0, 1-m, 1)/3, B = K - D with K = R_F(0, 1-m, 1), and
C = (D - B)/m (integrate d/dθ[sinθ cosθ/Δ] over [0, π/2]); C -> π/16 for m -> 0.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import elliprd, elliprf

from .cache import cached
from .base import ContactMethod, choice_option
from .coefficients import creep_coefficient_slopes, creep_coefficients, per_call_coefficients
from .hertz import held_spin_moment, held_spin_moment_derivatives
from .linear import linear_jacobian
from .result import make_result


def elliptic_bcd(m: float) -> tuple[float, float, float]:
    """Elliptic integrals (B, C, D) of Kalker 1979 eq 10 for the parameter m = k² in [0, 1)."""
    if m < 1e-9:  # C = (D - B)/m cancels; first-order series, error O(m²)
        return math.pi / 4 * (1 + m / 8), math.pi / 16 * (1 + 0.75 * m), math.pi / 4 * (1 + 3 * m / 8)
    rd = float(elliprd(0.0, 1.0 - m, 1.0))
    d = rd / 3.0
    bb = float(elliprf(0.0, 1.0 - m, 1.0)) - d
    return bb, (d - bb) / m, d


@cached(1024)
def jv_creep_coefficients(a_over_b: float, nu: float) -> tuple[float, float]:
    """Johnson–Vermeulen's coefficients (C11^JV, C22^JV) = (π/Φ, π/ψ1), Kalker 1979 eqs 11, 19."""
    r = a_over_b
    if r <= 1.0:  # eq 11a
        bb, cc, dd = elliptic_bcd(1.0 - r * r)
        big_phi = bb - nu * (dd - cc)
        psi1 = bb - nu * r * r * cc
    else:  # eq 11b
        bb, cc, dd = elliptic_bcd(1.0 - 1.0 / (r * r))
        big_phi = (dd - nu * (dd - cc)) / r
        psi1 = (dd - nu * cc) / r
    return math.pi / big_phi, math.pi / psi1


VARIANTS = ("kalker", "original")
SPIN_MODES = ("she", "ignore")


class JohnsonVermeulen(ContactMethod):
    """Johnson–Vermeulen's saturating creep-force law, with spin added the Shen–Hedrick–Elkins way."""

    name = "johnson_vermeulen"
    code = 2
    default_options = {"variant": "kalker", "spin": "she"}

    def _check_options(self) -> None:
        choice_option(self.options, "variant", VARIANTS)
        choice_option(self.options, "spin", SPIN_MODES)
        self._original = self.options["variant"] == "original"
        self._use_spin = self.options["spin"] == "she"
        self._coefficients = per_call_coefficients(self.effects.varying_geometry)

    def _jacobian_impl(self, xi, eta, phi, N, mu, a, b, G, nu, result):
        """The derivatives of the law (:mod:`contact_core.jacobian`): of the linear forces
        (as linear theory's), then of the scaling ε(τ) = 1 - τ/3 + τ²/27 for τ < 3 (the cubic
        of eq 13 divided by τ, exactly) and 1/τ beyond, τ = |F_linear|/(μN), and of Coulomb's
        bound on the moment where it holds it. Where the linear force vanishes τ's kink is
        taken as flat (dτ = 0: the forces' derivative is then linear theory's), and so is the
        slip fraction's there. ``variant="original"``: Johnson–Vermeulen's C11, C22 differ
        from Kalker's, their slope in a/b a central difference of step 1e-4 in ln(a/b) (near
        a/b = 1 eq 11's C = (D - B)/m loses the digits of m = |1 - (a/b)^±2|: a smaller step
        sees them)."""
        coefficients = slopes = None        # Kalker's
        if self._original:
            r = a / b
            h = 1e-4
            up, down = (jv_creep_coefficients(r * math.exp(s), nu) for s in (h, -h))
            coefficients = (*jv_creep_coefficients(r, nu), *creep_coefficients(r, nu)[2:])
            slopes = (*((math.log(u) - math.log(d)) / (2.0 * h) for u, d in zip(up, down)),
                      *creep_coefficient_slopes(r, nu)[2:])
        use_spin = self._use_spin
        if not use_spin:
            phi = 0.0
        # the linear forces and moment, linear in (ξ, η, φ), and their gradients
        d_fx, d_fy, d_mz = linear_jacobian(xi, eta, phi, a, b, G, nu, coefficients, slopes)[:3]
        fx = d_fx[0] * xi
        fy = d_fy[1] * eta + d_fy[2] * phi
        mz = d_mz[1] * eta + d_mz[2] * phi
        if not use_spin:                    # φ ignored, no moment
            d_fy[2] = 0.0
            mz, d_mz = 0.0, np.zeros(7)
        eps, d_eps, d_slip = 1.0, np.zeros(7), np.zeros(7)
        sat = self.effects.saturation
        mun = mu * N
        d_mun = np.array([0.0, 0.0, 0.0, mu, N, 0.0, 0.0])
        if sat:
            f = math.hypot(fx, fy)
            tau = f / mun
            d_tau = ((fx * d_fx + fy * d_fy) / f / mun - tau * d_mun / mun) if f > 0.0 \
                else np.zeros(7)
            if tau >= 3.0:
                eps, d_eps = 1.0 / tau, -d_tau / (tau * tau)
            elif tau > 0.0:
                s3 = 1.0 - tau / 3.0
                eps = (1.0 - s3 * s3 * s3) / tau
                d_eps = (-1.0 / 3.0 + 2.0 * tau / 27.0) * d_tau
                d_slip = 2.0 * s3 / 3.0 * d_tau
        J = np.zeros((4, 7))
        eff = self.effects
        if eff.longitudinal:
            J[0] = eps * d_fx + fx * d_eps
        if eff.lateral:
            J[1] = eps * d_fy + fy * d_eps
        if eff.spin:
            J[2] = eps * d_mz + mz * d_eps
            if sat:
                _, h_mz, h_mun, h_a, h_b = held_spin_moment_derivatives(eps * mz, mun, a, b)
                J[2] = h_mz * J[2] + h_mun * d_mun
                J[2, 5] += h_a
                J[2, 6] += h_b
        J[3] = d_slip
        return J

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        r = a / b
        c11, c22, c23, c33 = self._coefficients(r, nu)
        if self._original:
            c11, c22 = jv_creep_coefficients(r, nu)
        if not self._use_spin:
            phi = 0.0
        c2 = a * b
        c = math.sqrt(c2)
        fx = -G * c2 * c11 * xi
        fy = -G * (c2 * c22 * eta + c2 * c * c23 * phi)
        mz = -G * c2 * c * (-c23 * eta + c * c33 * phi) if self._use_spin else 0.0
        eps, slip = 1.0, 0.0
        if self.effects.saturation:
            tau = math.hypot(fx, fy) / (mu * N)
            if tau >= 3.0:
                eps, slip = 1.0 / tau, 1.0
            elif tau > 0.0:
                s = 1.0 - tau / 3.0
                eps, slip = (1.0 - s * s * s) / tau, 1.0 - s * s
        mz *= eps
        if self.effects.saturation:
            mz = held_spin_moment(mz, mu * N, a, b)
        eff = self.effects
        return make_result(eps * fx if eff.longitudinal else 0.0,
                             eps * fy if eff.lateral else 0.0,
                             mz if eff.spin else 0.0,
                             self.name, slip)
