"""The table lookup: numba kernels from the creepages to the normalised forces.

Interpolation is local and piecewise cubic: on each uniform axis the four nearest nodes with
Lagrange's weights (one-sided at the ends, except where the ghost row of a/b extends the axis:
``grid.Axes``), tensor product over ln(a/b), θ, ψ and s, linear in ν
(two nodes; an axis of fewer than 4 nodes is linear, which θ, ψ and s never are: ``grid.Axes``).
ψ is extended by one node beyond each end with the symmetries of the problem (:mod:`.grid`),
:func:`with_psi_ghosts`, so that its stencil is always central: ξ -> -ξ maps ψ to π - ψ and
flips Fx; (η, φ) -> -(η, φ) maps (θ, ψ) to (π - θ, -ψ) and flips Fy and Mz (this lowered the
largest errors near ψ = 0 and π/2, where a one-sided stencil was worst). A cubic spline through
all the nodes of ln(a/b) instead of the local cubic was tried and not kept, and scipy's
``RegularGridInterpolator`` costs far over the method's per-call budget at a point
(docs/notes/table_build.md); these kernels stay within it.

Being a tensor product, the interpolation can be done axis by axis, in one order everywhere:
over ν first (each value from 0.0), then over a/b (from 0.0), then over (θ, ψ, s).
:func:`_make_slice` interpolates the whole table at one (a/b, ν) into a 3-D slice over (θ, ψ, s),
from which :func:`_lookup_slice` interpolates with 64 nodes; :func:`_nu_rows` interpolates it at
one ν into rows over (θ, ψ, a/b, s), from which :func:`_lookup_rows` interpolates the 64 nodes of
its stencil at a/b (256 row values), then over (θ, ψ, s); :func:`_lookup` needs neither: it
interpolates the 64 nodes of its stencil at (a/b, ν) (512 table values). All sum in the same
order, so they give the same result to the bit. The method uses the slice where (a/b, ν) repeats,
as in a simulation of a fixed geometry, the rows where ν repeats and a/b does not (the effect
``varying_geometry``), and otherwise :func:`_lookup_state`, which also forms the table's
coordinates from the creepages (Kalker's coefficients and the spin weight compiled in, not
evaluated in Python around the kernel); so does :func:`_lookup_rows`.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..base import _moderate
from ..coefficients import SPLINE, spline_coefficients
from .grid import spin_weight


def _weights(x: float, lo: float, h: float, n: int) -> tuple[int, float, float, float, float]:
    """First node and the 4 interpolation weights at x on a uniform axis of ``n`` nodes from
    ``lo`` with step ``h``: cubic Lagrange on 4 nodes, linear (2 nodes) for n < 4."""
    t = (x - lo) / h
    if n < 4:
        i0 = min(max(int(math.floor(t)), 0), n - 2)
        p = t - i0
        return i0, 1.0 - p, p, 0.0, 0.0
    i0 = min(max(int(math.floor(t)) - 1, 0), n - 4)
    p = t - i0
    return (i0, -(p - 1.0) * (p - 2.0) * (p - 3.0) / 6.0, p * (p - 2.0) * (p - 3.0) / 2.0,
            -p * (p - 1.0) * (p - 3.0) / 2.0, p * (p - 1.0) * (p - 2.0) / 6.0)


def with_psi_ghosts(values: np.ndarray) -> np.ndarray:
    """The table (n_ab, n_ν, n_θ, n_ψ, n_s, 4) with one ψ node added before 0 and after π/2 from
    the symmetries (module docstring): shape (..., n_ψ + 2, ...); its ψ axis starts at -h."""
    below = values[:, :, ::-1, 1:2].copy()         # (θ, -h) <- (π - θ, h), Fy and Mz flipped
    below[..., 1:3] *= -1.0
    above = values[:, :, :, -2:-1].copy()           # π/2 + h <- π/2 - h, Fx flipped
    above[..., 0] *= -1.0
    return np.ascontiguousarray(np.concatenate([below, values, above], axis=3))


def _polar(u0: float, u1: float, u2: float) -> tuple[float, float, float, float, float]:
    """(sx, sy, θ, ψ, s) of the table coordinates (u0, u1, u2) (:mod:`.grid`): the symmetries
    ξ -> -ξ (sign sx of Fx) and (η, φ) -> -(η, φ) (sign sy of Fy and Mz) bring u into the
    tabulated quarter u0, u1 >= 0. s = 0 is the origin."""
    sx = math.copysign(1.0, u0)     # -0.0 too: atan2(u1, -0.0) would be ψ = π, off the axis
    u0 = abs(u0)
    sy = 1.0
    if u1 < 0.0:
        u1 = -u1
        u2 = -u2
        sy = -1.0
    r = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    if r == 0.0:
        return sx, sy, 0.0, 0.0, 0.0
    return (sx, sy, math.acos(min(1.0, max(-1.0, u2 / r))), math.atan2(u1, u0), r / (1.0 + r))


def _finish(sx: float, sy: float, s: float, g0: float, g1: float, g2: float,
            g3: float) -> tuple[float, float, float, float]:
    """Signs restored and Coulomb's bound |F| <= μN applied (interpolation between nodes may
    cross it)."""
    fx = sx * s * g0
    fy = sy * s * g1
    f = math.sqrt(fx * fx + fy * fy)
    if f > 1.0:
        fx /= f
        fy /= f
    return fx, fy, sy * s * g2, min(1.0, max(0.0, g3))


def _lookup(values: np.ndarray, axes: np.ndarray, u0: float, u1: float, u2: float,
            log_ab: float, nu: float) -> tuple[float, float, float, float]:
    """(Fx/(μN), Fy/(μN), Mz/(μN c), slip fraction) at the table coordinates (u0, u1, u2)
    (module :mod:`.grid`). ``values``: on the nodes (g0, g1, g2, slip fraction), shape
    (n_ab, n_nu, n_θ, n_ψ + 2, n_s, 4) (:func:`with_psi_ghosts`), C-contiguous; ``axes`` (2, 5):
    the start and the step of the five axes (ψ from the ghost node). Nothing is written outside
    the call (thread-safe).

    The 64 nodes of the (θ, ψ, s) stencil are first interpolated at (a/b, ν), summed in the
    order of :func:`_make_slice` and :func:`_nu_rows` (module docstring), then :func:`_cube`
    sums the nodes: the result is the same to the bit as :func:`_lookup_slice` on the slice and
    :func:`_lookup_rows` on the rows, whichever path a call takes."""
    sx, sy, theta, psi, s = _polar(u0, u1, u2)
    if s == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    lo = axes[0]
    h = axes[1]
    shape = values.shape
    ia, wa, na, inu, wn, nn = _pair_stencil(lo, h, shape[0], shape[1], log_ab, nu)
    it, wt, ip, wp, js, wk = _stencil(lo, h, shape[2], shape[3], shape[4], theta, psi, s)
    st_p = shape[4] * 4
    st_t = shape[3] * st_p
    st_n = shape[2] * st_t
    st_a = shape[1] * st_n
    flat = values.reshape(-1)            # a view (C-contiguous): plain offsets
    local = np.zeros(256)                # the stencil's 4 x 4 x 4 nodes at (a/b, ν)
    row = np.empty(16)
    for a in range(na):
        w = wa[a]
        base = (ia + a) * st_a + inu * st_n + js * 4
        j = 0
        for t in range(4):
            for p in range(4):
                o = base + (it + t) * st_t + (ip + p) * st_p
                row[:] = 0.0                 # 4 s nodes x 4 values at ν, as _nu_rows forms them
                for b in range(nn):
                    src = flat[o + b * st_n:o + b * st_n + 16]   # contiguous; views, which the
                    wb = wn[b]                                   # compiler vectorises
                    for m in range(16):
                        row[m] += wb * src[m]
                dst = local[j:j + 16]
                for m in range(16):
                    dst[m] += w * row[m]
                j += 16
    g0, g1, g2, g3 = _cube(local, 0, 4, 4, 4, 0, wt, 0, wp, 0, wk)
    return _finish(sx, sy, s, g0, g1, g2, g3)


def _scales(breaks: np.ndarray, pieces: np.ndarray, spin_power: float, ab: float,
            nu: float) -> tuple[float, float, float, float]:
    """The factors from the creepages to the table's coordinates at (a/b, ν) inside the table
    (:mod:`.grid`): Kalker's C11, C22 and w(a/b) C23 (``coefficients.SPLINE``), and ln(a/b)."""
    x = math.log(ab)
    c11, c22, c23 = spline_coefficients(breaks, pieces, x, nu)
    return c11, c22, spin_weight(ab, spin_power) * c23, x


