"""The normal contact problem on the grid: pressure >= 0, prescribed total force.

Two quasi-identical half-spaces; undeformed gap h = A x² + B y² of the Hertz geometry that gives
the ellipse (a, b) under the load N (Johnson, *Contact Mechanics*, 1985, eqs 4.38-4.40 in
Carlson's form, as in :mod:`contact_core.hertz`). Discrete problem (Kalker 1990, sec. 5.2):

    h_i + u_i - δ >= 0,   p_i >= 0,   p_i (h_i + u_i - δ) = 0,   Σ p_i dx dy = N,
    u_i = (1-ν) dx/(πG) Σ_j I_R(i - j) p_j                   (see :mod:`.influence`).

Solved with the constrained conjugate-gradient method of Polonsky & Keer (1999), *A numerical
method for solving rough contact problems based on the multi-level multi-summation and conjugate
gradient techniques*, Wear 231, 206-219 (the method CONTACT's NormCG builds on; Vollebregt 2014,
J. Comput. Phys. 257, 333-351), with FFT matrix-vector products (zero-padded linear convolution).

The problem is exactly scale-invariant: with x = a x̂, y = b ŷ, p = p0 p̂ (p0 = 3N/(2πab)) the
equations for p̂ depend only on the grid (mx, my, scale) and a/b (E* = G/(1-ν) cancels), so the
normalised solution is cached per (mx, my, scale, a/b, tol).
"""
from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np
import scipy.fft as sfft
from scipy.special import elliprd, elliprf

from .influence import normal_kernel_fft


def hertz_curvatures(a: float, b: float) -> tuple[float, float]:
    """Relative curvatures (A, B) times E*/p0 (units 1/m · m... i.e. 1/length) of the ellipse (a, b).

    With α >= β the semi-axes, g = β/α, Johnson eqs 4.39 in Carlson form (DLMF 19.25.1):
    A'(along α) = p0 β/(E* α²) R_D/3,  B'(along β) = p0/(E* β) (R_F - R_D/3),
    R_F = R_F(0, g², 1), R_D = R_D(0, g², 1). Returned divided by p0/E*.
    """
    alpha, beta = max(a, b), min(a, b)
    g2 = (beta / alpha) ** 2
    rf = float(elliprf(0.0, g2, 1.0))
    rd = float(elliprd(0.0, g2, 1.0))
    c_major = beta / alpha ** 2 * rd / 3.0
    c_minor = (rf - rd / 3.0) / beta
    return (c_major, c_minor) if a >= b else (c_minor, c_major)


def _solve_pk(mx: int, my: int, dx: float, dy: float, h: np.ndarray, total: float,
              tol: float, maxit: int, p_start: np.ndarray) -> tuple[np.ndarray, int, float]:
    """Polonsky–Keer CG for  Σ_j I_R(i-j) p_j + h_i = δ on {p > 0}, >= δ elsewhere, Σ p = total.

    Lengths in units of dx (h too); returns (p, iterations, final relative change).
    """
    kf = normal_kernel_fft(mx, my, dy / dx)
    shape2 = (2 * my, 2 * mx)

    def conv(v: np.ndarray) -> np.ndarray:
        return sfft.irfft2(kf * sfft.rfft2(v, s=shape2, workers=1), s=shape2,
                           workers=1)[:my, :mx]

    p = p_start * (total / p_start.sum())     # start: Hertz's pressure at the centres
    t = np.zeros_like(p)
    g_old = 1.0
    delta = 0.0
    err = math.inf
    it = 0
    for it in range(1, maxit + 1):
        gap = conv(p) + h
        act = p > 0.0
        gap -= gap[act].mean()
        G = float(np.dot(gap[act], gap[act]))
        t = np.where(act, gap + (delta * G / g_old) * t, 0.0)
        g_old = G
        r = conv(t)
        r -= r[act].mean()
        denom = float(np.dot(r[act], t[act]))
        tau = float(np.dot(gap[act], t[act])) / denom if denom > 0.0 else 0.0
        p_old = p
        p = np.where(act, p - tau * t, 0.0)
        p = np.maximum(p, 0.0)
        overlap = (p == 0.0) & (gap < 0.0)
        if overlap.any():
            p = p - np.where(overlap, tau * gap, 0.0)
            delta = 0.0
        else:
            delta = 1.0
        p *= total / p.sum()
        err = float(np.abs(p - p_old).sum()) / total
        if err < tol:
            break
    return p, it, err


_CACHE: OrderedDict = OrderedDict()
_CACHE_SIZE = 64


def normalised_pressure(mx: int, my: int, scale: float, a_over_b: float, kind: str,
                        tol: float = 1e-12, maxit: int = 500) -> tuple[np.ndarray, int, float]:
    """p/p0 (p0 = 3N/(2πab)) at the element centres, shape (my, mx); total Σ p̂ dx̂ dŷ = 2π/3.

    ``kind="numerical"``: Polonsky–Keer solution of the discrete problem; ``"hertz"``: Hertz's
    √(1 - x²/a² - y²/b²) at the centres, rescaled so that the discrete total force is exact.
    Also returns (iterations, final change) of the normal solver. Cached; read-only arrays.
    """
    key = (mx, my, scale, a_over_b, kind, tol)
    hit = _CACHE.get(key)
    if hit is not None:
        _CACHE.move_to_end(key)
        return hit
    # dimensionless coordinates: x̂ = x/a, ŷ = y/b;  dx̂ = 2 scale/mx etc.
    dxh, dyh = 2.0 * scale / mx, 2.0 * scale / my
    xh = -scale + (np.arange(mx) + 0.5) * dxh
    yh = -scale + (np.arange(my) + 0.5) * dyh
    total = 2.0 * math.pi / 3.0 / (dxh * dyh)   # Σ p̂ over elements
    r2 = xh[None, :] ** 2 + yh[:, None] ** 2
    p_hertz = np.sqrt(np.maximum(1.0 - r2, 0.0))
    if kind == "hertz":
        p = p_hertz * (total / p_hertz.sum())
        it, err = 0, 0.0
    else:
        # Physical lengths with b = 1: a = a_over_b. Gap h = A x² + B y² with A, B from Hertz;
        # h in units of p0/E*·length; u = (1-ν) dx/(πG) I_R p = dx/(π E*) I_R p.  Dividing the
        # equation by dx/(π E*) p0: I_R p̂ + π h/(p0 dx/E*) = δ'.
        a, b = a_over_b, 1.0
        ca, cb = hertz_curvatures(a, b)
        dx = dxh * a
        X = xh * a
        Y = yh * b
        h = (ca * X[None, :] ** 2 + cb * Y[:, None] ** 2) * math.pi / dx
        p, it, err = _solve_pk(mx, my, dx, dyh * b, h, total, tol, maxit, p_hertz)
        # The exact solution is symmetric in x and y: remove rounding-level asymmetry (so that
        # the contact set and the tangential solution are exactly mirror-symmetric).
        p = 0.25 * (p + p[::-1] + p[:, ::-1] + p[::-1, ::-1])
        p[p < 1e-12 * p.max()] = 0.0
        p *= total / p.sum()
    p.setflags(write=False)
    out = (p, it, err)
    _CACHE[key] = out
    if len(_CACHE) > _CACHE_SIZE:
        _CACHE.popitem(last=False)
    return out


def clear_cache() -> None:
    """Forget the cached normal solutions (benchmarks of fully cold solves)."""
    _CACHE.clear()
