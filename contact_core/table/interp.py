"""The table lookup: one numba kernel from the creepages to the normalised forces.

Interpolation is local and piecewise cubic: on each uniform axis the four nearest nodes with
Lagrange's weights (one-sided at the ends), tensor product over ln(a/b), θ, ψ and s, linear in ν
(two nodes). scipy's ``RegularGridInterpolator`` on the same table costs 0.1-0.8 ms per point
(measured on this table: cubic 96 µs, linear 770 µs, a loaded 2-core machine), far over the
method's per-call budget; this kernel costs a few µs (``python -m contact_core.table check``).
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np


def _weights(x: float, lo: float, h: float, n: int, w: np.ndarray) -> int:
    """First node and the interpolation weights (in ``w``, 4 slots) at x on a uniform axis of
    ``n`` nodes from ``lo`` with step ``h``: cubic Lagrange on 4 nodes, linear for n < 4."""
    t = (x - lo) / h
    if n < 4:
        i0 = min(max(int(math.floor(t)), 0), n - 2)
        p = t - i0
        w[0] = 1.0 - p
        w[1] = p
        w[2] = 0.0
        w[3] = 0.0
        return i0
    i0 = min(max(int(math.floor(t)) - 1, 0), n - 4)
    p = t - i0
    w[0] = -(p - 1.0) * (p - 2.0) * (p - 3.0) / 6.0
    w[1] = p * (p - 2.0) * (p - 3.0) / 2.0
    w[2] = -p * (p - 1.0) * (p - 3.0) / 2.0
    w[3] = p * (p - 1.0) * (p - 2.0) / 6.0
    return i0


def _lookup(values: np.ndarray, axes: np.ndarray, u0: float, u1: float, u2: float,
            log_ab: float, nu: float) -> tuple[float, float, float, float]:
    """(Fx/(μN), Fy/(μN), Mz/(μN c), slip fraction) at the table coordinates (u0, u1, u2)
    (module :mod:`.grid`), with the symmetries restoring the signs and |F| <= μN (Coulomb's
    bound, which interpolation between nodes may cross). ``values``: on the nodes (g0, g1, g2,
    slip fraction), shape (n_ab, n_nu, n_θ, n_ψ, n_s, 4), C-contiguous; ``axes`` (2, 5): the
    start and the step of the five axes. Nothing is written outside the call (thread-safe)."""
    lo = axes[0]
    h = axes[1]
    sx = 1.0
    if u0 < 0.0:
        u0 = -u0
        sx = -1.0
    sy = 1.0
    if u1 < 0.0:
        u1 = -u1
        u2 = -u2
        sy = -1.0
    r = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    if r == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    s = r / (1.0 + r)
    theta = math.acos(min(1.0, max(-1.0, u2 / r)))
    psi = math.atan2(u1, u0)
    shape = values.shape
    w = np.empty((5, 4))
    ia = _weights(log_ab, lo[0], h[0], shape[0], w[0])
    inu = _weights(nu, lo[1], h[1], shape[1], w[1])
    it = _weights(theta, lo[2], h[2], shape[2], w[2])
    ip = _weights(psi, lo[3], h[3], shape[3], w[3])
    js = _weights(s, lo[4], h[4], shape[4], w[4])
    na = 4 if shape[0] >= 4 else 2
    nn = 4 if shape[1] >= 4 else 2
    nt = 4 if shape[2] >= 4 else 2
    npp = 4 if shape[3] >= 4 else 2
    ns = 4 if shape[4] >= 4 else 2
    flat = values.reshape(-1)            # a view (C-contiguous): plain offsets, no sub-arrays
    st_s = 4
    st_p = shape[4] * st_s
    st_t = shape[3] * st_p
    st_n = shape[2] * st_t
    st_a = shape[1] * st_n
    g0 = 0.0
    g1 = 0.0
    g2 = 0.0
    g3 = 0.0
    for a in range(na):
        for b in range(nn):
            wab = w[0, a] * w[1, b]
            oab = (ia + a) * st_a + (inu + b) * st_n
            for t in range(nt):
                wabt = wab * w[2, t]
                oabt = oab + (it + t) * st_t
                for p in range(npp):
                    wabtp = wabt * w[3, p]
                    o = oabt + (ip + p) * st_p + js * st_s
                    for k in range(ns):
                        wk = wabtp * w[4, k]
                        g0 += wk * flat[o]
                        g1 += wk * flat[o + 1]
                        g2 += wk * flat[o + 2]
                        g3 += wk * flat[o + 3]
                        o += st_s
    fx = sx * s * g0
    fy = sy * s * g1
    f = math.sqrt(fx * fx + fy * fy)
    if f > 1.0:
        fx /= f
        fy /= f
    return fx, fy, sy * s * g2, min(1.0, max(0.0, g3))


_KERNEL: Callable | None = None


def kernel() -> Callable:
    """The numba-compiled :func:`_lookup` (numba imported on first use; cached on disk)."""
    global _KERNEL, _weights
    if _KERNEL is None:
        import numba
        _weights = numba.njit(cache=True, nogil=True, error_model="numpy")(_weights)
        _KERNEL = numba.njit(cache=True, nogil=True, error_model="numpy")(_lookup)
    return _KERNEL
