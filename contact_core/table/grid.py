"""The table's parametrisation: Kalker-reduced creepages on a quarter sphere, and the node axes.

Similarity of the Hertzian problem (Kalker 1967 ch. 2; Kalker 1979 sec. 2): with a/b and ν fixed,
F/(μN) and Mz/(μN c), c = √(ab), depend only on the creepages scaled by G c²/(μN). Scaled once
more by Kalker's coefficients (Kalker 1979, eqs 17-18; Kalker 1990, Table E.3), the reduced
creepages

    u = (C11 ξ, C22 η, C23 c φ) G c² / (μN)

are the linear theory's force contributions in units of μN, so |u| ~ 1 is where saturation sets
in for every a/b (Johnson–Vermeulen's normalised creepage; ``contact_tools.bench.cases``).

The table's coordinates are v = (u_ξ, u_η, w(a/b) u_φ): the spin component is weighted by

    w(a/b) = ((1 + (b/a)²) / 2)^(p/2),   p = ``Axes.spin_power``,

a choice of this package (not a formula of the theory; any w > 0 is exact at the nodes). Why: in
the saturated range the spin's share of the rigid slip, φ·y over the lateral half-width b, is
compared with ξ, so at a/b << 1 spin dominates at a reduced spin far below the reduced creepage:
unweighted, the forces change over a few degrees of θ there, a feature the θ nodes cannot follow.
w ~ (b/a)^p widens it for a/b < 1 and tends to a constant for a/b > 1 (where C23 alone already
spreads it); smooth in a/b, so the interpolation across a/b stays cubic. p = 0.8 and the node
counts (65 θ = 2 × 33 - 1 and 21 ψ = 2 × 11 - 1, so that the rays of coarser builds are reused by
``build --reuse``) were chosen on design studies against the exact solver, and a polar axis on
the angle of the rigid slip's pole (Kalker 1979, eq 35) was tried and not kept: the studies and
their figures are in the design notes, docs/notes/table_build.md.

Symmetries of the problem (exact theory, tests of ``contact_core.exact``): Fx is odd in ξ and Fy,
Mz even; (η, φ) -> (-η, -φ) flips Fy and Mz and keeps Fx. So the table covers v_ξ >= 0, v_η >= 0
(a quarter of the sphere of directions) and the signs are restored afterwards. On it:

* magnitude s = |v| / (1 + |v|) in [0, 1] (s = 1: full sliding);
* polar angle θ = arccos(v_φ/|v|) in [0, π] (0: pure spin φ > 0, π: φ < 0);
* azimuth ψ = atan2(v_η, v_ξ) in [0, π/2] (meaningless, and the values equal, at θ = 0, π).

Tabulated: g = (Fx/(μN), Fy/(μN), Mz/(μN c)) / s, smooth in s on [0, 1]: at s -> 0 it tends to
the linear theory's slopes, at s = 1 to the full-sliding forces. The values f = s g then vanish
exactly at zero creepage.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: |v| used for the node s = 0 (its g is the linear slope) and s = 1 (full sliding: the adhesion
#: zone below 1e-6 of the contact).
R_LINEAR, R_SLIDING = 1e-6, 1e6


@dataclass(frozen=True)
class Axes:
    """Uniform node axes. ``ab``: ln(a/b) from ``ab_lo`` to ``ab_hi`` (``n_ab`` nodes); ``nu``:
    Poisson's ratios (``n_nu`` nodes from ``nu_lo`` to ``nu_hi``); θ on [0, π], ψ on [0, π/2],
    s on [0, 1]; ``spin_power``: p of the spin weight (module docstring).

    ``ghost_below`` (0 or 1): a row of nodes one step of ln(a/b) below ``ab_lo``, solved like
    the others but only read by the cubic stencil of the first interval, which it makes central
    instead of one-sided (Lagrange's error constant of the one-sided cubic is about 4 times the
    central one's); the table's domain stays [``ab_lo``, ``ab_hi``]. No such row above
    ``ab_hi``: Kalker's coefficients end at a/b = 10, and a trial row there did not help
    (docs/notes/table_build.md)."""

    ab_lo: float = 0.1
    ab_hi: float = 10.0
    n_ab: int = 9
    nu_lo: float = 0.25
    nu_hi: float = 0.30
    n_nu: int = 2
    n_theta: int = 65
    n_psi: int = 21
    n_s: int = 32
    spin_power: float = 0.8
    ghost_below: int = 0

    def __post_init__(self) -> None:
        for name in ("n_theta", "n_psi", "n_s"):
            if getattr(self, name) < 4:     # the lookup is cubic on these axes (4 nodes)
                raise ValueError(f"{name}={getattr(self, name)!r} is invalid: allowed >= 4")
        if self.ghost_below not in (0, 1):
            raise ValueError(f"ghost_below={self.ghost_below!r} is invalid: allowed 0 or 1")

    @property
    def shape(self) -> tuple[int, int, int, int, int]:
        """Of the stored nodes: the a/b rows include the ghost row."""
        return (self.ghost_below + self.n_ab, self.n_nu, self.n_theta, self.n_psi, self.n_s)

    def ab_step(self) -> float:
        """The step of ln(a/b) between rows."""
        return math.log(self.ab_hi / self.ab_lo) / max(self.n_ab - 1, 1)

    def a_over_b(self) -> np.ndarray:
        """a/b of every stored row, the ghost row included (the rows inside [ab_lo, ab_hi]
        computed as without it: their rays are the same to the bit)."""
        inside = np.exp(np.linspace(math.log(self.ab_lo), math.log(self.ab_hi), self.n_ab))
        ghost = [math.exp(math.log(self.ab_lo) - self.ab_step())] * self.ghost_below
        return np.concatenate([ghost, inside])

    def nu(self) -> np.ndarray:
        return np.linspace(self.nu_lo, self.nu_hi, self.n_nu)

    def theta(self) -> np.ndarray:
        return np.linspace(0.0, math.pi, self.n_theta)

    def psi(self) -> np.ndarray:
        return np.linspace(0.0, 0.5 * math.pi, self.n_psi)

    def s(self) -> np.ndarray:
        return np.linspace(0.0, 1.0, self.n_s)

    def to_record(self) -> dict[str, float | int]:
        """The fields, without ``ghost_below`` when 0 (as in the tables built before it, whose
        recorded configuration and digest stay valid)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__
                if not (k == "ghost_below" and self.ghost_below == 0)}

    def spin_weight(self, a_over_b: float) -> float:
        """w(a/b), the weight of the reduced spin in the table's coordinates (module docstring)."""
        return spin_weight(a_over_b, self.spin_power)


