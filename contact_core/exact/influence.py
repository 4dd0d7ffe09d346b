"""Influence coefficients of the elastic half-space for piecewise-constant tractions on a grid.

Two quasi-identical half-spaces (same G, ν), tractions ``(X, Y, Z)`` on the wheel, displacement
difference ``u = u_wheel - u_rail`` (Kalker 1979 sec. 2). Boussinesq–Cerruti (Kalker 1979 eq 8;
Love, *A Treatise on the Mathematical Theory of Elasticity*, 4th ed. 1927, p. 243; Kalker 1990,
*Three-Dimensional Elastic Bodies in Rolling Contact*, sec. 1.5):

    u_x = 1/(πG) ∬ [((1-ν)/R + ν X²/R³) X + ν X Y/R³ · Y] dA',
    u_y = 1/(πG) ∬ [ν X Y/R³ · X + ((1-ν)/R + ν Y²/R³) Y] dA',
    u_z = (1-ν)/(πG) ∬ Z/R dA',                      X = x - x', Y = y - y', R = √(X²+Y²).

For quasi-identical bodies the normal–tangential coupling term (1-2ν)/(2πG) ∬ X/R² ... of one
body cancels against that of the other, so the normal and tangential problems are uncoupled
(Kalker 1990, sec. 1.5).

Constant traction over the rectangle |x'-x_j| <= dx/2, |y'-y_j| <= dy/2 gives the integrals in
closed form (Love 1929, *The stress produced in a semi-infinite solid by pressure on part of the
boundary*, Phil. Trans. R. Soc. A 228, 377-420, for 1/R; the others follow the same way). With
the primitives (∂²P/∂X∂Y equal to the integrand; asinh-form so that every corner is finite):

    1/R      :  P_R  = X asinh(Y/|X|) + Y asinh(X/|Y|)
    X²/R³    :  P_xx = Y asinh(X/|Y|)
    Y²/R³    :  P_yy = X asinh(Y/|X|)
    X Y/R³   :  P_xy = -R

the integral over the element centred at offset (X, Y) is the mixed difference
P(X+hx, Y+hy) - P(X+hx, Y-hy) - P(X-hx, Y+hy) + P(X-hx, Y-hy) (hx, hy: half-widths). (A term
X asinh(Y/|X|) differs from X ln(Y+R) by X ln|X|, a function of X only, which the mixed
difference removes.) All integrals scale with the length of the element: they are computed once,
dimensionless, with lengths in units of ``dx``, per (grid shape, dy/dx, ν) and cached.

Stored as *flipped tables* for the row-wise dot products of :mod:`.tangential`: entry
``K[iy_off + my - 1, t]`` is the coefficient at element offset ``(dix, diy) = (mx - t, iy_off)``,
``t = 0 .. 2 mx - 1`` (dix from mx down to -(mx-1)), ``diy = -(my-1) .. my-1``.
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from ..cache import cached


def _p_r(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    return _p_yy(X, Y) + _p_xx(X, Y)


def _p_xx(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    aY = np.abs(Y)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(aY > 0.0, Y * np.arcsinh(X / np.where(aY > 0.0, aY, 1.0)), 0.0)


def _p_yy(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    return _p_xx(Y, X)


def _p_xy(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    return -np.hypot(X, Y)


def _rect(prim, X: np.ndarray, Y: np.ndarray, hx: float, hy: float) -> np.ndarray:
    return (prim(X + hx, Y + hy) - prim(X + hx, Y - hy)
            - prim(X - hx, Y + hy) + prim(X - hx, Y - hy))


@cached(32)
def element_integrals(mx: int, my: int, ratio: float) -> tuple[np.ndarray, ...]:
    """Dimensionless rectangle integrals ``(I_R, I_xx, I_yy, I_xy)`` in units of ``dx``.

    ``ratio = dy/dx``. Arrays of shape ``(2 my - 1, 2 mx)`` in the flipped layout of the module
    docstring (x offsets mx .. -(mx-1), y offsets -(my-1) .. my-1). Read-only.
    """
    dix = mx - np.arange(2 * mx, dtype=float)              # mx .. -(mx-1)
    diy = np.arange(-(my - 1), my, dtype=float) * ratio    # in units of dx
    X, Y = np.meshgrid(dix, diy)                            # shape (2my-1, 2mx)
    hx, hy = 0.5, 0.5 * ratio
    out = tuple(_rect(p, X, Y, hx, hy) for p in (_p_r, _p_xx, _p_yy, _p_xy))
    for a in out:
        a.setflags(write=False)
    return out


@cached(32)
def tangential_tables(mx: int, my: int, ratio: float, nu: float) -> tuple[np.ndarray, ...]:
    """``(Kxx, Kxy, Kyy)``: πG/dx times the displacement per unit traction (flipped layout).

    ``u_i = dx/(πG) Σ_j K(i - j) p_j`` (Kalker 1979, eq 8 integrated over the element).
    """
    ir, ixx, iyy, ixy = element_integrals(mx, my, ratio)
    kxx = np.ascontiguousarray((1.0 - nu) * ir + nu * ixx)
    kyy = np.ascontiguousarray((1.0 - nu) * ir + nu * iyy)
    kxy = np.ascontiguousarray(nu * ixy)
    for a in (kxx, kxy, kyy):
        a.setflags(write=False)
    return kxx, kxy, kyy


@cached(32)
def normal_kernel_fft(mx: int, my: int, ratio: float) -> np.ndarray:
    """rfft2 of the normal kernel I_R, wrapped on the zero-padded (2 my, 2 mx) grid.

    With ``P`` the pressure zero-padded to (2 my, 2 mx), ``irfft2(F * rfft2(P))[:my, :mx]``
    is the linear (non-circular) convolution ``Σ_j I_R(i - j) p_j`` (``u_z = (1-ν) dx/(πG)``
    times it).
    """
    ir = element_integrals(mx, my, ratio)[0]
    wrapped = np.zeros((2 * my, 2 * mx))
    dix = mx - np.arange(2 * mx)
    diy = np.arange(-(my - 1), my)
    wrapped[np.ix_(diy % (2 * my), dix % (2 * mx))] = ir
    f = sfft.rfft2(wrapped, workers=1)
    f.setflags(write=False)
    return f
