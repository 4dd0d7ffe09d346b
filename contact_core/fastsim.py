"""Kalker's FASTSIM: the simplified theory of rolling contact, solved strip by strip.

Simplified theory (Kalker 1979, sec. 5, eqs 34-36) replaces the elastic half-space by a bed of
independent springs: the tangential displacement is u = L p (eq 34), with a flexibility L (m/Pa)
and the traction p bounded by |p| <= g = μ p_n (Coulomb). In steady rolling the slip is
ẇ = V[(ξ - φy, η + φx) - ∂u/∂x] (eq 35); in the stick zone ẇ = 0, in the slip zone p = -g ẇ/|ẇ|
(eq 36). FASTSIM (Kalker 1979/80; J. J. Kalker, *A fast algorithm for the simplified theory of
rolling contact*, Vehicle System Dynamics 11 (1982) 1-13) follows the particles from the leading
edge x = +a(y) of each strip y = const. to its trailing edge x = -a(y), and per step τ > 0
(Kalker 1979, eq 38):

    p_H(x) = p(x + τ) - (1/L) ∫_x^{x+τ} (ξ - φy, η + φx') dx'
           = p(x + τ) - (τ/L) (ξ - φy, η + φ(x + τ/2)),
    p(x)   = p_H                if |p_H| <= g(x)   (stick)
           = g(x) p_H / |p_H|   otherwise          (slip: scaled back onto the traction bound).

The rigid-slip integral is exact with the midpoint x + τ/2 (Kalker 1979, eq 37, the stick-zone
solution ``L_y Y(x) = L_y Y(x0) + [η + φ(x + x0)/2](x - x0)``), so in full stick the marched
tractions are exactly Kalker's linear simplified solution (Kalker 1979, eq 16) at the grid points
when the march starts at the leading edge itself (scheme "midpoint"; "kalker" starts half an
element ahead of it, see below).
Signs: with ξ > 0 the traction (rail on wheel) is negative, as in linear theory
(``Fx = -G c² C11 ξ``, Kalker 1979, eq 17).

Flexibilities (Kalker 1982; also Kalker 1990, *Three-Dimensional Elastic Bodies in Rolling
Contact*, sec. 3.3): integrating the stick solution over the ellipse and equating the forces to
linear theory (Kalker 1979, eq 17) defines one flexibility per creepage,

    L1 = 8a / (3 G C11),   L2 = 8a / (3 G C22),   L3 = π a √(a/b) / (4 G C23),

(check: p_x = -ξ (a(y) - x)/L1 gives Fx = -(8/3) a² b ξ / L1 = -G ab C11 ξ;
p_y = -φ(a(y)² - x²)/(2 L3) gives Fy = -(π/4) a³ b φ / L3 = -G (ab)^{3/2} C23 φ.) These are the
flexibilities CONTACT uses in its FASTSIM (the tests compare them with the FLX1..3 its
``tractcurv`` example lists).

Option ``flexibility``:

``"separate"`` — each creepage with its own flexibility (Kalker 1982; CONTACT): in stick
    dp_x/dx = ξ/L1 - φy/L3, dp_y/dx = η/L2 + φx/L3, so every linear term of Kalker's linear theory
    (C11 ξ, C22 η, C23 φ) is reproduced at once, also for combined creepage. In the slip zone the
    stick predictor p_H is brought onto the traction bound along the slip of a bed with the
    flexibility tensor diag(Lx, Ly) (Kalker 1979, eq 34, u = L p, with a diagonal L): the slip
    over a step is S = diag(Lx, Ly) (p - p_H) and p = -g S/|S|, i.e. p_i = p_H,i/(1 + λ/L_i) with
    the one λ > 0 that puts |p| on g (the slip law's projection, below). Lx, Ly weight L1, L2 with
    L3 by the shares of creepage and spin, Lx = (L1|ξ| + L3 c|φ|)/(|ξ| + c|φ|),
    Ly = (L2|η| + L3 c|φ|)/(|η| + c|φ|), so that with L1 = L2 = L3 this is FASTSIM's radial
    projection, and in full sliding under (ξ, η) the force is opposite to the creepage (μN at the
    angle of (ξ, η) as the creepage grows; a radial projection would keep the angle of
    (ξ/L1, η/L2) instead).
``"weighted"`` — Kalker 1982's single flexibility for all directions (Kalker 1979, sec. 5)

    L = (L1 |ξ| + L2 |η| + L3 c |φ|) / √(ξ² + η² + c² φ²),   c = √(ab),

    which reduces to L1, L2 or L3 for pure ξ, η or φ (the two options then agree exactly). For
    combined creepage it is too flexible (at ξ = η, L ≈ √2 times the mean of L1 and L2), and so
    far from the exact theory under (ξ, η) (docs/notes/fastsim.md).

``"blended-contact"`` — Vollebregt and Voltr's blend (E. A. H. Vollebregt & P. Voltr, *Improved
    accuracy for FASTSIM using one or three flexibility values*, Vehicle System Dynamics 61 (2023)
    309-317; the default FASTSIM of CONTACT, M=3): "separate" in the linear range, moving towards
    one flexibility for all directions as the creepage (ξ, η) grows,

        L_i -> (1 - w) L_i + w L_c,   L_c = (ξ² + η² + s²) / (ξ²/L1 + η²/L2 + s²/L3),  s = 3πaφ/32,
        w = min(1, |(ξ, η)| / (3 |(ξ_c, η_c)|)),  ξ_c = μN/(G c² C11),  η_c = μN/(G c² C22)

    (ξ_c, η_c: where linear theory reaches μN; the weights and the factor 3 as in CONTACT's
    ``simpflex``). Pure ξ, η or φ are as with "separate" (L_c = L1 or L2; w = 0 without ξ, η), and
    so is the linear range (w -> 0); without the saturation effect nothing slides and neither
    blend applies. The slip law of both blends is that of "separate" with one flexibility for the
    creepage's part, L_c of (ξ, η) alone, (ξ² + η²)/(ξ²/L1 + η²/L2) of the blended L1, L2, in both
    directions (the spin's part L3, by the shares as above): the bed the blend moves towards, so
    under (ξ, η) the slip zone's traction is the stick predictor scaled radially onto the bound,
    as in CONTACT's FASTSIM, and once w = 1, in full sliding, opposite to the creepage. Against the
    converged exact theory this turns the force under (ξ, η) towards the exact direction, where
    the anisotropic slip law of "separate" with the blended flexibilities turned it past
    (docs/notes/fastsim.md); with this slip law the option reproduces CONTACT's own FASTSIM where
    the blend moves CONTACT's (tests).
``"blended"`` (default) — the same blend with w scaled by a power of the creepage's share of
    the linear force, w -> w (F_c / (F_c + F_φ))^p, F_c = |(C11 ξ, C22 η)|, F_φ = C23 c |φ| (this
    package's): Vollebregt and Voltr's weight grows with (ξ, η) alone, so a large spin beside a
    large creepage had its own flexibility L3 replaced by the creepage's; with the share, w goes
    from 0 at pure spin to theirs at pure creepage continuously along the direction of the
    creepage. p = 1 with the parabolic bound, p = 1/3 with the elliptic one (``SHARE_POWER``; the
    two bounds answer the blend in opposite ways). With the parabolic bound the spin term -φy of
    the longitudinal slip has its own flexibility L3^(1-q) L4^q, q = 1/2 (``MOMENT_POWER``), also
    without the saturation effect: with L3 in both spin terms, simplified theory's moment under
    pure spin in stick is Mz = -(8/15) a² b³ φ / L3 (Kalker 1979, eq 16 integrated over the
    ellipse; only -φy contributes), an effective C33 = 32 C23 (b/a)^{3/2} / (15π), below C33 and
    the further the more elongated the contact; Kalker's rule for the flexibilities (1979, sec. 5:
    each fitted to a coefficient of linear theory) gives that term its own L4 = 8b/(15 G C33).
    Under (ξ, η) without spin both blends stay close to "separate"; with spin the blend is what
    they gain (docs/notes/fastsim.md).

How the exponents p and q, the scheme and the bound's default were chosen, against the converged
exact theory and against CONTACT's own FASTSIM (M=3, built from its source, eve70a/CONTACT d431cdb;
its results are data in the tests), and the variants tried and not kept, are in
docs/notes/fastsim.md; ``python -m contact_tools.fastsim_vs_contact`` regenerates the comparison
with CONTACT's FASTSIM (docs/reports/fastsim_vs_contact.md). The tests hold the default to it:
with spin and creepage it is not behind CONTACT's FASTSIM on the same number of elements.

The slip law's projection: with Lx ≠ Ly the slipping traction is p = (p_H,x/(1 + s),
p_H,y r/(r + s)), r = Ly/Lx, with the one s = λ/Lx > 0 that puts |p| on g, a quartic in s. The
march takes it in one step, without branches, so that it vectorises (``_project``): from its
expansion to second order in r - 1 about the radial projection (exact for r = 1), one step of
Householder's method of order 3 on the condition (a/(1 + s))² + (b r/(r + s))² = 1 (a, b =
p_H/g), scaled onto the bound. The step's residual decides: where it is not within
``_PROJECTION_TOL`` of the bound, the whole march is done again with every such element solved
exactly, by Newton's method on the secular equation 1/|p(s)| = 1/g safeguarded by bisection
(``_onto_bound``; the form of Moré & Sorensen 1983 for the trust-region step, nearly linear in
s). Either way the traction is the exact projection to within rounding and that tolerance.

Traction bound g = μ p_n (option ``bound``):

``"parabolic"`` (default) — Kalker's original FASTSIM: p_n = (2N/(πab)) (1 - x²/a² - y²/b²), the
    pressure of simplified theory itself (Winkler bed, Kalker 1979 fig. 4). It is the default
    because it is Kalker's algorithm and the one the published references use: CONTACT's
    ``tractcurv`` FASTSIM rows (B=3) and the known agreement of simplified theory with the
    Kalker-normalised Johnson–Vermeulen curve are both for the parabolic bound.
``"elliptic"`` — the Hertzian pressure p_n = (3N/(2πab)) √(1 - x²/a² - y²/b²), which Vollebregt
    recommends (E. A. H. Vollebregt & P. Wilders, *FASTSIM2: a second-order accurate frictional
    rolling contact algorithm*, Comput. Mech. 47 (2011) 105-116; CONTACT user guide, B=2). It
    saturates faster in creepage than the parabolic bound.

Discretisation (Kalker 1982's strip layout): the ellipse is cut into ``ny`` strips of equal width
2b/ny with centres y_j = b(-1 + (2j+1)/ny); strip j has half-length a_j = a √(1 - y_j²/b²) and
``nx`` elements of length Δx_j = 2a_j/nx. Both schemes (option ``scheme``) march eq 38 from the
leading edge (where p = 0) with the traction points at the element centres x_i = a_j - (i + ½) Δx_j
(i = 0 .. nx-1) and each element's traction bound the mean of μ p_n over it (the traction bound,
below); they differ in the length of the first step, from the leading edge to the first centre, and
in where the spin term is sampled. Every step of length τ ends at its traction point x and
integrates the rigid slip over [x, x + τ] (spin term at x + τ/2, exact, in "midpoint"). Forces are
sums F = Σ p ΔA with ΔA = Δx_j · 2b/ny, the spin moment is Mz = Σ (x p_y - y p_x) ΔA (z-moment about
the contact centre, same sign convention as linear theory).

``"midpoint"`` — a half step Δx_j/2 to the first centre (its exact distance from the
    leading edge), then full steps. In full stick the traction is exactly linear (ξ, η) or
    quadratic (φ) in x, so the only discretisation errors are the midpoint rules in x and y: the
    force converges as O(n⁻²) to linear theory (exactly 1/(2n²) for pure ξ; tests check the order).
``"kalker"`` (default) — Kalker's original FASTSIM discretisation as implemented in CONTACT
    (Kalker 1982, Vehicle System Dynamics 11, 1-13; CONTACT, E. A. H. Vollebregt & J. J. Kalker,
    open source): full steps Δx_j from the leading edge, tractions at the element centres. The first
    step overshoots the distance to the first centre by Δx_j/2, i.e. the march behaves as if the
    leading edge were half an element ahead of a_j; in stick every traction is too large by that
    much, so for pure ξ or η without saturation the force is (1 + 1/nx) times the converged value
    (plus the O(n⁻²) strip rule in y), first order. CONTACT samples the spin term φx of each step at
    x_i + Δx_j/6 (its ``facphi`` = 1/6 in the rigid slip of ``m_sdis.f90``), and so does this
    scheme: sampled at x_i + θ Δx_j, the pure-spin stick force exceeds the converged one by about
    6θ/nx (summing the march against Kalker 1979 eq 37; θ = ½ gives 3/nx), so θ = 1/6 gives
    every creepage the same first-order excess 1/nx. It is the default because of its accuracy
    against the exact theory, not against FASTSIM's own grid limit: simplified theory
    under-estimates the force in partial slip, and the first-order excess at the default grid makes
    up for much of it (docs/notes/fastsim.md; tests: on CONTACT's published ``tractcurv`` creep
    curve, exact, it is closer than "midpoint" and than CONTACT's own FASTSIM on its finer grid).
    The layout was taken from CONTACT (Kalker's 1982 listing was not available to check it
    against): this module reproduces CONTACT's ``tractcurv`` FASTSIM column (parabolic bound,
    48×44 rectangular grid) at every published point at the comparable nx = 44, ny = 40 (tests).

Both converge to the same continuum FASTSIM solution (tests: on CONTACT's tractcurv example the
Richardson-extrapolated "kalker" curve equals the fine-grid "midpoint" curve); "midpoint"
converges fastest, O(n⁻²) in stick and, with the parabolic bound, for pure ξ or η, first order in
partial slip with spin or under (ξ, η).

The traction bound of an element is the mean of μ p_n over it along its strip (exact: the
pressure's primitive, ``_bound_profile``), not its value at the centre. The element's traction p
stands for its mean traction (F = Σ p ΔA), and Coulomb's law |p(x)| <= μ p_n(x) at every point
bounds the mean by the mean, |mean p| <= mean μ p_n. Both pressures are concave, so the centre
value is larger and admits element means that no admissible traction has, most in the element at
either edge of a strip and most with the Hertzian pressure. Summed over a strip the means give its
load exactly; one constant k (depending on nx, ny and the bound only) corrects the midpoint rule
across the strips so that Σ p_n ΔA = N; full sliding then gives |F| = μN at any grid
(k = 1/(1 + 1/(2 ny²)) with the Hertzian pressure). CONTACT's FASTSIM takes the pressure at its
element centres as it is; what the mean changed against the exact theory is in
docs/notes/fastsim.md.

Known properties of simplified theory (not errors of this code): with three flexibilities
FASTSIM's Mz differs from linear theory's C33 (the effective C33 of L3 alone in the option
"blended" above; the default with the parabolic bound has the geometric mean of that and C33; see
the tests); and so does FASTSIM's coupling term for Fy/φ vs Mz/η (C32 ≠ -C23 in simplified
theory). Of the discretisation, not the theory: under small spin the "kalker" scheme's first-order
error in p_y (the march's overshoot and the spin term's sample point) has a moment of the order of
a times the spin's lateral force, which beside the small moment of an elongated contact is not
small: the moment at small spin exceeds linear theory's the more, the larger a/b and the coarser
the grid, where "midpoint" and the exact theory fall below it (docs/notes/fastsim.md); the forces
keep the scheme's excess 1/nx (above). CONTACT's FASTSIM shares the scheme.

Falling friction (the effect ``falling_friction``, :mod:`contact_core.friction`): with
``falling="local"`` (default) each element's bound is the friction at its own slip velocity,
solved element by element in the march (:mod:`contact_core.fastsim_falling`); with ``"creep"``
one coefficient at the creep velocity, as CONTACT's FASTSIM. Spiryagin's slope reduction (the
"modified FASTSIM" of M. Spiryagin, O. Polach & C. Cole, *Creep force modelling for rail traction
vehicles based on the Fastsim algorithm*, Vehicle System Dynamics 51 (2013) 1765-1783; options
``k0``, ``alpha_inf``, ``beta``) divides every flexibility by k = k0 (α∞ + (1 - α∞)/(1 + β ε)),
with or without falling friction; with CONTACT's settings it reproduces the modified-FASTSIM
series of CONTACT's ``tractcurv`` example (tests, examples/tractcurv_friction.py).

``fields=True`` returns a :class:`FastsimFields` in ``ContactResult.fields``. ``slip_fraction`` is
the slipping area over the contact area (of the discrete grid).

Speed: the march is numba kernels (``cache=True``), compiled, or loaded from numba's on-disk
cache, at the first call (not when ``contact_core`` is imported). It takes
one element of every strip per step, the strips being independent, so that each step is a loop
over the strips the compiler vectorises, with the slip law's projection in it (above); its cost
against a plain kernel is measured by ``python -m contact_tools.bench_fastsim``
(docs/notes/fastsim.md). The no-fields path allocates one small work array.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np

from .cache import cached
from .base import ContactMethod, bool_option, choice_option, float_option, int_option
from .coefficients import per_call_coefficients
from .friction import Rolling, creep_velocity, ratio_of
from .result import ContactResult, make_result

#: Allowed range of ``nx`` and ``ny`` (elements per strip, number of strips).
GRID_RANGE: tuple[int, int] = (1, 2000)
BOUNDS: tuple[str, ...] = ("parabolic", "elliptic")
#: Discretisations of the strip march (option ``scheme``): the length of the first step, from the
#: leading edge to the first element centre, as a fraction of the element length Δx_j (exact ½,
#: or Kalker's/CONTACT's full step), and where in each step the spin term φx of the rigid slip is
#: sampled, as a fraction of the step from its traction point (the step's midpoint, exact, or
#: CONTACT's Δx_j/6, module docstring). The traction points are the element centres in both.
SCHEMES: dict[str, tuple[float, float]] = {"midpoint": (0.5, 0.5), "kalker": (1.0, 1.0 / 6.0)}
#: Exponent p of the creepage's share in the default blend (flexibility "blended"), per bound
#: (module docstring; measured in docs/notes/fastsim.md): parabolic 1, the smallest maxima; elliptic
#: 1/3, the largest of 1, 1/2, 1/3 and 1/4 with which none of the elliptic figures the blend
#: changes is behind CONTACT's FASTSIM (docs/reports/fastsim_vs_contact.md).
SHARE_POWER: dict[str, float] = {"parabolic": 1.0, "elliptic": 1.0 / 3.0}
#: Exponent q of the spin term of the longitudinal slip's flexibility L3^(1-q) L4^q in the
#: default blend (flexibility "blended"), per bound (module docstring; measured in
#: docs/notes/fastsim.md): L4 = 8b/(15 G C33) reproduces linear theory's spin moment; parabolic 1/2,
#: elliptic 0 (L3 alone).
MOMENT_POWER: dict[str, float] = {"parabolic": 0.5, "elliptic": 0.0}
#: Flexibilities (option ``flexibility``, module docstring): one per creepage blended towards one
#: as the creepage grows (two weights), one per creepage, or Kalker 1982's single weighted one.
FLEXIBILITIES: tuple[str, ...] = ("blended", "blended-contact", "separate", "weighted")
#: With the effect falling_friction (option ``falling``): each element's bound at its own slip
#: velocity, or one coefficient at the creep velocity.
FALLING_MODES: tuple[str, ...] = ("local", "creep")
_BLENDED, _BLENDED_CONTACT, _SEPARATE, _WEIGHTED = range(len(FLEXIBILITIES))

# Rows of the fields array the kernel fills when asked.
_FX, _FY, _FPX, _FPY, _FG, _FSLIP, _FAREA = range(7)
# Rows of the march's work array by strip (_strips): the strip's centre y, half element length,
# bound peak and longitudinal stick slope; its last traction, the sums of its tractions and of
# x p_y, its slipping elements; its last stick predictor, its elements whose projection did not
# converge.
(_SY, _SHJ, _SG, _SWX, _SPX, _SPY, _SSX, _SSY, _SSXPY, _SNSL, _SHX, _SHY, _SBAD) = range(13)
_ROWS = 13
# The march's strips padded to a multiple of this: doubles in a vector register (4 or 8).
_LANES = 8
# The one-step projection (_project) counts as converged where |p|²/g² before its final scaling
# is within this of 1: the traction then lies within about 1e-13 g of the exact projection.
_PROJECTION_TOL = 2e-13


def _march(a: float, b: float, xi: float, eta: float, phi: float, k1: float, k2: float,
           k3: float, k3x: float, r21: float, g0: float, profile: Any,
           elliptic: bool, nx: int, ny: int, first: float, spin_at: float, do_x: bool,
           do_y: bool, do_mz: bool, saturate: bool,
           out: Any) -> tuple[float, float, float, float, float]:
    """FASTSIM strip march (Kalker 1979, eq 38) on the strip grid (module docstring).

    Arguments in SI units: semi-axes ``a, b`` (m), creepages ``xi, eta`` (-), spin ``phi`` (1/m),
    ``k1, k2, k3`` = 1/L1, 1/L2, 1/L3 (Pa/m; the flexibilities of ξ, η and φ), ``k3x`` that of
    the spin term -φy of the longitudinal slip (Pa/m; module docstring), ``r21`` = Ly/Lx
    (the slip law's flexibilities, module docstring), ``g0`` = peak of the traction bound μ p_n
    (Pa), ``profile`` its element means along a strip per unit peak (:func:`_bound_profile`,
    incl. the discrete load normalisation). The traction points are the element centres
    x_i = a_j - (i + ½) Δx_j,
    i = 0..nx-1; ``first`` is the length of the first step (from the leading edge to the first
    centre) as a fraction of Δx_j (``SCHEMES``: 0.5 "midpoint", 1.0 "kalker"), the others are
    Δx_j. Each step of length h ends at its traction point x and integrates the rigid slip over
    [x, x + h], its spin term sampled at x + ``spin_at`` h (``SCHEMES``: ½ "midpoint", 1/6
    "kalker"). ``do_x``/``do_y`` march the x/y traction components (the
    other stays 0), ``do_mz`` accumulates Mz, ``saturate`` applies the traction bound. ``out`` is
    None or a float array of shape (7, ny, nx) filled with x, y (m), px, py (Pa), bound (Pa),
    slip (0/1), area (m²).

    The strips are independent: the march takes one element of every strip per step
    (:func:`_sweep`), so that the work of a step is a loop over the strips that the compiler
    vectorises. Where the slip law is anisotropic its projection is first taken in one
    branch-free step (:func:`_project`); if any element's did not converge, the march is done
    again with every such element projected exactly (:func:`_onto_bound`).

    Returns (Fx, Fy, Mz, slip area, contact area) in N, N, N·m, m², m².
    """
    dy = 2.0 * b / ny
    # the anisotropic projection where it differs from the radial one: both components marched
    # and a bound to project onto (g0 = 0: every slipping traction is 0)
    aniso = saturate and r21 != 1.0 and do_x and do_y and g0 > 0.0
    work = _strips(a, b, xi, phi, k1, k3x, g0, elliptic, nx, ny, do_x)
    if _sweep(work, nx, ny, eta, phi, k2, k3, r21, profile, first, spin_at, do_y, saturate,
              aniso, False, dy, out) > 0.0:
        work = _strips(a, b, xi, phi, k1, k3x, g0, elliptic, nx, ny, do_x)
        _sweep(work, nx, ny, eta, phi, k2, k3, r21, profile, first, spin_at, do_y, saturate,
               aniso, True, dy, out)
    return _totals(work, nx, ny, dy, do_mz)


def _strips(a: float, b: float, xi: float, phi: float, k1: float, k3x: float, g0: float,
            elliptic: bool, nx: int, ny: int, do_x: bool) -> Any:
    """The march's work array, rows ``_SY`` .. ``_SBAD`` by strip: the strip layout of the module
    docstring, padded to a multiple of ``_LANES`` with strips of no length that never slip (their
    bound is positive, their tractions stay 0)."""
    nyp = (ny + _LANES - 1) // _LANES * _LANES
    work = np.zeros((_ROWS, nyp))
    for j in range(ny):
        y = b * (-1.0 + (2.0 * j + 1.0) / ny)
        s = 1.0 - (y / b) * (y / b)
        work[_SY, j] = y
        work[_SHJ, j] = (a * math.sqrt(s) if s > 0.0 else 0.0) / nx   # half element length
        work[_SG, j] = g0 * (math.sqrt(s) if elliptic else s) if s > 0.0 else 0.0  # its peak
        # dp_x/dx in stick (Kalker 1979, eq 37)
        work[_SWX, j] = xi * k1 - phi * y * k3x if do_x else 0.0
    work[_SG, ny:] = 1.0
    return work


def _predict(px: float, py: float, wx: float, x: float, h: float, ey: float, eta: float,
             k2: float, phi: float, k3: float, spin_at: float) -> tuple[float, float]:
    """The stick predictor p_H of Kalker 1979, eq 38: the traction (px, py) of the step before,
    less the rigid slip over the step [x, x + h] over the flexibilities, its spin term sampled at
    x + ``spin_at`` h; ``wx`` the longitudinal stick slope (:func:`_strips`), ``ey`` 1 (0: no
    lateral component)."""
    return px - wx * h, py - ey * (eta * k2 + phi * (x + spin_at * h) * k3) * h


def _settle(tx: Any, ty: Any, nslip: Any, sx: Any, sy: Any, sxpy: Any, j: int, x: float,
            px: float, py: float, slip: bool) -> None:
    """Strip j's element at x takes the traction (px, py): kept for the next step and summed."""
    tx[j] = px
    ty[j] = py
    nslip[j] += slip
    sx[j] += px
    sy[j] += py
    sxpy[j] += x * py


def _record(out: Any, i: int, j: int, x: float, y: float, px: float, py: float, g: float,
            slip: bool, da: float) -> None:
    """Element (j, i) in the fields array (rows ``_FX`` .. ``_FAREA``)."""
    out[_FX, j, i] = x
    out[_FY, j, i] = y
    out[_FPX, j, i] = px
    out[_FPY, j, i] = py
    out[_FG, j, i] = g
    out[_FSLIP, j, i] = 1.0 if slip else 0.0
    out[_FAREA, j, i] = da


def _sweep(work: Any, nx: int, ny: int, eta: float, phi: float, k2: float, k3: float,
           r21: float, profile: Any, first: float, spin_at: float, do_y: bool,
           saturate: bool, aniso: bool, exact: bool, dy: float, out: Any) -> float:
    """March every strip of ``work`` (:func:`_strips`) from its leading edge, one element of all
    strips per step; arguments as :func:`_march`'s. Slipping tractions are the stick
    predictor's projection onto the bound: radial, or with ``aniso`` by the slip law's
    anisotropic projection, first in :func:`_project`'s one step; with ``exact`` every element
    whose projection did not converge is projected again by :func:`_onto_bound`. Returns the
    number of elements whose projection was not converged and not projected again."""
    nyp = work.shape[1]
    y, hjs, gs, wxs, tx, ty = work[_SY], work[_SHJ], work[_SG], work[_SWX], work[_SPX], work[_SPY]
    sx, sy, sxpy, nslip, hx, hy, bad = (work[_SSX], work[_SSY], work[_SSXPY], work[_SNSL],
                                        work[_SHX], work[_SHY], work[_SBAD])
    ey = 1.0 if do_y else 0.0
    rho = r21 - 1.0
    nxf = float(nx)
    for i in range(nx):
        ci = nxf - 2.0 * i - 1.0             # the centre a_j - (i + ½) Δx_j = ci hj
        fh = first if i == 0 else 1.0        # the step over Δx_j: the first from the leading edge
        prof = profile[i]
        # two loops, not one with the branch inside: each is vectorised
        if aniso:
            for j in range(nyp):
                hj = hjs[j]
                x = ci * hj
                px, py = _predict(tx[j], ty[j], wxs[j], x, fh * (2.0 * hj), ey, eta, k2, phi,
                                  k3, spin_at)
                g = gs[j] * prof
                hx[j] = px
                hy[j] = py
                qx, qy, q = _project(px, py, g, r21, rho)
                slip = px * px + py * py > g * g
                bad[j] += slip & (not abs(q - 1.0) <= _PROJECTION_TOL)     # NaN: not converged
                if slip:
                    px = qx
                    py = qy
                _settle(tx, ty, nslip, sx, sy, sxpy, j, x, px, py, slip)
                if out is not None and j < ny:
                    _record(out, i, j, x, y[j], px, py, g, slip, 2.0 * hj * dy)
        else:
            for j in range(nyp):
                hj = hjs[j]
                x = ci * hj
                px, py = _predict(tx[j], ty[j], wxs[j], x, fh * (2.0 * hj), ey, eta, k2, phi,
                                  k3, spin_at)
                g = gs[j] * prof
                n2 = px * px + py * py
                slip = saturate & (n2 > g * g)
                if slip:
                    f = g / n2 ** 0.5               # ** 0.5: the vectorisable sqrt
                    px *= f
                    py *= f
                _settle(tx, ty, nslip, sx, sy, sxpy, j, x, px, py, slip)
                if out is not None and j < ny:
                    _record(out, i, j, x, y[j], px, py, g, slip, 2.0 * hj * dy)
        if exact:
            for j in range(ny):
                if bad[j] != 0.0:
                    bad[j] = 0.0
                    qx, qy = _onto_bound(hx[j], hy[j], gs[j] * prof, r21)
                    dpy = qy - ty[j]
                    sx[j] += qx - tx[j]
                    sy[j] += dpy
                    sxpy[j] += ci * hjs[j] * dpy
                    tx[j] = qx
                    ty[j] = qy
                    if out is not None:
                        out[_FPX, j, i] = qx
                        out[_FPY, j, i] = qy
    return bad.sum()


def _totals(work: Any, nx: int, ny: int, dy: float,
            do_mz: bool) -> tuple[float, float, float, float, float]:
    """(Fx, Fy, Mz, slip area, contact area) of the marched strips of ``work``: F = Σ p ΔA,
    Mz = Σ (x p_y - y p_x) ΔA."""
    fx = 0.0
    fy = 0.0
    mz = 0.0
    a_slip = 0.0
    a_tot = 0.0
    for j in range(ny):
        da = 2.0 * work[_SHJ, j] * dy
        fx += work[_SSX, j] * da
        fy += work[_SSY, j] * da
        if do_mz:
            mz += (work[_SSXPY, j] - work[_SY, j] * work[_SSX, j]) * da
        a_slip += work[_SNSL, j] * da
        a_tot += nx * da
    return fx, fy, mz, a_slip, a_tot


def _flexibilities(a: float, b: float, G: float, mu: float, N: float, xi: float, eta: float,
                   phi: float, c11: float, c22: float, c23: float, c33: float, mode: int,
                   share_power: float,
                   moment_power: float) -> tuple[float, float, float, float, float, float]:
    """(1/L1, 1/L2, 1/L3, 1/L3x, Ly/Lx, Lx) of one state (Pa/m, Pa/m, Pa/m, Pa/m, -, m/Pa;
    module docstring): Kalker 1982's flexibilities, the spin term of the longitudinal slip's L3x =
    L3^(1-q) L4^q (q = ``moment_power``, ``MOMENT_POWER``; 0 outside the default blend), all
    changed by ``mode`` (``_BLENDED`` ... ``_WEIGHTED``, the index in ``FLEXIBILITIES``; the
    blends only with the saturation effect, the caller's choice; the share's exponent
    ``share_power``, ``SHARE_POWER``), and the slip law's."""
    l1 = 8.0 * a / (3.0 * G * c11)
    l2 = 8.0 * a / (3.0 * G * c22)
    l3 = math.pi * a * math.sqrt(a / b) / (4.0 * G * c23)
    l3x = l3
    if moment_power != 0.0:
        l4 = 8.0 * b / (15.0 * G * c33)    # pure spin, stick: Mz = -(8/15) a² b³ φ / L4
        l3x = l3 * (l4 / l3) ** moment_power
    cphi = math.sqrt(a * b) * abs(phi)
    if mode == _WEIGHTED and (xi != 0.0) + (eta != 0.0) + (phi != 0.0) > 1:
        l1 = (l1 * abs(xi) + l2 * abs(eta) + l3 * cphi) / math.sqrt(xi * xi + eta * eta
                                                                     + cphi * cphi)
        l2 = l3 = l3x = l1
    elif (mode == _BLENDED or mode == _BLENDED_CONTACT) and (xi != 0.0 or eta != 0.0):
        # Vollebregt & Voltr 2023: towards the creepage-weighted harmonic mean as (ξ, η) grows
        # to three times the creepage of linear theory's μN (creepages scaled by the largest:
        # no underflow for tiny inputs)
        sphi = 3.0 * math.pi * a * phi / 32.0
        m = max(abs(xi), abs(eta), abs(sphi))
        wx, wy, wp = (xi / m) ** 2, (eta / m) ** 2, (sphi / m) ** 2
        l_one = (wx + wy + wp) / (wx / l1 + wy / l2 + wp / l3)
        ch = mu * N / (G * a * b)           # > 0: N = 0 or μ = 0 never get here
        w = min(1.0, math.sqrt(xi * xi + eta * eta) / (3.0 * ch * math.sqrt(
            1.0 / (c11 * c11) + 1.0 / (c22 * c22))))
        if mode == _BLENDED:
            # scaled by a power of the creepage's share of the linear force
            f_creep = math.sqrt((c11 * xi / m) ** 2 + (c22 * eta / m) ** 2)
            share = f_creep / (f_creep + c23 * cphi / m)
            w *= share if share_power == 1.0 else share ** share_power
        l1 += w * (l_one - l1)
        l2 += w * (l_one - l2)
        l3 += w * (l_one - l3)
        l3x += w * (l_one - l3x)
    # the slip law's flexibilities along x and y: the creepage's part L1, L2, with the blends
    # one for both, Vollebregt & Voltr's L_c of (ξ, η) alone (module docstring); the spin's L3
    # by the shares (as weights in [0, 1]: no underflow to a zero flexibility for denormal
    # inputs; the creepages scaled by the larger)
    lcx, lcy = l1, l2
    if (mode == _BLENDED or mode == _BLENDED_CONTACT) and (xi != 0.0 or eta != 0.0):
        m = max(abs(xi), abs(eta))
        wx, wy = (xi / m) ** 2, (eta / m) ** 2
        lcx = lcy = (wx + wy) / (wx / l1 + wy / l2)
    ax, ay = abs(xi) + cphi, abs(eta) + cphi
    lx = lcx + (l3 - lcx) * (cphi / ax) if ax > 0.0 else lcx
    ly = lcy + (l3 - lcy) * (cphi / ay) if ay > 0.0 else lcy
    return 1.0 / l1, 1.0 / l2, 1.0 / l3, 1.0 / l3x, ly / lx, lx


def _onto_bound(hx: float, hy: float, g: float, r21: float) -> tuple[float, float]:
    """The slipping traction from the stick predictor (hx, hy), |(hx, hy)| > g > 0, for the slip
    law's flexibility tensor diag(Lx, Ly), r21 = Ly/Lx (module docstring, flexibility
    "separate"): p = (hx/(1 + s), hy r21/(r21 + s)) with the one s > 0 that puts |p| on g
    (s = λ/Lx, λ the slip's multiplier; s = |h|/g - 1 for r21 = 1).

    Newton's method on the secular equation 1/|p(s)| = 1/g, nearly linear in s (exactly for
    r21 = 1; Moré & Sorensen 1983's form for the trust-region step), kept by bisection in the
    bracket of the isotropic solutions with the smaller and the larger flexibility, started from
    :func:`_projection_estimate`; converged to rounding, then scaled onto the bound."""
    n = math.sqrt(hx * hx + hy * hy)
    a = hx / g
    b = r21 * hy / g
    e = n / g - 1.0
    lo = min(1.0, r21) * e
    hi = max(1.0, r21) * e
    s = _projection_estimate(n / g, (hy / n) ** 2, g / n, r21 - 1.0) - 1.0
    if not lo <= s <= hi:
        s = 0.5 * (lo + hi)
    for _ in range(200):
        u = 1.0 / (1.0 + s)
        v = 1.0 / (r21 + s)
        pa2 = (a * u) ** 2
        pb2 = (b * v) ** 2
        p2 = pa2 + pb2                       # (|p|/g)², decreasing in s
        if p2 > 1.0:
            lo = s
        else:
            hi = s
        s_new = s + p2 * (math.sqrt(p2) - 1.0) / (pa2 * u + pb2 * v)
        if not lo <= s_new <= hi:
            s_new = 0.5 * (lo + hi)
        # converged to rounding in the traction, ∝ 1/(1 + s) and 1/(r21 + s)
        tol = 8e-16 * (min(1.0, r21) + s)
        if abs(s_new - s) <= tol or hi - lo <= tol:
            s = s_new
            break
        s = s_new
    px = hx / (1.0 + s)
    py = hy * r21 / (r21 + s)
    f = g / math.sqrt(px * px + py * py)    # land exactly on the bound
    return px * f, py * f


def _projection_estimate(z0: float, c2: float, inv_z0: float, rho: float) -> float:
    """1 + s of :func:`_onto_bound` to second order in ρ = r21 - 1 about the isotropic
    solution z0 = |h|/g (``c2`` = hy²/|h|², ``inv_z0`` = 1/z0): from the expansion of the
    condition a²/z² + b²(1 + ρ)²/(z + ρ)² = 1 on the bound (a, b = hx/g, hy/g; z = 1 + s),
    z = z0 + ρ c² (z0 - 1)(1 + ρ (1 - c²)(z0 - 3)/(2 z0))."""
    return z0 + rho * c2 * (z0 - 1.0) * (1.0 + rho * (1.0 - c2) * (z0 - 3.0) * (0.5 * inv_z0))


def _project(hx: float, hy: float, g: float, r21: float,
             rho: float) -> tuple[float, float, float]:
    """:func:`_onto_bound` in one branch-free step, for the vectorised march: from
    :func:`_projection_estimate` one step of Householder's method of order 3 (quartic
    convergence) on G(z) = z² - a² - b² r21² z²/(z + ρ)² (z = 1 + s, a, b = hx/g, hy/g; G and
    its first three derivatives times (z + ρ)^2 .. (z + ρ)^5, so that the step and the traction
    take one division), scaled onto the bound to second order. Returns (px, py, q),
    q = |p'|²/g² of the traction p' before that scaling: its distance from 1 is the step's
    residual (NaN where the step failed, e.g. off the slip zone, where |h| <= g and the result
    is not used); where it is not within ``_PROJECTION_TOL``, (px, py) is the radial
    projection instead."""
    n2 = hx * hx + hy * hy
    inv = 1.0 / (g * n2)
    ginv = n2 * inv
    n = n2 ** 0.5                            # ** 0.5: the vectorisable sqrt
    z = _projection_estimate(n * ginv, hy * hy * (g * inv), g * g * n * inv, rho)
    gi2 = ginv * ginv
    a2 = hx * hx * gi2
    b2 = r21 * r21 * hy * hy * gi2
    u = z + rho
    u2 = u * u
    z2 = z * z
    f0 = u2 * (z2 - a2) - b2 * z2
    br = b2 * rho
    f1 = (u2 * u - br) * z                   # G', G'' over 2 (G''' = -12 br (z - ρ))
    f2 = u2 * u2 - br * (u - 3.0 * z)
    # Householder's ratio (6 G G'² - 3 G² G'')/(6 G'³ - 6 G G' G'' + G² G''') over 6
    f1f1 = f1 * f1
    num = f0 * (4.0 * f1f1 - f0 * f2)
    den = 4.0 * f1 * (2.0 * f1f1 - f0 * f2) - 2.0 * f0 * f0 * br * (z - rho)
    # the step z' = z - u num/den: 1/z' = den/zd, 1/(z' + ρ) = den/ud
    zd = z * den - u * num
    ud = u * (den - num)
    d = den / (zd * ud)
    px = hx * ud * d
    py = hy * r21 * zd * d
    q = (px * px + py * py) * gi2
    land = 1.5 - 0.5 * q                     # 1/√q to second order
    # where the step failed (it overflows for |h|/g beyond about 1e20, or did not converge), the
    # radial projection: finite, so that the strip's sums stay finite until the element is
    # projected again exactly (_sweep)
    ok = abs(q - 1.0) <= _PROJECTION_TOL     # NaN: not converged
    radial = g / n
    return (px * land if ok else hx * radial), (py * land if ok else hy * radial), q


_KERNELS: tuple[Callable, Callable] | None = None


def _kernels() -> tuple[Callable, Callable]:
    """The numba-compiled :func:`_march` and :func:`_flexibilities` (compiled at the first call;
    cached on disk). The march's per-element helpers are inlined into its loops: the compiler
    vectorises a loop only without calls."""
    global _KERNELS
    if _KERNELS is None:
        import numba
        global _onto_bound, _projection_estimate, _project, _predict, _settle, _record
        global _strips, _sweep, _totals
        jit = numba.njit(cache=True, nogil=True, error_model="numpy")
        inline = numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
        _projection_estimate = inline(_projection_estimate)
        _project = inline(_project)
        _predict = inline(_predict)
        _settle = inline(_settle)
        _record = inline(_record)
        _onto_bound = jit(_onto_bound)
        _strips = jit(_strips)
        _sweep = jit(_sweep)
        _totals = jit(_totals)
        _KERNELS = (jit(_march), jit(_flexibilities))
    return _KERNELS


@cached(64)
def _bound_profile(nx: int, ny: int, elliptic: bool) -> np.ndarray:
    """The traction bound of the ``nx`` elements of a strip per unit peak of the strip's pressure
    (leading edge first): the pressure shape's mean over each element, exact, times the load
    normalisation k of the grid (module docstring, the traction bound).

    Along a strip of half-length a_j the shape is 1 - x²/a_j² (parabolic) or √(1 - x²/a_j²)
    (Hertz) times the strip's peak (1 - y_j²/b², or its root); with u = x/a_j the element from
    u_{i+1} to u_i has the mean (P(u_i) - P(u_{i+1}))/(u_i - u_{i+1}) of the primitive
    P(u) = u - u³/3, or (u √(1 - u²) + asin u)/2. Summed over a strip these means give its
    integral exactly; k corrects the midpoint rule across the strips, k Σ p̂ ΔA = ∫ p̂ dA on the
    unit circle (the sums scale with ab like the integrals, so k depends on the grid and the
    shape only): ∫(1 - r²) dA = π/2, ∫√(1 - r²) dA = 2π/3.
    """
    u = 1.0 - 2.0 * np.arange(nx + 1) / nx                # element edges, x/a_j
    if elliptic:
        prim = 0.5 * (u * np.sqrt(np.maximum(1.0 - u * u, 0.0)) + np.arcsin(u))
    else:
        prim = u - u ** 3 / 3.0
    mean = (prim[:-1] - prim[1:]) * (nx / 2.0)           # element length 2/nx in u
    y = -1.0 + (2.0 * np.arange(ny) + 1.0) / ny
    s = np.maximum(1.0 - y * y, 0.0)
    peak = np.sqrt(s) if elliptic else s
    # Σ_j peak_j Σ_i mean_i (2 a_j/nx)(2/ny), with Σ_i mean_i 2/nx = ∫ shape du exactly
    discrete = float(np.sum(peak * np.sqrt(s))) * (2.0 / ny) * float(np.sum(mean)) * (2.0 / nx)
    exact = 2.0 * math.pi / 3.0 if elliptic else math.pi / 2.0
    return mean * (exact / discrete)


@dataclass(frozen=True)
class FastsimFields:
    """Traction maps of one FASTSIM solution, arrays of shape (ny, nx) (strip j, element i).

    Attributes
    ----------
    x, y : ndarray
        Traction points, m (x rolling direction, leading edge at x = +a(y); y lateral): the
        element centres (both schemes).
    px, py : ndarray
        Tangential tractions of the rail on the wheel, Pa (same sign convention as the forces).
    bound : ndarray
        Traction bound of each element, Pa: μ p_n averaged over the element along its strip
        (incl. the discrete load normalisation; with the local falling-friction law μ at the
        element's slip velocity); with the ``saturation`` effect off it is reported but not
        applied.
    slip : ndarray of bool
        True where the element slips (|p| = bound), False where it sticks.
    area : ndarray
        Element areas, m²: ``Fx == (px * area).sum()`` (up to rounding).
    """

    x: np.ndarray
    y: np.ndarray
    px: np.ndarray
    py: np.ndarray
    bound: np.ndarray
    slip: np.ndarray
    area: np.ndarray

    def scaled(self, length: float, pressure: float, bound: float, traction: float,
               slip: float) -> "FastsimFields":
        """The fields in other units (``ContactMethod._similar``): lengths, the friction bound
        and the tractions times the given factors (``pressure`` and ``slip`` unused here)."""
        return replace(self, x=self.x * length, y=self.y * length, px=self.px * traction,
                       py=self.py * traction, bound=self.bound * bound,
                       area=self.area * (length * length))


class Fastsim(ContactMethod):
    """Kalker's FASTSIM (simplified theory, strip march; Kalker 1979, sec. 5, Kalker 1982).

    Options
    -------
    nx : int, default 20
        Elements per strip along the rolling direction (1 .. 2000).
    ny : int, default 20
        Number of strips across the contact (1 .. 2000).
    bound : {"parabolic", "elliptic"}, default "parabolic"
        Traction-bound shape (see the module docstring for the choice of default).
    scheme : {"midpoint", "kalker"}, default "kalker"
        Discretisation of the march (module docstring); tractions at the element centres in both:
        Kalker's/CONTACT's full first step, first order (the default: closer to the exact theory
        at 20×20), or a half first step, second order in FASTSIM's own grid limit.
    flexibility : {"blended", "blended-contact", "separate", "weighted"}, default "blended"
        One flexibility per creepage (L1, L2, L3, Kalker 1982) blended towards one as the
        creepage grows, by a power of its share of the linear force ("blended", the power per
        bound in ``SHARE_POWER``; with the parabolic bound the spin moment's own flexibility,
        ``MOMENT_POWER``) or as CONTACT does (Vollebregt & Voltr 2023); one per creepage; or
        Kalker 1982's single weighted one (module docstring).
    fields : bool, default False
        Return :class:`FastsimFields` (grid, tractions, bound, stick/slip mask, areas).
    falling : {"local", "creep"}, default "local"
        With the effect ``falling_friction``: each element's bound at its own slip velocity
        (:mod:`contact_core.fastsim_falling`), or one coefficient at the creep velocity for the
        whole contact (Spiryagin et al. 2013, CONTACT's modified FASTSIM).
    k0, alpha_inf, beta : float, default 1.0, 1.0, 0.0
        Spiryagin's slope reduction (the "modified FASTSIM"; M. Spiryagin, O. Polach & C. Cole,
        *Creep force modelling for rail traction vehicles based on the Fastsim algorithm*,
        Vehicle System Dynamics 51 (2013) 1765-1783): the flexibilities divided by
        k = k0 (α∞ + (1 - α∞)/(1 + β ε)), ε = (π/4) G ab k0 c_jj s_C/(μ N) Polach's gradient
        of the tangential stress (Polach 2005; c_jj = |(C11 ξ, C22 η)|/|(ξ, η)|, C11 without
        creepage, as CONTACT takes C11; s_C and μ at the creep velocity as in
        :mod:`contact_core.polach`); 0 < k0 <= 1, 0 <= α∞ <= 1, β >= 0. k0 = α∞ = 1 (default):
        Kalker's FASTSIM. With k0 < 1 the linear range's slope is k0 times FASTSIM's.

    Default grid 20×20, for the speed budget (its cost: ``python -m contact_tools.bench_fastsim``;
    its accuracy against the exact theory: docs/reports/accuracy_vs_time.md,
    docs/notes/fastsim.md). Refine (40×40, 80×80) for smoother traction maps; the error against
    the exact theory is then dominated by simplified theory itself.
    """

    name = "fastsim"
    code = 3
    default_options = {"nx": 20, "ny": 20, "bound": "parabolic", "scheme": "kalker",
                       "flexibility": "blended", "fields": False, "falling": "local",
                       "k0": 1.0, "alpha_inf": 1.0, "beta": 0.0}

    def _check_options(self) -> None:
        o = self.options
        int_option(o, "nx", *GRID_RANGE, "elements per strip")
        int_option(o, "ny", *GRID_RANGE, "number of strips")
        choice_option(o, "bound", BOUNDS)
        choice_option(o, "scheme", tuple(SCHEMES))
        choice_option(o, "flexibility", FLEXIBILITIES)
        bool_option(o, "fields")
        choice_option(o, "falling", FALLING_MODES)
        self._k0 = float_option(o, "k0", 0.0, 1.0, lo_open=True)
        self._alpha_inf = float_option(o, "alpha_inf", 0.0, 1.0)
        self._beta = float_option(o, "beta", 0.0, math.inf, hi_open=True)
        self._reduce = not (self._k0 == 1.0 and self._alpha_inf == 1.0)
        self._falling_local = self.friction is not None and o["falling"] == "local"
        if self._falling_local:
            from .fastsim_falling import kernel   # only with the effect: its own kernel
            self._kern_falling = kernel()
        self._nx = self.options["nx"]
        self._ny = self.options["ny"]
        self._elliptic = self.options["bound"] == "elliptic"
        self._share_power = SHARE_POWER[o["bound"]]
        # the spin moment's flexibility is part of the default blend, with or without saturation
        self._moment_power = (MOMENT_POWER[o["bound"]] if o["flexibility"] == "blended"
                              else 0.0)
        self._first, self._spin_at = SCHEMES[o["scheme"]]
        self._fields = bool(self.options["fields"])
        # Peak of p_n per unit N/(ab): 2/π (parabolic) or 3/(2π) (Hertz); the elements' share
        # of it (with the load normalisation of the discrete grid) in the profile.
        self._g_factor = 1.5 / math.pi if self._elliptic else 2.0 / math.pi
        self._profile = _bound_profile(self._nx, self._ny, self._elliptic)
        eff = self.effects
        self._do_x = bool(eff.longitudinal or eff.spin)
        self._do_y = bool(eff.lateral or eff.spin)
        self._do_mz = bool(eff.spin)
        self._saturate = bool(eff.saturation)
        # (index in FLEXIBILITIES) without the saturation effect nothing slides: no blend, the
        # linear range's flexibilities throughout
        self._mode = FLEXIBILITIES.index(o["flexibility"])
        if not self._saturate and self._mode in (_BLENDED, _BLENDED_CONTACT):
            self._mode = _SEPARATE
        self._kern, self._flex = _kernels()
        self._coefficients = per_call_coefficients(eff.varying_geometry)

    def _step_impl(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                   b: float, G: float, nu: float, warm_start: ContactResult | None,
                   rolling: Rolling | None = None) -> ContactResult:
        c11, c22, c23, c33 = self._coefficients(a / b, nu)
        k1, k2, k3, k3x, r21, lx = self._flex(a, b, G, mu, N, xi, eta, phi, c11, c22, c23,
                                              c33, self._mode, self._share_power,
                                              self._moment_power)
        if self._reduce:
            mu_c = mu if rolling is None else mu * ratio_of(
                self._law, creep_velocity(rolling.V, xi, eta, phi, a))
            k = self._slope_factor(xi, eta, phi, N, mu_c, a, b, G, c11, c22)
            k1, k2, k3, k3x, lx = k1 * k, k2 * k, k3 * k, k3x * k, lx / k
        g0 = mu * N * self._g_factor / (a * b)
        nx, ny = self._nx, self._ny
        out = np.empty((7, ny, nx)) if self._fields else None
        if rolling is not None and rolling.V > 0.0:
            fx, fy, mz, a_slip, a_tot = self._kern_falling(
                a, b, xi, eta, phi, k1, k2, k3, k3x, r21, lx, g0, self._profile,
                self._elliptic, nx, ny, self._first, self._spin_at, self._do_x, self._do_y,
                self._do_mz, self._law, rolling.V, rolling.memory, out)
        else:
            fx, fy, mz, a_slip, a_tot = self._kern(
                a, b, xi, eta, phi, k1, k2, k3, k3x, r21, g0, self._profile, self._elliptic,
                nx, ny, self._first, self._spin_at,
                self._do_x, self._do_y, self._do_mz, self._saturate, out)
        eff = self.effects
        fields = None
        if out is not None:
            fields = FastsimFields(x=out[_FX], y=out[_FY], px=out[_FPX], py=out[_FPY],
                                   bound=out[_FG], slip=out[_FSLIP] > 0.5, area=out[_FAREA])
        return make_result(fx if eff.longitudinal else 0.0,
                           fy if eff.lateral else 0.0,
                           mz if eff.spin else 0.0,
                           self.name, a_slip / a_tot if a_tot > 0.0 else 0.0, fields)

    def _slope_factor(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                      b: float, G: float, c11: float, c22: float) -> float:
        """Spiryagin et al. 2013's k = k0 (α∞ + (1 - α∞)/(1 + β ε)) (option ``k0``)."""
        if not self._saturate:
            return self._k0                    # μ -> ∞: ε = 0
        s = math.hypot(xi, eta)
        cjj = math.hypot(c11 * xi, c22 * eta) / s if s > 0.0 else c11
        s_c = creep_velocity(1.0, xi, eta, phi, a)
        eps = 0.25 * math.pi * G * a * b * self._k0 * cjj * s_c / (mu * N)
        return self._k0 * (self._alpha_inf + (1.0 - self._alpha_inf) / (1.0 + self._beta * eps))
