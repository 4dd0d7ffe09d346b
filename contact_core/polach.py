"""Polach's method: creep forces in closed form, with spin, reduction factors and falling friction.

O. Polach, *A fast wheel-rail forces calculation computer code*, Vehicle System Dynamics 33
suppl. (1999) 728-739 (also *Influence of locomotive tractive effort on the forces between
wheel and rail*, VSD 35 suppl. (2001) 7-22), and its extension for traction at the adhesion
limit, O. Polach, *Creep forces in simulations of traction vehicles running on adhesion limit*,
Wear 258 (2005) 992-1000. The method of Simpack and ADAMS/Rail for traction studies.

Idea (Polach 1999): in the adhesion area the tangential stress grows linearly from the leading
edge with the gradient ε (normalised), until it meets Coulomb's bound on the Hertzian pressure; on
a strip the adhesion area ends at x = a δ, δ = (ε² - 1)/(ε² + 1), and the integral gives

    F = (2 μN/π) (ε/(1 + ε²) + arctan ε),    ε = (π/4) G ab c_jj s_C / (μN)

(Polach 1999: ε = (2/3) C π a² b s_C/(Q f) with C = (3/8)(G/a) c_jj; Q = N, f = μ). The
creepages: s_x = ξ, s_y = η, and with spin s_yC = η + φ a where |η + φ a| > |η|, else η
(:func:`~contact_core.friction.lateral_creep_with_spin`); s = |(ξ, η)|, s_C = |(ξ, s_yC)|;
c_jj = |(C11 ξ, C22 η)|/s weights Kalker's coefficients by the creepages. The force acts against
the creepage: Fx = -F ξ/s_C, Fy = -F η/s_C + F_yS (our sign convention, forces of the rail on the
wheel, Kalker 1979 sec. 2), with the lateral force of the spin

    F_yS = (9/16) a μN K_M k_s φ/s_C,   k_s = 1 + 6.3 (1 - e^(-a/b)),
    ε_M = (8/3) G b √(ab) C23 |s_yC| / (k_s μN),   δ = (ε_M² - 1)/(ε_M² + 1),
    K_M = ε_M (δ³/3 - δ²/2 + 1/6) - (1/3) √((1 - δ²)³) = -(2/3) ε_M / (1 + ε_M²)²

(the last form is Polach's K_M simplified exactly: with δ = 1 - 2/(1 + ε_M²) both terms are
polynomials in 1/(1 + ε_M²); it has no cancellation at small or large ε_M).

Reduction factors (Polach 2005, eq. 12): F = (2 μN/π) (k_A ε/(1 + (k_A ε)²) + arctan(k_S ε)),
k_S <= k_A <= 1 (options ``k_A``, ``k_S``; 1 and 1: Polach 1999), which lower the initial slope
to (k_A + k_S)/2 of Kalker's and, with k_S < k_A, give the curve a maximum of its own.
Falling friction (Polach 2005, eq. 14): μ = μ0 [(1 - A) e^(-B w) + A] at the creep velocity
w = V s_C, in ε, F and F_yS alike: the effect ``falling_friction``, whose "creep" mode
(``ContactMethod._step_falling``) passes μ(w) as the friction of this method.

Linear limit (ε, ε_M -> 0). Pure ξ, pure η, pure φ: Kalker's linear theory exactly (Kalker 1979,
eq 17, with C11, C22, C23). Combined creepage: the force has Kalker's magnitude
G ab |(C11 ξ, C22 η)| but the direction of the creepage (ξ, η), not of (C11 ξ, C22 η); with
spin and creepage the creepage's force is G ab c_jj (ξ, η) and the spin's -G (ab)^(3/2) C23 φ
|s_yC|/s_C. Times (k_A + k_S)/2 with reduction factors. Without the effect ``saturation`` the
method returns this limit.

Spin moment: the method has none. As Johnson–Vermeulen's default (``spin="she"``, after Shen,
Hedrick & Elkins 1983) it is Kalker's linear moment scaled by the force's reduction
|F|/|F_linear| (1 where Kalker's linear force vanishes) and held to Coulomb's bound μ∫p_n r dA
(``hertz.held_spin_moment``): use ``table``, ``fastsim`` or ``exact`` where the moment matters.
The force is held to Coulomb's bound |F| <= μN, which the spin's share F_yS added to the
creepage's can pass. ``slip_fraction``: the slipping share of each strip in Polach's picture,
1 - (1 - δ)/2 = ε²/(1 + ε²) (ε_M's without creepage).
"""
from __future__ import annotations

