"""Hertz's elliptic contact patch of two bodies of the same material.

Gap between the undeformed surfaces h = A x² + B y², with A = ½(1/R1x + 1/R2x) and
B = ½(1/R1y + 1/R2y) (convex radii positive; a concave wheel throat enters with a negative radius;
a straight direction has infinite radius). x is the rolling direction: the returned semi-axis
``a`` is along x, ``b`` along y, whichever is the major axis (the major axis lies along the
direction of the smaller relative curvature).

Formulas (K. L. Johnson, *Contact Mechanics*, CUP 1985, sec. 4.2, eqs 4.38-4.40 and 3.68), with
the semi-axes α >= β, g = β/α, m = e² = 1 - g², curvature A' along α and B' along β (A' <= B'),
p0 = 3N/(2παβ) and E* = E/(2(1-ν²)):

    A' = p0 β (K - E) / (E* α² m),   B' = p0 β (E/g² - K) / (E* α² m),   δ = p0 β K / E*,

K, E the complete elliptic integrals of parameter m. The differences K - E and E/g² - K cancel
for m -> 0, so they are evaluated with Carlson's symmetric integrals (DLMF 19.25.1:
K = R_F(0,g²,1), K - E = (m/3) R_D(0,g²,1)), which gives the curvature ratio and the major axis as

    B'/A' = (3 R_F / R_D - 1) / g²,      α³ = N R_D / (2π E* A').

The ratio equation is solved once per geometry for g with Brent's method (``scipy.optimize.brentq``)
in ln g; then α, β ∝ N^{1/3}, δ ∝ N^{2/3} (Kalker 1979 sec. 2).

A geometry that changes at every step (a contact point moving over curved profiles) cannot
afford a root-finding per step. The load-independent solution depends on the curvature
ratio q = B'/A' >= 1 alone, so it is tabulated once: with the same Carlson form, ln q and
(1/3) ln(R_D/(2π)) are explicit functions of g, evaluated on nodes uniform in ln g over the
supported ratios, and scipy's interpolating quintic spline (``make_interp_spline``, k = 5,
not-a-knot) through (ln q, ln g) and (ln q, (1/3) ln(R_D/(2π))) gives, per call,

    α = exp((1/3) ln(R_D/(2π))) (N/(E* A'))^{1/3},   β = g α.

:func:`tabulated_patch` evaluates it (one interval search and two polynomials; compiled by
:func:`patch_kernel`); it agrees with :func:`hertz_geometry`'s root within a few units of the
last digit (``TABULATED_RTOL``, tests).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numba.extending import register_jitable
from scipy.interpolate import BSpline, PPoly, make_interp_spline
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk, ellipkm1, elliprd, elliprf

from .cache import compiled_with_data
from .material import contact_modulus

#: Supported range of the curvature ratio A/B.
CURVATURE_RATIO_RANGE: tuple[float, float] = (1e-3, 1e3)


@register_jitable
def max_pressure(N: float, a: float, b: float) -> float:
    """Hertz's peak pressure p0 = 3N/(2πab), Pa (Kalker 1979, eq 3 at the centre; also
    compiled into kernels: numba's ``register_jitable``)."""
    return 1.5 * (N / (math.pi * a * b))  # N divided first: finite up to the largest N


def coulomb_spin_moment(mu_n: float, a: float, b: float) -> float:
    """The largest spin moment Coulomb's law allows on a Hertz patch, μ∫ p_n r dA, N·m
    (``mu_n`` = μN in N; semi-axes ``a``, ``b`` in m).

    Every traction with |p| <= μ p_n (Coulomb, Kalker 1979 eq 5) has |Mz| <= μ ∫ p_n r dA, r the
    distance from the centre. With Hertz's pressure p_n = p0 √(1 - x²/a² - y²/b²) (Kalker 1979,
    eq 3) and x = aρ cos θ, y = bρ sin θ, the integral is p0 ab ∫₀¹ ρ²√(1-ρ²) dρ ∮ √(a² cos²θ +
    b² sin²θ) dθ = p0 ab (π/16) P, P the ellipse's perimeter: the bound is 3 μN P/32 (3π/16 μNa
    on a circle). P = 4α E(1 - β²/α²), α >= β the semi-axes and E the complete elliptic integral
    of the second kind; since E >= 1 the bound is at least 3 μN α/8.
    """
    hi, lo = (a, b) if a >= b else (b, a)
    return 0.375 * mu_n * hi * float(ellipe(1.0 - (lo / hi) ** 2))


