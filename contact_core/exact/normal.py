"""The normal contact problem on the grid: pressure >= 0, prescribed total force.

Two quasi-identical half-spaces; undeformed gap h = A x² + B y² of the Hertz geometry that gives
the ellipse (a, b) under the load N (Johnson, *Contact Mechanics*, 1985, eqs 4.38-4.40 in
Carlson's form, as in :mod:`contact_core.hertz`). Discrete problem (Kalker 1990, sec. 5.2):

    h_i + u_i - δ >= 0,   p_i >= 0,   p_i (h_i + u_i - δ) = 0,   Σ p_i dx dy = N,
    u_i = (1-ν) dx/(πG) Σ_j I_R(i - j) p_j                   (see :mod:`.influence`).

Solved with the constrained conjugate-gradient method of Polonsky & Keer (1999), *A numerical
method for solving rough contact problems based on the multi-level multi-summation and conjugate
gradient techniques*, Wear 231, 206-219 (the method CONTACT's NormCG builds on; Vollebregt 2014,
J. Comput. Phys. 257, 333-351). Matrix-vector products: for grids whose quarter has at most
``DENSE_MAX`` elements, a dense product with the operator folded onto the quarter grid (the
problem and its unique solution are symmetric in x and y), the whole iteration compiled with
numba (an order of magnitude faster than the Python loop with FFTs on those grids:
docs/notes/exact_solver.md); for larger grids zero-padded FFTs (linear convolution) as before.

The problem is exactly scale-invariant: with x = a x̂, y = b ŷ, p = p0 p̂ (p0 = 3N/(2πab)) the
equations for p̂ depend only on the grid (mx, my, scale) and a/b (E* = G/(1-ν) cancels), so the
normalised solution is cached per (mx, my, scale, a/b, tol).
"""
from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft
from numba import njit

from ..cache import cached
from ..hertz import ellipse_curvatures
from .influence import element_integrals, normal_kernel_fft