import math

from .base import ContactMethod, float_option
from .coefficients import per_call_coefficients
from .friction import lateral_creep_with_spin
from .hertz import held_spin_moment
from .result import make_result


def _over_one_plus_square(e: float) -> float:
    """e/(1 + e²), e >= 0, without overflow."""
    if e > 1.0:
        u = 1.0 / e
        return u / (1.0 + u * u)
    return e / (1.0 + e * e)


def _slipping_share(e: float) -> float:
    """ε²/(1 + ε²), ε >= 0: the slipping share of a strip in Polach's picture."""
    return 1.0 / (1.0 + 1.0 / (e * e)) if e > 1.0 else e * e / (1.0 + e * e)


class Polach(ContactMethod):
    """Polach's closed-form creep forces with spin (1999) and reduction factors (2005).

    Options
    -------
    k_A, k_S : float, default 1.0
        Polach 2005's reduction factors in the adhesion and the slip area, 0 < k_S <= k_A <= 1
        (1, 1: Polach 1999). Falling friction: the effect ``falling_friction``.
    """

    name = "polach"
    code = 6
    default_options = {"k_A": 1.0, "k_S": 1.0}

    def _check_options(self) -> None:
        o = self.options
        self._k_a = float_option(o, "k_A", 0.0, 1.0, lo_open=True)
        self._k_s = float_option(o, "k_S", 0.0, 1.0, lo_open=True)
        if self._k_s > self._k_a:
            raise ValueError(f"k_S={self._k_s!r} is invalid with k_A={self._k_a!r}: allowed "
                             "0 < k_S <= k_A <= 1 (Polach 2005: the slip area's reduction is "
                             "the stronger)")
        self._coefficients = per_call_coefficients(self.effects.varying_geometry)

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        eff = self.effects
        sat = eff.saturation
        eta_c = lateral_creep_with_spin(eta, phi, a)
        s_c = math.hypot(xi, eta_c)
        if s_c == 0.0:
            return make_result(0.0, 0.0, 0.0, self.name)
        c11, c22, c23, c33 = self._coefficients(a / b, nu)
        c2 = a * b
        c = math.sqrt(c2)
        mun = mu * N
        k_a, k_s = self._k_a, self._k_s
        fx = fy = 0.0
        slip = 0.0
        s = math.hypot(xi, eta)
        if s > 0.0:
            lin = G * c2 * math.hypot(c11 * xi, c22 * eta) / s * s_c   # Kalker's |F|, c_jj s_C
            if sat:
                eps = 0.25 * math.pi * lin / mun
                f = 2.0 * mun / math.pi * (_over_one_plus_square(k_a * eps)
                                           + math.atan(k_s * eps))
                slip = _slipping_share(eps)
            else:
                f = 0.5 * (k_a + k_s) * lin
            fx = -f * xi / s_c
            fy = -f * eta / s_c
        if phi != 0.0:
            spin_lin = G * c2 * c * c23 * abs(eta_c)              # Kalker's C23 term, |s_yC|
            if sat:
                ks = 1.0 + 6.3 * (1.0 - math.exp(-a / b))
                em = 8.0 / 3.0 * spin_lin / (ks * a * mun)       # ε_M: G b √(ab) = G c³/a
                u = 1.0 / em if em > 1.0 else em                    # ε_M/(1 + ε_M²)², no overflow
                km = u / (1.0 + u * u) ** 2 * (u * u if em > 1.0 else 1.0)
                fys = -0.375 * a * mun * ks * km
                if s == 0.0:
                    slip = _slipping_share(em)
            else:
                fys = -spin_lin
            fy += fys * phi / s_c
        if sat:
            f_abs = math.hypot(fx, fy)
            if f_abs > mun:                                        # Coulomb's bound
                fx, fy = fx * (mun / f_abs), fy * (mun / f_abs)
        mz = 0.0
        if eff.spin:
            fx_lin = -G * c2 * c11 * xi
            fy_lin = -G * (c2 * c22 * eta + c2 * c * c23 * phi)
            f_lin = math.hypot(fx_lin, fy_lin)
            mz = -G * c2 * c * (-c23 * eta + c * c33 * phi)
            if f_lin > 0.0:
                mz *= math.hypot(fx, fy) / f_lin
            if sat:
                mz = held_spin_moment(mz, mun, a, b)
        return make_result(fx if eff.longitudinal else 0.0, fy if eff.lateral else 0.0, mz,
                           self.name, slip)
