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
compared with ξ, so at a/b << 1 spin dominates at a reduced spin far below the reduced creepage.
Measured on the exact solver at a/b = 0.1, |u| = 1: Fx falls from 0.71 to 0.43 μN when u_φ/u_ξ
goes from 0 to 0.13 (7.5° of θ), a feature the θ nodes cannot follow. w ~ (b/a)^p widens it
for a/b < 1 and tends to a constant for a/b > 1 (where C23 alone already spreads it); smooth in
a/b, so the interpolation across a/b stays cubic. p = 0.8 and the node counts were chosen on a
design study (exact 20×20 stand-in, 400 random states per a/b; |F| and Mz max error, % of μN and
μN·c, at a/b = 0.1): w = 1 on 25 × 13 θ × ψ nodes 8.5 / 26; p = 0.8 on 33 × 11: 0.66 / 1.4.
Then, with the exact solver's nodes (80×80 at small a/b), the largest held-out errors were near
full sliding, where the force turns with the spin share over a few degrees of θ. A second design
study (FASTSIM 20×20 elliptic as stand-in, the 2000 held-out states of ``check``, interpolation
error only, |F| / Mz max): 33 × 11 θ × ψ nodes 1.13 / 0.97; 65 θ nodes 0.84 / 0.52; 21 ψ nodes
1.12 / 1.04; 48 s nodes 1.10 / 1.04; 13 a/b nodes 1.14 / 0.99. Hence 65 θ nodes, 2 × 33 - 1, so
that the 33-node build's rays are reused (``build --reuse``). Measured on the exact nodes
afterwards (interpolation error alone: table against the exact solver at the nodes' own setting,
2000 states sampled like ``check``'s hard region, |F| / Mz p95 and max): 33 θ: 0.56 / 0.43 and
1.76 / 4.51; 65 θ: 0.46 / 0.23 and 1.69 / 3.68. Most of the largest errors that remain (the
2000 held-out states and the hard region of ``check``) lie where the pole of the rigid slip,
(-η/φ, ξ/φ) (Kalker 1979, eq 35), crosses the contact's edge: near full sliding the forces are
not smooth there, and in these coordinates that crossing runs obliquely between the nodes of
every axis (measured on the exact solver along θ at a/b = 0.195, ψ = 3.3°, s = 0.959: cubic
interpolation 0.3-0.6 % of μN off around the crossing). A polar axis on the pole's angle,
tan θ' = √((ξ/b)² + (η/a)²)/φ, puts that crossing on the nodes θ' = π/4, 3π/4 (along θ there,
0.05 %), but was worse overall: one row of it solved (a/b = 0.1, ν = 0.25, 65 × 11 nodes, exact
80×80 extrapolated) and compared at that a/b and ν with this table, both against the exact solver
at the same setting, 120 random directions and 120 states of ``check``'s hard region, |F| / Mz
max: this table 0.33 / 0.14 and 2.08 / 1.17 %; the pole angle 1.70 / 6.88 and 5.06 / 9.73 %. At
a fixed distance the pole turns about the centre within a few degrees of ψ near pure ξ (at
a/b = 0.1 the pole's lateral position is 13 times as sensitive to η as its longitudinal one to
ξ), which the ψ nodes do not follow.
Hence 21 ψ nodes, 2 × 11 - 1 (the 11-node build's rays reused). Measured on the exact solver
(80×80 extrapolated at a/b = 0.1, 48×48 at a/b = 10) along ψ over the 27° next to an end, at
fixed θ and s taken from the worst states above, cubic interpolation with the ghost nodes, |F|
max in % of μN, four lines: 11 uniform nodes 2.25, 0.73, 1.59, 1.02; 21 uniform 0.42, 0.09,
0.58, 0.22; 11 nodes clustered at both ends (ψ = (π/4)(1 - cos πχ), χ uniform) 0.87, 0.96,
0.47, 0.29; 15 such nodes 0.54, 0.30, 0.21, 0.34. (Mz: 0.19-0.68 with 11 uniform nodes,
0.09-0.31 with 21.) On the row a/b = 0.1, ν = 0.25 of the 21-node build and the same 240
states as the pole-angle trial above (|F| / Mz, p95 and max): random directions 11 nodes 0.18 /
0.03 and 0.33 / 0.14, 21 nodes 0.18 / 0.03 and 0.34 / 0.14; hard region 11 nodes 0.50 / 0.19 and
2.08 / 1.17, 21 nodes 0.31 / 0.27 and 0.81 / 1.07 (the reference itself scatters: with the
spin pole inside the contact, the exact solver's values 0.35° apart in θ had second differences
of 0.2-0.4 % of μN at a/b = 0.195). The whole 21-node table against the converged exact
solver (``check``, |F| / Mz max, 11 nodes before): 2000 random states 0.97 / 1.00 (0.94 / 0.97),
hard region 1.08 / 0.87 (1.09 / 1.20), spin band 1.22 / 1.52 (the same): less than the lines
above promised, because near full sliding the θ crossing dominates and in the spin band the
nodes' own error does.

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
    instead of one-sided; the table's domain stays [``ab_lo``, ``ab_hi``]. Measured on the four
    worst states of ``check``'s hard region with a/b in [0.1, 0.178] (the row a/b = 0.0562
    solved, 80×80 extrapolated, for their stencils only), |F| error in % of μN: 1.03 -> 0.31,
    0.94 -> 0.31, 0.91 -> 0.14, 0.30 -> 0.36 (Lagrange's error constant of the one-sided cubic
    is about 4 times the central one's; the row's grid: ``build``). No such row above
    ``ab_hi``: a/b = 17.8 (48×48) took the four worst states of the spin band with a/b in
    [5.62, 10] from 0.21, 0.71, 0.65, 0.56 to 0.29, 0.71, 0.49, 0.45 % of μN, and Kalker's
    coefficients end at a/b = 10."""

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