def held_spin_moment(mz: float, mu_n: float, a: float, b: float) -> float:
    """``mz`` (N·m) held to Coulomb's bound :func:`coulomb_spin_moment`, its sign kept, for a
    method whose moment is not a sum of tractions within the bound (a scaled or interpolated one).
    The elliptic integral only where ``mz`` may pass the bound: 3μNα/8 never does."""
    if abs(mz) > 0.375 * mu_n * (a if a > b else b):
        return math.copysign(min(abs(mz), coulomb_spin_moment(mu_n, a, b)), mz)
    return mz


def held_spin_moment_derivatives(mz: float, mu_n: float, a: float,
                                 b: float) -> tuple[float, float, float, float, float]:
    """:func:`held_spin_moment` and its derivatives with respect to ``mz``, ``mu_n``, ``a``,
    ``b`` (for the analytic Jacobians): (mz, 1, 0, 0, 0) where the moment is not held; where
    it is, those of the bound B = 3μN P/32 = 0.375 μN α E(m), m = 1 - (β/α)² (α >= β the
    semi-axes, E the complete elliptic integral of the second kind; dE/dm = (E - K)/(2m),
    DLMF 19.4.1, and -π/8 - 3πm/64 for m < 1e-4, the derivative of the series of E, DLMF
    19.5.2)."""
    held = held_spin_moment(mz, mu_n, a, b)
    if held == mz:
        return mz, 1.0, 0.0, 0.0, 0.0
    alpha, beta = (a, b) if a >= b else (b, a)
    q = (beta / alpha) ** 2
    m = 1.0 - q
    e = float(ellipe(m))
    de = (-math.pi / 8.0 - 3.0 * math.pi * m / 64.0 if m < 1e-4
          else (e - float(ellipk(m))) / (2.0 * m))
    sign = math.copysign(1.0, mz)
    d_alpha = sign * 0.375 * mu_n * (e + 2.0 * q * de)
    d_beta = -sign * 0.75 * mu_n * (beta / alpha) * de
    d_a, d_b = (d_alpha, d_beta) if a >= b else (d_beta, d_alpha)
    return held, 0.0, held / mu_n, d_a, d_b


@dataclass(frozen=True)
class HertzPatch:
    """Hertz contact patch: semi-axes ``a`` (rolling direction x) and ``b`` (lateral y), m;
    maximum pressure ``p0``, Pa; ``approach`` (mutual approach of distant points), m."""

    a: float
    b: float
    p0: float
    approach: float


@dataclass(frozen=True)
class HertzGeometry:
    """The load-independent part of the Hertz solution of one geometry and material.

    ``a = ka N^{1/3}``, ``b = kb N^{1/3}``, ``approach = kd N^{2/3}``; :meth:`patch` evaluates
    them for a load without any root-finding (cheap enough for every simulation step).
    """

    ka: float
    kb: float
    kd: float

    def patch(self, N: float) -> HertzPatch:
        """The contact patch under normal load ``N`` (N >= 0; N = 0 gives a zero patch)."""
        if not (math.isfinite(N) and N >= 0.0):
            raise ValueError(f"N={N!r} is out of range: allowed 0 <= N < inf (normal load, N)")
        if N == 0.0:
            return HertzPatch(0.0, 0.0, 0.0, 0.0)
        s = N ** (1.0 / 3.0)
        a, b = self.ka * s, self.kb * s
        return HertzPatch(a, b, max_pressure(N, a, b), self.kd * s * s)


