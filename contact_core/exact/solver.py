"""Kalker's exact theory of steady rolling: the method ``"exact"`` (boundary elements).

Half-space, quasi-identical materials (normal and tangential problems uncoupled), steady rolling,
Coulomb friction (Kalker 1979, sec. 2, eqs 4-8, and sec. 4; Kalker 1990, *Three-Dimensional Elastic
Bodies in Rolling Contact*, ch. 5). The potential contact area is the rectangle
[-scale·a, scale·a] × [-scale·b, scale·b] divided into ``mx × my`` elements with constant
tractions. Steps:

1. normal problem on the grid (:mod:`.normal`; Polonsky–Keer CG), or Hertz's pressure at the
   element centres (``normal="hertz"``); both scaled to the exact total N;
2. tangential steady-rolling problem (:mod:`.sweeps`; SteadyGS-type block Gauss–Seidel with
   the traction differences as unknowns, Anderson-accelerated: :mod:`.anderson`) with the
   influence coefficients of :mod:`.influence` (:mod:`.kernels`).

Sign convention as everywhere in contact_core: forces of the rail on the wheel, so that the
small-creepage limit is ``Fx = -G c² C11 ξ`` etc. with Kalker's positive coefficients.

Effects: without ``saturation`` the friction bound is infinite (μ → ∞: every element sticks,
the linear problem). With η = φ = 0 (e.g. ``longitudinal`` only) the problem is symmetric under
the mirror y → -y (X even, Y odd in y; the lateral tractions are still coupled to X through the
ν-terms of the Cerruti solution): it is solved on the half grid y >= 0 with the kernels folded
onto it (:func:`.sweeps.solve_steady_half`), every sum of the iteration weighted as on the
full grid, so the iterates are those of the full solve up to rounding, at about half the time
(option ``half=False`` solves the full grid). Unselected outputs are reported as 0.0.

Warm start (``warm_start=previous_result``): the iteration starts from the previous tractions
(scaled to the new μ p0), multiplied by the projection s of the new normalised creepages on the
old ones: exact when no element slips (the problem is then linear, p(sσ) = s p(σ)) and for a
sign reversal (the problem is odd), a first guess otherwise. When the previous result was itself
warm-started, its state also holds the solution before it, and the start is extrapolated along
the secant of the two instead (a co-simulation sequence, where it saves sweeps over scaling
alone). Option ``predictor``: ``"secant"`` (this, the default), ``"scale"`` (scaling
only), ``"none"`` (the previous solution as it is). The state is an :class:`ExactWarmState`.
The tractions are kept on the grid of the semi-axes, in units of μ p0, so a new a/b (a contact
geometry that changes at every step, the effect ``varying_geometry``) keeps both predictors:
they need the same ν only (``contact_tools.bench_geometry`` compares the sweeps with cold
starts).
``python -m contact_tools.bench_exact`` reports the speed-ups against the size of the change.

Rigid slip with spin (option ``spin_shift``). The steady-rolling slip of element i is the rigid
slip minus the upwind difference (u_i - u_{i+1})/dx of the displacements towards the leading edge
(Kalker 1990, ch. 5; as in CONTACT). The spin term φx of the lateral rigid slip is sampled at
x_i + θ dx, θ = ``spin_shift`` elements downstream of the element centre (towards the leading
edge). The default θ = 1/6 is CONTACT's (E. A. H. Vollebregt, CONTACT, github.com/eve70a/CONTACT
d431cdb: ``kin%facphi`` in ``m_sdis.f90``, read as an optional fourth value after CHI, DQ, VELOC,
default 1/6, not in its user guide): with it this solver is CONTACT's discretisation: on equal
grids it gives CONTACT's forces and moments (exact steady rolling, M=0, B=0, over 1.1× the
ellipse) to within the solver's tolerance, which the tests hold on CONTACT's published results
(``tests/data/contact_exact_spin.csv``). No θ is best for every output against the
grid-converged solution: θ = 0 under-estimates the spin's lateral force and θ = 1/2 (the centre
of the upwind difference) over-estimates it, as the grid's pure-creepage response does; θ = 1/4
has the smallest |F| tails, θ = 3/8..1/2 the smallest Mz. The default keeps CONTACT's, so that a
fixed grid here and in CONTACT give the same forces; ``spin_shift=0.25`` trades that for less
|F| error in the worst spin cases. The default ``extrapolate`` setting cancels the first-order
term the shift moves. Pure ξ and η do not depend on θ. Kalker's reciprocity C32 = -C23 (Mz per
η equals -Fy per φ·c) holds in the limit: the shift changes Fy(φ) by -G c² C22 φ θ dx, first
order in the element size (tests). The comparison with CONTACT and the errors of each θ are in
the design notes (docs/notes/exact_solver.md).

Extrapolation (option ``extrapolate``, default on): the solve is repeated on the half grid
(mx/2 × my/2) and the two are combined by Richardson's rule for a first-order error,
q = q1 + (q1 - q2)/(r - 1), r = √(mx·my/(mx2·my2)) the refinement ratio. Plain grids are not in the
asymptotic range: the contact area of the discrete normal problem (elements whose centres carry
pressure) differs from πab by a staircase error of a few % that jumps with the grid, and the
forces follow it. Before
extrapolating, each grid is therefore mapped to the continuum's area by Kalker's similarity (Kalker
1967 ch. 2; Kalker 1979 sec. 2: with a/b and ν fixed, F/(μN) and Mz/(μN c) depend on the creepages
only through ξ G c²/(μN), η G c²/(μN), φ G c³/(μN)): a grid whose contact area is k πab is solved
as the ellipse of semi-axes √k a, √k b, i.e. with creepages ξ/k, η/k, φ/k^1.5, and its Mz divided
by √k. After the combination |F| is held to μN and |Mz| to μ ∫ p_n r dA (Coulomb's bounds, which
each grid meets but a combination need not). Far from the asymptotic range the combination can
reverse a sign both grids agree on: Mz of small pure spin with elements a/b times as long as wide,
from a/b = 12 on 16×16 and 15 on 24×24 extrapolated (a small moment of the wrong sign); near a
component's zero crossing (e.g. Fy where the η and φ terms cancel) such a reversal is the
correction working, so no guard keeps the fine grid's value. Beyond a/b = 10 that moment
converges slowly on any grid. The fields and the warm state are the fine grid's; the half grid
starts cold.

The default, 52×52 extrapolated, is the cheapest square grid found within 1 % of Kalker's
coefficients C11, C22 over a/b 0.1..10 (ν = 0.25; 44 and 48 miss at a/b = 10).
``extrapolate=False`` solves one grid as it is (CONTACT's discretisation: "Rigid slip with
spin"). The accuracy and cost of each setting against the converged reference:
``python -m contact_tools.bench`` (docs/reports/accuracy_vs_time.md); the settings compared
when the default was chosen: docs/notes/exact_solver.md.

Falling friction (the effect ``falling_friction``, option ``falling="local"``): each element's
bound at its own slip velocity, by an outer iteration between the friction field and the
Coulomb problem (:mod:`.falling`); with the option ``layer`` (an elastic interfacial layer,
:mod:`.layer`) and the law's friction memory this is CONTACT's series 2 of its ``tractcurv``
example, which it reproduces on CONTACT's grid to the data's 4 digits (tests). The outer
iteration costs 2-3 Coulomb solves (each warm-started) on the adhesion curve's falling branch.

Non-convergence: if the tolerance is not reached within ``maxit`` sweeps, the result carries
``converged=False`` and an :class:`ExactSolverWarning` is issued (never an exception); the
result is the last iterate (feasible: |p| <= μ p_n holds in every iterate).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .. import notices
from ..base import ContactMethod, bool_option, choice_option, float_option, int_option
from ..cache import cached
from ..friction import Rolling
from ..hertz import max_pressure
from ..result import ContactResult
from .falling import local_friction
from .kernels import folded_kernel_tables, kernel_tables, traction_differences
from .layer import layer_folded_tables, layer_kernel_tables
from .normal import normalised_pressure
from .sweeps import EXTERIOR, SLIP, STICK, slip_field, solve_steady, solve_steady_half


# Anderson acceleration of the sweeps (see :mod:`.anderson`): history depth and first
# accelerated sweep (deeper histories gain nothing: docs/notes/exact_solver.md). Passed explicitly: numba's fast dispatch path needs every argument.
_AA_DEPTH, _AA_START = 5, 2
#: Warm-start predictors (option ``predictor``; see the module docstring).
PREDICTORS = ("secant", "scale", "none")


class ExactSolverWarning(RuntimeWarning):
    """The exact solver stopped at ``maxit`` sweeps before reaching its tolerance."""


@dataclass(frozen=True)
class ExactFields:
    """Traction fields of one exact solution (``fields=True``); arrays of shape (my, mx).

    ``x`` (mx,), ``y`` (my,): element centres, m. ``pn``: pressure, Pa. ``px, py``: tangential
    tractions on the wheel, Pa. ``sx, sy``: true slip velocity per rolling speed V
    (dimensionless; zero outside the contact). ``status``: 0 exterior, 1 stick, 2 slip
    (``EXTERIOR, STICK, SLIP``).
    """

    x: np.ndarray
    y: np.ndarray
    pn: np.ndarray
    px: np.ndarray
    py: np.ndarray
    sx: np.ndarray
    sy: np.ndarray
    status: np.ndarray

    def scaled(self, length: float, pressure: float, bound: float, traction: float,
               slip: float) -> "ExactFields":
        """The fields in other units (``ContactMethod._similar``): lengths, pressure, tractions
        and slips times the given factors (``bound`` unused here)."""
        return replace(self, x=self.x * length, y=self.y * length, pn=self.pn * pressure,
                       px=self.px * traction, py=self.py * traction, sx=self.sx * slip,
                       sy=self.sy * slip)


@dataclass(frozen=True)
class ContactGrid:
    """The discretised contact of one grid and a/b: pressure and the elements in contact."""

    pn: np.ndarray          # p/p0 at the element centres, (my, mx)
    contact: np.ndarray     # bool (my, mx)
    e_lo: np.ndarray        # per row first/last contact element
    e_hi: np.ndarray
    c_lo: np.ndarray        # per row first/last possibly non-zero traction difference column
    c_hi: np.ndarray
    normal_iterations: int
    area_ratio: float       # discrete contact area / πab


@cached(64)
def contact_grid(mx: int, my: int, scale: float, a_over_b: float, normal: str) -> ContactGrid:
    """:class:`ContactGrid` of an ``mx × my`` grid on [-scale a, scale a] × [-scale b, scale b]
    (``normal``: "numerical" or "hertz", see :func:`.normal.normalised_pressure`)."""
    pn, it, _ = normalised_pressure(mx, my, scale, a_over_b, normal)
    con = pn > 0.0
    rows = con.any(axis=1)
    first = np.where(rows, con.argmax(axis=1), mx)
    last = np.where(rows, mx - 1 - con[:, ::-1].argmax(axis=1), -1)
    e_lo = first.astype(np.int64)
    e_hi = last.astype(np.int64)
    # q_j = p_j - p_{j+1} is non-zero for j = e_lo-1 .. e_hi, i.e. columns c = j+1 = e_lo .. e_hi+1
    c_lo = e_lo.copy()
    c_hi = np.where(rows, e_hi + 1, -1).astype(np.int64)
    area_ratio = float(con.sum()) * (2.0 * scale) ** 2 / (mx * my * math.pi)
    return ContactGrid(pn, con, e_lo, e_hi, c_lo, c_hi, it, area_ratio)


@dataclass(frozen=True)
class ExactWarmState:
    """What an exact solution leaves for the next solve (``ContactResult.warm_state``).

    The grid and problem it belongs to (``mx, my, scale, saturation``: a state of another grid
    is not used; ``nu``: the scaled start and the secant need the same one; ``a_over_b``), the
    solution's tractions divided by the reference scale (μ p0 with saturation, G otherwise)
    ``px, py`` (my, mx), its normalised creepages ``sigma`` = (ξ, η, φ √(ab))/(μ p0/G), and
    ``previous``: (px, py, sigma) of the solution it was started from, for the secant.
    """

    mx: int
    my: int
    scale: float
    saturation: bool
    a_over_b: float
    nu: float
    px: np.ndarray
    py: np.ndarray
    sigma: np.ndarray
    previous: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def to_record(self) -> dict[str, Any]:
        """Data only: numbers and float arrays (``prev_px`` etc. for ``previous``)."""
        rec: dict[str, Any] = {k: getattr(self, k) for k in _WARM_SCALARS + _WARM_ARRAYS}
        if self.previous is not None:
            rec.update(zip(_WARM_PREVIOUS, self.previous))
        return rec

    @classmethod
    def from_record(cls, record: dict[str, Any]) -> "ExactWarmState":
        """The inverse of :meth:`to_record`, checked: the keys it writes, finite numbers, a grid
        of 4..400 elements per side, tractions of shape (my, mx) and creepages of length 3."""
        keys = set(_WARM_SCALARS + _WARM_ARRAYS)
        if not isinstance(record, dict) or set(record) not in (keys, keys | set(_WARM_PREVIOUS)):
            raise ValueError(f"the warm state must have the keys {sorted(keys)} (and optionally "
                             f"all of {list(_WARM_PREVIOUS)})")
        for k in _WARM_SCALARS:
            v = record[k]
            if type(v) not in (int, float, bool) or not math.isfinite(v):
                raise ValueError(f"warm state {k}={v!r} is not a finite number")
        mx, my = record["mx"], record["my"]
        if not (mx == int(mx) and my == int(my) and 4 <= mx <= 400 and 4 <= my <= 400):
            raise ValueError(f"warm state grid {mx!r} x {my!r} is out of range: allowed whole "
                             "numbers 4..400")
        previous = _WARM_PREVIOUS[0] in record
        shapes = {"px": (int(my), int(mx)), "py": (int(my), int(mx)), "sigma": (3,)}
        for k in _WARM_ARRAYS + (_WARM_PREVIOUS if previous else ()):
            a = record[k]
            want = shapes[k.removeprefix("prev_")]
            if not (isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == want
                    and np.isfinite(a).all()):
                raise ValueError(f"warm state {k} must be a finite float64 array of shape {want}")
        return cls(int(mx), int(my), float(record["scale"]), bool(record["saturation"]),
                   float(record["a_over_b"]), float(record["nu"]), record["px"], record["py"],
                   record["sigma"],
                   tuple(record[k] for k in _WARM_PREVIOUS) if previous else None)


_WARM_SCALARS = ("mx", "my", "scale", "saturation", "a_over_b", "nu")
_WARM_ARRAYS = ("px", "py", "sigma")
_WARM_PREVIOUS = ("prev_px", "prev_py", "prev_sigma")


@dataclass(frozen=True)
class _GridSolution:
    result: ContactResult
    moment_bound: float     # ∫ p_n r dA on the grid, N·m (times μ: Coulomb's bound on |Mz|)


class Exact(ContactMethod):
    """Kalker's exact steady-rolling theory on a grid of ``mx × my`` elements.

    Options
    -------
    mx, my : int
        Elements along x (rolling) and y, 4..400 each. Default 52 × 52 with ``extrapolate``
        (the module docstring; the cost and accuracy of other settings: docs/reports/
        accuracy_vs_time.md).
        Without extrapolation the error is first order in the element size, with a staircase
        part that jumps with the grid (see ``extrapolate``).
    scale : float
        Half-size of the potential contact area in semi-axes, 1 < scale <= 3 (default 1.1, as in
        CONTACT).
    tol : float
        Stop when the rms traction update of a sweep is below ``tol`` times the rms traction,
        0 < tol < 1 (default 1e-5: forces converged to about 1e-7 relative).
    maxit : int
        Maximum number of Gauss–Seidel sweeps, 1..100000 (default 2000).
    normal : {"numerical", "hertz"}
        Pressure from the discrete normal problem on the same grid (default: consistent with
        the tangential discretisation), or Hertz's at the element centres.
    fields : bool
        Attach an :class:`ExactFields` to the result (default False).
    half : bool
        Solve η = φ = 0 on the half grid (default True; False: the full grid, same result).
    predictor : {"secant", "scale", "none"}
        Start of a warm-started solve (module docstring; default "secant").
    extrapolate : bool
        Richardson extrapolation from this grid and its half (default True; module docstring;
        needs mx, my >= 16). False: the one grid as it is, at about 1/1.1 of the time.
    spin_shift : float
        Where the spin term of the lateral rigid slip is sampled, in elements downstream of the
        element centre, 0 <= spin_shift <= 0.5 (default 1/6, CONTACT's: the same forces as
        CONTACT on the same grid; 0.25: smaller worst-case spin errors on a fixed grid; module
        docstring, "Rigid slip with spin").
    falling : {"local", "creep"}
        With the effect ``falling_friction``: each element's bound at its own slip velocity
        (default; :mod:`.falling`), or one coefficient at the creep velocity (the closed
        forms' way, for comparison).
    layer : float
        Flexibility h/G3 of an elastic interfacial layer, m/Pa (default 0: none; :mod:`.layer`).
        Inputs outside the physical range (which the method solves in similarity units, where
        the layer has no scale) are refused with it.
    """

    name = "exact"
    code = 4
    default_options: dict = {"mx": 52, "my": 52, "scale": 1.1, "tol": 1e-5, "maxit": 2000,
                             "normal": "numerical", "fields": False, "half": True,
                             "predictor": "secant", "extrapolate": True,
                             "spin_shift": 1.0 / 6.0, "falling": "local", "layer": 0.0}
    option_units = {"layer": "m/Pa"}

    def _check_options(self) -> None:
        o = self.options
        int_option(o, "mx", 4, 400)
        int_option(o, "my", 4, 400)
        int_option(o, "maxit", 1, 100000)
        float_option(o, "scale", 1.0, 3.0, lo_open=True)
        float_option(o, "tol", 0.0, 1.0, lo_open=True, hi_open=True)
        float_option(o, "spin_shift", 0.0, 0.5)
        choice_option(o, "normal", ("numerical", "hertz"))
        bool_option(o, "fields")
        bool_option(o, "half")
        choice_option(o, "predictor", PREDICTORS)
        bool_option(o, "extrapolate")
        choice_option(o, "falling", ("local", "creep"))
        float_option(o, "layer", 0.0, math.inf, hi_open=True)
        self._falling_local = self.friction is not None and o["falling"] == "local"
        if o["extrapolate"]:
            for k in ("mx", "my"):
                if o[k] < 16:
                    raise ValueError(f"{k}={o[k]!r} is invalid with extrapolate=True: allowed an "
                                     f"integer 16 <= {k} <= 400 (the half grid needs 8 elements "
                                     "per side), or extrapolate=False")

    @classmethod
    def warm_state_from_record(cls, record: dict[str, Any] | None) -> ExactWarmState | None:
        return None if record is None else ExactWarmState.from_record(record)

    def _similar(self, *args, **kwargs) -> ContactResult:
        if self.options["layer"] > 0.0:
            raise ValueError(f"layer={self.options['layer']!r} with inputs outside the physical "
                             "range (semi-axes 1e-8..1e3 m, G 1e-3..1e15 Pa, N and mu*N "
                             "1e-12..1e12 N, normalised creepage 1e-60..1e6), which are solved "
                             "in similarity units where the layer has no scale: allowed layer=0 "
                             "there")
        return super()._similar(*args, **kwargs)

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start,
                   rolling: Rolling | None = None):
        o = self.options
        mx, my = o["mx"], o["my"]
        fine = self._grid_solve(mx, my, o["extrapolate"], xi, eta, phi, N, mu, a, b, G, nu,
                                warm_start, rolling)
        if not o["extrapolate"]:
            return fine.result
        mx2, my2 = mx // 2, my // 2
        coarse = self._grid_solve(mx2, my2, True, xi, eta, phi, N, mu, a, b, G, nu, None,
                                  rolling)
        # Richardson, first order in the element size h ∝ 1/m: q = q1 + (q1 - q2)/(r - 1)
        w = 1.0 / (math.sqrt(mx * my / (mx2 * my2)) - 1.0)
        rf, rc = fine.result, coarse.result
        Fx = rf.Fx + w * (rf.Fx - rc.Fx)
        Fy = rf.Fy + w * (rf.Fy - rc.Fy)
        Mz = rf.Mz + w * (rf.Mz - rc.Mz)
        if self.effects.saturation:
            # Coulomb's bounds, which each grid meets but their combination need not
            f = math.hypot(Fx, Fy)
            if f > mu * N:
                Fx, Fy = Fx * (mu * N / f), Fy * (mu * N / f)
            Mz = math.copysign(min(abs(Mz), mu * fine.moment_bound), Mz)
        return replace(rf, Fx=Fx, Fy=Fy, Mz=Mz, converged=rf.converged and rc.converged,
                       iterations=rf.iterations + rc.iterations,
                       residual=max(rf.residual, rc.residual))

    def _grid_solve(self, mx: int, my: int, continuum_area: bool, xi, eta, phi, N, mu, a, b, G,
                    nu, warm_start, rolling: Rolling | None = None) -> "_GridSolution":
        """One solve on an ``mx × my`` grid. ``continuum_area``: map it to the continuum's
        contact area by similarity (module docstring, "Extrapolation"). ``rolling``: local
        falling friction (:mod:`.falling`)."""
        o = self.options
        scale = o["scale"]
        eff = self.effects
        grid = contact_grid(mx, my, scale, a / b, o["normal"])
        k = grid.area_ratio if continuum_area else 1.0
        if k != 1.0:
            xi, eta, phi = xi / k, eta / k, phi / k ** 1.5
        p0 = max_pressure(N, a, b)
        dx, dy = 2.0 * scale * a / mx, 2.0 * scale * b / my
        x = -scale * a + (np.arange(mx) + 0.5) * dx
        y = -scale * b + (np.arange(my) + 0.5) * dy
        ratio = dy / dx
        layer = o["layer"] * G / dx
        if layer > 0.0:
            kxx, kxy, kyy = layer_kernel_tables(mx, my, ratio, nu, layer)
        else:
            kxx, kxy, kyy = kernel_tables(mx, my, ratio, nu)
        con = grid.contact
        saturation = eff.saturation
        # tractions in units of G; reference scale of the warm state
        ref = mu * p0 / G if saturation else 1.0
        bound = np.where(con, mu * p0 / G * grid.pn if saturation else np.inf, 0.0)
        sx = np.where(con, xi - phi * y[:, None], 0.0)
        # rigid slip; its spin term sampled spin_shift elements downstream (module docstring)
        sy = np.where(con, eta + phi * (x[None, :] + o["spin_shift"] * dx), 0.0)
        # normalised creepages of the warm state's secant predictor
        sigma = np.array([xi, eta, phi * math.sqrt(a * b)]) / ref
        px, py, start = self._initial(warm_start, saturation, a / b, nu, sigma, ref, con, bound)
        fold = None
        if o["half"] and eta == 0.0 and phi == 0.0:
            fold = (layer_folded_tables(mx, my, ratio, nu, layer) if layer > 0.0
                    else folded_kernel_tables(mx, my, ratio, nu))

        def solve(px, py, bound):
            if fold is None:
                return self._solve_full(px, py, bound, sx, sy, con, kxx, kxy, kyy, grid)
            return self._solve_half(px, py, bound, sx, sy, con, kxx, kyy, fold, grid)

        it, rel, px, py, status, qx, qy = solve(px, py, bound)
        outer_ok = True
        if rolling is not None and rolling.V > 0.0:
            # the slip of the grid's problem is k times the continuum's (its creepages / k);
            # its elements stand for dx / √k of the continuum's contact
            def slip(px, py, qx, qy, status):
                wx, wy = slip_field(px, py, qx, qy, status, sx, sy, kxx, kxy, kyy, grid.c_lo,
                                    grid.c_hi, grid.e_lo, grid.e_hi)
                return k * wx, k * wy
            (it, rel, px, py, status, qx, qy), outer, change = local_friction(
                solve, slip, (it, rel, px, py, status, qx, qy), bound, self._law, rolling.V,
                dx / (math.sqrt(k) * rolling.V), rolling.memory, 10.0 * o["tol"])
            outer_ok = change <= 10.0 * o["tol"]
            if not outer_ok:
                notices.warn(f"exact: falling friction not settled after {outer} outer "
                             f"iterations (friction field change {change:.3g}); xi={xi:g}, "
                             f"eta={eta:g}, phi={phi:g}, {mx}x{my} grid", ExactSolverWarning,
                             stacklevel=4)
        converged = bool(rel <= o["tol"]) and outer_ok
        if not converged:
            notices.warn(f"exact: not converged after {it} sweeps (relative update {rel:.3g} > "
                         f"tol={o['tol']:g}); xi={xi:g}, eta={eta:g}, phi={phi:g}, "
                         f"a/b={a / b:g}, {mx}x{my} grid", ExactSolverWarning, stacklevel=4)
        dA = G * dx * dy
        Fx = float(px.sum()) * dA if eff.longitudinal else 0.0
        # half grid: X even and Y odd in y, so Fy = Mz = 0 exactly (not only to rounding)
        Fy = float(py.sum()) * dA if eff.lateral and fold is None else 0.0
        Mz = (float((x[None, :] * py).sum() - (y[:, None] * px).sum()) * dA / math.sqrt(k)
              if eff.spin and fold is None else 0.0)
        ncon = int(con.sum())
        nslip = int((status == SLIP).sum())
        fields = None
        if o["fields"]:
            wx, wy = slip_field(px, py, qx, qy, status, sx, sy, kxx, kxy, kyy, grid.c_lo,
                                grid.c_hi, grid.e_lo, grid.e_hi)
            fields = ExactFields(x=x, y=y, pn=p0 * grid.pn, px=G * px, py=G * py, sx=wx, sy=wy,
                                 status=status.copy())
        # with the solution this one was started from: the secant predictor of the next step
        warm_state = ExactWarmState(mx, my, scale, saturation, a / b, float(nu), px / ref,
                                    py / ref, sigma, start)
        result = ContactResult(Fx, Fy, Mz, self.name,
                               slip_fraction=nslip / ncon if ncon else 0.0, converged=converged,
                               iterations=int(it), residual=float(rel), fields=fields,
                               warm_state=warm_state)
        # ∫ p_n r dA over the grid (times μ: the largest |Mz| Coulomb friction allows)
        moment_bound = (float((grid.pn * np.hypot(x[None, :], y[:, None])).sum()) * p0 * dx * dy
                        if continuum_area else math.inf)
        return _GridSolution(result, moment_bound)

    def _solve_full(self, px, py, bound, sx, sy, con, kxx, kxy, kyy, grid):
        o = self.options
        qx, qy = traction_differences(px, py)
        status = _status(px, py, con, bound)
        it, rel = solve_steady(px, py, qx, qy, status, bound, sx, sy, kxx, kxy, kyy,
                               grid.c_lo, grid.c_hi, grid.e_lo, grid.e_hi, o["tol"], o["maxit"],
                               1.0, _AA_DEPTH, _AA_START)
        return it, rel, px, py, status, qx, qy

    def _solve_half(self, px, py, bound, sx, sy, con, kxx, kyy, fold, grid):
        """η = φ = 0: X even, Y odd in y; solve on the rows y >= 0 (:func:`solve_steady_half`),
        then mirror (the full arrays are exactly symmetric)."""
        o = self.options
        my = px.shape[0]
        npair = (my + 1) // 2
        h = slice(my - npair, my)
        hpx = np.ascontiguousarray(px[h])
        hpy = np.ascontiguousarray(py[h])
        if my % 2:
            hpy[0] = 0.0                 # Y odd in y: zero on the centre row
        hb = np.ascontiguousarray(bound[h])
        hcon = con[h]
        qx, qy = traction_differences(hpx, hpy)
        status = _status(hpx, hpy, hcon, hb)
        it, rel = solve_steady_half(hpx, hpy, qx, qy, status, hb, np.ascontiguousarray(sx[h]),
                                    np.ascontiguousarray(sy[h]), kxx, kyy, *fold, my,
                                    grid.c_lo[h], grid.c_hi[h], grid.e_lo[h], grid.e_hi[h],
                                    o["tol"], o["maxit"], 1.0, _AA_DEPTH, _AA_START)
        m = slice(npair - 1, None, -1) if my % 2 == 0 else slice(npair - 1, 0, -1)
        # mirror rows: full row my-1-iy; the lower half is the upper half reversed
        px = np.concatenate([hpx[m], hpx])
        py = np.concatenate([-hpy[m], hpy])
        status = np.concatenate([status[m], status])
        qx = np.concatenate([qx[m], qx])
        qy = np.concatenate([-qy[m], qy])
        return it, rel, px, py, status, qx, qy

    def _initial(self, warm_start: Any, saturation: bool, a_over_b: float, nu: float,
                 sigma: np.ndarray, ref: float, con: np.ndarray,
                 bound: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple | None]:
        """Start from a compatible previous solution (scaled to the new μ p0), else from zero.

        With the solution the previous one was started from (a co-simulation sequence), the
        start is extrapolated along the secant: p = p_k + α (p_k - p_{k-1}), α the projection of
        the change of the normalised creepages σ = (ξ, η, φ √(ab))/(μ p0/G) onto the last one
        (|α| <= 3). Otherwise (same ν; a/b may differ) p = s p_k with s = σ·σ_k/|σ_k|², then
        clipped to the friction bound. ``predictor`` "scale" skips the secant, "none" both.
        Returns (px, py, (px/ref, py/ref, σ) of the start or None).
        """
        o = self.options
        my, mx = con.shape
        st = getattr(warm_start, "warm_state", None)
        if not (isinstance(st, ExactWarmState) and st.mx == mx and st.my == my
                and st.scale == o["scale"] and st.saturation == saturation):
            return np.zeros((my, mx)), np.zeros((my, mx)), None
        px_k, py_k, sig_k = st.px, st.py, st.sigma
        px = px_k
        py = py_k
        # the tractions are on a grid of the semi-axes, in units of μ p0: for another a/b (a
        # geometry that changes at every step) they are a start as good as for the same one
        same = st.nu == nu
        predictor = o["predictor"]
        secant = False
        if predictor == "secant" and same and st.previous is not None:
            prev_px, prev_py, prev_sigma = st.previous
            d_old = sig_k - prev_sigma
            nn = float(d_old @ d_old)
            if nn > 0.0:
                alpha = float((sigma - sig_k) @ d_old) / nn
                if 0.0 < abs(alpha) <= 3.0:
                    px = px_k + alpha * (px_k - prev_px)
                    py = py_k + alpha * (py_k - prev_py)
                    secant = True
        if predictor != "none" and same and not secant:
            nn = float(sig_k @ sig_k)
            if nn > 0.0:
                s = float(sigma @ sig_k) / nn
                px = s * px_k
                py = s * py_k
        px = np.where(con, px * ref, 0.0)
        py = np.where(con, py * ref, 0.0)
        absp = np.hypot(px, py)
        over = absp > bound
        if over.any():
            f = np.where(over, bound / np.where(over, absp, 1.0), 1.0)
            px *= f
            py *= f
        start = (px_k, py_k, sig_k) if same else None
        return px, py, start


def _status(px: np.ndarray, py: np.ndarray, con: np.ndarray, bound: np.ndarray) -> np.ndarray:
    absp = np.hypot(px, py)
    return np.where(con, np.where(absp >= bound * (1.0 - 1e-12), SLIP, STICK),
                    EXTERIOR).astype(np.int8)
