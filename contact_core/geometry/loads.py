"""How a wheel's load divides between its patches, and a wheel's forces for a given vertical load.

Load sharing (multi-Hertzian contact with a common rigid approach; e.g. Piotrowski & Chollet
2005, "Wheel–rail contact models for vehicle system dynamics including multi-point contact",
Vehicle System Dynamics 43): every patch of a wheel is a Hertz contact of its own curvatures A, B
(:mod:`.search`), and all of them share the wheel's rigid displacement. A patch whose deepest
point overlaps the rail by the vertical distance −g has the normal approach −g cos δ (δ the
contact angle there), so that Hertz's approach–load relation δ_n = k_d N^{2/3}
(:func:`contact_core.hertz.hertz_geometry`) gives

    N = (−g cos δ / k_d)^{3/2}   for g < 0, else 0.

A wheel's vertical force on the rail in the track frame is the sum over its patches of
N cos δ + F_s sin δ, F_s the lateral creep force on the rail in the contact plane (CONTACT's
module 1 solves the wheelset height for this total, tangential parts included: Vollebregt,
CONTACT user guide, "Wheelset geometry & state"). :func:`solve_wheel` finds the height z at which a wheel carries a
given vertical load (Brent's method), with the contact search, the creepages
(:mod:`.kinematics`) and the creep forces (:func:`contact_core.solve`) of every patch evaluated at
each trial height.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

from scipy.optimize import brentq

from ..api import solve
from ..hertz import HertzGeometry, HertzPatch, hertz_geometry
from ..material import shear_modulus
from ..result import ContactResult
from .kinematics import Creepage, WheelsetMotion, creepages
from .search import ContactPoint, WheelsetPosition, touch_height, wheel_contact
from .track import SIDES, WheelsetOnTrack


def _normal_load(point: ContactPoint, kd: float, approach: float = 0.0) -> float:
    """Hertz's load of a patch whose wheel is moved ``approach`` (m) further down."""
    overlap = (approach - point.gap) * math.cos(point.delta_deepest)
    return (overlap / kd) ** 1.5 if overlap > 0.0 else 0.0


def normal_loads(points: Sequence[ContactPoint], E: float, nu: float) -> tuple[float, ...]:
    """Normal load (N) of each patch from its overlap (module docstring); ``E`` Young's modulus
    (Pa) and ``nu`` Poisson's ratio of wheel and rail."""
    return tuple(_normal_load(p, patch_geometry(p, E, nu).kd) for p in points)


def share_load(points: Sequence[ContactPoint], load: float, E: float,
               nu: float) -> tuple[float, ...]:
    """Normal loads (N) of the patches when the wheel, moved down rigidly from the position of
    ``points`` until they overlap, carries the vertical ``load`` (N) without tangential forces:
    Σ N cos δ = load with a common approach (module docstring)."""
    if not (math.isfinite(load) and load > 0.0):
        raise ValueError(f"load={load!r} is out of range: allowed 0 < load < inf (N)")
    kd = [patch_geometry(p, E, nu).kd for p in points]

    def excess(d: float) -> float:
        return sum(_normal_load(p, k, d) * math.cos(p.delta) for p, k in zip(points, kd)) - load
    # bracket: the approach at which the deepest patch alone carries the load, widened
    i = min(range(len(points)), key=lambda j: points[j].gap)
    c = math.cos(points[i].delta_deepest)
    lo = points[i].gap
    hi = lo + kd[i] * (load / c) ** (2 / 3) / c
    while excess(hi) < 0.0:
        hi += hi - lo
    d = brentq(excess, lo, hi, xtol=1e-15, rtol=1e-13)
    return tuple(_normal_load(p, k, d) for p, k in zip(points, kd))


def patch_geometry(point: ContactPoint, E: float, nu: float) -> HertzGeometry:
    """Hertz's load-independent solution (:class:`contact_core.HertzGeometry`) of a patch; a
    conformal patch (B <= 0) is outside Hertz's theory and is a ``ValueError``."""
    if not point.B > 0.0:
        raise ValueError(f"{point.side} wheel, patch {point.slot}: relative curvature B="
                         f"{point.B!r} 1/m <= 0 at y_w={point.y_wheel!r} m: a conformal contact, "
                         "outside Hertz's theory")
    return hertz_geometry(point.A, point.B, E, nu)