def spin_weight(a_over_b: float, power: float) -> float:
    """w(a/b) = ((1 + (b/a)²)/2)^(p/2), p = ``power`` (module docstring; numba compiles it in the
    lookup, :mod:`.interp`)."""
    return ((1.0 + a_over_b ** -2) / 2.0) ** (0.5 * power)


def node_magnitude(s: float) -> float:
    """|v| of the nodes at s: s/(1 - s), and ``R_LINEAR``, ``R_SLIDING`` at s = 0, 1."""
    return R_LINEAR if s <= 0.0 else R_SLIDING if s >= 1.0 else s / (1.0 - s)


def node_reduced_creepage(theta: float, psi: float, s: float, w: float) -> np.ndarray:
    """The reduced creepage u of a node (θ, ψ, s) of a table of spin weight ``w`` (s = 0 and 1 at
    |v| = ``R_LINEAR``, ``R_SLIDING``)."""
    r = node_magnitude(s)
    st = math.sin(theta)
    return r * np.array([st * math.cos(psi), st * math.sin(psi), math.cos(theta) / w])


def creepages_from_reduced(u: np.ndarray, c11: float, c22: float, c23: float, c: float,
                           k: float) -> tuple[float, float, float]:
    """(ξ, η, φ) of the reduced creepage u, k = G c²/(μN)."""
    return (float(u[0]) / (c11 * k), float(u[1]) / (c22 * k), float(u[2]) / (c23 * c * k))