def ellipse_curvatures(a: float, b: float) -> tuple[float, float]:
    """Relative curvatures (A along x, B along y) in 1/m, divided by p0/E*, that make the
    ellipse with semi-axes ``a`` (x), ``b`` (y) in m (Johnson eq 4.39 in Carlson form, above):
    A' = β R_D/(3 α²), B' = (R_F - R_D/3)/β along the major (α) and minor (β) axes."""
    alpha, beta = max(a, b), min(a, b)
    g2 = (beta / alpha) ** 2
    rf = float(elliprf(0.0, g2, 1.0))
    rd = float(elliprd(0.0, g2, 1.0))
    c_major = beta / alpha ** 2 * rd / 3.0
    c_minor = (rf - rd / 3.0) / beta
    return (c_major, c_minor) if a >= b else (c_minor, c_major)


def _curvature_ratio(g: float) -> float:
    """B'/A' for minor/major axis ratio g."""
    c_major, c_minor = ellipse_curvatures(1.0, g)
    return c_minor / c_major


def _axis_ratio(q: float) -> float:
    """Minor/major axis ratio g for curvature ratio q = B'/A' >= 1."""
    if q == 1.0:
        return 1.0
    lnq = math.log(q)
    return math.exp(brentq(lambda lng: math.log(_curvature_ratio(math.exp(lng))) - lnq,
                           math.log(1e-6), 0.0, xtol=1e-15, rtol=1e-15, maxiter=200))


def hertz_geometry(A: float, B: float, E: float, nu: float) -> HertzGeometry:
    """Solve the load-independent Hertz problem for relative curvatures A (x), B (y) in 1/m."""
    for name, v in (("A", A), ("B", B), ("E", E)):
        if not (math.isfinite(v) and v > 0.0):
            raise ValueError(f"{name}={v!r} is out of range: allowed 0 < {name} < inf")
    if not (0.0 <= nu < 0.5):
        raise ValueError(f"nu={nu!r} is out of range: allowed 0 <= nu < 0.5")
    lo, hi = CURVATURE_RATIO_RANGE
    if not (lo <= A / B <= hi):
        raise ValueError(f"A/B={A / B!r} is out of range: allowed {lo} <= A/B <= {hi}")
    e_star = contact_modulus(E, nu)
    a_small = min(A, B)  # A': curvature along the major axis
    g = _axis_ratio(max(A, B) / a_small)
    k_major = (float(elliprd(0.0, g * g, 1.0)) / (2.0 * math.pi * e_star * a_small)) ** (1.0 / 3.0)
    k_minor = g * k_major
    # δ = p0 β K / E* with p0 β = 3N/(2π α): the N-independent factor of N^{2/3}.
    kd = 3.0 * float(ellipkm1(g * g)) / (2.0 * math.pi * k_major * e_star)
    ka, kb = (k_major, k_minor) if A <= B else (k_minor, k_major)
    return HertzGeometry(ka, kb, kd)


#: Nodes of the tabulated solution (uniform in ln g), and its accuracy against the root of
#: :func:`hertz_geometry`, relative, in a and b over ``CURVATURE_RATIO_RANGE`` (tests): with
#: 400 nodes the interpolation error is below the root's rounding.
_TABLE_NODES = 400
TABULATED_RTOL = 1e-14