def _lookup_state(values: np.ndarray, axes: np.ndarray, breaks: np.ndarray, pieces: np.ndarray,
                  spin_power: float, xi: float, eta: float, phi: float, c: float, k: float,
                  ab: float, nu: float) -> tuple[float, float, float, float]:
    """:func:`_lookup` at the creepages (ξ, η, φ) of a contact of a/b and ν (inside the table),
    c = √(ab), k = G c²/(μN): the coordinates (u0, u1, u2) formed from :func:`_scales` as the
    method forms them for :func:`_lookup_slice` (the same operations, so the same bits)."""
    s_xi, s_eta, s_phi, log_ab = _scales(breaks, pieces, spin_power, ab, nu)
    return _lookup(values, axes, s_xi * xi * k, s_eta * eta * k, s_phi * c * phi * k, log_ab, nu)


def _count(n: int) -> int:
    """Nodes of an axis's stencil (:func:`_weights`)."""
    return 4 if n >= 4 else 2


def _pair_stencil(lo: np.ndarray, h: np.ndarray, n_ab: int, n_nu: int, log_ab: float,
                  nu: float) -> tuple:
    """First nodes, weights and node counts on the ln(a/b) and ν axes (:func:`_weights`)."""
    ia, a0, a1, a2, a3 = _weights(log_ab, lo[0], h[0], n_ab)
    inu, v0, v1, v2, v3 = _weights(nu, lo[1], h[1], n_nu)
    return ia, (a0, a1, a2, a3), _count(n_ab), inu, (v0, v1, v2, v3), _count(n_nu)


