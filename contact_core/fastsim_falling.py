"""FASTSIM with local falling friction: each element's traction bound at its own slip velocity.

The strip march of :mod:`contact_core.fastsim` (Kalker 1982; Kalker 1979 eq 38) with the bound
g = μ(s) p_n of the effect ``falling_friction`` (:mod:`contact_core.friction`), s the element's
slip velocity, as CONTACT takes the friction of each element of its exact solver (Vollebregt,
CONTACT user guide, "Slip velocity dependent friction"; its FASTSIM takes one coefficient at the
creep velocity instead, the option ``falling="creep"``).

Slip of an element: the march's stick predictor p_H is the traction the element would have
without slip; a slipping element's traction p lies on its bound, and the slip over the step of
length h is the bed's displacement difference, S = diag(Lx, Ly)(p - p_H) (the slip law of
:mod:`.fastsim`, flexibilities Lx and Ly = r21 Lx), so its slip velocity is s = V |S|/h
(Kalker 1979 eq 35, ẇ = V[rigid slip - ∂u/∂x], discretised over the step). The bound depends on
s and s on the bound: one scalar equation per slipping element,

    r = Φ(r),   g = r g_s,   Φ(r) = θ μ_up/μ_stat + (1 - θ) ρ(s(r g_s)),

g_s = μ_stat p_n the static bound, ρ the law's μ/μ_stat, θ the friction memory's weight of the
upstream element's coefficient μ_up (0 without memory; :mod:`contact_core.friction`). Φ rises
with r (more bound, less slip, more friction), and a falling law can make r = Φ(r) have several
roots: the non-uniqueness of falling friction (CONTACT user guide, INISLP: its "low-slip" and
"high-slip" solutions). The march takes the root of least slip, the continuation of the
element's solution from the onset of slip (where r = 1) as the slip grows from zero along the
strip: from r = min(1, |p_H|/g_s), where r >= Φ(r), one fixed-point step Φ(r) (which stays at or
above that root, Φ rising; or the root of the strip's last slipping element, whose slip is
nearly this one's), then secant steps through the last two points (the fixed-point step
where the secant leaves [0, r]) until a step lands below the root, then regula falsi (Illinois)
in the bracket. (Where the law makes several roots lie within one secant step this may find a
lower one; with Coulomb's and the exponential law without memory, 1 - Φ is concave in r and has
one root with r < Φ(r) below it.) The stick test of an element uses its memory coefficient at
zero slip (μ_stat without memory).

Cost: every slipping element solves its equation (where the traction is scaled radially and
without memory, Newton's steps on r - ρ(c (|p_H| - r g_s)) from the upstream element's root, a
few evaluations of the law; otherwise the secant steps above, each through the slip law's
projection, :func:`contact_core.fastsim._onto_bound`), so a march in full sliding costs a
multiple of the Coulomb march; the march goes strip by strip, as these solves do not vectorise
(``python -m contact_tools.bench_falling``, docs/reports/falling_friction.md).
"""
from __future__ import annotations

import math
from typing import Any, Callable

from . import fastsim as _fastsim
from .friction import memory_step, ratio_and_slope_of, ratio_of

# fastsim's compiled kernels, bound by kernel()
_onto_bound: Callable | None = None
_strips: Callable | None = None
_predict: Callable | None = None
_settle: Callable | None = None
_record: Callable | None = None
_totals: Callable | None = None
_ratio: Callable | None = None
_ratio_slope: Callable | None = None
_memory_step: Callable | None = None


def _phi(r: float, hx: float, hy: float, gs: float, r21: float, slip_per_traction: float,
         law: Any, mu_up: float, theta_num: float, dt_per_v: float) -> float:
    """Φ(r) of the module docstring: ``slip_per_traction`` = V Lx/h (m/s per Pa of
    |diag(1, r21)(p - p_H)|), ``theta_num`` = d_c (m), ``dt_per_v`` = h/V (s), so that the
    memory's weight is θ = d_c/(d_c + (h/V) max(s, s_0))."""
    g = r * gs
    n = math.sqrt(hx * hx + hy * hy)
    if g >= n:
        dx = 0.0
        dy = 0.0
    elif r21 == 1.0 or hx == 0.0 or hy == 0.0:
        f = g / n - 1.0
        dx = hx * f
        dy = hy * f
    else:
        qx, qy = _onto_bound(hx, hy, g, r21)
        dx = qx - hx
        dy = qy - hy
    s = slip_per_traction * math.sqrt(dx * dx + (r21 * dy) * (r21 * dy))   # m/s
    return _memory_step(mu_up, _ratio(law, s), s, theta_num, dt_per_v, law[7])


