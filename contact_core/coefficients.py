"""Kalker's creepage and spin coefficients C11, C22, C23, C33 of linear rolling-contact theory.

Source: J. J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer 1990, Table E.3
(also Kalker's 1967 thesis, pp. 91-93), shipped as ``data/kalker_coefficients.csv`` (see the
file's header). Definition (Kalker 1979, eqs 17-18, with c = √(ab)):

    Fx = -G c² C11 ξ,   Fy = -G (c² C22 η + c³ C23 φ),   Mz = -G (-c³ C23 η + c⁴ C33 φ).

Interpolation inside the table (0.1 <= a/b <= 10, 0 <= ν <= 0.5): an interpolating bicubic-by-
quadratic spline (``scipy.interpolate.RectBivariateSpline``, kx=3, ky=2, s=0) of ln C over
(ln(a/b), ν). It passes through every tabulated value, covers both branches a/b <= 1 and
b/a <= 1 with one smooth (C²) curve in ln(a/b), and is exactly quadratic in ν between the three
tabulated Poisson ratios (CONTACT's ``linrol`` is also quadratic in ν, applied to 1/C). It is
evaluated in its piecewise-polynomial form (``scipy.interpolate.PPoly.from_spline``), the same
values to rounding. Between the rows a/b = 5 and 10, where C11, C22 grow by a factor 1.5 and C23
by 2.2, it stays within 1 % of the exact theory's linear range (a/b = 6.5, 7.5; tests); a
straight line in b/a between the rows, as ``linrol`` interpolates, is 6-17 % above it there.

Outside the table, Kalker's asymptotes (Kalker 1990, Table E.3 footnotes; the same formulas are in
CONTACT's ``m_hertz.f90``, routine ``linrol``) with Λ = ln(16/g²):

* a/b = g -> 0:  C11 = π²/(4(1-ν)),  C22 = π²/4,  C23 = π√g/(3(1-ν)) (1 + ν(ln(16/g) - 5)),
  C33 = π²/(16(1-ν)g);
* b/a = g -> 0:  C11 = 2π/((Λ-2ν)g) (1 + (3-ln4)/(Λ-2ν)),
  C22 = 2π/g (1 + (1-ν)(3-ln4)/((1-ν)Λ+2ν)) / ((1-ν)Λ+2ν),  C23 = 2π/(3g^1.5 ((1-ν)Λ-2+4ν)).

The asymptote is multiplied by a factor that equals table/asymptote at the table's end (g = 0.1)
and tends linearly in g to 1 as g -> 0, so the coefficients are continuous at the table's edge
and exact in the limit. Kalker gives no asymptote for C33 as b/a -> 0; the table shows C33 nearly
flat there (change < 1 % from a/b = 5 to 10 for ν <= 0.25), so for a/b > 10 C33 is held at its
a/b = 10 value and a ``CoefficientExtrapolationWarning`` is issued (shown once by Python's
default warning filter).
Beyond the supported range ``A_OVER_B_RANGE`` a ``ValueError`` is raised.

C33 and the exact theory: C11, C22 and C23 of the table agree with the converged exact theory
(``contact_core.exact``) within 1 % (tests), and so does C33 for a/b < 1; for a/b > 1 the
exact theory's C33 is lower than the table's, increasingly with a/b (about 5 % at a/b = 2 and
30 % at a/b = 5; the grid convergence behind these figures is in docs/notes/coefficients.md).
This package keeps Kalker's tabulated C33 (it is what "Kalker's linear theory" and its users
mean; the source of the table's C33 column is the one the file's header names), so at small spin
with a/b > 1 the spin moment of ``linear`` and of ``johnson_vermeulen`` (and FASTSIM's, whose L4
is fitted to it) is that much above the one of ``exact`` and ``table`` (test_exact's xfail on
C33; the methods' contract declares it: ``tests/test_method_contract.py``).
"""
from __future__ import annotations