def _solve_pk_fft(mx: int, my: int, dx: float, dy: float, h: np.ndarray, total: float,
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
        if not p.sum() > 0.0:       # the step emptied the contact (tiny grids): keep the last
            p = p_old
            break
        p *= total / p.sum()
        err = float(np.abs(p - p_old).sum()) / total
        if err < tol:
            break
    return p, it, err


# ------------------------------------------------------------------ folded (quarter) operator
#
# The Hertzian normal problem is symmetric under x -> -x and y -> -y, and so is its (unique)
# solution. Restricted to symmetric pressures, the operator u = I_R * p acts on the quarter
# grid ix < ceil(mx/2), iy < ceil(my/2) through the folded matrix
#     A[i, k] = sum over the distinct mirror images k* of k of I_R(i - k*),
# (symmetric, since I_R is even in both offsets) and every full-grid sum becomes a weighted
# quarter sum with weight = number of distinct images (1, 2 or 4). Polonsky-Keer's iteration on
# the quarter with these weights is the full-grid iteration (up to rounding), at 1/16 of the
# cost of a dense full-grid product. Used when the quarter has at most DENSE_MAX elements
# (the dense product beats the zero-padded FFTs there); the FFT path is kept for larger grids.

DENSE_MAX = 1200


@njit(cache=True)
def _folded_matrix(ir, mx, my):
    hx = (mx + 1) // 2
    hy = (my + 1) // 2
    n = hx * hy
    A = np.empty((n, n))
    w = np.empty(n)
    for l in range(hy):
        for k in range(hx):
            c = l * hx + k
            nx = 1 if 2 * k == mx - 1 else 2
            ny = 1 if 2 * l == my - 1 else 2
            w[c] = nx * ny
    for j in range(hy):
        for i in range(hx):
            r = j * hx + i
            for l in range(hy):
                lm = my - 1 - l
                for k in range(hx):
                    km = mx - 1 - k
                    # flipped layout: entry [diy + my - 1, mx - dix]
                    s = ir[j - l + my - 1, mx - (i - k)]
                    if km != k:
                        s += ir[j - l + my - 1, mx - (i - km)]
                    if lm != l:
                        s += ir[j - lm + my - 1, mx - (i - k)]
                        if km != k:
                            s += ir[j - lm + my - 1, mx - (i - km)]
                    A[r, l * hx + k] = s
    return A, w


@njit(cache=True, fastmath=True)
def _matvec_cols(At, v, idx, nidx, out):
    """out = A[:, idx] v[idx], with At = A^T stored row-contiguous (columns of A)."""
    n = At.shape[0]
    for r in range(n):
        out[r] = 0.0
    for m in range(nidx):
        c = idx[m]
        vc = v[c]
        row = At[c]
        for r in range(n):
            out[r] += vc * row[r]


@njit(cache=True, fastmath=True)
def _solve_pk_dense(At, w, h, total, tol, maxit, p):
    """Polonsky-Keer CG on the folded quarter problem (weights w); p: start, changed in place.

    ``At``: the transposed folded matrix (W A is symmetric, A itself only for even mx, my).

    Same iteration as :func:`_solve_pk_fft` (Polonsky & Keer 1999, Wear 231, algorithm of
    sec. 3) with weighted inner products. Returns (iterations, final relative change).
    """
    n = p.shape[0]
    s = 0.0
    for c in range(n):
        s += w[c] * p[c]
    for c in range(n):
        p[c] *= total / s
    t = np.zeros(n)
    gap = np.empty(n)
    r = np.empty(n)
    idx = np.empty(n, np.int64)
    p_old = np.empty(n)
    g_old = 1.0
    delta = 0.0
    err = np.inf
    it = 0
    for it in range(1, maxit + 1):
        na = 0
        for c in range(n):
            if p[c] > 0.0:
                idx[na] = c
                na += 1
        _matvec_cols(At, p, idx, na, gap)
        sg = 0.0
        sw = 0.0
        for m in range(na):
            c = idx[m]
            gap[c] += h[c]
            sg += w[c] * gap[c]
            sw += w[c]
        mean = sg / sw
        for c in range(n):
            if p[c] <= 0.0:
                gap[c] += h[c]
            gap[c] -= mean
        G = 0.0
        for m in range(na):
            c = idx[m]
            G += w[c] * gap[c] * gap[c]
        beta = delta * G / g_old
        for c in range(n):
            t[c] = gap[c] + beta * t[c] if p[c] > 0.0 else 0.0
        g_old = G
        _matvec_cols(At, t, idx, na, r)
        sr = 0.0
        for m in range(na):
            c = idx[m]
            sr += w[c] * r[c]
        mr = sr / sw
        denom = 0.0
        num = 0.0
        for m in range(na):
            c = idx[m]
            denom += w[c] * (r[c] - mr) * t[c]
            num += w[c] * gap[c] * t[c]
        tau = num / denom if denom > 0.0 else 0.0
        overlap = False
        for c in range(n):
            p_old[c] = p[c]
            if p[c] > 0.0:
                v = p[c] - tau * t[c]
                p[c] = v if v > 0.0 else 0.0
            if p[c] == 0.0 and gap[c] < 0.0:
                overlap = True
        if overlap:
            for c in range(n):
                if p[c] == 0.0 and gap[c] < 0.0:
                    p[c] = -tau * gap[c]
            delta = 0.0
        else:
            delta = 1.0
        s = 0.0
        for c in range(n):
            s += w[c] * p[c]
        if not s > 0.0:             # the step emptied the contact (tiny grids): keep the last
            for c in range(n):
                p[c] = p_old[c]
            break
        f = total / s
        e = 0.0
        for c in range(n):
            p[c] *= f
            e += w[c] * abs(p[c] - p_old[c])
        err = e / total
        if err < tol:
            break
    return it, err


@cached(16)
def folded_operator(mx: int, my: int, ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """(A^T, w) of the folded quarter problem (see above); cached per grid and dy/dx."""
    ir = element_integrals(mx, my, ratio)[0]
    A, w = _folded_matrix(np.ascontiguousarray(ir), mx, my)
    At = np.ascontiguousarray(A.T)
    At.setflags(write=False)
    w.setflags(write=False)
    return At, w


def _solve_pk(mx: int, my: int, dx: float, dy: float, h: np.ndarray, total: float,
              tol: float, maxit: int, p_start: np.ndarray,
              dense_max: int) -> tuple[np.ndarray, int, float]:
    """Dispatch: folded dense quarter iteration for small grids, else the FFT iteration."""
    hx, hy = (mx + 1) // 2, (my + 1) // 2
    if hx * hy > dense_max:
        return _solve_pk_fft(mx, my, dx, dy, h, total, tol, maxit, p_start)
    At, w = folded_operator(mx, my, dy / dx)
    p = np.ascontiguousarray(p_start[:hy, :hx]).ravel().copy()
    hq = np.ascontiguousarray(h[:hy, :hx]).ravel()
    it, err = _solve_pk_dense(At, w, hq, total, tol, maxit, p)
    pq = p.reshape(hy, hx)
    full = np.empty((my, mx))
    full[:hy, :hx] = pq
    full[:hy, mx - hx:] = pq[:, ::-1]
    full[my - hy:, :] = full[:hy, :][::-1]
    return full, it, err


@cached(64)
def normalised_pressure(mx: int, my: int, scale: float, a_over_b: float, kind: str,
                        tol: float = 1e-12, maxit: int = 500,
                        dense_max: int = DENSE_MAX) -> tuple[np.ndarray, int, float]:
    """p/p0 (p0 = 3N/(2πab)) at the element centres, shape (my, mx); total Σ p̂ dx̂ dŷ = 2π/3.

    ``kind="numerical"``: Polonsky–Keer solution of the discrete problem; ``"hertz"``: Hertz's
    √(1 - x²/a² - y²/b²) at the centres, rescaled so that the discrete total force is exact.
    Also returns (iterations, final change) of the normal solver. ``dense_max``: the largest
    quarter grid solved with the dense folded operator (else FFT). Cached; read-only arrays.
    """
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
        ca, cb = ellipse_curvatures(a, b)
        dx = dxh * a
        X = xh * a
        Y = yh * b
        h = (ca * X[None, :] ** 2 + cb * Y[:, None] ** 2) * math.pi / dx
        p, it, err = _solve_pk(mx, my, dx, dyh * b, h, total, tol, maxit, p_hertz,
                               dense_max)
        # The exact solution is symmetric in x and y: remove rounding-level asymmetry (so that
        # the contact set and the tangential solution are exactly mirror-symmetric).
        p = 0.25 * (p + p[::-1] + p[:, ::-1] + p[::-1, ::-1])
        p[p < 1e-12 * p.max()] = 0.0
        p *= total / p.sum()
    p.setflags(write=False)
    return p, it, err