def _slip_ratio_radial(n: float, gs: float, c: float, law: Any, guess: float) -> float:
    """:func:`_slip_ratio` where the traction is the predictor scaled radially and there is no
    memory: r = ρ(c (n - r g_s)), n = |p_H|, c = V Lx/h. F(r) = r - ρ is concave for the
    exponential and the rational law (ρ convex in s, s linear in r), so Newton's steps from below
    the root rise monotonically to it; bracketed, with bisection where a step leaves the
    bracket (the linear law's kink)."""
    hi = min(1.0, n / gs)
    lo = 0.0
    r = guess if 0.0 < guess < hi else hi
    tol = 1e-13
    for _ in range(100):
        rho, slope = _ratio_slope(law, c * (n - r * gs))
        f = r - rho
        if abs(f) <= tol:
            return r
        if f < 0.0:
            lo = r
        else:
            hi = r
        if hi - lo <= tol:
            return r
        dfdr = 1.0 + c * gs * slope
        step = r - f / dfdr if dfdr > 0.0 else -1.0
        r = step if lo < step < hi else 0.5 * (lo + hi)
    return r


def _slip_ratio(hx: float, hy: float, gs: float, r21: float, slip_per_traction: float,
                law: Any, mu_up: float, theta_num: float, dt_per_v: float,
                guess: float) -> float:
    """The root r of r = Φ(r) of least slip in [0, min(1, |p_H|/g_s)] (module docstring);
    ``guess``: the upstream element's root (-1: none), tried first."""
    if theta_num == 0.0 and (r21 == 1.0 or hx == 0.0 or hy == 0.0):
        n = math.sqrt(hx * hx + hy * hy)
        lx_scale = 1.0 if (r21 == 1.0 or hy == 0.0) else r21
        return _slip_ratio_radial(n, gs, slip_per_traction * lx_scale, law, guess)
    hi = min(1.0, math.sqrt(hx * hx + hy * hy) / gs)
    f_hi = hi - _phi(hi, hx, hy, gs, r21, slip_per_traction, law, mu_up, theta_num, dt_per_v)
    tol = 1e-13
    if f_hi <= tol:
        return hi
    # the fixed-point step (or the upstream element's root), then secant steps through the last
    # two points above the root (the fixed-point step where the secant leaves [0, r]) until a
    # step lands below it
    x = guess if 0.0 < guess < hi else hi - f_hi
    lo = -1.0
    f_lo = 0.0
    for _ in range(100):
        fx = x - _phi(x, hx, hy, gs, r21, slip_per_traction, law, mu_up, theta_num, dt_per_v)
        if abs(fx) <= tol:
            return x
        if fx < 0.0:
            lo, f_lo = x, fx
            break
        sec = x - fx * (x - hi) / (fx - f_hi) if fx != f_hi else -1.0
        hi, f_hi = x, fx
        x = sec if 0.0 <= sec < hi else hi - f_hi
    if lo < 0.0:
        return hi
    # bracketed: regula falsi with Illinois' halving
    side = 0
    for _ in range(100):
        r = hi - f_hi * (hi - lo) / (f_hi - f_lo)
        if not (lo < r < hi):
            r = 0.5 * (lo + hi)
        fr = r - _phi(r, hx, hy, gs, r21, slip_per_traction, law, mu_up, theta_num, dt_per_v)
        if abs(fr) <= tol or hi - lo <= tol:
            return r
        if fr > 0.0:
            hi, f_hi = r, fr
            if side == 1:
                f_lo *= 0.5
            side = 1
        else:
            lo, f_lo = r, fr
            if side == -1:
                f_hi *= 0.5
            side = -1
    return hi