import csv
import math
from bisect import bisect_right
from importlib import resources
from typing import Callable

import numpy as np
from numba import objmode
from numba.extending import register_jitable
from scipy.interpolate import BSpline, PPoly, RectBivariateSpline

from . import notices
from .cache import cached, compiled_with_data

#: Supported range of a/b (table 0.1..10 plus Kalker's asymptotes beyond it).
A_OVER_B_RANGE: tuple[float, float] = (0.005, 200.0)
_TABLE_EDGE = 0.1  # g = min(a/b, b/a) at the table's ends


class CoefficientExtrapolationWarning(UserWarning):
    """A coefficient was extended beyond Kalker's table without a published asymptote."""


def _load_table() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    text = resources.files(__package__).joinpath("data/kalker_coefficients.csv").read_text()
    rows = [r for r in csv.reader(line for line in text.splitlines() if not line.startswith("#"))]
    header, body = rows[0], np.array(rows[1:], dtype=float)
    assert header == ["a_over_b", "nu", "C11", "C22", "C23", "C33"], header
    ratios = np.unique(body[:, 0])
    nus = np.unique(body[:, 1])
    coef = np.empty((4, ratios.size, nus.size))
    for row in body:
        i = np.searchsorted(ratios, row[0])
        j = np.searchsorted(nus, row[1])
        coef[:, i, j] = row[2:]
    return ratios, nus, coef


def _polynomial_pieces(splines: tuple[RectBivariateSpline, ...]) -> tuple[list[float], np.ndarray]:
    """The splines as polynomials (scipy's ``PPoly.from_spline``): the breakpoints x_i in
    ln(a/b) and per interval the coefficients ``P[i, k, q, p]`` of (x - x_i)^q ν^p in ln C_k.
    In ν each spline is one quadratic piece (knots 0, 0, 0, 0.5, 0.5, 0.5)."""
    tx, ty, _ = splines[0].tck
    assert list(ty) == [0.0, 0.0, 0.0, 0.5, 0.5, 0.5], ty
    # the three quadratic B-splines in ν as polynomials: N_j(ν) = Σ_p M[j, p] ν^p
    M = np.array([PPoly.from_spline(BSpline(ty, np.eye(3)[j], 2)).c[::-1, 2] for j in range(3)])
    per_j = [[PPoly.from_spline(BSpline(tx, s.tck[2].reshape(-1, 3)[:, j], 3)) for j in range(3)]
             for s in splines]
    x = per_j[0][0].x
    A = np.array([[pp.c[::-1] for pp in row] for row in per_j])        # (k, j, q, interval)
    P = np.einsum("kjqi,jp->ikqp", A, M)
    keep = np.flatnonzero(np.diff(x) > 0)       # the end knots repeat: empty intervals
    return x[keep].tolist(), np.ascontiguousarray(P[keep])


_RATIOS, _NUS, _TABLE = _load_table()


def tabulated(nu: float) -> list[tuple[float, tuple[float, float, float, float]]]:
    """Kalker's Table E.3 as shipped (no interpolation): (a/b, (C11, C22, C23, C33)) of every
    tabulated a/b, ascending, at the Poisson ratio ``nu``, which must be one of the table's
    (else a ``ValueError`` naming them). For comparisons against the table itself."""
    j = np.flatnonzero(_NUS == nu)
    if j.size != 1:
        raise ValueError(f"nu={nu!r} is not tabulated: allowed {', '.join(map(str, _NUS))}")
    return [(float(ab), tuple(float(c) for c in _TABLE[:, i, j[0]]))
            for i, ab in enumerate(_RATIOS)]


_BREAKS, _PIECES = _polynomial_pieces(tuple(
    RectBivariateSpline(np.log(_RATIOS), _NUS, np.log(_TABLE[k]), kx=3, ky=2, s=0)
    for k in range(4)))