def _stencil(lo: np.ndarray, h: np.ndarray, n_t: int, n_p: int, n_s: int, theta: float,
             psi: float, s: float) -> tuple:
    """First nodes and weights on the θ, ψ and s axes (:func:`_weights`)."""
    it, t0, t1, t2, t3 = _weights(theta, lo[2], h[2], n_t)
    ip, p0, p1, p2, p3 = _weights(psi, lo[3], h[3], n_p)
    js, k0, k1, k2, k3 = _weights(s, lo[4], h[4], n_s)
    return it, (t0, t1, t2, t3), ip, (p0, p1, p2, p3), js, (k0, k1, k2, k3)


def _cube(flat: np.ndarray, base: int, n_t: int, n_p: int, n_s: int, it: int, wt: tuple,
          ip: int, wp: tuple, js: int, wk: tuple) -> tuple[float, float, float, float]:
    """The cubic interpolation over (θ, ψ, s) of the block (n_θ, n_ψ, n_s, 4) that starts at
    ``flat[base]``, with the stencil (first nodes and weights) of :func:`_stencil` (4 nodes per
    axis: fixed loops, which the compiler unrolls)."""
    st_p = n_s * 4
    st_t = n_p * st_p
    g0 = 0.0
    g1 = 0.0
    g2 = 0.0
    g3 = 0.0
    for t in range(4):
        for p in range(4):
            wtp = wt[t] * wp[p]
            o = base + (it + t) * st_t + (ip + p) * st_p + js * 4
            for k in range(4):
                w = wtp * wk[k]
                g0 += w * flat[o]
                g1 += w * flat[o + 1]
                g2 += w * flat[o + 2]
                g3 += w * flat[o + 3]
                o += 4
    return g0, g1, g2, g3


