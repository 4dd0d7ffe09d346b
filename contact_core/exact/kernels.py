"""Kernel tables of the tangential problem and the slip sums over them (numba).

The influence of the traction differences q on the slip (:mod:`.sweeps`, Kalker 1990 ch. 5):
``w_i = s_i + 1/(πG) Σ_j K(i - j) q_j`` with the rectangle-integrated Boussinesq–Cerruti
kernels of :mod:`.influence`. Here: the tables as the sweeps use them (divided by π,
contiguous; cached per grid, dy/dx and ν), folded onto the half grid for y-mirror-symmetric
problems, and the row-contiguous dot products that evaluate the sums.
All quantities are dimensionless: tractions in units of G, lengths of the kernel in units of dx.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..cache import cached
from .influence import tangential_tables

#: Folded kernel tables larger than this are not built (the full grid is solved instead).
FOLD_MAX_BYTES = 64 * 2 ** 20


@cached(16)
def kernel_tables(mx: int, my: int, ratio: float, nu: float) -> tuple[np.ndarray, ...]:
    """``(Kxx, Kxy, Kyy)/π`` of an ``mx × my`` grid with ``ratio`` = dy/dx (flipped layout of
    :func:`.influence.tangential_tables`), contiguous."""
    return tuple(np.ascontiguousarray(t / math.pi) for t in tangential_tables(mx, my, ratio, nu))


@cached(16)
def folded_kernel_tables(mx: int, my: int, ratio: float,
                         nu: float) -> tuple[np.ndarray, ...] | None:
    """:func:`folded_tables` of :func:`kernel_tables` (None when larger than FOLD_MAX_BYTES)."""
    npair = (my + 1) // 2
    if 4 * npair * npair * 2 * mx * 8 > FOLD_MAX_BYTES:
        return None
    return folded_tables(*kernel_tables(mx, my, ratio, nu), mx, my)


def traction_differences(px: np.ndarray, py: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Traction differences q (rows × (mx+1)), column c = jx + 1: q_j = p_j - p_{j+(1,0)}."""
    my, mx = px.shape
    qx = np.zeros((my, mx + 1))
    qy = np.zeros((my, mx + 1))
    qx[:, 1:] = px
    qx[:, :mx] -= px
    qy[:, 1:] = py
    qy[:, :mx] -= py
    return qx, qy


@njit(cache=True, fastmath=True, boundscheck=False, inline="always")
def _row_dot(axx, axy, ayx, ayy, bx, by):
    """(Σ axx·bx + axy·by, Σ ayx·bx + ayy·by) over one row of sources: the 2×2 kernel block
    times the traction differences. Four separate accumulators so that LLVM vectorises the
    loop (several times faster than one 2×2-block accumulation: docs/notes/exact_solver.md)."""
    s1 = 0.0
    s2 = 0.0
    s3 = 0.0
    s4 = 0.0
    for c in range(bx.size):
        s1 += axx[c] * bx[c]
        s2 += axy[c] * by[c]
        s3 += ayx[c] * bx[c]
        s4 += ayy[c] * by[c]
    return s1 + s2, s3 + s4


@njit(cache=True, fastmath=True, boundscheck=False)
def _slip_at(ix, iy, mx, my, qx, qy, kxx, kxy, kyy, c_lo, c_hi, r_lo, r_hi):
    """Σ_j K(i - j) q_j (2-vector) at element (ix, iy); K already divided by π (rows of
    sources through :func:`_row_dot`)."""
    wx = 0.0
    wy = 0.0
    off = mx - 1 - ix
    for jy in range(r_lo, r_hi + 1):
        lo = c_lo[jy]
        hi = c_hi[jy] + 1
        if lo >= hi:
            continue
        ky = iy - jy + my - 1
        dx, dy = _row_dot(kxx[ky, off + lo:off + hi], kxy[ky, off + lo:off + hi],
                          kxy[ky, off + lo:off + hi], kyy[ky, off + lo:off + hi],
                          qx[jy, lo:hi], qy[jy, lo:hi])
        wx += dx
        wy += dy
    return wx, wy