_LOG_LO, _LOG_HI = math.log(_RATIOS[0]), math.log(_RATIOS[-1])
# Evaluated in plain floats: ν is a variable like a/b here, and a contact point moving over
# curved profiles meets a new a/b at every step. Plain-float loops cost a fraction of scipy's
# spline calls; a numba kernel with the spline frozen into it costs less again but its first
# call compiles, which processes that compile nothing else (the linear and Johnson-Vermeulen
# FMUs) are spared: :func:`per_call_coefficients` uses it only where a/b changes at every call
# (the measurements: docs/notes/coefficients.md). Code that is compiled anyway (the method
# "table") calls :func:`spline_coefficients` inside its kernel instead.
_PIECE_LIST = _PIECES[:, :, ::-1, :].tolist()       # (interval, k, power 3..0, ν power 0..2)
#: The spline as arrays, for :func:`spline_coefficients`: breakpoints in ln(a/b), and per
#: interval, coefficient k and power 3..0 of (x - x_i) the factors of ν^0, ν^1, ν^2.
SPLINE = (np.array(_BREAKS), np.ascontiguousarray(_PIECES[:, :, ::-1, :]))


def _table(a_over_b: float, nu: float) -> list[float]:
    x = math.log(a_over_b)
    i = min(max(bisect_right(_BREAKS, x) - 1, 0), len(_BREAKS) - 1)
    dx = x - _BREAKS[i]
    return [math.exp((((p3[0] + nu * (p3[1] + nu * p3[2])) * dx
                       + p2[0] + nu * (p2[1] + nu * p2[2])) * dx
                      + p1[0] + nu * (p1[1] + nu * p1[2])) * dx
                     + p0[0] + nu * (p0[1] + nu * p0[2]))
            for p3, p2, p1, p0 in _PIECE_LIST[i]]


@register_jitable
def _interval(breaks: np.ndarray, x: float) -> tuple[int, float]:
    """The spline's interval i at ln(a/b) = x and the distance x - x_i (:func:`_table`)."""
    i = min(max(int(np.searchsorted(breaks, x, side="right")) - 1, 0), breaks.shape[0] - 1)
    return i, x - breaks[i]


@register_jitable
def _piece_value(p: np.ndarray, dx: float, nu: float) -> float:
    """One coefficient from its piece ``p`` (power 3..0 of dx by ν power 0..2), as :func:`_table`
    evaluates it."""
    return math.exp((((p[0, 0] + nu * (p[0, 1] + nu * p[0, 2])) * dx
                      + p[1, 0] + nu * (p[1, 1] + nu * p[1, 2])) * dx
                     + p[2, 0] + nu * (p[2, 1] + nu * p[2, 2])) * dx
                    + p[3, 0] + nu * (p[3, 1] + nu * p[3, 2]))


def spline_coefficients(breaks: np.ndarray, pieces: np.ndarray, x: float,
                        nu: float) -> tuple[float, float, float]:
    """(C11, C22, C23) at ln(a/b) = x inside Kalker's table (``_LOG_LO <= x <= _LOG_HI``) from
    the arrays ``SPLINE``: the same spline, operations and order as :func:`_table`, written for
    numba (array arguments, no Python objects), for kernels that compile anyway."""
    i, dx = _interval(breaks, x)
    p = pieces[i]
    return _piece_value(p[0], dx, nu), _piece_value(p[1], dx, nu), _piece_value(p[2], dx, nu)


_SPLINE_BREAKS, _SPLINE_PIECES = SPLINE


@register_jitable
def table_coefficients(a_over_b: float, nu: float) -> tuple[float, float, float, float]:
    """(C11, C22, C23, C33) inside Kalker's table (0.1 <= a/b <= 10, 0 <= ν <= 0.5, unchecked)
    as :func:`_table` gives them, written for numba with the spline as frozen module arrays
    (:func:`_per_call`)."""
    i, dx = _interval(_SPLINE_BREAKS, math.log(a_over_b))
    p = _SPLINE_PIECES[i]
    return (_piece_value(p[0], dx, nu), _piece_value(p[1], dx, nu), _piece_value(p[2], dx, nu),
            _piece_value(p[3], dx, nu))