def _make_slice(values: np.ndarray, axes: np.ndarray, log_ab: float, nu: float) -> np.ndarray:
    """The table interpolated at (ln(a/b), ν) on every (θ, ψ, s) node: shape (n_θ, n_ψ, n_s, 4),
    the same weights and order as :func:`_lookup`."""
    shape = values.shape
    ia, wa, na, inu, wn, nn = _pair_stencil(axes[0], axes[1], shape[0], shape[1], log_ab, nu)
    size = shape[2] * shape[3] * shape[4] * 4
    st_a = shape[1] * size
    flat = values.reshape(-1)
    out = np.zeros(size)
    for a in range(na):
        w = wa[a]
        o = (ia + a) * st_a + inu * size
        for j in range(size):
            r = 0.0
            for b in range(nn):
                r += wn[b] * flat[o + b * size + j]
            out[j] += w * r
    return out.reshape((shape[2], shape[3], shape[4], 4))


def _nu_rows(values: np.ndarray, axes: np.ndarray, nu: float) -> np.ndarray:
    """The table interpolated at ν on every node, the same weights and order as :func:`_lookup`
    (the rows of :func:`_lookup_rows`): shape (n_θ, n_ψ, n_ab, n_s, 4), so that the a/b nodes a
    lookup reads at one (θ, ψ) lie next to each other."""
    shape = values.shape
    inu, v0, v1, v2, v3 = _weights(nu, axes[0][1], axes[1][1], shape[1])
    wn = (v0, v1, v2, v3)
    nn = _count(shape[1])
    block = shape[4] * 4
    size = shape[2] * shape[3] * block
    flat = values.reshape(-1)
    out = np.empty((shape[2], shape[3], shape[0], shape[4], 4))
    dst = out.reshape(-1)
    for a in range(shape[0]):
        o = (a * shape[1] + inu) * size
        for tp in range(shape[2] * shape[3]):
            d = (tp * shape[0] + a) * block
            for j in range(block):
                r = 0.0
                for b in range(nn):
                    r += wn[b] * flat[o + b * size + tp * block + j]
                dst[d + j] = r
    return out


def _lookup_rows(rows: np.ndarray, axes: np.ndarray, xi: float, eta: float, phi: float,
                 c: float, k: float, ab: float) -> tuple[float, float, float, float]:
    """:func:`_lookup_state` from the rows of :func:`_nu_rows` at ν (the same value to the bit):
    the 64 nodes of the (θ, ψ, s) stencil from 4 rows of a/b (each from 0.0), then
    :func:`_cube`. ``axes``: the table's (2, 5) and a third row (spin power, ν, ...): every
    argument that does not change from call to call is in an array, and Kalker's spline is
    frozen into the compiled code (``_SPLINE``; :func:`check_frozen`), for numba's dispatch."""
    s_xi, s_eta, s_phi, log_ab = _scales(_SPLINE[0], _SPLINE[1], axes[2, 0], ab, axes[2, 1])
    sx, sy, theta, psi, s = _polar(s_xi * xi * k, s_eta * eta * k, s_phi * c * phi * k)
    if s == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    lo = axes[0]
    h = axes[1]
    shape = rows.shape                  # (θ, ψ, a/b, s, 4)
    ia, a0, a1, a2, a3 = _weights(log_ab, lo[0], h[0], shape[2])
    wa = (a0, a1, a2, a3)
    na = _count(shape[2])
    it, wt, ip, wp, js, wk = _stencil(lo, h, shape[0], shape[1], shape[3], theta, psi, s)
    st_a = shape[3] * 4
    st_p = shape[2] * st_a
    st_t = shape[1] * st_p
    flat = rows.reshape(-1)
    first = ia * st_a + js * 4
    nv = 4 * _count(shape[3])           # 16, but not a constant: the loop stays a loop, which
    local = np.zeros(256)               # the compiler vectorises
    j = 0
    for t in range(4):
        for p in range(4):
            o = first + (it + t) * st_t + (ip + p) * st_p
            dst = local[j:j + nv]       # the 4 s nodes x 4 values of (θ, ψ) at (a/b, ν)
            for a in range(na):
                w = wa[a]
                src = flat[o + a * st_a:o + a * st_a + nv]
                for m in range(nv):
                    dst[m] += w * src[m]
            j += 16
    g0, g1, g2, g3 = _cube(local, 0, 4, 4, 4, 0, wt, 0, wp, 0, wk)
    return _finish(sx, sy, s, g0, g1, g2, g3)


