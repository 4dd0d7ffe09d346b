"""The linearised 4-state wheelset with Kalker's linear creep coefficients, for the summary.

States x = (y, ψ, ẏ, ψ̇); per contact f11 = G c² C11, f22 = G c² C22, f23 = G c³ C23,
f33 = G c⁴ C33 (Kalker's linear theory, c² = ab; Wickens 2003 uses f11, f22 and, with
spin, f23, f33). With the kinematics of ``wheelset_dynamics`` (equal loads, so the constant spin
±λ/r0 cancels between the wheels):

    m ÿ   + 2f22 (ẏ/V - ψ) + 2f23 ψ̇/V + k_y y = 0
    I_z ψ̈ + 2f11 b0 (λy/r0 + b0ψ̇/V) - 2f23 (ẏ/V - ψ) + 2f33 ψ̇/V + k_ψ ψ = 0

The critical speed V_c is where the largest real part of the eigenvalues of the state matrix
crosses zero. :func:`cosim_matrix` is the exact discrete map of the co-simulation of the same
linear system with the creep forces held over a step h (Gauss-Seidel: forces of x_k; Jacobi: of
x_{k-1}): its spectral radius > 1 is the numerical instability of a too-large communication step.
The tests re-derive all of this independently (``tests/test_wheelsets.py``).
:func:`coupling_map` is the exact discrete map of the explicit and of the linearly implicit
coupling of ``master.py`` (constant and linear hold) of the same system, the reference of
``examples/run_implicit_coupling.py`` and ``tests/test_implicit_coupling.py``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm
from scipy.optimize import brentq

from .systems import creep_coefficients_f


class LinearWheelset:
    def __init__(self, m=1500.0, I_z=800.0, r0=0.46, b0=0.75, conicity=0.15, k_y=1e6, k_psi=2e6,
                 axle_load=100e3, E=210e9, nu=0.28, R_rail=0.3):
        self.m, self.I_z, self.r0, self.b0, self.lam = m, I_z, r0, b0, conicity
        self.k_y, self.k_psi = k_y, k_psi
        self.f = creep_coefficients_f(N=0.5 * axle_load, r0=r0, R_rail=R_rail, E=E, nu=nu)

    def split(self, V):
        """(A_s, B_s, K_c): suspension-only dynamics ẋ = A_s x + B_s u and the creep forces
        u = (Fy_total, Mz_total) = K_c x."""
        f11, f22, f23, f33 = (self.f[k] for k in ("f11", "f22", "f23", "f33"))
        Mi = np.diag([1 / self.m, 1 / self.I_z])
        As = np.block([[np.zeros((2, 2)), np.eye(2)],
                       [-Mi @ np.diag([self.k_y, self.k_psi]), np.zeros((2, 2))]])
        Bs = np.vstack([np.zeros((2, 2)), Mi])
        stiff = np.array([[0.0, -2 * f22], [2 * f11 * self.b0 * self.lam / self.r0, 2 * f23]])
        damp = np.array([[2 * f22 / V, 2 * f23 / V],
                         [-2 * f23 / V, (2 * f11 * self.b0 ** 2 + 2 * f33) / V]])
        return As, Bs, -np.hstack([stiff, damp])

    def matrix(self, V):
        As, Bs, Kc = self.split(V)
        return As + Bs @ Kc

    def hunting_eigenvalue(self, V):
        ev = np.linalg.eigvals(self.matrix(V))
        osc = ev[ev.imag > 1e-9]
        return osc[np.argmax(osc.real)]

    def critical_speed(self, lo=1.0, hi=300.0):
        g = lambda V: np.linalg.eigvals(self.matrix(V)).real.max()
        return brentq(g, lo, hi, xtol=1e-10)

    def cosim_matrix(self, V, h, scheme="gauss-seidel"):
        As, Bs, Kc = self.split(V)
        aug = np.zeros((6, 6))
        aug[:4, :4], aug[:4, 4:] = As * h, Bs * h
        E = expm(aug)
        Phi, Gam = E[:4, :4], E[:4, 4:]
        if scheme == "gauss-seidel":
            return Phi + Gam @ Kc
        return np.block([[Phi, Gam @ Kc], [np.eye(4), np.zeros((4, 4))]])

    def step_limit(self, V, scheme="gauss-seidel", lo=1e-5, hi=0.1):
        """Smallest communication step whose discrete map has a spectral radius above that of the
        exact flow's (exp(h max Re λ)): the explicit coupling's stability limit."""
        sc = np.linalg.eigvals(self.matrix(V)).real.max()

        def excess(h):
            rho = np.abs(np.linalg.eigvals(self.cosim_matrix(V, h, scheme))).max()
            return math.log(rho) / h - max(sc, 0.0) - 1e-3

        hs = np.geomspace(lo, hi, 200)
        vals = [excess(h) for h in hs]
        i = next(i for i, v in enumerate(vals) if v > 0)
        return brentq(excess, hs[i - 1], hs[i], xtol=1e-9)

    def tau(self, V):
        return min(self.m * V / (2 * self.f["f22"]),
                   self.I_z * V / (2 * self.f["f11"] * self.b0 ** 2))

    def curving(self, R):
        """Steady state (y, ψ) in a curve of radius R at balance speed (independent of V)."""
        f11, f22, f23, f33 = (self.f[k] for k in ("f11", "f22", "f23", "f33"))
        M = np.array([[-self.k_y, 2 * f22],
                      [-2 * f11 * self.b0 * self.lam / self.r0, -2 * f23 - self.k_psi]])
        rhs = np.array([2 * f23 / R, 2 * f11 * self.b0 ** 2 / R + 2 * f33 / R])
        return np.linalg.solve(M, rhs)


# ------------------------------------------------------------------------------------------------
# Exact discrete maps of the couplings of master.py (explicit, linearly implicit)
# ------------------------------------------------------------------------------------------------
def coupling_map(lw: LinearWheelset, V: float, h: float, scheme: str = "gauss-seidel",
                 hold: str = "constant") -> np.ndarray:
    """x_{k+1} = M x_k for the linear wheelset (x = y, ψ, ẏ, ψ̇) with the creep forces u = K x
    exchanged every h: explicit (``scheme="gauss-seidel"``), u_k held; linearly implicit (exact
    for a linear law), u_{k+1} held (``hold="constant"``) or u ramped from u_k to u_{k+1}
    (``hold="linear"``, Busch 2016's first-order hold). The suspension is integrated exactly:
    Φ = e^{A h}, Γ0 = ∫ e^{A(h-s)} B ds and Γ1 = ∫ e^{A(h-s)} B s/h ds are blocks of the
    exponential of the system augmented by the hold's polynomial (C. F. Van Loan, "Computing
    integrals involving the matrix exponential", IEEE Trans. Automatic Control 23 (1978)
    395-404, block-triangular exponential); the maps are derived here from them."""
    As, Bs, K = lw.split(V)
    aug = np.zeros((8, 8))
    aug[:4, :4], aug[:4, 4:6], aug[4:6, 6:8] = As, Bs, np.eye(2)
    E = expm(aug * h)
    Phi, G0, G1 = E[:4, :4], E[:4, 4:6], E[:4, 6:8] / h   # G1: response to the ramp (t/h) u
    I = np.eye(4)
    if scheme == "gauss-seidel":
        return Phi + G0 @ K
    if hold == "constant":
        return np.linalg.solve(I - G0 @ K, Phi)
    return np.linalg.solve(I - G1 @ K, Phi + (G0 - G1) @ K)


def hunting_multiplier(lw: LinearWheelset, V: float, h: float, scheme: str = "gauss-seidel",
                       hold: str = "constant") -> complex:
    """The eigenvalue of :func:`coupling_map` that continues exp(λ h) of the hunting mode."""
    ev = np.linalg.eigvals(coupling_map(lw, V, h, scheme, hold))
    return complex(ev[np.argmin(np.abs(ev - np.exp(lw.hunting_eigenvalue(V) * h)))])


def creep_mode_excess(lw: LinearWheelset, V: float, h: float, scheme: str = "gauss-seidel",
                      hold: str = "constant") -> float:
    """The largest modulus of the map's eigenvalues other than the hunting pair, minus 1 (> 0:
    the coupling is numerically unstable)."""
    ev = np.linalg.eigvals(coupling_map(lw, V, h, scheme, hold))
    hunting = np.exp(lw.hunting_eigenvalue(V) * h)
    ev = ev[np.argsort(np.minimum(np.abs(ev - hunting), np.abs(ev - np.conj(hunting))))[2:]]
    return float(np.abs(ev).max()) - 1.0


def explicit_limit(lw: LinearWheelset, V: float) -> float:
    """The explicit coupling's stability limit: the smallest step at which an eigenvalue of its
    :func:`coupling_map` other than the hunting pair leaves the unit circle (≈ 2τ)."""
    hs = np.geomspace(1e-4, 0.05, 200)
    i = next(i for i, h in enumerate(hs) if creep_mode_excess(lw, V, h) > 0)
    return brentq(lambda h: creep_mode_excess(lw, V, h), hs[i - 1], hs[i], xtol=1e-10)