def _march_falling(a: float, b: float, xi: float, eta: float, phi: float, k1: float,
                   k2: float, k3: float, k3x: float, r21: float, lx: float, g0: float,
                   profile: Any, elliptic: bool, nx: int, ny: int, first: float,
                   spin_at: float, do_x: bool, do_y: bool, do_mz: bool, law: Any, speed: float,
                   memory: float, out: Any) -> tuple[float, float, float, float, float]:
    """:func:`contact_core.fastsim._march` with the bound at each element's slip velocity
    (module docstring), on its strips (``_strips``, ``_predict``, ``_settle``, ``_record``,
    ``_totals`` of :mod:`contact_core.fastsim`). Besides ``_march``'s arguments: ``lx`` the
    slip law's Lx (m/Pa), ``law`` (:meth:`~contact_core.friction.FrictionLaw.params`),
    ``speed`` the rolling speed (m/s, > 0), ``memory`` the memory distance d_c (m; 0: none);
    ``g0`` is the static bound's peak. ``out`` row 4 holds each element's bound g = μ(s) p_n."""
    dy = 2.0 * b / ny
    work = _strips(a, b, xi, phi, k1, k3x, g0, elliptic, nx, ny, do_x)
    y, hjs, gss, wxs, tx, ty = (work[_fastsim._SY], work[_fastsim._SHJ], work[_fastsim._SG],
                                work[_fastsim._SWX], work[_fastsim._SPX], work[_fastsim._SPY])
    sx, sy, sxpy, nslip = (work[_fastsim._SSX], work[_fastsim._SSY], work[_fastsim._SSXPY],
                           work[_fastsim._SNSL])
    ey = 1.0 if do_y else 0.0
    nxf = float(nx)
    s0 = law[7]
    # strip by strip (the elements' root solves do not vectorise)
    for j in range(ny):
        hj = hjs[j]
        mu_up = 1.0                          # μ/μ_stat of the material entering the contact
        guess = -1.0                         # the last slipping element's root
        for i in range(nx):
            x = (nxf - 2.0 * i - 1.0) * hj
            h = (first if i == 0 else 1.0) * (2.0 * hj)
            px, py = _predict(tx[j], ty[j], wxs[j], x, h, ey, eta, k2, phi, k3, spin_at)
            gs = gss[j] * profile[i]
            dt_per_v = h / speed             # time to cross the step, per unit slip velocity
            mu_stick = _memory_step(mu_up, 1.0, 0.0, memory, dt_per_v, s0)   # sticking: ρ(0) = 1
            slip = False
            g = mu_stick * gs
            n2 = px * px + py * py
            if n2 > g * g:
                slip = True
                if gs > 0.0:
                    r = _slip_ratio(px, py, gs, r21, speed * lx / h, law, mu_up, memory,
                                    dt_per_v, guess)
                    guess = r
                else:
                    r = 0.0
                g = r * gs
                mu_up = r
                if g <= 0.0:
                    px = 0.0
                    py = 0.0
                elif r21 == 1.0 or px == 0.0 or py == 0.0:
                    f = g / math.sqrt(n2)
                    px *= f
                    py *= f
                else:
                    px, py = _onto_bound(px, py, g, r21)
            else:
                mu_up = mu_stick
            _settle(tx, ty, nslip, sx, sy, sxpy, j, x, px, py, slip)
            if out is not None:
                _record(out, i, j, x, y[j], px, py, g, slip, 2.0 * hj * dy)
    return _totals(work, nx, ny, dy, do_mz)


_KERNEL: Callable | None = None


def kernel() -> Callable:
    """The numba-compiled :func:`_march_falling` (compiled on first use; cached on disk)."""
    global _KERNEL, _ratio, _ratio_slope, _memory_step, _phi, _slip_ratio_radial, _slip_ratio
    global _onto_bound, _strips, _predict, _settle, _record, _totals
    if _KERNEL is None:
        import numba
        _fastsim._kernels()                  # compiles fastsim's march and its helpers
        jit = numba.njit(cache=True, nogil=True, error_model="numpy")
        _onto_bound, _strips, _predict, _settle, _record, _totals = (
            _fastsim._onto_bound, _fastsim._strips, _fastsim._predict, _fastsim._settle,
            _fastsim._record, _fastsim._totals)
        _ratio = jit(ratio_of)
        _ratio_slope = jit(ratio_and_slope_of)
        _memory_step = jit(memory_step)
        _phi = jit(_phi)
        _slip_ratio_radial = jit(_slip_ratio_radial)
        _slip_ratio = jit(_slip_ratio)
        _KERNEL = jit(_march_falling)
    return _KERNEL