def _lookup_slice(slab: np.ndarray, axes: np.ndarray, u0: float, u1: float,
                  u2: float) -> tuple[float, float, float, float]:
    """:func:`_lookup` from a slice of :func:`_make_slice` (same value, 64 nodes)."""
    sx, sy, theta, psi, s = _polar(u0, u1, u2)
    if s == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    shape = slab.shape
    it, wt, ip, wp, js, wk = _stencil(axes[0], axes[1], shape[0], shape[1], shape[2], theta,
                                      psi, s)
    g0, g1, g2, g3 = _cube(slab.reshape(-1), 0, shape[0], shape[1], shape[2], it, wt, ip, wp,
                           js, wk)
    return _finish(sx, sy, s, g0, g1, g2, g3)


def _step_rows(rows: np.ndarray, axes: np.ndarray, xi: float, eta: float, phi: float, N: float,
               mu: float, a: float, b: float, G: float,
               nu: float) -> tuple[int, float, float, float, float]:
    """One state of the method with every effect of Coulomb friction, from the rows at ν
    (:func:`_nu_rows`), in one compiled call: the method's ``step`` and ``_step_impl`` (their
    checks, operations and order: the same bits) where they take the rows. ``axes``: the rows'
    (:func:`_lookup_rows`) with a third row (spin power, ν brought onto the table, the table's
    a/b range) and a fourth (the a/b accepted, with the edges' tolerance).

    Returns (done, Fx, Fy, Mz, slip fraction): done 0, a state the general path must solve
    (inputs outside ``base._moderate``, a/b outside the table); 1, the result; 2, the result
    before Coulomb's bounds, which the caller holds (``hertz.held_spin_moment`` on Mz, and
    ``ContactMethod._held`` where |(Fx, Fy)| may exceed μN: checked here with a margin, in
    Python to the bit)."""
    ab = a / b
    if not (_moderate(xi, eta, phi, N, mu, a, b, G, nu, True)
            and axes[3, 0] <= ab <= axes[3, 1]):
        return 0, 0.0, 0.0, 0.0, 0.0
    c = math.sqrt(a * b)
    k = G * a * b / (mu * N)
    lo = axes[2, 2]
    hi = axes[2, 3]
    inside = ab if lo <= ab <= hi else min(hi, max(lo, ab))
    fx, fy, mz, slip = _lookup_rows(rows, axes, xi, eta, phi, c, k, inside)
    mun = mu * N
    fx = fx * mun
    fy = fy * mun
    mz = mz * mun * c
    done = 1
    if (abs(mz) > 0.375 * mun * (a if a > b else b)
            or fx * fx + fy * fy > (1.0 - 1e-12) * (mu * N) * (mu * N)):
        done = 2
    return done, fx, fy, mz, slip


def _weights_d(x: float, lo: float, h: float, n: int) -> tuple[int, tuple, tuple]:
    """:func:`_weights` and their derivatives with respect to x (Lagrange's cubic
    differentiated; linear for n < 4)."""
    i0, w0, w1, w2, w3 = _weights(x, lo, h, n)
    p = (x - lo) / h - i0
    if n < 4:
        return i0, (w0, w1, w2, w3), (-1.0 / h, 1.0 / h, 0.0, 0.0)
    d0 = -((p - 2.0) * (p - 3.0) + (p - 1.0) * (p - 3.0) + (p - 1.0) * (p - 2.0)) / 6.0
    d1 = ((p - 2.0) * (p - 3.0) + p * (p - 3.0) + p * (p - 2.0)) / 2.0
    d2 = -((p - 1.0) * (p - 3.0) + p * (p - 3.0) + p * (p - 1.0)) / 2.0
    d3 = ((p - 1.0) * (p - 2.0) + p * (p - 2.0) + p * (p - 1.0)) / 6.0
    return i0, (w0, w1, w2, w3), (d0 / h, d1 / h, d2 / h, d3 / h)