@dataclass(frozen=True)
class PatchSolution:
    """A loaded patch: its geometry ``point``, ``creepage``, normal load ``N`` (N), Hertz patch
    ``hertz`` (semi-axes a along x, b across, m) and the contact law's ``result`` (forces of the
    rail on the wheel in the contact frame, contact_core's convention)."""

    point: ContactPoint
    creepage: Creepage
    N: float
    hertz: HertzPatch
    result: ContactResult

    def rail_force(self) -> tuple[float, float, float]:
        """Force on the rail in the track frame (x, y, z), N: −(Fx, Fy) in the contact plane and
        N along the contact normal n = (0, −sin δ, cos δ)."""
        cd, sd = math.cos(self.point.delta), math.sin(self.point.delta)
        fs = -self.result.Fy
        return -self.result.Fx, fs * cd - self.N * sd, fs * sd + self.N * cd


@dataclass(frozen=True)
class WheelSolution:
    """One wheel carrying its load: the wheelset's ``position`` (its height ``z`` solved for
    this wheel) and the wheel's loaded ``patches``."""

    side: str
    position: WheelsetPosition
    patches: tuple[PatchSolution, ...]

    def rail_force(self) -> tuple[float, float, float]:
        """Total force of the wheel on the rail, track frame, N."""
        f = [p.rail_force() for p in self.patches]
        return tuple(sum(c) for c in zip(*f)) if f else (0.0, 0.0, 0.0)


def solve_wheel(model: WheelsetOnTrack, side: str, *, y: float, yaw: float, roll: float,
                load: float, motion: WheelsetMotion, mu: float, E: float, nu: float,
                method: str = "table", options: dict[str, Any] | None = None) -> WheelSolution:
    """The ``side`` wheel of the wheelset at ``y`` (m), ``yaw``, ``roll`` (rad) and the height
    at which its vertical force on the rail, tangential parts included, is ``load`` (N):
    patches, creepages from ``motion``, normal loads (common approach) and creep forces of
    ``method`` (friction ``mu``, Young's modulus ``E`` in Pa, Poisson's ratio ``nu``)."""
    if side not in SIDES:
        raise ValueError(f"side={side!r} is invalid: allowed {list(SIDES)}")
    if not (math.isfinite(load) and load > 0.0):
        raise ValueError(f"load={load!r} is out of range: allowed 0 < load < inf (N)")
    G, r0, opts = shear_modulus(E, nu), model.wheelset.nominal_radius, options or {}
    z0 = touch_height(model, side, y, roll, yaw)

    def state(d: float) -> WheelSolution:
        position = WheelsetPosition(y, z0 + d, roll, yaw)
        points = wheel_contact(model, side, y, z0 + d, roll, yaw).points
        patches = []
        for p in points:
            geometry = patch_geometry(p, E, nu)
            N = _normal_load(p, geometry.kd)
            if N == 0.0:
                continue
            c = creepages(position, p, motion, r0)
            h = geometry.patch(N)
            res = solve(method, xi=c.xi, eta=c.eta, phi=c.phi, N=N, mu=mu, a=h.a, b=h.b, G=G,
                        nu=nu, **opts)
            patches.append(PatchSolution(p, c, N, h, res))
        return WheelSolution(side, position, tuple(patches))

    def excess(d: float) -> float:
        return state(d).rail_force()[2] - load

    # bracket: the approach without tangential forces, widened until it holds
    points = wheel_contact(model, side, y, z0, roll, yaw).points
    N = share_load(points, load, E, nu)
    i = max(range(len(points)), key=lambda j: N[j])
    hi = 2.0 * (patch_geometry(points[i], E, nu).kd * N[i] ** (2 / 3)
                / math.cos(points[i].delta_deepest) + points[i].gap)
    while excess(hi) < 0.0:
        hi *= 2.0
        if hi > 0.01:
            raise ValueError(f"{side} wheel: no height carries load={load!r} N")
    d = brentq(excess, 0.0, hi, xtol=1e-14, rtol=1e-12)   # the load to about 1e-9 relative
    return state(d)
