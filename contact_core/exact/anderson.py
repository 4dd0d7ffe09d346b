"""Anderson acceleration of the Gauss–Seidel sweeps of :mod:`.sweeps` (numba).

Anderson mixing of the sweep map G (D. G. Anderson, J. ACM 12 (1965) 547-560; in the form of
H. F. Walker & P. Ni, *Anderson acceleration for fixed-point iterations*, SIAM J. Numer. Anal. 49
(2011) 1715-1735): the next sweep starts from x = G(x_k) - ΔG γ, γ minimising |f_k - ΔF γ|
(f = G(x) - x; least squares via the small normal equations: γ only steers the next starting
point, the sweeps correct any inaccuracy of it). For a fixed stick/slip partition this is a
Krylov (GMRES-like) acceleration of the Gauss–Seidel iteration, the role the Krylov/CG finishes
play in Vollebregt's solvers; when the partition changes it is only a better starting point for
the next exact sweep. History depth 5 from sweep 2 (``solver._AA_DEPTH``, ``_AA_START``; the
savings: docs/notes/exact_solver.md).
"""
from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _small_solve(M, r):
    """Solve the small system M γ = r (Gaussian elimination, partial pivoting; M, r changed).

    A zero pivot (dependent differences) gives γ_j = 0 for that direction.
    """
    n = r.shape[0]
    for k in range(n):
        piv = k
        for i in range(k + 1, n):
            if abs(M[i, k]) > abs(M[piv, k]):
                piv = i
        if piv != k:
            for j in range(n):
                M[k, j], M[piv, j] = M[piv, j], M[k, j]
            r[k], r[piv] = r[piv], r[k]
        if M[k, k] == 0.0:
            continue
        for i in range(k + 1, n):
            f = M[i, k] / M[k, k]
            for j in range(k, n):
                M[i, j] -= f * M[k, j]
            r[i] -= f * r[k]
    g = np.zeros(n)
    for k in range(n - 1, -1, -1):
        if M[k, k] == 0.0:
            continue
        v = r[k]
        for j in range(k + 1, n):
            v -= M[k, j] * g[j]
        g[k] = v / M[k, k]
    return g


@njit(cache=True, boundscheck=False)
def mix(xs, gs, cur, nh, wel, dfv, x):
    """Anderson mixture of the sweep map: the next starting point ``x`` (written in place).

    ``xs[j], gs[j]`` ring buffers (length m + 1) of sweep inputs x_j and outputs G(x_j), the
    newest at ``cur``, ``nh`` >= 2 of them valid; ``wel`` the weights of the sums (half grid:
    2 per mirrored row); ``dfv`` scratch of length >= m. x = G(x_k) - ΔG γ, γ minimising
    |f_k - ΔF γ| with f = G(x) - x and Δ the differences of consecutive entries.
    """
    m = xs.shape[0] - 1
    n = x.shape[0] // 2
    nd = nh - 1
    # least squares through the (nd × nd) normal equations of the differences: γ only
    # steers the next starting point (the sweeps correct any inaccuracy of it)
    ia = np.empty(nd, np.int64)
    for j in range(nd):
        ia[j] = (cur - nd + j + m + 1) % (m + 1)
    M = np.zeros((nd, nd))
    rhs = np.zeros(nd)
    for i in range(2 * n):
        fc = gs[cur, i] - xs[cur, i]
        for j in range(nd):
            a = ia[j]
            b = (a + 1) % (m + 1)
            dfj = (gs[b, i] - xs[b, i]) - (gs[a, i] - xs[a, i])
            dfv[j] = dfj
            rhs[j] += wel[i] * dfj * fc
        for j in range(nd):
            for l in range(j + 1):
                M[j, l] += wel[i] * dfv[j] * dfv[l]
    tr = 0.0
    for j in range(nd):
        for l in range(j):
            M[l, j] = M[j, l]
        tr += M[j, j]
    for j in range(nd):
        M[j, j] += 1e-13 * tr
    gamma = _small_solve(M, rhs)
    for i in range(2 * n):
        v = gs[cur, i]
        for j in range(nd):
            a = ia[j]
            b = (a + 1) % (m + 1)
            v -= (gs[b, i] - gs[a, i]) * gamma[j]
        x[i] = v