def _tabulate(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The breakpoints in ln q and per interval the coefficients (power 5 .. 0 of the distance
    to its breakpoint) of ln g and of (1/3) ln(R_D(0, g², 1)/(2π)) (module docstring)."""
    g_end = _axis_ratio(max(CURVATURE_RATIO_RANGE[1], 1.0 / CURVATURE_RATIO_RANGE[0])) ** 1.01
    ln_g = np.linspace(0.0, math.log(g_end), n)
    g2 = np.exp(2.0 * ln_g)
    rf, rd = elliprf(0.0, g2, 1.0), elliprd(0.0, g2, 1.0)
    # B'/A' = (3 R_F/R_D - 1)/g² (ellipse_curvatures with α = 1, β = g); exactly 0 at g = 1
    ln_q = np.log(3.0 * rf / rd - 1.0) - 2.0 * ln_g
    ln_q[0] = 0.0
    spline = make_interp_spline(ln_q, np.stack([ln_g, np.log(rd / (2.0 * math.pi)) / 3.0], 1),
                                k=5)
    polys = [PPoly.from_spline(BSpline(spline.t, spline.c[:, j], 5)) for j in range(2)]
    keep = np.flatnonzero(np.diff(polys[0].x) > 0)      # the end knots repeat: empty intervals
    pieces = np.stack([p.c[:, keep].T for p in polys], axis=1)   # (interval, function, power)
    return np.ascontiguousarray(polys[0].x[keep]), np.ascontiguousarray(pieces)


_LN_Q, _PIECES = _tabulate(_TABLE_NODES)
_RATIO_LO, _RATIO_HI = CURVATURE_RATIO_RANGE


def tabulated_patch(N: float, A: float, B: float, e_star: float) -> tuple[float, float, float]:
    """Hertz's semi-axes ``a`` (x), ``b`` (y), m, and peak pressure ``p0``, Pa, for the load
    ``N`` (0 < N < inf), relative curvatures ``A``, ``B`` (1/m) and contact modulus ``e_star``
    (Pa) from the tabulated solution (module docstring); (nan, nan, nan) where A, B are not
    finite, not positive (no Hertz patch: a contact with A <= 0 or B <= 0 is not Hertzian), or
    their ratio is outside ``CURVATURE_RATIO_RANGE`` (the caller says which). Written for numba
    (:func:`patch_kernel`)."""
    if not (0.0 < A < math.inf and 0.0 < B < math.inf and _RATIO_LO <= A / B <= _RATIO_HI):
        return math.nan, math.nan, math.nan
    small = A if A <= B else B
    x = math.log((B if A <= B else A) / small)
    i = min(int(np.searchsorted(_LN_Q, x, side="right")) - 1, _LN_Q.shape[0] - 1)
    dx = x - _LN_Q[i]
    p = _PIECES[i]
    ln_g = ((((p[0, 0] * dx + p[0, 1]) * dx + p[0, 2]) * dx + p[0, 3]) * dx + p[0, 4]) * dx \
        + p[0, 5]
    ln_k = ((((p[1, 0] * dx + p[1, 1]) * dx + p[1, 2]) * dx + p[1, 3]) * dx + p[1, 4]) * dx \
        + p[1, 5]
    major = math.exp(ln_k) * (N / (e_star * small)) ** (1.0 / 3.0)
    minor = math.exp(ln_g) * major
    a, b = (major, minor) if A <= B else (minor, major)
    return a, b, max_pressure(N, a, b)


def tabulated_patch_derivatives(N: float, A: float, B: float,
                                e_star: float) -> tuple[float, float, float, np.ndarray]:
    """:func:`tabulated_patch`'s (a, b, p0) and their derivatives with respect to (N, A, B)
    (a 3 x 3 array; for the Jacobians of a contact whose curvatures are inputs): its quintic
    pieces differentiated. With x = ln(q), q the larger over the smaller curvature, the major
    semi-axis is k(x) (N/(E* A'))^(1/3) and the minor g(x) times it (module docstring), so
    d ln(major) = dN/(3N) - (1/3 + k'/k) dA'/A' + (k'/k) dA''/A'' (A' the smaller curvature,
    A'' the larger), the minor's adds (g'/g)(dA''/A'' - dA'/A'), and
    d ln p0 = dN/N - d ln a - d ln b. Valid inputs only (a finite patch)."""
    a, b, p0 = tabulated_patch(N, A, B, e_star)
    small = A if A <= B else B
    x = math.log((B if A <= B else A) / small)
    i = min(int(np.searchsorted(_LN_Q, x, side="right")) - 1, _LN_Q.shape[0] - 1)
    dx = x - _LN_Q[i]
    p = _PIECES[i]
    dln_g, dln_k = (float(np.polyval(np.polyder(p[j]), dx)) for j in range(2))
    # d ln(major), d ln(minor) by (ln N, ln A', ln A'')
    major = np.array([1.0 / 3.0, -1.0 / 3.0 - dln_k, dln_k])
    minor = major + np.array([0.0, -dln_g, dln_g])
    la, lb = (major, minor) if A <= B else (minor, major)
    lp = np.array([1.0, 0.0, 0.0]) - la - lb
    # columns: by (ln N, ln A', ln A'') -> by (N, A, B)
    to_nab = np.array([[1.0 / N, 0.0, 0.0],
                       [0.0, 1.0 / A, 0.0] if A <= B else [0.0, 0.0, 1.0 / B],
                       [0.0, 0.0, 1.0 / B] if A <= B else [0.0, 1.0 / A, 0.0]])
    d = np.array([a * la, b * lb, p0 * lp]) @ to_nab
    return a, b, p0, d


_PATCH_KERNEL = None


def patch_kernel() -> Callable[[float, float, float, float], tuple[float, float, float]]:
    """:func:`tabulated_patch` compiled by numba (on first use; cached on disk and checked,
    :func:`~contact_core.cache.compiled_with_data`)."""
    global _PATCH_KERNEL
    if _PATCH_KERNEL is None:
        e_star = contact_modulus(210e9, 0.28)
        samples = [(1e5, 1.0, q, e_star) for q in (1.0, 1.7, 40.0, 999.0)]
        _PATCH_KERNEL = compiled_with_data(tabulated_patch, samples)
    return _PATCH_KERNEL


def hertz(N: float, A: float, B: float, E: float, nu: float) -> HertzPatch:
    """Hertz patch for load ``N`` (N), relative curvatures ``A``, ``B`` (1/m), Young's modulus
    ``E`` (Pa) and Poisson's ratio ``nu`` of both bodies."""
    return hertz_geometry(A, B, E, nu).patch(N)


def wheel_rail_curvatures(R_wheel: float, R_wheel_profile: float,
                          R_rail_profile: float) -> tuple[float, float]:
    """Relative curvatures (A, B) in 1/m of a wheel on a straight rail.

    ``R_wheel``: rolling radius (x-z plane); ``R_wheel_profile``: transverse radius of the wheel
    profile (y-z plane; negative for a concave/hollow tread or throat, ``inf`` for a cone);
    ``R_rail_profile``: rail-crown radius (y-z plane, convex positive). The rail is straight
    along x. A = ½/R_wheel, B = ½(1/R_wheel_profile + 1/R_rail_profile).
    """
    for name, v in (("R_wheel", R_wheel), ("R_wheel_profile", R_wheel_profile),
                    ("R_rail_profile", R_rail_profile)):
        if math.isnan(v) or v == 0.0:
            raise ValueError(f"{name}={v!r} is out of range: allowed a non-zero radius in m "
                             "(inf for a straight profile)")
    if not R_wheel > 0.0:
        raise ValueError(f"R_wheel={R_wheel!r} is out of range: allowed 0 < R_wheel <= inf")
    return 0.5 / R_wheel, 0.5 * (1.0 / R_wheel_profile + 1.0 / R_rail_profile)


def hertz_from_radii(N: float, R_wheel: float, R_wheel_profile: float, R_rail_profile: float,
                     E: float, nu: float) -> HertzPatch:
    """Hertz patch of a wheel on a straight rail from the radii of :func:`wheel_rail_curvatures`."""
    A, B = wheel_rail_curvatures(R_wheel, R_wheel_profile, R_rail_profile)
    return hertz(N, A, B, E, nu)