@njit(cache=True, fastmath=True, boundscheck=False)
def _slip_pair(ix, iy, iym, mx, my, qx, qy, kxx, kxy, kyy, c_lo, c_hi, r_lo, r_hi):
    """:func:`_slip_at` at the mirror pair (ix, iy), (ix, iym = my-1-iy) in one pass.

    The kernel row of offset d = iy - jy serves both: element (ix, iym) sees row jym = my-1-jy
    through the offset iym - jym = -d, and Kxx, Kyy are even, Kxy odd in the y offset. So each
    kernel entry is loaded once for two elements (same sums as two calls of
    :func:`_slip_at`, in another order).
    """
    w1x = 0.0
    w1y = 0.0
    w2x = 0.0
    w2y = 0.0
    off = mx - 1 - ix
    for jy in range(r_lo, r_hi + 1):
        jym = my - 1 - jy
        lo = min(c_lo[jy], c_lo[jym])
        hi = max(c_hi[jy], c_hi[jym]) + 1
        if lo >= hi:
            continue
        ky = iy - jy + my - 1
        a1 = kxx[ky, off + lo:off + hi]
        a2 = kxy[ky, off + lo:off + hi]
        a3 = kyy[ky, off + lo:off + hi]
        b1 = qx[jy, lo:hi]
        b2 = qy[jy, lo:hi]
        d1 = qx[jym, lo:hi]
        d2 = qy[jym, lo:hi]
        s1 = 0.0
        s2 = 0.0
        s3 = 0.0
        s4 = 0.0
        t1 = 0.0
        t2 = 0.0
        t3 = 0.0
        t4 = 0.0
        for c in range(hi - lo):
            k1 = a1[c]
            k2 = a2[c]
            k3 = a3[c]
            s1 += k1 * b1[c]
            s2 += k2 * b2[c]
            s3 += k2 * b1[c]
            s4 += k3 * b2[c]
            t1 += k1 * d1[c]
            t2 += k2 * d2[c]
            t3 += k2 * d1[c]
            t4 += k3 * d2[c]
        w1x += s1 + s2
        w1y += s3 + s4
        w2x += t1 - t2
        w2y += t4 - t3
    return w1x, w1y, w2x, w2y


@njit(cache=True, fastmath=True, boundscheck=False)
def _slip_half(ix, h, mx, qx, qy, fxx, fxy1, fxy2, fyy, c_lo, c_hi, r_lo, r_hi):
    """Σ_j K(i - j) q_j at element (ix, h) of the half grid, for y-mirror-symmetric q.

    ``fxx .. fyy[h, hj]`` are the folded kernel rows (:func:`folded_tables`): the source row hj
    and its mirror (qx even, qy odd in y) in one table entry, so each element costs half the
    multiply-adds of :func:`_slip_at` on the full grid.
    """
    wx = 0.0
    wy = 0.0
    off = mx - 1 - ix
    for hj in range(r_lo, r_hi + 1):
        lo = c_lo[hj]
        hi = c_hi[hj] + 1
        if lo >= hi:
            continue
        dx, dy = _row_dot(fxx[h, hj, off + lo:off + hi], fxy1[h, hj, off + lo:off + hi],
                          fxy2[h, hj, off + lo:off + hi], fyy[h, hj, off + lo:off + hi],
                          qx[hj, lo:hi], qy[hj, lo:hi])
        wx += dx
        wy += dy
    return wx, wy


def folded_tables(kxx: np.ndarray, kxy: np.ndarray, kyy: np.ndarray, mx: int,
                  my: int) -> tuple[np.ndarray, ...]:
    """Kernel tables folded onto the half grid for tractions X even, Y odd in y.

    Half row h is the full row iy = my - npair + h (npair = ceil(my/2), y >= 0); its mirror
    is my-1-iy. A symmetric traction difference (qx, qy) in half row hj acts on half row h
    through offsets d = iy - jy and d' = iy - jym (jym the mirror of jy; not added when jy is
    its own mirror, the centre row of an odd ``my``):

        wx = Σ (Kxx(d) + Kxx(d')) qx + (Kxy(d) - Kxy(d')) qy,
        wy = Σ (Kxy(d) + Kxy(d')) qx + (Kyy(d) - Kyy(d')) qy.

    Returns ``(Fxx, Fxy1, Fxy2, Fyy)``, each (npair, npair, 2 mx), in the flipped x layout of
    :mod:`.influence`.
    """
    npair = (my + 1) // 2
    h = np.arange(npair)
    iy = my - npair + h
    jy = my - npair + h
    jym = my - 1 - jy
    i1 = iy[:, None] - jy[None, :] + my - 1
    i2 = iy[:, None] - jym[None, :] + my - 1
    m = (jym != jy).astype(float)[None, :, None]
    out = tuple(np.ascontiguousarray(t) for t in
                (kxx[i1] + m * kxx[i2], kxy[i1] - m * kxy[i2], kxy[i1] + m * kxy[i2],
                 kyy[i1] - m * kyy[i2]))
    if my % 2 == 1:
        # centre row: wy = 0 by symmetry (exactly, not only to the rounding of the tables)
        out[2][0] = 0.0
        out[3][0] = 0.0
    return out
