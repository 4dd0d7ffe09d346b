"""Steady-rolling tangential problem on the grid: a nonlinear block Gauss–Seidel solver (numba).

Discrete problem (Kalker 1979, eqs 4-6 and 8; Kalker 1990, *Three-Dimensional Elastic Bodies in
Rolling Contact*, ch. 5). Element i = (ix, iy), material flowing in -x, so the upstream
neighbour of i is i + (1, 0). With u = u_wheel - u_rail and p the traction on the wheel, the true
slip per rolling speed V (the material derivative Du/Dt = -V ∂u/∂x of eq 4 discretised between
the element and its upstream neighbour, first order, as in CONTACT) is

    w_i = (ξ - φ y_i, η + φ x_i) + (u_i - u_{i+(1,0)}) / dx,      u = dx/(πG) K * p,

and because K is a convolution (see :mod:`.influence`) the difference can be moved onto the
traction (the terms at the ends vanish since p = 0 outside the grid):

    w_i = s_i + 1/(πG) Σ_j K(i - j) q_j,      q_j = p_j - p_{j+(1,0)}   (j = -1 .. mx-1 per row).

Coulomb (Kalker 1979, eq 5): |p_i| <= μ p_n,i =: g_i; w_i = 0 (stick) or p_i = -g_i w_i/|w_i|
(slip); p = 0 outside the contact (p_n = 0).

Solver: the idea of Vollebregt's SteadyGS (E. A. H. Vollebregt, *A Gauss–Seidel type solver for
special convex programs, with application to frictional contact mechanics*, J. Optim. Theory
Appl. 87 (1995) 47-67; CONTACT user guide): rows of constant y are swept element by element from
the trailing to the leading edge. The unknown updated at element i is the traction *difference*
q_i (not p_i): the change Δ of p_i is carried on by all stick elements downstream of i up to the
first element jx in slip or outside the contact (their q stays fixed; in a stick zone the traction
differences, not the tractions, are nearly right). Then only q_i and q_jx change, by +Δ and -Δ,
and the slip at i changes by C Δ with the 2×2 matrix C = (K(0,0) - K(ix-jx, 0))/(πG), diagonal
because the xy coupling vanishes along a row. The element problem "w_i⁰ + C Δ satisfies Coulomb
with p_i + Δ" is solved exactly: stick if |p_i - C⁻¹ w_i⁰| <= g_i, otherwise p = g e on the
friction circle with (g C + λ I) e = -(w_i⁰ - C p_i), λ >= 0 from a safeguarded Newton iteration
on |e(λ)| = 1. Downstream stick elements pushed beyond their bound are clipped onto it.

Every element update recomputes its slip from all traction differences (row-contiguous dot
products against the flipped kernel tables): O(n_contact · n_grid) per sweep, compiled with numba.
The two elements of a mirror pair of rows share every kernel load (:func:`.kernels._slip_pair`;
faster per sweep than two separate sums), and the sweeps are Anderson-accelerated
(:mod:`.anderson`; fewer sweeps). Measurements: docs/notes/exact_solver.md.
All quantities are dimensionless: tractions in units of G, lengths of the kernel in units of dx.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .anderson import mix
from .kernels import _slip_at, _slip_half, _slip_pair

EXTERIOR, STICK, SLIP = 0, 1, 2


@njit(cache=True)
def _element(wx, wy, pxo, pyo, cx, cy, g, omega):
    """Exact solution of one element problem; returns (px, py, status).

    A stick solution is over-relaxed by ``omega`` (and kept inside the friction circle).
    """
    bx = wx - cx * pxo
    by = wy - cy * pyo
    tx = -bx / cx
    ty = -by / cy
    if tx * tx + ty * ty <= g * g:
        if omega != 1.0:
            tx = pxo + omega * (tx - pxo)
            ty = pyo + omega * (ty - pyo)
            a2 = tx * tx + ty * ty
            if a2 > g * g:
                f = g / math.sqrt(a2)
                tx *= f
                ty *= f
        return tx, ty, STICK
    if g == 0.0:
        return 0.0, 0.0, SLIP
    # slip: e_k = -b_k/(g c_k + λ), |e| = 1, λ >= 0 bracketed by |b| - g c_max <= λ <= |b| - g c_min
    nb = math.sqrt(bx * bx + by * by)
    cmax = max(cx, cy)
    cmin = min(cx, cy)
    lo = max(0.0, nb - g * cmax)
    hi = max(lo, nb - g * cmin)
    lam = 0.5 * (lo + hi)
    for _ in range(60):
        dx_ = g * cx + lam
        dy_ = g * cy + lam
        ex = bx / dx_
        ey = by / dy_
        f = ex * ex + ey * ey - 1.0
        if f > 0.0:
            lo = lam
        else:
            hi = lam
        if hi - lo <= 1e-15 * (hi + 1e-300):
            break
        df = -2.0 * (ex * ex / dx_ + ey * ey / dy_)
        new = lam - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        lam = new
    ex = -bx / (g * cx + lam)
    ey = -by / (g * cy + lam)
    ne = math.sqrt(ex * ex + ey * ey)
    return g * ex / ne, g * ey / ne, SLIP


@njit(cache=True, boundscheck=False)
def _update(ix, iy, wx, wy, px, py, qx, qy, status, bound, cx, cy, omega):
    """Apply the element solution at (ix, iy) given its current slip; returns |Δp|²."""
    mx = px.shape[1]
    jx = ix - 1
    while jx >= 0 and status[iy, jx] == STICK:
        jx -= 1
    pxo = px[iy, ix]
    pyo = py[iy, ix]
    pxn, pyn, st = _element(wx, wy, pxo, pyo, cx, cy, bound[iy, ix], omega)
    status[iy, ix] = st
    px[iy, ix] = pxn
    py[iy, ix] = pyn
    nxt_x = px[iy, ix + 1] if ix + 1 < mx else 0.0
    nxt_y = py[iy, ix + 1] if ix + 1 < mx else 0.0
    qx[iy, ix + 1] = pxn - nxt_x
    qy[iy, ix + 1] = pyn - nxt_y
    # carry the change through the stick elements downstream (their q fixed), clip to the bound
    for k in range(ix - 1, jx, -1):
        vx = px[iy, k + 1] + qx[iy, k + 1]
        vy = py[iy, k + 1] + qy[iy, k + 1]
        g = bound[iy, k]
        a2 = vx * vx + vy * vy
        if a2 > g * g:
            f = g / math.sqrt(a2)
            vx *= f
            vy *= f
            qx[iy, k + 1] = vx - px[iy, k + 1]
            qy[iy, k + 1] = vy - py[iy, k + 1]
        px[iy, k] = vx
        py[iy, k] = vy
    # difference at jx (slip or exterior: its traction stays)
    if jx >= 0:
        qx[iy, jx + 1] = px[iy, jx] - px[iy, jx + 1]
        qy[iy, jx + 1] = py[iy, jx] - py[iy, jx + 1]
    else:
        qx[iy, 0] = -px[iy, 0]
        qy[iy, 0] = -py[iy, 0]
    return (pxn - pxo) ** 2 + (pyn - pyo) ** 2


@njit(cache=True, boundscheck=False)
def _coef(ix, iy, status, kxx, kyy, my):
    """Diagonal of C = (K(0,0) - K(ix - jx, 0))/π for the element update at (ix, iy)
    (``my``: rows of the full grid, which index the kernel tables)."""
    mx = status.shape[1]
    jx = ix - 1
    while jx >= 0 and status[iy, jx] == STICK:
        jx -= 1
    t = mx - (ix - jx)
    return kxx[my - 1, mx] - kxx[my - 1, t], kyy[my - 1, mx] - kyy[my - 1, t]


@njit(cache=True, boundscheck=False)
def _sweep(px, py, qx, qy, status, bound, sx, sy, kxx, kxy, kyy, c_lo, c_hi, e_lo, e_hi,
           r_lo, r_hi, omega):
    """One Gauss–Seidel sweep over all contact elements; returns Σ |Δp|²."""
    my, mx = px.shape
    dif = 0.0
    npair = (my + 1) // 2
    for kp in range(npair):
        iy = npair - 1 - kp
        iym = my - 1 - iy
        lo = min(e_lo[iy], e_lo[iym])
        hi = max(e_hi[iy], e_hi[iym])
        for ix in range(lo, hi + 1):
            act1 = status[iy, ix] != EXTERIOR
            act2 = iym != iy and status[iym, ix] != EXTERIOR
            if act1 and act2:
                w1x, w1y, w2x, w2y = _slip_pair(ix, iy, iym, mx, my, qx, qy, kxx, kxy, kyy,
                                                c_lo, c_hi, r_lo, r_hi)
                c1x, c1y = _coef(ix, iy, status, kxx, kyy, my)
                c2x, c2y = _coef(ix, iym, status, kxx, kyy, my)
            elif act1:
                w1x, w1y = _slip_at(ix, iy, mx, my, qx, qy, kxx, kxy, kyy, c_lo, c_hi,
                                    r_lo, r_hi)
                c1x, c1y = _coef(ix, iy, status, kxx, kyy, my)
            elif act2:
                w2x, w2y = _slip_at(ix, iym, mx, my, qx, qy, kxx, kxy, kyy, c_lo, c_hi,
                                    r_lo, r_hi)
                c2x, c2y = _coef(ix, iym, status, kxx, kyy, my)
            if act1:
                dif += _update(ix, iy, w1x + sx[iy, ix], w1y + sy[iy, ix], px, py, qx, qy,
                               status, bound, c1x, c1y, omega)
            if act2:
                dif += _update(ix, iym, w2x + sx[iym, ix], w2y + sy[iym, ix], px, py, qx,
                               qy, status, bound, c2x, c2y, omega)
    return dif


@njit(cache=True, boundscheck=False)
def _sweep_half(px, py, qx, qy, status, bound, sx, sy, kxx, kyy, fxx, fxy1, fxy2, fyy,
                c_lo, c_hi, e_lo, e_hi, r_lo, r_hi, omega, my, wrow):
    """:func:`_sweep` on the half grid of a y-mirror-symmetric problem (rows ``h`` = full rows
    ``my - npair + h``, i.e. y >= 0, taken from the centre outwards as the mirror pairs of
    :func:`_sweep`); returns Σ |Δp|² over the full grid (row weights ``wrow``: 2, or 1 for the
    centre row of an odd ``my``)."""
    nh, mx = px.shape
    dif = 0.0
    for h in range(nh):
        for ix in range(e_lo[h], e_hi[h] + 1):
            if status[h, ix] == EXTERIOR:
                continue
            wx, wy = _slip_half(ix, h, mx, qx, qy, fxx, fxy1, fxy2, fyy, c_lo, c_hi,
                                r_lo, r_hi)
            cx, cy = _coef(ix, h, status, kxx, kyy, my)
            dif += wrow[h] * _update(ix, h, wx + sx[h, ix], wy + sy[h, ix], px, py, qx, qy,
                                     status, bound, cx, cy, omega)
    return dif


@njit(cache=True, boundscheck=False)
def _gather(px, py, iyc, ixc, out):
    n = iyc.shape[0]
    for k in range(n):
        out[k] = px[iyc[k], ixc[k]]
        out[n + k] = py[iyc[k], ixc[k]]


@njit(cache=True, boundscheck=False)
def _scatter(x, px, py, qx, qy, status, bound, iyc, ixc):
    """Set the contact tractions from x (clipped to the friction bound), the traction
    differences q and the stick/slip status consistently (as for a warm start)."""
    my, mx = px.shape
    n = iyc.shape[0]
    for k in range(n):
        iy = iyc[k]
        ix = ixc[k]
        vx = x[k]
        vy = x[n + k]
        g = bound[iy, ix]
        a2 = vx * vx + vy * vy
        st = STICK
        if a2 >= g * g * (1.0 - 1e-12) ** 2:
            st = SLIP
            if a2 > g * g:
                f = g / math.sqrt(a2)
                vx *= f
                vy *= f
        px[iy, ix] = vx
        py[iy, ix] = vy
        status[iy, ix] = st
    for iy in range(my):
        qx[iy, 0] = -px[iy, 0]
        qy[iy, 0] = -py[iy, 0]
        for c in range(1, mx):
            qx[iy, c] = px[iy, c - 1] - px[iy, c]
            qy[iy, c] = py[iy, c - 1] - py[iy, c]
        qx[iy, mx] = px[iy, mx - 1]
        qy[iy, mx] = py[iy, mx - 1]


@njit(cache=True, boundscheck=False)
def solve_steady(px, py, qx, qy, status, bound, sx, sy, kxx, kxy, kyy, c_lo, c_hi,
                 e_lo, e_hi, tol, maxit, omega, depth=5, aa_start=2):
    """The steady-rolling problem on the full grid; see :func:`_solve`."""
    my = px.shape[0]
    empty = np.zeros((0, 0, 0))
    return _solve(px, py, qx, qy, status, bound, sx, sy, kxx, kxy, kyy, empty, empty, empty,
                  empty, np.ones(my), my, c_lo, c_hi, e_lo, e_hi, tol, maxit, omega, depth,
                  aa_start)


@njit(cache=True, boundscheck=False)
def solve_steady_half(px, py, qx, qy, status, bound, sx, sy, kxx, kyy, fxx, fxy1, fxy2, fyy,
                      my, c_lo, c_hi, e_lo, e_hi, tol, maxit, omega, depth, aa_start):
    """The y-mirror-symmetric problem (η = φ = 0: X even, Y odd in y) on the half grid.

    Arrays hold the half rows (full rows ``my - npair + h``, y >= 0; ``py`` zero on the centre
    row of an odd ``my``); ``fxx .. fyy`` from :func:`folded_tables`. Every sum of the full
    iteration (sweep update, norm, Anderson inner products) is taken with the row weight 2
    (1 for the centre row), so the iterates are those of :func:`solve_steady` on the full grid
    from the mirrored start, up to rounding, at about half the multiply-adds per sweep.
    """
    nh = px.shape[0]
    wrow = np.full(nh, 2.0)
    if my % 2 == 1:
        wrow[0] = 1.0
    return _solve(px, py, qx, qy, status, bound, sx, sy, kxx, kxx, kyy, fxx, fxy1, fxy2, fyy,
                  wrow, my, c_lo, c_hi, e_lo, e_hi, tol, maxit, omega, depth, aa_start)


@njit(cache=True, boundscheck=False)
def _solve(px, py, qx, qy, status, bound, sx, sy, kxx, kxy, kyy, fxx, fxy1, fxy2, fyy, wrow,
           my_full, c_lo, c_hi, e_lo, e_hi, tol, maxit, omega, depth, aa_start):
    """Sweep until the rms update of the tractions is below ``tol`` times their rms.

    ``px, py`` (my, mx) tractions/G, updated in place; ``qx, qy`` (my, mx+1) their differences
    (column c = jx + 1), consistent with p on entry; ``status`` (my, mx) int8, updated;
    ``bound`` = μ p_n/G (inf without saturation); ``sx, sy`` rigid slip; kernels /π (flipped);
    ``c_lo, c_hi`` per row the q-columns that may be non-zero; ``e_lo, e_hi`` per row the
    contact elements (lo > hi: none).

    Rows are taken in mirror pairs (iy, my-1-iy), from the centre outwards (fewer
    sweeps than outside-in or alternating: docs/notes/exact_solver.md), and at each ix the slips of
    both elements are computed before either is updated: the iteration is then equivariant under
    the mirror y -> -y (up to rounding), so the computed forces have the exact symmetries of the
    continuous problem (Fy, Mz even in ξ etc.) whatever the tolerance.

    Acceleration (``depth`` > 0): from sweep ``aa_start`` on, the next sweep starts from the
    Anderson mixture of the last ``depth`` + 1 sweeps (:func:`.anderson.mix`), projected onto the
    friction discs with the stick/slip status re-derived from it (:func:`_scatter`); the history
    is dropped when the update grows. The returned iterate is always the output of a plain sweep
    (feasible, |p| <= μ p_n) and the stopping test is the update of that sweep. Mixing commutes
    with the y-mirror, so the symmetry above is kept.
    Half grid (:func:`solve_steady_half`): ``fxx`` non-empty, ``my_full`` the full row count,
    ``wrow`` the row weights of the sums; full grid: ``wrow`` = 1.
    Returns (sweeps, relative rms update of the last sweep).
    """
    my, mx = px.shape
    half = fxx.shape[0] > 0
    r_lo = my
    r_hi = -1
    n = 0
    for iy in range(my):
        if e_lo[iy] <= e_hi[iy]:
            r_lo = min(r_lo, iy)
            r_hi = max(r_hi, iy)
        for ix in range(mx):
            if status[iy, ix] != EXTERIOR:
                n += 1
    iyc = np.empty(n, np.int64)
    ixc = np.empty(n, np.int64)
    wel = np.empty(2 * n)
    k = 0
    for iy in range(my):
        for ix in range(mx):
            if status[iy, ix] != EXTERIOR:
                iyc[k] = iy
                ixc[k] = ix
                wel[k] = wrow[iy]
                wel[n + k] = wrow[iy]
                k += 1
    m = max(depth, 0)
    xs = np.zeros((m + 1, 2 * n))     # ring buffers: sweep inputs x_j and outputs G(x_j)
    gs = np.zeros((m + 1, 2 * n))
    nh = 0
    head = 0
    x = np.empty(2 * n)
    dfv = np.empty(max(m, 1))
    rel = math.inf
    rel_prev = math.inf
    it = 0
    while it < maxit:
        it += 1
        if m > 0:
            _gather(px, py, iyc, ixc, x)
        if half:
            dif = _sweep_half(px, py, qx, qy, status, bound, sx, sy, kxx, kyy, fxx, fxy1,
                              fxy2, fyy, c_lo, c_hi, e_lo, e_hi, r_lo, r_hi, omega, my_full,
                              wrow)
        else:
            dif = _sweep(px, py, qx, qy, status, bound, sx, sy, kxx, kxy, kyy, c_lo, c_hi,
                         e_lo, e_hi, r_lo, r_hi, omega)
        nrm = 0.0
        for iy in range(r_lo, r_hi + 1):
            r = 0.0
            for ix in range(e_lo[iy], e_hi[iy] + 1):
                r += px[iy, ix] ** 2 + py[iy, ix] ** 2
            nrm += wrow[iy] * r
        if nrm > 0.0:
            rel = math.sqrt(dif / nrm)
        else:
            rel = 0.0 if dif == 0.0 else math.inf
        if rel <= tol or it >= maxit:
            break
        if m == 0:
            continue
        if rel > rel_prev:
            nh = 0                       # update grew: restart the history
        rel_prev = rel
        xs[head] = x
        _gather(px, py, iyc, ixc, gs[head])
        cur = head
        head = (head + 1) % (m + 1)
        nh = min(nh + 1, m + 1)
        if it < aa_start or nh < 2:
            continue
        mix(xs, gs, cur, nh, wel, dfv, x)
        _scatter(x, px, py, qx, qy, status, bound, iyc, ixc)
    return it, rel


@njit(cache=True)
def slip_field(px, py, qx, qy, status, sx, sy, kxx, kxy, kyy, c_lo, c_hi, e_lo, e_hi):
    """True slip per V, (wx, wy), at every contact element (zero outside)."""
    my, mx = px.shape
    wx = np.zeros((my, mx))
    wy = np.zeros((my, mx))
    r_lo = my
    r_hi = -1
    for iy in range(my):
        if e_lo[iy] <= e_hi[iy]:
            r_lo = min(r_lo, iy)
            r_hi = max(r_hi, iy)
    for iy in range(r_lo, r_hi + 1):
        for ix in range(e_lo[iy], e_hi[iy] + 1):
            if status[iy, ix] == EXTERIOR:
                continue
            a, b = _slip_at(ix, iy, mx, my, qx, qy, kxx, kxy, kyy, c_lo, c_hi, r_lo, r_hi)
            wx[iy, ix] = a + sx[iy, ix]
            wy[iy, ix] = b + sy[iy, ix]
    return wx, wy