def _gradient(values: np.ndarray, axes: np.ndarray, theta: float, psi: float, s: float,
              log_ab: float, nu: float) -> np.ndarray:
    """The interpolant of :func:`_lookup` (without the signs and bounds of :func:`_finish`) at
    (θ, ψ, s, ln(a/b), ν) in the tabulated quarter, and its derivatives: shape (4, 5), per
    value (g0, g1, g2, slip fraction) the value and ∂/∂θ, ∂/∂ψ, ∂/∂s, ∂/∂ln(a/b) (the weights
    of one axis replaced by their derivatives, :func:`_weights_d`). For the table's Jacobian;
    the value sums in another order than the lookups (the same to rounding)."""
    lo = axes[0]
    h = axes[1]
    shape = values.shape
    ia, wa, da = _weights_d(log_ab, lo[0], h[0], shape[0])
    inu, wn, _ = _weights_d(nu, lo[1], h[1], shape[1])
    it, wt, dt = _weights_d(theta, lo[2], h[2], shape[2])
    ip, wp, dp = _weights_d(psi, lo[3], h[3], shape[3])
    js, wk, dk = _weights_d(s, lo[4], h[4], shape[4])
    na = _count(shape[0])
    nn = _count(shape[1])
    out = np.zeros((4, 5))
    for a in range(na):
        for b in range(nn):
            wab = wa[a] * wn[b]
            dab = da[a] * wn[b]
            for t in range(4):
                for p in range(4):
                    for k in range(4):
                        w = wab * wt[t] * wp[p] * wk[k]
                        w_t = wab * dt[t] * wp[p] * wk[k]
                        w_p = wab * wt[t] * dp[p] * wk[k]
                        w_s = wab * wt[t] * wp[p] * dk[k]
                        w_l = dab * wt[t] * wp[p] * wk[k]
                        for m in range(4):
                            v = values[ia + a, inu + b, it + t, ip + p, js + k, m]
                            out[m, 0] += w * v
                            out[m, 1] += w_t * v
                            out[m, 2] += w_p * v
                            out[m, 3] += w_s * v
                            out[m, 4] += w_l * v
    return out


#: Kalker's spline (``coefficients.SPLINE``), which :func:`_lookup_rows` reads as a global:
#: numba freezes it into the compiled code.
_SPLINE = SPLINE
_FROZEN_CHECKED = False


def check_frozen() -> None:
    """Once per process, before the rows are used (after :func:`kernels`): numba keys its disk
    cache on this file only, and :func:`_lookup_rows` carries Kalker's spline as constants, so a
    compiled cache of other data differs from :func:`_lookup_state` (which takes the spline as
    arguments) on a small random table; it is then compiled afresh."""
    global _FROZEN_CHECKED
    if _FROZEN_CHECKED:
        return
    _FROZEN_CHECKED = True
    rng = np.random.default_rng(0)
    values = rng.random((6, 2, 6, 6, 6, 4)).astype(np.float32)    # the table's types
    values.setflags(write=False)
    axes = np.array([[math.log(0.1), 0.25, 0.0, -0.1, 0.0], [0.9, 0.05, 0.6, 0.3, 0.2],
                     [0.8, 0.27, 0.0, 0.0, 0.0]])
    rows = _nu_rows(values, axes, 0.27)
    rows.setflags(write=False)
    breaks, pieces = SPLINE
    for ab in (0.2, 0.9, 6.0):
        state = (1e-3, -4e-4, 0.3, 0.01, 50.0, ab)
        if _lookup_rows(rows, axes, *state) != _lookup_state(values, axes, breaks, pieces, 0.8,
                                                              *state, 0.27):
            _lookup_rows.recompile()
            return


_STEP_ROWS = None