def _asymptote_thin_a(g: float, nu: float) -> list[float]:
    """Kalker's asymptotes for a/b = g -> 0 (contact narrow in the rolling direction)."""
    return [math.pi ** 2 / (4.0 * (1.0 - nu)),
            math.pi ** 2 / 4.0,
            math.pi * math.sqrt(g) / (3.0 * (1.0 - nu)) * (1.0 + nu * (math.log(16.0 / g) - 5.0)),
            math.pi ** 2 / (16.0 * (1.0 - nu) * g)]


def _asymptote_thin_b(g: float, nu: float) -> list[float]:
    """Kalker's asymptotes for b/a = g -> 0 (C11, C22, C23; none published for C33)."""
    lam = math.log(16.0 / g ** 2)
    c11 = 2.0 * math.pi / ((lam - 2.0 * nu) * g) * (1.0 + (3.0 - math.log(4.0)) / (lam - 2.0 * nu))
    d = (1.0 - nu) * lam + 2.0 * nu
    c22 = 2.0 * math.pi / g * (1.0 + (1.0 - nu) * (3.0 - math.log(4.0)) / d) / d
    c23 = 2.0 * math.pi / (3.0 * g ** 1.5 * ((1.0 - nu) * lam - 2.0 + 4.0 * nu))
    return [c11, c22, c23, float("nan")]


def _blend(asym_g: list[float], asym_edge: list[float], table_edge: list[float],
           g: float) -> list[float]:
    w = g / _TABLE_EDGE  # 1 at the table's edge, 0 in the limit
    return [ag * (1.0 + (te / ae - 1.0) * w) for ag, ae, te in zip(asym_g, asym_edge, table_edge)]


def _coefficients(a_over_b: float, nu: float) -> tuple[float, float, float, float]:
    x = math.log(a_over_b)
    if _LOG_LO <= x <= _LOG_HI:
        c = _table(a_over_b, nu)
    elif x < _LOG_LO:
        c = _blend(_asymptote_thin_a(a_over_b, nu), _asymptote_thin_a(_TABLE_EDGE, nu),
                   _table(_RATIOS[0], nu), a_over_b)
    else:
        edge = _table(_RATIOS[-1], nu)
        c = _blend(_asymptote_thin_b(1.0 / a_over_b, nu), _asymptote_thin_b(_TABLE_EDGE, nu),
                   edge, 1.0 / a_over_b)
        c[3] = edge[3]
        notices.warn(f"C33 for a/b > {_RATIOS[-1]:g} is held at its tabulated value at "
                     f"a/b = {_RATIOS[-1]:g} (Kalker gives no asymptote for it)",
                     CoefficientExtrapolationWarning, stacklevel=3)
    return (c[0], c[1], c[2], c[3])


@cached(4096)  # errors are raised, not cached
def creep_coefficients(a_over_b: float, nu: float) -> tuple[float, float, float, float]:
    """Kalker's coefficients ``(C11, C22, C23, C33)`` for semi-axis ratio a/b and Poisson's ratio ν.

    ``a`` is the semi-axis along the rolling direction. Raises ``ValueError`` outside
    ``A_OVER_B_RANGE`` or for ν outside [0, 0.5].
    """
    lo, hi = A_OVER_B_RANGE
    if not (math.isfinite(a_over_b) and lo <= a_over_b <= hi):
        raise ValueError(f"a_over_b={a_over_b!r} is out of range: allowed {lo} <= a/b <= {hi}")
    if not (0.0 <= nu <= 0.5):
        raise ValueError(f"nu={nu!r} is out of range: allowed 0 <= nu <= 0.5")
    return _coefficients(float(a_over_b), float(nu))


