"""Local falling friction in the exact solver: each element's bound at its own slip velocity.

With the effect ``falling_friction`` (:mod:`contact_core.friction`) the traction bound of element
i is μ_i p_n,i, μ_i the friction at the element's slip velocity s_i = V |w_i| (w the true slip
per rolling speed, :func:`.sweeps.slip_field`), through the friction memory along its row
(μ_i = θ μ_upstream + (1 - θ) μ(s_i), from μ_stat at the leading edge; θ = d_c/(d_c + (dx/V)
max(s_i, s_0))). The bound depends on the solution and the solution on the bound; as CONTACT does
(Vollebregt, CONTACT user guide, "Slip velocity dependent friction" and its parameters INISLP,
OMGSLP; E. A. H. Vollebregt & H. M. Schuttelaars, *Quasi-static analysis of 2-dimensional
rolling contact with slip-velocity dependent friction*, J. Sound Vib. 331 (2012) 2141-2155;
E. A. H. Vollebregt, *Numerical modeling of measured railway creep versus creep-force curves
with CONTACT*, Wear 314 (2014) 87-95), an outer fixed-point iteration alternates:

1. the friction field from the current slip (:func:`friction_field`),
2. the steady-rolling problem with that field as a fixed Coulomb bound (the Gauss–Seidel solver
   of :mod:`.sweeps`, warm-started from the previous tractions),

until the friction field changes by less than the tolerance. It starts from static friction, the
no-slip field (CONTACT's INISLP < 0, "approximated from below": the low-slip solution where a
falling law allows several). Each update of the field is relaxed, μ ← μ + ω (μ_new - μ), ω
halved whenever the change grows (a falling law makes the plain iteration overshoot: more slip,
less friction, more slip), down to 1/16; the result carries ``converged=False`` (and the solver
warns) if the field has not settled within the outer iteration limit.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numba import njit

from ..friction import memory_step, ratio_of
from .sweeps import EXTERIOR

_ratio = njit(cache=True)(ratio_of)
_memory_step = njit(cache=True)(memory_step)

#: Outer iterations at most, and the smallest relaxation factor.
MAX_OUTER, OMEGA_MIN = 200, 1.0 / 16.0


@njit(cache=True)
def friction_field(speed_w: np.ndarray, status: np.ndarray, law, dt_per_v: float,
                   memory: float) -> np.ndarray:
    """μ/μ_stat per element (rows y, columns x; the leading edge at the largest x) from the slip
    velocities ``speed_w`` (m/s) along each row from the leading edge: θ-weighted with the
    upstream element's coefficient (``memory`` = d_c > 0, ``dt_per_v`` = dx/V) or the law
    itself; 1 outside the contact."""
    my, mx = speed_w.shape
    out = np.ones((my, mx))
    s0 = law[7]
    for iy in range(my):
        up = 1.0
        for ix in range(mx - 1, -1, -1):
            if status[iy, ix] == EXTERIOR:
                up = 1.0
                continue
            s = speed_w[iy, ix]
            rho = _memory_step(up, _ratio(law, s), s, memory, dt_per_v, s0)
            out[iy, ix] = rho
            up = rho
    return out


def local_friction(solve: Callable, slip: Callable, first: tuple, static_bound: np.ndarray,
                   law: tuple, speed: float, dt_per_v: float, memory: float,
                   tol: float) -> tuple:
    """The outer iteration of the module docstring.

    ``solve(px, py, bound)`` solves the Coulomb problem with the given bound from the given
    start and returns ``(sweeps, rel, px, py, status, qx, qy)``; ``first`` is its result with
    the static bound; ``slip(px, py, qx, qy, status)`` the slip per rolling speed (wx, wy) in the
    true problem's units; ``static_bound`` μ_stat p_n/G per element; ``speed`` V (m/s).
    Returns ``solve``'s tuple of the last solve with the total sweeps, and the number of outer
    iterations and the final change of the friction field (max over the contact).
    """
    sweeps, rel, px, py, status, qx, qy = first
    ratio = np.ones_like(static_bound)
    omega = 1.0
    change = math.inf
    last = math.inf
    outer = 0
    while outer < MAX_OUTER:
        wx, wy = slip(px, py, qx, qy, status)
        target = friction_field(speed * np.hypot(wx, wy), status, law, dt_per_v, memory)
        step = target - ratio
        change = float(np.abs(step).max())
        if change <= tol:
            break
        if change > last and omega > OMEGA_MIN:
            omega *= 0.5
        last = change
        ratio = ratio + omega * step
        bound = static_bound * ratio
        absp = np.hypot(px, py)
        over = absp > bound
        if over.any():
            f = np.where(over, bound / np.where(over, absp, 1.0), 1.0)
            px = px * f
            py = py * f
        it, rel, px, py, status, qx, qy = solve(px, py, bound)
        sweeps += it
        outer += 1
    return (sweeps, rel, px, py, status, qx, qy), outer, change