def step_rows_kernel() -> Callable:
    """:func:`_step_rows` compiled for floats (an int is converted, anything else refused with
    a ``TypeError``), after :func:`kernels`. numba's disk cache keys on this file only, and the
    kernel compiles ``base._moderate`` in: it is checked against its interpreted self once per
    process on a small random table (as :func:`check_frozen`) and compiled afresh if they
    differ."""
    global _STEP_ROWS
    if _STEP_ROWS is None:
        import numba
        from numba import types
        kernels()
        f8 = types.float64
        sig = types.Tuple((types.int64, f8, f8, f8, f8))(
            types.Array(f8, 5, "C", readonly=True), types.Array(f8, 2, "C"), *[f8] * 9)
        kernel = numba.njit(sig, cache=True, nogil=True, error_model="numpy")(_step_rows)
        rng = np.random.default_rng(1)
        values = rng.random((6, 2, 6, 6, 6, 4)).astype(np.float32)    # the table's types
        axes = np.array([[math.log(0.1), 0.25, 0.0, -0.1, 0.0], [0.9, 0.05, 0.6, 0.3, 0.2],
                         [0.8, 0.27, 0.1, 10.0, 0.0], [0.1, 10.0, 0.0, 0.0, 0.0]])
        rows = _nu_rows(values, axes, 0.27)
        rows.setflags(write=False)
        for a, phi, N in ((4e-3, 0.3, 1e5), (7e-2, 2.0, 3e4), (5e-4, 0.0, 1e5), (2.0, 0.1, 1e5)):
            state = (rows, axes, 1e-3, -4e-4, phi, N, 0.3, a, 6e-3, 8e10, 0.27)
            if kernel(*state) != _step_rows(*state):
                kernel.recompile()
                break
        _STEP_ROWS = kernel
    return _STEP_ROWS


_GRADIENT = None


def gradient_kernel() -> Callable:
    """:func:`_gradient` compiled (on first use, after :func:`kernels`)."""
    global _GRADIENT, _weights_d
    if _GRADIENT is None:
        import numba
        kernels()
        jit = numba.njit(cache=True, nogil=True, error_model="numpy")
        _weights_d = jit(_weights_d)
        _GRADIENT = jit(_gradient)
    return _GRADIENT


_JITTED = False


def kernels() -> tuple[Callable, ...]:
    """The numba-compiled (:func:`_lookup_state`, :func:`_scales`, :func:`_make_slice`,
    :func:`_lookup_slice`, :func:`_nu_rows`, :func:`_lookup_rows`), compiled on first use or
    loaded from numba's disk cache (numba itself is imported with ``contact_core``: the
    coefficients and the exact solver use it at import). Every function of this module, and the two it calls from ``coefficients``
    and ``grid``, is replaced by its compiled version (module attributes, as numba's cache
    statistics expect). numba's disk cache keys on this file only: after editing those two
    functions, delete ``__pycache__``."""
    global _JITTED, _weights, _count, _polar, _finish, _pair_stencil, _stencil, _cube
    global _lookup, _make_slice, _lookup_slice, _scales, _lookup_state, _nu_rows, _lookup_rows
    global spline_coefficients, spin_weight
    if not _JITTED:
        import numba
        jit = numba.njit(cache=True, nogil=True, error_model="numpy")
        spline_coefficients, spin_weight = jit(spline_coefficients), jit(spin_weight)
        _weights, _count, _polar, _finish = jit(_weights), jit(_count), jit(_polar), jit(_finish)
        _pair_stencil, _stencil, _cube = jit(_pair_stencil), jit(_stencil), jit(_cube)
        _lookup, _make_slice, _lookup_slice = jit(_lookup), jit(_make_slice), jit(_lookup_slice)
        _scales, _lookup_state = jit(_scales), jit(_lookup_state)
        _nu_rows, _lookup_rows = jit(_nu_rows), jit(_lookup_rows)
        _JITTED = True
    return _lookup_state, _scales, _make_slice, _lookup_slice, _nu_rows, _lookup_rows