_TABLE_AB_LO, _TABLE_AB_HI = float(_RATIOS[0]), float(_RATIOS[-1])
#: a/b of the table's first and last rows: :func:`table_coefficients` applies between them.
TABLE_A_OVER_B = (_TABLE_AB_LO, _TABLE_AB_HI)


def _per_call(a_over_b: float, nu: float) -> tuple[float, float, float, float]:
    """:func:`creep_coefficients` uncached: inside the table :func:`table_coefficients`, outside
    it (Kalker's asymptotes, and the warning for C33) the cached Python function, called from
    the compiled code (numba's object mode: rare, and a Python call anyway)."""
    if _TABLE_AB_LO <= a_over_b <= _TABLE_AB_HI:
        return table_coefficients(a_over_b, nu)
    with objmode(c11="float64", c22="float64", c23="float64", c33="float64"):
        c11, c22, c23, c33 = creep_coefficients(a_over_b, nu)
    return c11, c22, c23, c33


_PER_CALL = None


def per_call_coefficients(varying: bool) -> Callable[[float, float],
                                                     tuple[float, float, float, float]]:
    """The function a method gets its coefficients from: :func:`creep_coefficients` (cached per
    (a/b, ν)) for a contact whose a/b repeats, and with ``varying`` (the effect
    ``varying_geometry``: a new a/b at every call, where a cache only misses) :func:`_per_call`
    compiled (the same values; numba compiles it, or loads it from its cache, on first use,
    which fixed-geometry processes are spared). Inputs as the methods check them (a/b in
    ``A_OVER_B_RANGE``, 0 <= ν < 0.5)."""
    global _PER_CALL
    if not varying:
        return creep_coefficients
    if _PER_CALL is None:
        samples = [(r, nu) for r in (0.1, 0.37, 1.0, 4.2, 10.0) for nu in (0.0, 0.28, 0.5)]
        # object mode holds the GIL in its branch: compiled without nogil (which would warn)
        _PER_CALL = compiled_with_data(_per_call, samples, nogil=False)
    return _PER_CALL


def creep_coefficient_slopes(a_over_b: float, nu: float) -> tuple[float, float, float, float]:
    """The slopes d ln C/d ln(a/b) of Kalker's ``(C11, C22, C23, C33)`` at a/b and ν (the
    analytic Jacobians' dependence on the semi-axes): inside the table the derivative of its
    spline (the polynomial pieces of :func:`_table`, differentiated); outside it a central
    difference in ln(a/b) of step 1e-6 of :func:`creep_coefficients` (Kalker's closed-form
    asymptotes blended onto the table: smooth, so the difference is within about 1e-9 of the
    slope; one-sided at the ends of ``A_OVER_B_RANGE``; zero for C33 held beyond a/b = 10).
    Inputs as :func:`creep_coefficients`."""
    creep_coefficients(a_over_b, nu)           # its checks (and warning)
    x = math.log(a_over_b)
    if _LOG_LO <= x <= _LOG_HI:
        i = min(max(bisect_right(_BREAKS, x) - 1, 0), len(_BREAKS) - 1)
        dx = x - _BREAKS[i]
        return tuple((3.0 * (p3[0] + nu * (p3[1] + nu * p3[2])) * dx
                      + 2.0 * (p2[0] + nu * (p2[1] + nu * p2[2]))) * dx
                     + p1[0] + nu * (p1[1] + nu * p1[2])
                     for p3, p2, p1, _ in _PIECE_LIST[i])
    h = 1e-6
    lo, hi = math.log(A_OVER_B_RANGE[0]), math.log(A_OVER_B_RANGE[1])
    left, right = max(x - h, lo), min(x + h, hi)
    up = creep_coefficients(math.exp(right), nu)
    down = creep_coefficients(math.exp(left), nu)
    return tuple((math.log(u) - math.log(d)) / (right - left) for u, d in zip(up, down))
